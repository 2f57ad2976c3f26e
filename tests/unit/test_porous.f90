!> The porous field (module porous) against what it must be: inside a region
!> the porosity and Van Gent's coefficients of that region; outside, none;
!> across the outline a smooth step that takes half the drop at the outline
!> and is done a half width away; two regions sharing an edge meet at the mean
!> of their porosities without a jump; the pore water's acceleration
!> balances gravity at the terminal velocity of the Forchheimer law.
program test_porous
   use kinds, only: rp
   use constants, only: ndim, kind_fluid, kind_fixed, kind_floating
   use porous, only: porous_t, porous_point, porous_field, porous_accel, porous_rate_max, porous_lookup, n_por
   use testing, only: check, check_close, test_summary
   implicit none
   type(porous_t) :: por
   real(rp) :: f(n_por), fa(n_por), fb(n_por), kl, kq, ca, n, d, g, vt, eps, jump
   real(rp) :: x3(ndim, 3), ff3(n_por, 3)
   real(rp) :: v(ndim, 2), acc(ndim, 2), ff(n_por, 2), dr(2)
   integer :: k

   ! a core 1 m x 0.5 m (n = 0.4, D = 0.05 m) with a filter layer (n = 0.5,
   ! D = 0.02 m) on top of it, sharing the edge y = 0.5; transition 0.04 m wide
   por%on = .true.
   allocate (por%r(2))
   call region(por%r(1), 0.0_rp, 1.0_rp, 0.0_rp, 0.5_rp, 0.4_rp, 0.05_rp)
   call region(por%r(2), 0.0_rp, 1.0_rp, 0.5_rp, 0.6_rp, 0.5_rp, 0.02_rp)

   ! deep inside the core: its own porosity and Van Gent's coefficients
   n = 0.4_rp
   d = 0.05_rp
   f = porous_point(por, [0.5_rp, 0.25_rp])
   call check_close(f(1), n, 1.0e-15_rp, 'porosity inside')
   kl = 1000.0_rp*1.0e-6_rp*(1.0_rp - n)**2/(n**3*d*d)*n          ! g a n: alpha (1-n)^2/n^3 nu/D^2 times n
   kq = 1.1_rp*(1.0_rp - n)/(n**3*d)*n*n                           ! g b n^2: beta (1-n)/n^3 /D times n^2
   ca = 0.34_rp*(1.0_rp - n)/n
   call check_close(f(2), kl, 1.0e-14_rp, 'linear rate inside')
   call check_close(f(3), kq, 1.0e-14_rp, 'quadratic factor inside')
   call check_close(f(4), ca, 1.0e-14_rp, 'added mass inside')

   ! outside every region, and a half width outside the outline: no pores
   f = porous_point(por, [1.5_rp, 0.25_rp])
   call check(maxval(abs(f - [1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp])) < tiny(1.0_rp), 'no pores outside')
   f = porous_point(por, [1.02_rp + 1.0e-12_rp, 0.25_rp])
   call check(abs(f(1) - 1.0_rp) < tiny(1.0_rp), 'no pores a half width outside')
   f = porous_point(por, [0.98_rp - 1.0e-12_rp, 0.25_rp])
   call check_close(f(1), n, 1.0e-12_rp, 'all of the porosity a half width inside')
   ! on the outline: half of the drop
   f = porous_point(por, [1.0_rp, 0.25_rp])
   call check_close(f(1), 1.0_rp - 0.5_rp*(1.0_rp - n), 1.0e-14_rp, 'half the drop on the outline')

   ! the step is smooth: the largest change between points 1 mm apart across
   ! the outline stays near the slope of the smoothstep, 1.5 (1 - n)/width per m
   jump = 0.0_rp
   fa = porous_point(por, [0.95_rp, 0.25_rp])
   do k = 1, 100
      fb = porous_point(por, [0.95_rp + 0.001_rp*k, 0.25_rp])
      jump = max(jump, abs(fb(1) - fa(1)))
      fa = fb
   end do
   call check(jump <= 1.5_rp*(1.0_rp - n)/0.04_rp*0.001_rp*1.0001_rp, 'no jump across the outline')

   ! two regions sharing an edge: the mean of their porosities on it, and no jump across it
   f = porous_point(por, [0.5_rp, 0.5_rp])
   call check_close(f(1), 0.45_rp, 1.0e-14_rp, 'mean porosity on a shared edge')
   jump = 0.0_rp
   fa = porous_point(por, [0.5_rp, 0.45_rp])
   do k = 1, 100
      fb = porous_point(por, [0.5_rp, 0.45_rp + 0.001_rp*k])
      jump = max(jump, abs(fb(1) - fa(1)))
      fa = fb
   end do
   call check(jump <= 1.5_rp*0.1_rp/0.04_rp*0.001_rp*1.0001_rp, 'no jump across a shared edge')

   call check(norm2(porous_point(por, [0.5_rp, 0.25_rp]) - [n, kl, kq, ca]) < 1.0e-12_rp, &
              'deep inside: the region''s own properties')

   ! the field of particles: wall particles lend their pressure with the porosity where they are
   x3 = spread([0.5_rp, 0.25_rp], 2, 3)
   call porous_field(por, 3, x3, [kind_fluid, kind_fixed, kind_floating], ff3)
   call check_close(ff3(1, 1), n, 1.0e-15_rp, 'fluid particle in the core')
   call check_close(ff3(1, 2), n, 1.0e-15_rp, 'wall particle in the core')
   call check(abs(ff3(1, 3) - 1.0_rp) < tiny(1.0_rp) .and. maxval(abs(ff3(2:, 3))) < tiny(1.0_rp), &
              'a floating body is open water to the pores, wherever it is')

   ! with no pair forces, the pore water falls at the terminal velocity of
   ! the Forchheimer law, where kl V + kq V^2 = g: the acceleration vanishes
   g = 9.81_rp
   f = porous_point(por, [0.5_rp, 0.25_rp])
   vt = (-f(2) + sqrt(f(2)**2 + 4.0_rp*f(3)*g))/(2.0_rp*f(3))
   v(:, 1) = [0.0_rp, -vt]
   v(:, 2) = [0.0_rp, -0.5_rp*vt]
   acc(:, 1) = [0.0_rp, -g]
   acc(:, 2) = [0.0_rp, -g]
   ff(:, 1) = f
   ff(:, 2) = f
   dr = 0.0_rp
   call porous_accel(2, [kind_fluid, kind_fluid], ff, v, acc, dr)
   call check(abs(acc(2, 1)) < 1.0e-12_rp*g, 'terminal velocity: no acceleration')
   ! slower: accelerated by what the resistance leaves of gravity, over 1 + c_A
   eps = (g - f(2)*0.5_rp*vt - f(3)*(0.5_rp*vt)**2)/(1.0_rp + f(4))
   call check_close(-acc(2, 2), eps, 1.0e-13_rp, 'accelerating pore water')
   ! the rate that limits an explicit step: the derivative of the resistance over 1 + c_A
   call check_close(porous_rate_max(1, [kind_fluid], ff, v), (f(2) + 2.0_rp*f(3)*vt)/(1.0_rp + f(4)), 1.0e-14_rp, &
                    'resistance rate')
   ! a wall particle among the pores took part in the pairs as pore water of
   ! mass n m and density n rho: back to its own mass and density
   acc(:, 2) = [0.1_rp, -0.2_rp]
   dr(2) = 3.0_rp
   call porous_accel(2, [kind_fluid, kind_fixed], ff, v, acc, dr)
   call check(norm2(acc(:, 2) - n*[0.1_rp, -0.2_rp]) < 1.0e-15_rp, 'wall: force per true mass')
   call check_close(dr(2), 3.0_rp/n, 1.0e-15_rp, 'wall: rate of its own density')

   ! the lookup grid of porous_field gives every particle exactly what
   ! porous_point gives it: on a lattice over the regions and around them
   block
      integer, parameter :: m = 97
      real(rp), allocatable :: xs(:, :), fl(:, :)
      real(rp) :: fp(n_por), dev
      integer, allocatable :: ks(:)
      integer :: i, j
      type(porous_t) :: pl
      allocate (xs(ndim, m*m), fl(n_por, m*m), ks(m*m))
      pl = por
      call porous_lookup(pl, 0.01_rp)
      call check(pl%cell > 0.0_rp, 'the lookup grid is built')
      ! (the grid spans the regions' reach: points beyond it are out of reach)
      call check(count(pl%code == 1) > 0 .and. count(pl%code == 2) > 0 .and. count(pl%code == 0) > 0, &
                 'cells deep in either region and along the outlines')
      do j = 1, m
         do i = 1, m
            xs(:, (j - 1)*m + i) = [-0.1_rp + 1.2_rp*(i - 1)/(m - 1), -0.1_rp + 0.8_rp*(j - 1)/(m - 1)]
         end do
      end do
      ks = kind_fluid
      call porous_field(pl, m*m, xs, ks, fl)
      dev = 0.0_rp
      do i = 1, m*m
         fp = porous_point(por, xs(:, i))
         dev = max(dev, maxval(abs(fl(:, i) - fp)))
      end do
      call check(dev < tiny(1.0_rp), 'the lookup grid is exact')
   end block

   call test_summary('test_porous')

contains

   subroutine region(r, x0, x1, y0, y1, nr, d50)
      use porous, only: porous_region_t
      type(porous_region_t), intent(out) :: r
      real(rp), intent(in) :: x0, x1, y0, y1, nr, d50
      r%v = reshape([x0, y0, x1, y0, x1, y1, x0, y1], [2, 4])
      r%n = nr
      r%d50 = d50
      r%alpha = 1000.0_rp
      r%beta = 1.1_rp
      r%gamma = 0.34_rp
      r%nu = 1.0e-6_rp
      r%width = 0.04_rp
      r%bb = [x0 - 0.02_rp, x1 + 0.02_rp, y0 - 0.02_rp, y1 + 0.02_rp]
   end subroutine region
end program test_porous

!> The modified dynamic boundary (module bc_mdbc): the first-order corrected
!> interpolation at a ghost point is exact for a linear field on disordered
!> particles of unequal volumes, so a solid particle takes exactly the linear
!> density at its own position (extrapolated along the gradient) and, with a
!> slip condition, exactly the mirrored velocity (no-slip: 2 v_wall - v_g;
!> free-slip: the ghost's tangential velocity, the normal one mirrored). A ghost
!> point with a single fluid neighbour takes the Shepard value; one with none,
!> rho0; no solid particle falls below rho0. The elimination solves a pivoting
!> system and gives its determinant.
program test_mdbc
   use kinds, only: rp, lk
   use constants, only: kind_fluid, kind_fixed
   use particles, only: particles_t, particles_alloc
   use grid, only: grid_t, grid_init, grid_sort
   use params, only: params_t, slip_wall, slip_noslip, slip_freeslip
   use kernel, only: kernel_wendland, kernel_cubic, kernel_norm
   use bc_mdbc, only: mdbc_update, mdbc_solve, mdbc_work_t
   use testing, only: check, check_close, test_summary, random_seed_fixed
   implicit none
   integer, parameter :: nx = 30, ny = 20, nwall = 3*nx, nextra = 2
   real(rp), parameter :: dp = 0.01_rp, rho0 = 1000.0_rp
   real(rp), parameter :: r0 = 1010.0_rp, gr(2) = [300.0_rp, -500.0_rp]     ! density rho0 + ... [kg/m3], gradient [kg/m4]
   real(rp), parameter :: u0(2) = [0.2_rp, -0.1_rp], gu(2, 2) = reshape([1.5_rp, 0.4_rp, -0.7_rp, 2.0_rp], [2, 2])
   type(particles_t) :: p
   type(grid_t) :: g
   type(mdbc_work_t) :: md
   type(params_t) :: prm
   logical(lk), allocatable :: drop(:)
   real(rp), allocatable :: vol(:), vb(:, :)
   real(rp) :: a(4, 4), b(4, 2), s(4, 2), det, xg(2), vg(2), nrm(2), err_r, err_v, want(2), lone_rho
   integer :: i, j, k, n, kern, slip
   integer, parameter :: kernels(2) = [kernel_wendland, kernel_cubic]

   ! the elimination: a system that needs row exchanges, and its determinant
   a = reshape([0.0_rp, 2.0_rp, 1.0_rp, 0.5_rp, 1.0_rp, 0.0_rp, 3.0_rp, 1.0_rp, &
                4.0_rp, 1.0_rp, 0.0_rp, 2.0_rp, 1.0_rp, 1.0_rp, 1.0_rp, 0.0_rp], [4, 4])
   b(:, 1) = matmul(a, [1.0_rp, -2.0_rp, 0.5_rp, 3.0_rp])
   b(:, 2) = matmul(a, [0.0_rp, 1.0_rp, 1.0_rp, -1.0_rp])
   call mdbc_solve(a, b, s, det)
   call check(maxval(abs(s(:, 1) - [1.0_rp, -2.0_rp, 0.5_rp, 3.0_rp])) < 1.0e-13_rp, 'solve: first column')
   call check(maxval(abs(s(:, 2) - [0.0_rp, 1.0_rp, 1.0_rp, -1.0_rp])) < 1.0e-13_rp, 'solve: second column')
   call check_close(det, determinant4(a), 1.0e-13_rp, 'solve: determinant')

   n = nx*ny + nwall + nextra
   allocate (drop(n), vol(n), vb(2, n))
   do k = 1, size(kernels)
      kern = kernels(k)
      do slip = slip_wall, slip_freeslip
         call scene()
         prm%kernel = kern
         prm%h = sqrt(2.0_rp)*dp
         prm%support2 = 4.0_rp*prm%h**2
         prm%aw = kernel_norm(kern, prm%h)
         prm%fw = prm%aw/prm%h**2
         prm%rho0 = rho0
         prm%slip = slip
         call grid_init(g, -0.05_rp, 0.35_rp, -0.05_rp, 0.25_rp, prm%h)
         drop = .false.
         call grid_sort(g, p, drop)
         call mdbc_update(prm, g, p, vol, vb, md)
         err_r = 0.0_rp
         err_v = 0.0_rp
         do i = 1, p%n
            if (p%kind(i) == kind_fluid) cycle
            if (p%id(i) == n - 1) then
               ! a ghost point with one fluid particle near: its density (Shepard)
               call check_close(p%rho(i), lone_rho, 1.0e-12_rp, 'one neighbour: the Shepard value')
               cycle
            else if (p%id(i) == n) then
               call check_close(p%rho(i), rho0, 1.0e-15_rp, 'no water near the ghost point: rho0')
               cycle
            end if
            err_r = max(err_r, abs(p%rho(i) - linear_rho(p%x(:, i)))/rho0)
            xg = p%x(:, i) + p%gof(:, i)
            vg = linear_v(xg)
            select case (slip)
            case (slip_noslip)
               want = 2.0_rp*p%v(:, i) - vg
            case (slip_freeslip)
               nrm = p%gof(:, i)/norm2(p%gof(:, i))
               want = vg - 2.0_rp*dot_product(vg - p%v(:, i), nrm)*nrm
            case default
               want = vb(:, i)
            end select
            err_v = max(err_v, maxval(abs(vb(:, i) - want)))
         end do
         call check(err_r < 1.0e-12_rp, 'solid density: the linear field at the particle (largest relative error '// &
                    real_text(err_r)//')')
         if (slip /= slip_wall) call check(err_v < 1.0e-12_rp, 'solid velocity: the mirrored linear field '// &
                                           '(largest error '//real_text(err_v)//' m/s)')
      end do
   end do

   ! a density below rho0 at the wall is raised to rho0 (a wall does not pull water)
   call scene(-0.02_rp)
   call grid_init(g, -0.05_rp, 0.35_rp, -0.05_rp, 0.25_rp, prm%h)
   drop = .false.
   call grid_sort(g, p, drop)
   prm%slip = slip_wall
   call mdbc_update(prm, g, p, vol, vb, md)
   call check(minval(p%rho(1:p%n), mask=p%kind(1:p%n) /= kind_fluid) >= rho0, 'no solid particle below rho0')
   call test_summary('test_mdbc')

contains

   !> Disordered fluid particles (a lattice shaken by up to 0.3 dp, masses
   !> varying by 20 %) with a linear density and velocity; three rows of
   !> wall below them mirrored across y = 0; one wall particle whose ghost
   !> point has a single fluid particle near (far right), one with none.
   subroutine scene(shift)
      real(rp), intent(in), optional :: shift
      real(rp) :: r(2), off
      integer :: ix, iy, m
      off = 0.0_rp
      if (present(shift)) off = shift*rho0
      if (allocated(p%x)) deallocate (p%x, p%v, p%rho, p%p, p%mass, p%nrm, p%xb, p%nb, p%surf, p%kind, p%body, p%id, &
                                      p%gof, p%gob)
      p%history = .false.
      p%mdbc = .true.
      call particles_alloc(p, n)
      call random_seed_fixed()
      m = 0
      do iy = 1, ny
         do ix = 1, nx
            m = m + 1
            call random_number(r)
            p%x(:, m) = [(ix - 0.5_rp)*dp, (iy - 0.5_rp)*dp] + 0.3_rp*dp*(r - 0.5_rp)
            p%kind(m) = kind_fluid
            call random_number(r)
            p%mass(m) = rho0*dp*dp*(0.9_rp + 0.2_rp*r(1))
            p%rho(m) = linear_rho(p%x(:, m)) + off
            p%v(:, m) = linear_v(p%x(:, m))
            p%gof(:, m) = 0.0_rp
         end do
      end do
      do iy = 1, 3
         do ix = 1, nx
            m = m + 1
            p%x(:, m) = [(ix - 0.5_rp)*dp, -(iy - 0.5_rp)*dp]
            p%kind(m) = kind_fixed
            p%mass(m) = rho0*dp*dp
            p%rho(m) = rho0
            p%v(:, m) = [0.05_rp, 0.0_rp]*real(ix, rp)/nx
            p%gof(:, m) = [0.0_rp, 2.0_rp*(iy - 0.5_rp)*dp]
         end do
      end do
      ! a lone fluid particle at (0.33, 0.02), a wall particle whose ghost is beside it
      ! (the fluid particle's index is stored in lone_index); and a wall with no water near
      m = m + 1
      p%x(:, m) = [0.335_rp, -0.01_rp]
      p%kind(m) = kind_fixed
      p%mass(m) = rho0*dp*dp
      p%rho(m) = rho0
      p%v(:, m) = 0.0_rp
      p%gof(:, m) = [0.0_rp, 0.02_rp]
      m = m + 1
      p%x(:, m) = [0.34_rp, 0.24_rp]
      p%kind(m) = kind_fixed
      p%mass(m) = rho0*dp*dp
      p%rho(m) = rho0
      p%v(:, m) = 0.0_rp
      p%gof(:, m) = [0.0_rp, -0.005_rp]
      ! the lone fluid particle takes the place of the last lattice particle
      p%x(:, lone_index() + 1) = [0.33_rp, 0.005_rp]
      p%rho(lone_index() + 1) = linear_rho(p%x(:, lone_index() + 1)) + off
      lone_rho = p%rho(lone_index() + 1)
      p%v(:, lone_index() + 1) = linear_v(p%x(:, lone_index() + 1))
      do j = 1, m
         p%id(j) = j
         p%body(j) = 0
         p%surf(j) = 0
         p%nrm(:, j) = 0.0_rp
         p%xb(:, j) = p%x(:, j)
         p%nb(:, j) = 0.0_rp
         p%gob(:, j) = p%gof(:, j)
      end do
      p%n = m
      p%n_own = m
      p%n_id = m
   end subroutine scene

   !> id - 1 of the lone fluid particle: the last of the lattice.
   pure integer function lone_index()
      lone_index = nx*ny - 1
   end function lone_index

   pure real(rp) function linear_rho(x)
      real(rp), intent(in) :: x(2)
      linear_rho = r0 + dot_product(gr, x)
   end function linear_rho

   pure function linear_v(x) result(v)
      real(rp), intent(in) :: x(2)
      real(rp) :: v(2)
      v = u0 + matmul(gu, x)
   end function linear_v

   pure real(rp) function determinant4(m) result(d)
      real(rp), intent(in) :: m(4, 4)
      integer :: c
      d = 0.0_rp
      do c = 1, 4
         d = d + (-1.0_rp)**(c + 1)*m(1, c)*det3(minor(m, c))
      end do
   end function determinant4

   pure function minor(m, c) result(r)
      real(rp), intent(in) :: m(4, 4)
      integer, intent(in) :: c
      real(rp) :: r(3, 3)
      integer :: k, l
      l = 0
      do k = 1, 4
         if (k == c) cycle
         l = l + 1
         r(:, l) = m(2:4, k)
      end do
   end function minor

   pure real(rp) function det3(m)
      real(rp), intent(in) :: m(3, 3)
      det3 = m(1, 1)*(m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)) - m(1, 2)*(m(2, 1)*m(3, 3) - m(2, 3)*m(3, 1)) + &
             m(1, 3)*(m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1))
   end function det3

   function real_text(x) result(s)
      real(rp), intent(in) :: x
      character(len=12) :: s
      write (s, '(es12.3)') x
   end function real_text

end program test_mdbc

!> Neighbour grid: the pairs found by the half stencil equal the brute-force
!> set (each pair exactly once) for random sets with a dense cluster, empty
!> cells and points on cell edges; dropped particles leave the store; the
!> production pair loop gives the brute-force continuity and pressure sums,
!> and with particle shifting its sums too (and the same forces). In the
!> dimensions of the build: the 3D build runs it too (make unit-3d), over a
!> domain a few cells wide.
module test_grid_state
   use kinds, only: rp
   use particles, only: particles_t
   implicit none
   private
   public :: p, seen
   type(particles_t) :: p
   integer, allocatable :: seen(:, :)
end module test_grid_state

program test_grid
   use test_grid_state, only: p, seen
   use kinds, only: rp, lk
   use constants, only: kind_fluid, kind_fixed, ndim
   use particles, only: particles_alloc
   use grid, only: grid_t, grid_init, grid_sort, grid_point_ranges, grid_line_ranges, grid_npoint
   use params, only: params_t, visc_artificial, diff_none, kgc_none, integ_symplectic, shift_none, shift_fickian
   use kernel, only: kernel_wendland, kernel_cubic, kernel_norm, kernel_gradw, kernel_f
   use nbr_list, only: nbr_t, nbr_build
   use fluid_forces, only: forces_work_t, forces_init, forces_prepare, forces_sweep, forces_sweep_last
   use comm_halo, only: halo_t
   use testing, only: check, check_close, test_summary, random_seed_fixed
   implicit none
   integer, parameter :: n = 900
   type(grid_t) :: g
   type(params_t) :: prm
   type(forces_work_t) :: w, ws
   type(nbr_t) :: nb
   type(halo_t) :: hl                  ! one rank, no periodic sides: no halo, no images
   logical(lk), allocatable :: drop(:)
   real(rp) :: h, r(ndim), d(ndim), gw(ndim), dr, a(ndim), err_d, err_a, scale_d, scale_a, pij, err_f
   real(rp) :: gc(ndim), divr, err_c, err_r, scale_c, scale_r, ext(ndim), mid(ndim), edge(ndim)
   integer :: i, j, k, nbad, nmiss, ndup, kk, m, jlo(grid_npoint), jhi(grid_npoint), nq
   integer :: wrap(3), wrap_q(3)
   integer, allocatable :: hits(:)
   integer, parameter :: kernels(2) = [kernel_wendland, kernel_cubic]

   h = 0.02_rp
   ! the domain: 1 x 0.6 (x 0.15 across in 3D, four cells)
   ext(1:2) = [1.0_rp, 0.6_rp]
   if (ndim == 3) ext(ndim) = 0.15_rp
   mid(1:2) = [0.3_rp, 0.2_rp]
   if (ndim == 3) mid(ndim) = 0.07_rp
   wrap = [20, 13, 3]
   wrap_q = [26, 16, 4]
   call particles_alloc(p, n)
   p%n = n
   p%n_id = n
   call random_seed_fixed()
   do i = 1, n
      call random_number(r)
      if (i <= 400) then            ! dense cluster: many particles per cell
         p%x(:, i) = mid + 0.03_rp*(r - 0.5_rp)
      else if (i <= 450) then       ! exactly on cell edges
         p%x(:, i) = 0.04_rp*mod(i, wrap(1:ndim))
      else                          ! sparse, leaving empty cells
         p%x(:, i) = ext*r
      end if
      p%id(i) = i
      p%kind(i) = merge(kind_fixed, kind_fluid, mod(i, 7) == 0)
      p%mass(i) = 1.0_rp + 0.1_rp*mod(i, 5)
      call random_number(r)
      p%v(:, i) = r - 0.5_rp
      call random_number(r)
      p%rho(i) = 1000.0_rp*(1.0_rp + 0.01_rp*(r(1) - 0.5_rp))
   end do
   call grid_init(g, 0.0_rp, ext(1), 0.0_rp, ext(2), h, zmin=0.0_rp, zmax=ext(ndim))
   allocate (drop(n))
   drop = .false.
   call grid_sort(g, p, drop)
   call check(p%n == n, 'no particle lost by sorting')

   allocate (seen(n, n))

   ! the pair list of an evaluation holds the same pairs, each once, with the kernel factor of the pair
   do kk = 1, 2
      call nbr_build(nb, g, p%x, p%n, kernels(kk), h, 4.0_rp*h*h, kernel_norm(kernels(kk), h)/(h*h))
      seen = 0
      err_f = 0.0_rp
      nbad = 0
      do i = 1, n
         do k = nb%first(i), nb%first(i + 1) - 1
            j = nb%j(k)
            if (j <= i) nbad = nbad + 1
            seen(p%id(i), p%id(j)) = seen(p%id(i), p%id(j)) + 1
            dr = norm2(p%x(:, i) - p%x(:, j))
            ! against the largest factor, F(0+): F itself falls to 0 at the edge of the support
            err_f = max(err_f, abs(nb%f(k) - kernel_f(kernels(kk), dr, h))/abs(kernel_f(kernels(kk), 1.0e-9_rp*h, h)))
         end do
      end do
      call against_brute_force(h, nmiss, ndup, k)
      nbad = nbad + k
      call check(nb%np == count(seen > 0) .and. nb%first(n + 1) == nb%np + 1, 'pair list: its length is its pairs')
      call check(nmiss == 0 .and. ndup == 0 .and. nbad == 0, 'pair list: the brute-force set, each pair once, j after i')
      call check(err_f < 1.0e-13_rp, 'pair list: kernel factor F(r) of every pair to 1e-13 of F(0)')
      call check(count(seen > 0) > 10*n, 'the set has many pairs (test is not vacuous)')
   end do

   ! the passes around a point (mDBC ghost points) and a vertical line (water-level
   ! gauges): the ranges hold every particle within 2h, none twice, and none beyond the store
   allocate (hits(n))
   nmiss = 0
   ndup = 0
   nq = 0
   do m = 1, 300
      call random_number(r)
      edge = 0.04_rp*mod(m, wrap_q(1:ndim))        ! on cell edges, and on the domain's
      select case (mod(m, 3))
      case (0)
         r = ext*r                                     ! anywhere
      case (1)
         r = edge
      case default
         r = 1.1_rp*ext*r - 0.05_rp*ext                 ! near and past the sides
      end select
      hits = 0
      call grid_point_ranges(g, r, jlo, jhi)
      do k = 1, grid_npoint
         if (jlo(k) <= jhi(k)) hits(jlo(k):jhi(k)) = hits(jlo(k):jhi(k)) + 1
      end do
      ndup = ndup + count(hits > 1)
      do i = 1, n
         if (norm2(p%x(:, i) - r) < 2.0_rp*h) then
            nq = nq + 1
            if (hits(i) == 0) nmiss = nmiss + 1
         end if
      end do
      hits = 0
      call grid_line_ranges(g, r, jlo, jhi)
      do k = 1, grid_npoint
         if (jlo(k) <= jhi(k)) hits(jlo(k):jhi(k)) = hits(jlo(k):jhi(k)) + 1
      end do
      ndup = ndup + count(hits > 1)
      do i = 1, n
         ! within 2h of the vertical line through r: every horizontal distance
         d = p%x(:, i) - r
         d(2) = 0.0_rp
         if (norm2(d) < 2.0_rp*h .and. hits(i) == 0) nmiss = nmiss + 1
      end do
   end do
   call check(nmiss == 0 .and. ndup == 0, 'point and line ranges: every particle within 2h, each once')
   call check(nq > 1000, 'the points have many neighbours (test is not vacuous)')

   ! the production pair loop: continuity and pressure sums against brute force; with
   ! particle shifting its sums (the concentration gradient, the divergence of
   ! position) too, and the forces as without it
   do kk = 1, 2
      prm%dp = h/1.3_rp
      prm%h = h; prm%h2 = h*h; prm%support2 = 4.0_rp*h*h; prm%eta2 = 0.01_rp*h*h
      prm%kernel = kernels(kk)
      prm%aw = kernel_norm(prm%kernel, h); prm%fw = prm%aw/prm%h2; prm%w0 = prm%aw
      prm%rho0 = 1000.0_rp; prm%gamma = 7.0_rp; prm%g = 0.0_rp; prm%c0 = 20.0_rp
      prm%b = prm%c0**2*prm%rho0/prm%gamma
      prm%visc = visc_artificial; prm%alpha = 0.0_rp
      prm%diffusion = diff_none; prm%kgc = kgc_none; prm%integrator = integ_symplectic
      prm%shift = shift_none
      call forces_init(w, prm)
      call forces_prepare(prm, p, w)
      call forces_sweep(prm, g, p, w, hl)
      call forces_sweep_last(prm, g, p, w)
      prm%shift = shift_fickian
      call forces_init(ws, prm)
      ws%shift_now = .true.             ! the step sets it for the evaluation it shifts by
      call forces_prepare(prm, p, ws)
      call forces_sweep(prm, g, p, ws, hl)
      call forces_sweep_last(prm, g, p, ws)
      err_d = 0.0_rp; err_a = 0.0_rp; scale_d = 0.0_rp; scale_a = 0.0_rp
      err_c = 0.0_rp; err_r = 0.0_rp; scale_c = 0.0_rp; scale_r = 0.0_rp
      do i = 1, n
         dr = 0.0_rp
         a = 0.0_rp
         gc = 0.0_rp
         divr = 0.0_rp
         do j = 1, n
            if (j == i) cycle
            if (p%kind(i) /= kind_fluid .and. p%kind(j) /= kind_fluid) cycle
            d = p%x(:, i) - p%x(:, j)
            if (dot_product(d, d) >= 4.0_rp*h*h) cycle
            gw = kernel_gradw(prm%kernel, d, h)
            dr = dr + p%mass(j)*dot_product(p%v(:, i) - p%v(:, j), gw)
            pij = (p%p(i) + p%p(j))/(p%rho(i)*p%rho(j))
            a = a - p%mass(j)*pij*gw
            gc = gc + p%mass(j)/p%rho(j)*gw
            divr = divr - p%mass(j)/p%rho(j)*dot_product(d, gw)
         end do
         err_d = max(err_d, abs(dr - w%drho(i)))
         err_a = max(err_a, norm2(a - w%acc(:, i)))
         scale_d = max(scale_d, abs(dr))
         scale_a = max(scale_a, norm2(a))
         err_c = max(err_c, norm2(gc - ws%sh(1:ndim, i)))
         err_r = max(err_r, abs(divr - ws%sh(ndim + 1, i)))
         scale_c = max(scale_c, norm2(gc))
         scale_r = max(scale_r, abs(divr))
      end do
      call check_close(err_d, 0.0_rp, 1.0_rp, 'pair loop continuity = brute force', floor=1.0e-12_rp*scale_d)
      call check_close(err_a, 0.0_rp, 1.0_rp, 'pair loop pressure force = brute force', floor=1.0e-12_rp*scale_a)
      call check(maxval(abs(ws%acc(:, 1:n) - w%acc(:, 1:n))) <= 1.0e-12_rp*scale_a, &
                 'pair loop with shifting: the same forces')
      call check_close(err_c, 0.0_rp, 1.0_rp, 'shifting: grad C = brute force', floor=1.0e-12_rp*scale_c)
      call check_close(err_r, 0.0_rp, 1.0_rp, 'shifting: div r = brute force', floor=1.0e-12_rp*scale_r)
      call check(scale_r > 1.0_rp, 'shifting: div r of the order of ndim (test is not vacuous)')
   end do

   ! dropped particles leave the store; the rest keep their ids
   drop = .false.
   drop(1:n:3) = .true.
   call grid_sort(g, p, drop)
   call check(p%n == n - count(drop), 'dropped particles removed')
   call check(size(unique_ids()) == p%n, 'ids stay unique after dropping')
   call test_summary('test_grid')

contains

   !> The pairs recorded in seen (by id) against every pair of the set: pairs within
   !> 2h not recorded (nmiss), recorded twice (ndup), recorded beyond 2h (nbad).
   subroutine against_brute_force(h, nmiss, ndup, nbad)
      real(rp), intent(in) :: h
      integer, intent(out) :: nmiss, ndup, nbad
      integer :: a, b, s
      nmiss = 0; ndup = 0; nbad = 0
      do b = 1, n
         do a = b + 1, n
            s = seen(a, b) + seen(b, a)
            if (norm2(p%x(:, p_of(a)) - p%x(:, p_of(b))) < 2.0_rp*h) then
               if (s == 0) nmiss = nmiss + 1
               if (s > 1) ndup = ndup + 1
            else if (s > 0) then
               nbad = nbad + 1
            end if
         end do
      end do
   end subroutine against_brute_force

   !> Index of the particle with a given id (the store is sorted by cell).
   integer function p_of(id)
      integer, intent(in) :: id
      integer :: k
      p_of = 0
      do k = 1, p%n
         if (p%id(k) == id) then
            p_of = k
            return
         end if
      end do
   end function p_of

   function unique_ids() result(u)
      integer, allocatable :: u(:)
      logical :: mark(n)
      integer :: k
      mark = .false.
      do k = 1, p%n
         mark(p%id(k)) = .true.
      end do
      u = pack([(k, k=1, n)], mark)
   end function unique_ids

end program test_grid

!> Periodic sides across the width (make unit-3d). For widths of one, two and
!> five cell columns, with particles scattered past both sides:
!> - grid_wrap takes every position back into the width;
!> - with the images of comm_halo_images the half stencil meets every pair
!>   within 2h under the periodic distance exactly once (a particle and
!>   another's image one width away count as a pair of their own);
!> - the pair loop's rates (continuity and momentum, with and without the
!>   gradient correction, whose matrices the sweep completes column by
!>   column), with the images' shares given back to their originals, equal
!>   those of the middle copy of five copies side by side without periodic
!>   sides, to 1e-12 of their scale.
program test_periodic3d
   use kinds, only: rp, lk
   use constants, only: kind_fluid, kind_fixed, ndim
   use particles, only: particles_t, particles_alloc
   use grid, only: grid_t, grid_init, grid_sort, grid_wrap
   use comm_halo, only: halo_t, comm_halo_images, comm_halo_reverse, comm_halo_forward
   use params, only: params_t, visc_artificial, visc_laminar_sps, diff_none, kgc_none, kgc_gradient, integ_symplectic, shift_none
   use kernel, only: kernel_wendland, kernel_norm
   use nbr_list, only: nbr_t, nbr_build
   use fluid_forces, only: forces_work_t, forces_init, forces_prepare, forces_sweep, forces_sweep_last
   use testing, only: check, check_close, test_summary, random_seed_fixed
   implicit none
   integer, parameter :: n = 500, ncopy = 5, mid = 2   ! mid: the middle copy (0-based)
   real(rp), parameter :: h = 0.02_rp, lx = 0.4_rp, ly = 0.3_rp
   ! widths of one (2.25 h), two and five cell columns
   real(rp), parameter :: widths(3) = [0.045_rp, 0.09_rp, 0.2_rp]
   real(rp) :: xs(ndim, n), vs(ndim, n), rhos(n), r(ndim)
   integer :: kinds(n), iw, i, k

   call check(ndim == 3, 'a 3D build (ndim = 3)')
   call random_seed_fixed()
   do iw = 1, size(widths)
      do i = 1, n
         call random_number(r)
         xs(:, i) = [lx, ly, 1.4_rp*widths(iw)]*r
         xs(ndim, i) = xs(ndim, i) - 0.2_rp*widths(iw)       ! a fifth of a width past either side
         if (i <= 150) xs(:, i) = [0.2_rp, 0.15_rp, 0.0_rp] + 0.03_rp*(r - 0.5_rp)   ! a cluster across a side
         call random_number(r)
         vs(:, i) = r - 0.5_rp
         rhos(i) = 1000.0_rp*(1.0_rp + 0.01_rp*(r(1) - 0.5_rp))
         kinds(i) = merge(kind_fixed, kind_fluid, mod(i, 7) == 0)
      end do
      call pairs_once(widths(iw))
      do k = 1, 3
         call rates_as_copies(widths(iw), merge(kgc_none, kgc_gradient, k == 1), k == 3)
      end do
   end do
   call test_summary('test_periodic3d')

contains

   !> The particles xs in p, wrapped into the width w (periodic grid g) and sorted, with their images.
   subroutine periodic_set(w, g, p, hl)
      real(rp), intent(in) :: w
      type(grid_t), intent(out) :: g
      type(particles_t), intent(out) :: p
      type(halo_t), intent(out) :: hl
      logical(lk) :: drop(n)
      integer :: i
      call fill(p, n)
      do i = 1, n
         p%x(:, i) = xs(:, i)
      end do
      call grid_init(g, 0.0_rp, lx, 0.0_rp, ly, h, zmin=0.0_rp, zmax=w, periodic=.true.)
      call grid_wrap(g, p%n, p%x)
      drop = .false.
      call grid_sort(g, p, drop)
      call comm_halo_images(hl, g, p)
   end subroutine periodic_set

   !> A store of m particles with the fields of xs, vs, rhos, kinds (repeated).
   subroutine fill(p, m)
      type(particles_t), intent(out) :: p
      integer, intent(in) :: m
      integer :: i, i0
      call particles_alloc(p, m)
      p%n = m
      p%n_own = m
      p%n_id = m
      do i = 1, m
         i0 = modulo(i - 1, n) + 1
         p%x(:, i) = xs(:, i0)
         p%v(:, i) = vs(:, i0)
         p%rho(i) = rhos(i0)
         p%kind(i) = kinds(i0)
         p%id(i) = i
         p%mass(i) = 1.0_rp + 0.1_rp*mod(i0, 5)
      end do
   end subroutine fill

   !> Every pair within 2h under the periodic distance met once by the pair list.
   subroutine pairs_once(w)
      real(rp), intent(in) :: w
      type(grid_t) :: g
      type(particles_t) :: p
      type(halo_t) :: hl
      type(nbr_t) :: nb
      integer, allocatable :: seen(:, :, :)
      integer :: i, j, k, a, b, s, jo, nmiss, ndup, nbad, nout, nimg, slot(n)
      real(rp) :: d(ndim)
      call periodic_set(w, g, p, hl)
      do i = 1, p%n_own
         slot(p%id(i)) = i
      end do
      nout = count(p%x(ndim, 1:p%n_own) < 0.0_rp .or. p%x(ndim, 1:p%n_own) >= w)
      call check(nout == 0, 'wrap: every position within the width')
      nimg = p%n - p%n_own
      call check(nimg == hl%n_img .and. nimg > 0, 'the images follow the particles')
      allocate (seen(n, n, -1:1))
      seen = 0
      call nbr_build(nb, g, p%x, p%n, kernel_wendland, h, 4.0_rp*h*h, 1.0_rp)
      nbad = 0
      do i = 1, p%n_own
         do k = nb%first(i), nb%first(i + 1) - 1
            j = nb%j(k)
            s = 0
            jo = j
            if (j > p%n_own) then
               jo = hl%img_src(j - p%n_own)
               s = nint((p%x(ndim, j) - p%x(ndim, jo))/w)
            end if
            ! the pair (a, b, s): x_a - (x_b + s w e_z), a < b
            a = p%id(i)
            b = p%id(jo)
            if (a == b) then
               nbad = nbad + 1
               cycle
            end if
            if (a > b) then
               seen(b, a, -s) = seen(b, a, -s) + 1
            else
               seen(a, b, s) = seen(a, b, s) + 1
            end if
         end do
      end do
      nmiss = 0
      ndup = 0
      do a = 1, n
         do b = a + 1, n
            do s = -1, 1
               d = p%x(:, slot(a)) - p%x(:, slot(b))
               d(ndim) = d(ndim) - s*w
               if (norm2(d) < 2.0_rp*h) then
                  if (seen(a, b, s) == 0) nmiss = nmiss + 1
                  if (seen(a, b, s) > 1) ndup = ndup + 1
               else if (seen(a, b, s) > 0) then
                  nbad = nbad + 1
               end if
            end do
         end do
      end do
      call check(nmiss == 0 .and. ndup == 0 .and. nbad == 0, &
                 'periodic pair list: the brute-force set, each pair once (width '//wstr(w)//')')
      call check(count(seen(:, :, -1) > 0) + count(seen(:, :, 1) > 0) > 100, &
                 'many pairs across the sides (test is not vacuous)')
   end subroutine pairs_once

   !> The rates on the periodic set against those of the middle of five copies side by side.
   subroutine rates_as_copies(w, kgc, sps)
      real(rp), intent(in) :: w
      integer, intent(in) :: kgc
      logical, intent(in) :: sps     !< with the laminar + SPS viscosity
      type(grid_t) :: g, gt
      type(particles_t) :: p, pt
      type(halo_t) :: hl, hn
      type(forces_work_t) :: wp, wt
      type(params_t) :: prm
      logical(lk), allocatable :: drop(:)
      integer :: i, j, c
      real(rp) :: err_a, err_d, sc_a, sc_d
      character(len=48) :: tag
      call periodic_set(w, g, p, hl)
      ! the copies: the wrapped positions, shifted by whole widths
      call fill(pt, ncopy*n)
      do i = 1, ncopy*n
         j = modulo(i - 1, n) + 1
         c = (i - 1)/n
         pt%x(:, i) = p%x(:, j)
         pt%v(:, i) = p%v(:, j)
         pt%rho(i) = p%rho(j)
         pt%kind(i) = p%kind(j)
         pt%mass(i) = p%mass(j)
         pt%id(i) = p%id(j) + c*n
         pt%x(ndim, i) = p%x(ndim, j) + (c - mid)*w
      end do
      call grid_init(gt, 0.0_rp, lx, 0.0_rp, ly, h, zmin=-(mid)*w, zmax=(mid + 1)*w)
      allocate (drop(ncopy*n))
      drop = .false.
      call grid_sort(gt, pt, drop)
      call params_for(prm, kgc, sps)
      call evaluate(prm, g, p, hl, wp)
      call evaluate(prm, gt, pt, hn, wt)
      err_a = 0.0_rp
      err_d = 0.0_rp
      sc_a = 0.0_rp
      sc_d = 0.0_rp
      do j = 1, ncopy*n
         ! the middle copy: ids n (mid) + 1 .. n (mid + 1)
         if ((pt%id(j) - 1)/n /= mid) cycle
         i = pos(p, pt%id(j) - (mid)*n)
         err_a = max(err_a, norm2(wp%acc(:, i) - wt%acc(:, j)))
         err_d = max(err_d, abs(wp%drho(i) - wt%drho(j)))
         sc_a = max(sc_a, norm2(wt%acc(:, j)))
         sc_d = max(sc_d, abs(wt%drho(j)))
      end do
      tag = ' (width '//wstr(w)//')'
      if (kgc == kgc_gradient) tag = ' (width '//wstr(w)//', gradient correction)'
      if (sps) tag = ' (width '//wstr(w)//', gradient correction, SPS)'
      call check_close(err_a, 0.0_rp, 1.0_rp, 'periodic momentum = the middle copy''s'//trim(tag), floor=1.0e-12_rp*sc_a)
      call check_close(err_d, 0.0_rp, 1.0_rp, 'periodic continuity = the middle copy''s'//trim(tag), floor=1.0e-12_rp*sc_d)
      call check(sc_a > 1.0_rp .and. sc_d > 1.0_rp, 'rates of some size (test is not vacuous)')
   end subroutine rates_as_copies

   !> One force evaluation as the step makes it on one rank.
   subroutine evaluate(prm, g, p, hl, w)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(halo_t), intent(inout) :: hl
      type(forces_work_t), intent(out) :: w
      call forces_init(w, prm)
      call forces_prepare(prm, p, w)
      call forces_sweep(prm, g, p, w, hl)
      if (prm%kgc == kgc_gradient) then
         call comm_halo_reverse(hl, w%lm, p%n_own, images=.false.)
         call comm_halo_forward(hl, w%lm, p%n_own)
      end if
      if (prm%visc == visc_laminar_sps) then
         call comm_halo_reverse(hl, w%gv, p%n_own, images=.false.)
         call comm_halo_forward(hl, w%tau, p%n_own)
      end if
      call forces_sweep_last(prm, g, p, w)
      call comm_halo_reverse(hl, w%acc, w%drho, p%n_own)
   end subroutine evaluate

   subroutine params_for(prm, kgc, sps)
      type(params_t), intent(out) :: prm
      integer, intent(in) :: kgc
      logical, intent(in) :: sps
      prm%dp = h/1.3_rp
      prm%h = h; prm%h2 = h*h; prm%support2 = 4.0_rp*h*h; prm%eta2 = 0.01_rp*h*h
      prm%kernel = kernel_wendland
      prm%aw = kernel_norm(prm%kernel, h); prm%fw = prm%aw/prm%h2; prm%w0 = prm%aw
      prm%rho0 = 1000.0_rp; prm%gamma = 7.0_rp; prm%g = 0.0_rp; prm%c0 = 20.0_rp
      prm%b = prm%c0**2*prm%rho0/prm%gamma
      prm%visc = visc_artificial; prm%alpha = 0.1_rp
      prm%diffusion = diff_none; prm%kgc = kgc; prm%integrator = integ_symplectic
      prm%shift = shift_none
      if (sps) then
         prm%visc = visc_laminar_sps
         prm%nu = 1.0e-6_rp
         prm%sps_smag = (0.12_rp*prm%dp)**2
         prm%sps_blin = (2.0_rp/3.0_rp)*0.0066_rp*prm%dp**2
      end if
   end subroutine params_for

   !> Slot of the particle with this id among the owned ones.
   integer function pos(p, id)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: id
      integer :: k
      pos = 0
      do k = 1, p%n_own
         if (p%id(k) == id) then
            pos = k
            return
         end if
      end do
   end function pos

   function wstr(w) result(s)
      real(rp), intent(in) :: w
      character(len=8) :: s
      write (s, '(f6.3)') w
   end function wstr
end program test_periodic3d

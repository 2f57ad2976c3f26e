!> The repulsive boundary's wall weight: a fluid particle at a height psi
!> above a flat wall (one row of wall particles at spacing dp; in 3D a square
!> lattice) feels the force of one wall particle straight below it, the
!> Monaghan-Kos force of Eq. 4 at psi, wherever it stands along the wall: the
!> weights of the wall particles around it sum to one (in 3D the product of
!> the 2D weight along the lattice's two axes). The production pair loop
!> against that, at random places over a lattice cell, and for the faces
!> whose normal lies along each axis (floor, end wall, and in 3D a side wall).
!> Runs in the 2D and the 3D build (make unit, make unit-3d).
program test_repulsive
   use kinds, only: rp, lk
   use constants, only: kind_fluid, kind_fixed, ndim
   use particles, only: particles_t, particles_alloc
   use grid, only: grid_t, grid_init, grid_sort
   use params, only: params_t, visc_artificial, diff_none, kgc_none, integ_symplectic, shift_none, bnd_repulsive
   use kernel, only: kernel_wendland, kernel_norm
   use fluid_forces, only: forces_work_t, forces_init, forces_prepare, forces_sweep, forces_sweep_last
   use comm_halo, only: halo_t
   use testing, only: check, check_close, test_summary, random_seed_fixed
   implicit none
   integer, parameter :: m = 10          !< wall particles along each axis of the wall
   integer, parameter :: trials = 40     !< places of the fluid particle per face
   type(particles_t) :: p
   type(grid_t) :: g
   type(params_t) :: prm
   type(forces_work_t) :: w
   type(halo_t) :: hl
   logical(lk), allocatable :: drop(:)
   real(rp) :: dp, h, psi, q, expect, err_n, err_t, r(ndim), ext, a(ndim), nrm(ndim), xf(ndim)
   integer :: face, t, i, nwall, ifl, nfaces

   dp = 0.01_rp
   h = sqrt(2.0_rp)*dp
   ext = (m + 3)*dp
   psi = 0.6_rp*dp
   prm%dp = dp
   prm%h = h; prm%h2 = h*h; prm%support2 = 4.0_rp*h*h; prm%eta2 = 0.01_rp*h*h
   prm%kernel = kernel_wendland
   prm%aw = kernel_norm(prm%kernel, h); prm%fw = prm%aw/prm%h2; prm%w0 = prm%aw
   prm%rho0 = 1000.0_rp; prm%gamma = 7.0_rp; prm%g = 0.0_rp; prm%c0 = 20.0_rp
   prm%b = prm%c0**2*prm%rho0/prm%gamma
   prm%visc = visc_artificial; prm%alpha = 0.0_rp
   prm%diffusion = diff_none; prm%kgc = kgc_none; prm%integrator = integ_symplectic
   prm%shift = shift_none
   prm%boundary = bnd_repulsive
   prm%rep_a = 0.01_rp*prm%c0**2/h; prm%rep_b = prm%c0/h; prm%rep_q0 = 1.0e-3_rp
   prm%rep_u = 40.0_rp/prm%c0; prm%rep_rhswl = 10.0_rp
   ! the still-water level below the particle: eps takes its floor, 0.02
   prm%y_surface = -1.0_rp
   ! Eq. 4 of one wall particle straight below: A (1 - q) / sqrt(q + q0) eps at q = psi / 2h
   q = psi/(2.0_rp*h)
   expect = prm%rep_a*(1.0_rp - q)/sqrt(q + prm%rep_q0)*0.02_rp
   nwall = m**(ndim - 1)
   nfaces = ndim
   call random_seed_fixed()
   call particles_alloc(p, nwall + 1)
   do face = 1, nfaces
      err_n = 0.0_rp
      err_t = 0.0_rp
      nrm = 0.0_rp
      nrm(face) = 1.0_rp
      do t = 1, trials
         p%n = nwall + 1
         p%n_id = p%n
         ! the wall: the plane x(face) = dp, its particles on whole spacings over the other axes
         do i = 1, nwall
            p%x(:, i) = lattice_point(i, face)
            p%kind(i) = kind_fixed
            p%surf(i) = 1
            p%nrm(:, i) = nrm
         end do
         ! the fluid particle at psi above it, anywhere over the middle cell of the lattice
         call random_number(r)
         xf = (0.5_rp*m + r)*dp
         xf(face) = dp + psi
         ifl = nwall + 1
         p%x(:, ifl) = xf
         p%kind(ifl) = kind_fluid
         p%surf(ifl) = 0
         p%nrm(:, ifl) = 0.0_rp
         do i = 1, p%n
            p%id(i) = i
            p%mass(i) = prm%rho0*dp**ndim
            p%rho(i) = prm%rho0
            p%v(:, i) = 0.0_rp
         end do
         call grid_init(g, 0.0_rp, ext, 0.0_rp, ext, h, zmin=0.0_rp, zmax=ext)
         if (allocated(drop)) deallocate (drop)
         allocate (drop(p%n))
         drop = .false.
         call grid_sort(g, p, drop)
         ifl = findloc(p%kind(1:p%n), kind_fluid, dim=1)
         call forces_init(w, prm)
         call forces_prepare(prm, p, w)
         call forces_sweep(prm, g, p, w, hl)
         call forces_sweep_last(prm, g, p, w)
         a = w%acc(:, ifl)
         err_n = max(err_n, abs(a(face) - expect))
         a(face) = 0.0_rp
         err_t = max(err_t, norm2(a))
      end do
      call check_close(err_n, 0.0_rp, 1.0_rp, 'repulsive wall, normal along axis '//achar(iachar('w') + face)// &
                       ': the force of one wall particle straight below, anywhere along the wall', &
                       floor=1.0e-12_rp*expect)
      call check(err_t <= 1.0e-12_rp*expect, 'repulsive wall, normal along axis '//achar(iachar('w') + face)// &
                 ': no force along the wall')
   end do
   call check(expect > 1.0_rp, 'the force is of the order of A (test is not vacuous)')
   call test_summary('test_repulsive')

contains

   !> Wall particle i of the plane x(face) = dp: whole spacings from dp over the other axes.
   function lattice_point(i, face) result(x)
      integer, intent(in) :: i, face
      real(rp) :: x(ndim)
      integer :: idx(ndim - 1), a, b
      idx(1) = mod(i - 1, m)
      if (ndim == 3) idx(ndim - 1) = (i - 1)/m
      b = 0
      do a = 1, ndim
         if (a == face) then
            x(a) = dp
         else
            b = b + 1
            x(a) = (1 + idx(b))*dp
         end if
      end do
   end function lattice_point
end program test_repulsive

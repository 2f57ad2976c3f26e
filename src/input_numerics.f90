!> &numerics: resolution, kernel, time stepping and the optional models.
module input_numerics
   use kinds, only: rp
   use constants, only: name_len, msg_len, ndim
   use input_check, only: open_case, read_failed, check_real, check_int, group_count, var_given, lower
   use options, only: option_index, kernel_names, integ_names, visc_names, bnd_names, diff_names, kgc_names, &
                      kernel_wendland, integ_symplectic, visc_artificial, bnd_dynamic, bnd_repulsive, diff_none, &
                      diff_fourtakas, kgc_none, kgc_gradient, slip_names, slip_wall, shift_names, shift_none, &
                      mass_names, mass_rho0
   use errors, only: input_error
   implicit none
   private
   public :: numerics_cfg, read_numerics, write_numerics

   type :: numerics_cfg
      real(rp) :: dp = -huge(1.0_rp)                          !< particle spacing [m], required
      real(rp) :: h_over_dp = 1.4142135623730951_rp      !< smoothing length / dp [-]
      character(len=name_len) :: kernel = 'wendland'     !< 'wendland' | 'cubic'
      real(rp) :: cfl = 0.2_rp                           !< Courant number [-]
      real(rp) :: dt_fixed = 0.0_rp                      !< fixed time step [s]; 0: variable
      character(len=name_len) :: integrator = 'symplectic'  !< 'symplectic' | 'predictor_corrector' | 'verlet'
      integer :: verlet_every = 40                       !< Verlet: an Euler step every N steps
      character(len=name_len) :: viscosity = 'artificial'  !< 'artificial' | 'laminar_sps'
      real(rp) :: alpha = 0.01_rp                        !< artificial viscosity coefficient [-]
      real(rp) :: nu = 1.0e-6_rp                         !< kinematic viscosity (laminar) [m2/s]
      real(rp) :: cs_sps = 0.12_rp                       !< Smagorinsky constant (SPS) [-]
      real(rp) :: ci_sps = 0.0066_rp                     !< Blin constant (SPS) [-]
      character(len=name_len) :: diffusion = 'fourtakas'  !< 'none' | 'molteni' | 'fourtakas'
                                                         !< (default 'none' with boundary = 'repulsive')
      real(rp) :: delta = 0.1_rp                         !< density diffusion coefficient [-]
      character(len=name_len) :: kernel_correction = 'none'  !< 'none' | 'gradient' | 'shepard'
      integer :: shepard_every = 30                      !< Shepard density filter every N steps
      logical :: kgc_continuity = .true.                 !< the gradient correction also in the continuity equation
      character(len=name_len) :: boundary = 'dynamic'    !< fluid on solids: 'dynamic' | 'repulsive' | 'mdbc'
      character(len=name_len) :: mdbc_slip = 'wall'      !< mDBC: velocity of the solid particles: 'wall' | 'noslip' | 'freeslip'
      character(len=name_len) :: shifting = 'none'       !< particle shifting: 'none' | 'fickian'
      real(rp) :: shift_coef = 2.0_rp                    !< shifting: A of D = A h |v| dt [-]
      !> shifting: div r below it: the surface band, not shifted [-]; 0.95 of its value inside
      !> the water (ndim), the same band in 2D and 3D
      real(rp) :: shift_tfs = merge(1.9_rp, 2.85_rp, ndim == 2)
      !> a water particle's mass: 'rho0' (rho0 dp^d) | 'hydrostatic' (its start density times dp^d)
      character(len=name_len) :: particle_mass = 'rho0'
      ! the choices as their values in options, set where they are read
      integer :: kernel_id = kernel_wendland, integrator_id = integ_symplectic, viscosity_id = visc_artificial
      integer :: diffusion_id = diff_fourtakas, kgc_id = kgc_none, boundary_id = bnd_dynamic, slip_id = slip_wall
      integer :: shift_id = shift_none, mass_id = mass_rho0
   end type numerics_cfg

   real(rp) :: dp, h_over_dp, cfl, dt_fixed, alpha, nu, cs_sps, ci_sps, delta, shift_coef, shift_tfs
   character(len=name_len) :: kernel, integrator, viscosity, diffusion, kernel_correction, boundary, mdbc_slip, shifting, &
      particle_mass
   integer :: verlet_every, shepard_every
   logical :: kgc_continuity
   namelist /numerics/ dp, h_over_dp, kernel, cfl, dt_fixed, integrator, verlet_every, viscosity, alpha, &
      nu, cs_sps, ci_sps, diffusion, delta, kernel_correction, shepard_every, kgc_continuity, boundary, mdbc_slip, &
      shifting, shift_coef, shift_tfs, particle_mass

contains

   subroutine to_vars(c)
      type(numerics_cfg), intent(in) :: c
      dp = c%dp; h_over_dp = c%h_over_dp; kernel = c%kernel; cfl = c%cfl; dt_fixed = c%dt_fixed
      integrator = c%integrator; verlet_every = c%verlet_every; viscosity = c%viscosity
      alpha = c%alpha; nu = c%nu; cs_sps = c%cs_sps; ci_sps = c%ci_sps
      diffusion = c%diffusion; delta = c%delta; kernel_correction = c%kernel_correction
      shepard_every = c%shepard_every; boundary = c%boundary; kgc_continuity = c%kgc_continuity
      mdbc_slip = c%mdbc_slip; shifting = c%shifting; shift_coef = c%shift_coef; shift_tfs = c%shift_tfs
      particle_mass = c%particle_mass
   end subroutine to_vars

   subroutine from_vars(c)
      type(numerics_cfg), intent(out) :: c
      c%dp = dp; c%h_over_dp = h_over_dp; c%kernel = kernel; c%cfl = cfl; c%dt_fixed = dt_fixed
      c%integrator = integrator; c%verlet_every = verlet_every; c%viscosity = viscosity
      c%alpha = alpha; c%nu = nu; c%cs_sps = cs_sps; c%ci_sps = ci_sps
      c%diffusion = diffusion; c%delta = delta; c%kernel_correction = kernel_correction
      c%shepard_every = shepard_every; c%boundary = boundary; c%kgc_continuity = kgc_continuity
      c%mdbc_slip = mdbc_slip; c%shifting = shifting; c%shift_coef = shift_coef; c%shift_tfs = shift_tfs
      c%particle_mass = particle_mass
   end subroutine from_vars

   !> waves: the case is a wave flume (a wavemaker, neither bodies nor porous
   !> regions: bodies keep the numerics their contact is validated with, the
   !> pores' terms need h = 2 dp without the gradient correction);
   !> keep_dynamic: the boundary stays 'dynamic' (the contact model 'dynamic'
   !> needs it; an absorbing paddle absorbs better with it). applied: the wave
   !> defaults the case took ('name = value, ...'; '' for none).
   subroutine read_numerics(file, c, waves, keep_dynamic, applied)
      character(len=*), intent(in) :: file
      type(numerics_cfg), intent(out) :: c
      logical, intent(in) :: waves, keep_dynamic
      character(len=:), allocatable, intent(out) :: applied
      integer :: u, ios
      character(len=msg_len) :: msg
      type(numerics_cfg) :: d
      applied = ''
      if (group_count(file, 'numerics') == 0) call input_error(file, 'numerics', '', 'required group is missing')
      if (group_count(file, 'numerics') > 1) call input_error(file, 'numerics', '', 'group appears more than once')
      call to_vars(d)
      diffusion = ''                   ! left blank: its default depends on boundary
      u = open_case(file)
      read (u, nml=numerics, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, 'numerics', ios, msg)) return
      call from_vars(c)
      if (waves) call take_wave_defaults(file, c, keep_dynamic, applied)
      if (c%dp <= d%dp) call input_error(file, 'numerics', 'dp', 'is required (particle spacing in m, > 0)')
      call check_real(file, 'numerics', 'dp', c%dp, 0.0_rp, 1.0e3_rp, lo_open=.true.)
      call check_real(file, 'numerics', 'h_over_dp', c%h_over_dp, 1.0_rp, 2.0_rp)
      c%kernel_id = option_index(file, 'numerics', 'kernel', c%kernel, kernel_names)
      c%kernel = kernel_names(c%kernel_id)
      call check_real(file, 'numerics', 'cfl', c%cfl, 0.0_rp, 0.5_rp, lo_open=.true.)
      call check_real(file, 'numerics', 'dt_fixed', c%dt_fixed, 0.0_rp, 1.0e3_rp)
      c%integrator_id = option_index(file, 'numerics', 'integrator', c%integrator, integ_names)
      c%integrator = integ_names(c%integrator_id)
      call check_int(file, 'numerics', 'verlet_every', c%verlet_every, 1, 1000)
      c%viscosity_id = option_index(file, 'numerics', 'viscosity', c%viscosity, visc_names)
      c%viscosity = visc_names(c%viscosity_id)
      call check_real(file, 'numerics', 'alpha', c%alpha, 0.0_rp, 1.0_rp)
      call check_real(file, 'numerics', 'nu', c%nu, 0.0_rp, 1.0_rp)
      call check_real(file, 'numerics', 'cs_sps', c%cs_sps, 0.0_rp, 1.0_rp)
      call check_real(file, 'numerics', 'ci_sps', c%ci_sps, 0.0_rp, 1.0_rp)
      c%boundary_id = option_index(file, 'numerics', 'boundary', c%boundary, bnd_names)
      c%boundary = bnd_names(c%boundary_id)
      c%slip_id = option_index(file, 'numerics', 'mdbc_slip', c%mdbc_slip, slip_names)
      c%mdbc_slip = slip_names(c%slip_id)
      if (len_trim(c%diffusion) == 0) c%diffusion = merge(diff_names(diff_none), diff_names(diff_fourtakas), &
                                                          c%boundary_id == bnd_repulsive)
      c%diffusion_id = option_index(file, 'numerics', 'diffusion', c%diffusion, diff_names)
      c%diffusion = diff_names(c%diffusion_id)
      ! next to a repulsive wall the water needs a density above the
      ! hydrostatic one (the wall lends it no pressure); diffusion removes it
      ! and drives a current along the wall (doc/theory.md)
      if (c%boundary_id == bnd_repulsive .and. c%diffusion_id /= diff_none) call input_error(file, 'numerics', 'diffusion', &
         "must be 'none' with boundary = 'repulsive' (got '"//trim(c%diffusion)//"')")
      call check_real(file, 'numerics', 'delta', c%delta, 0.0_rp, 1.0_rp)
      c%kgc_id = option_index(file, 'numerics', 'kernel_correction', c%kernel_correction, kgc_names)
      c%kernel_correction = kgc_names(c%kgc_id)
      call check_int(file, 'numerics', 'shepard_every', c%shepard_every, 1, 100000)
      if (.not. c%kgc_continuity .and. c%kgc_id /= kgc_gradient) call input_error(file, 'numerics', &
         'kgc_continuity', ".false. needs kernel_correction = 'gradient' (got '"//trim(c%kernel_correction)//"')")
      ! both corrections assume the full kernel support that a wall lacking
      ! pressure does not give (doc/theory.md)
      if (c%boundary_id == bnd_repulsive .and. c%kgc_id /= kgc_none) call input_error(file, 'numerics', &
         'kernel_correction', "must be 'none' with boundary = 'repulsive' (got '"//trim(c%kernel_correction)//"')")
      c%shift_id = option_index(file, 'numerics', 'shifting', c%shifting, shift_names)
      c%shifting = shift_names(c%shift_id)
      call check_real(file, 'numerics', 'shift_coef', c%shift_coef, 0.0_rp, 10.0_rp)
      call check_real(file, 'numerics', 'shift_tfs', c%shift_tfs, 0.0_rp, 3.0_rp)
      ! the concentration gradient needs the walls' particles in the water's
      ! pair terms, which the repulsive boundary leaves out (it would push the
      ! water into the walls)
      if (c%boundary_id == bnd_repulsive .and. c%shift_id /= shift_none) call input_error(file, 'numerics', &
         'shifting', "must be 'none' with boundary = 'repulsive' (got '"//trim(c%shifting)//"')")
      c%mass_id = option_index(file, 'numerics', 'particle_mass', c%particle_mass, mass_names)
      c%particle_mass = mass_names(c%mass_id)
   end subroutine read_numerics

   !> The numerics a case with a wavemaker gets for what its &numerics leaves
   !> out (doc/input.md, "Wave defaults"): measured, they keep a regular wave
   !> within 3 % of its height over 6 wavelengths at 15 particles over the
   !> depth, where the general defaults lose it at several per cent per
   !> wavelength (doc/waves.md).
   subroutine take_wave_defaults(file, c, keep_dynamic, applied)
      character(len=*), intent(in) :: file
      type(numerics_cfg), intent(inout) :: c
      logical, intent(in) :: keep_dynamic
      character(len=:), allocatable, intent(inout) :: applied
      if (.not. given('boundary') .and. .not. keep_dynamic) then
         c%boundary = 'mdbc'
         applied = applied//", boundary = 'mdbc'"
      end if
      if (.not. given('h_over_dp')) then
         c%h_over_dp = 1.6_rp
         applied = applied//', h_over_dp = 1.6'
      end if
      ! the gradient correction needs the walls' pressure (not the repulsive boundary)
      if (.not. given('kernel_correction') .and. lower(trim(c%boundary)) /= 'repulsive') then
         c%kernel_correction = 'gradient'
         applied = applied//", kernel_correction = 'gradient'"
      end if
      if (.not. given('kgc_continuity') .and. lower(trim(c%kernel_correction)) == 'gradient') then
         c%kgc_continuity = .false.
         applied = applied//', kgc_continuity = .false.'
      end if
      if (.not. given('viscosity')) then
         c%viscosity = 'laminar_sps'
         applied = applied//", viscosity = 'laminar_sps'"
      end if
      if (len(applied) > 0) applied = applied(3:)
   contains
      logical function given(var)
         character(len=*), intent(in) :: var
         given = var_given(file, 'numerics', var)
      end function given
   end subroutine take_wave_defaults

   subroutine write_numerics(u, c)
      integer, intent(in) :: u
      type(numerics_cfg), intent(in) :: c
      call to_vars(c)
      write (u, nml=numerics)
   end subroutine write_numerics
end module input_numerics

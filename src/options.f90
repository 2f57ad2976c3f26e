!> Every model choice of a case file, in one place: for each option the names
!> a user may write and the enumerated values the code works with, the value
!> being the position of the name in its list. Input readers validate against
!> these lists, and option_index is the one routine that turns a name into its
!> value: a name not in the list is an input error that names the file, the
!> group, the variable and the allowed values, never a silent default.
module options
   use constants, only: name_len
   use input_check, only: lower
   use errors, only: input_error
   implicit none
   private
   public :: option_index
   public :: kernel_names, kernel_wendland, kernel_cubic
   public :: visc_names, visc_artificial, visc_laminar_sps
   public :: diff_names, diff_none, diff_molteni, diff_fourtakas
   public :: kgc_names, kgc_none, kgc_gradient, kgc_shepard
   public :: integ_names, integ_symplectic, integ_predictor_corrector, integ_verlet
   public :: bnd_names, bnd_dynamic, bnd_repulsive, bnd_mdbc
   public :: slip_names, slip_wall, slip_noslip, slip_freeslip
   public :: shift_names, shift_none, shift_fickian
   public :: mass_names, mass_rho0, mass_hydrostatic
   public :: contact_names, model_dynamic, model_repulsive, model_noncohesive, model_spring, model_hertz
   public :: role_names, role_solid, role_fluid, role_filter
   public :: wall_motion_names, wall_fixed, wall_oscillate, wall_wavemaker
   public :: shape_names, shape_circle, shape_box, shape_wedge, shape_polygon, shape_stl
   public :: body_motion_names, motion_floating, motion_fixed, motion_prescribed
   public :: paddle_names, paddle_piston, paddle_flap
   public :: wave_names, wave_regular, wave_irregular, wave_file
   public :: placement_names, placement_regular, placement_irregular
   public :: core_names, core_impermeable, core_porous
   public :: gauge_names, gauge_elevation, gauge_pressure

   !> &numerics kernel
   character(len=name_len), parameter :: kernel_names(*) = [character(len=name_len) :: 'wendland', 'cubic']
   integer, parameter :: kernel_wendland = 1, kernel_cubic = 2
   !> &numerics viscosity
   character(len=name_len), parameter :: visc_names(*) = [character(len=name_len) :: 'artificial', 'laminar_sps']
   integer, parameter :: visc_artificial = 1, visc_laminar_sps = 2
   !> &numerics diffusion
   character(len=name_len), parameter :: diff_names(*) = [character(len=name_len) :: 'none', 'molteni', 'fourtakas']
   integer, parameter :: diff_none = 1, diff_molteni = 2, diff_fourtakas = 3
   !> &numerics kernel_correction
   character(len=name_len), parameter :: kgc_names(*) = [character(len=name_len) :: 'none', 'gradient', 'shepard']
   integer, parameter :: kgc_none = 1, kgc_gradient = 2, kgc_shepard = 3
   !> &numerics integrator
   character(len=name_len), parameter :: integ_names(*) = [character(len=name_len) :: 'symplectic', &
                                                           'predictor_corrector', 'verlet']
   integer, parameter :: integ_symplectic = 1, integ_predictor_corrector = 2, integ_verlet = 3
   !> &numerics boundary
   character(len=name_len), parameter :: bnd_names(*) = [character(len=name_len) :: 'dynamic', 'repulsive', 'mdbc']
   integer, parameter :: bnd_dynamic = 1, bnd_repulsive = 2, bnd_mdbc = 3
   !> &numerics mdbc_slip: the velocity the water sees at an mDBC solid particle
   character(len=name_len), parameter :: slip_names(*) = [character(len=name_len) :: 'wall', 'noslip', 'freeslip']
   integer, parameter :: slip_wall = 1, slip_noslip = 2, slip_freeslip = 3
   !> &numerics shifting: particle shifting
   character(len=name_len), parameter :: shift_names(*) = [character(len=name_len) :: 'none', 'fickian']
   integer, parameter :: shift_none = 1, shift_fickian = 2
   !> a water particle's mass: rho0 dp^d, or the density of its start depth times
   !> dp^d, so that its volume m/rho is the dp^d it fills on the start lattice
   character(len=name_len), parameter :: mass_names(*) = [character(len=name_len) :: 'rho0', 'hydrostatic']
   integer, parameter :: mass_rho0 = 1, mass_hydrostatic = 2
   !> &contact model
   character(len=name_len), parameter :: contact_names(*) = [character(len=name_len) :: 'dynamic', 'repulsive', &
                                                             'noncohesive', 'noncohesive_spring', 'hertz']
   integer, parameter :: model_dynamic = 1, model_repulsive = 2, model_noncohesive = 3, model_spring = 4, &
                         model_hertz = 5

   !> &box, &polygon role (solid or fluid); &slope role (solid or filter: a
   !> row that stops bodies and lets the water through)
   character(len=name_len), parameter :: role_names(*) = [character(len=name_len) :: 'solid', 'fluid', 'filter']
   integer, parameter :: role_solid = 1, role_fluid = 2, role_filter = 3
   !> &box, &polygon motion; a case file may name the first two, the flume
   !> builder gives the paddle 'wavemaker'
   character(len=name_len), parameter :: wall_motion_names(*) = [character(len=name_len) :: 'fixed', 'oscillate', &
                                                                 'wavemaker']
   integer, parameter :: wall_fixed = 1, wall_oscillate = 2, wall_wavemaker = 3
   !> &body shape
   character(len=name_len), parameter :: shape_names(*) = [character(len=name_len) :: 'circle', 'box', 'wedge', &
                                                           'polygon', 'stl']
   integer, parameter :: shape_circle = 1, shape_box = 2, shape_wedge = 3, shape_polygon = 4, shape_stl = 5
   !> &body motion
   character(len=name_len), parameter :: body_motion_names(*) = [character(len=name_len) :: 'floating', 'fixed', &
                                                                 'prescribed']
   integer, parameter :: motion_floating = 1, motion_fixed = 2, motion_prescribed = 3
   !> &wavemaker paddle
   character(len=name_len), parameter :: paddle_names(*) = [character(len=name_len) :: 'piston', 'flap']
   integer, parameter :: paddle_piston = 1, paddle_flap = 2
   !> &wavemaker wave
   character(len=name_len), parameter :: wave_names(*) = [character(len=name_len) :: 'regular', 'irregular', 'file']
   integer, parameter :: wave_regular = 1, wave_irregular = 2, wave_file = 3
   !> &armour placement
   character(len=name_len), parameter :: placement_names(*) = [character(len=name_len) :: 'regular', 'irregular']
   integer, parameter :: placement_regular = 1, placement_irregular = 2
   !> &breakwater core: one solid, or stones the water flows through (a porous
   !> core under a porous underlayer, the armour on a filter)
   character(len=name_len), parameter :: core_names(*) = [character(len=name_len) :: 'impermeable', 'porous']
   integer, parameter :: core_impermeable = 1, core_porous = 2
   !> &gauge kind
   character(len=name_len), parameter :: gauge_names(*) = [character(len=name_len) :: 'elevation', 'pressure']
   integer, parameter :: gauge_elevation = 1, gauge_pressure = 2

contains

   !> The value of the name value among names (its position); an input error
   !> naming file, group, variable and the allowed names when it is none of them.
   integer function option_index(file, group, var, value, names) result(k)
      character(len=*), intent(in) :: file, group, var, value, names(:)
      character(len=len(value)) :: v
      v = lower(adjustl(value))
      do k = 1, size(names)
         if (trim(names(k)) == trim(v)) return
      end do
      k = 0
      call input_error(file, group, var, "value '"//trim(v)//"' is not one of "//option_list(names))
   end function option_index

   !> 'a', 'b', 'c': the names as an error message lists them.
   function option_list(names) result(s)
      character(len=*), intent(in) :: names(:)
      character(len=:), allocatable :: s
      integer :: i
      s = ''
      do i = 1, size(names)
         s = s//"'"//trim(names(i))//"'"
         if (i < size(names)) s = s//', '
      end do
   end function option_list
end module options

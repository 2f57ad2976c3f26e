!> &breakwater (the flume bed, the foreshore and a rubble-mound breakwater
!> with its still water) and &armour (a single layer of cubes on the front
!> slope). Both are expanded into geometry objects and bodies by scene_flume.
module input_breakwater
   use kinds, only: rp
   use constants, only: name_len, msg_len, ndim
   use input_check, only: open_case, read_failed, check_real, check_int, group_count
   use errors, only: input_error
   use options, only: option_index, placement_names, placement_regular, core_names, core_impermeable, core_porous
   implicit none
   private
   public :: breakwater_cfg, armour_cfg, read_breakwater, write_breakwater, read_armour, write_armour

   !> Lengths in metres, angles in degrees; the bed at the paddle is y = 0.
   type :: breakwater_cfg
      logical :: on = .false.
      real(rp) :: x_start = 0.0_rp          !< paddle face at rest, where the water starts [m]
      real(rp) :: depth = 0.6_rp            !< still-water depth at the paddle [m]
      real(rp) :: toe_depth = 0.2_rp        !< still-water depth at the toe of the breakwater [m]
      real(rp) :: flat_length = 1.0_rp      !< flat bed between the paddle and the foreshore [m]
      real(rp) :: foreshore_angle = 5.0_rp  !< foreshore slope [deg]
      real(rp) :: slope_cot = 1.5_rp        !< front slope of the breakwater, cot(alpha) [-]
      real(rp) :: rc = 0.13_rp              !< crest freeboard above still water [m]
      real(rp) :: crest_width = 0.3_rp      !< [m]
      real(rp) :: rear_cot = 1.5_rp         !< rear slope, cot [-]
      integer :: layers = 0                 !< wall thickness in particle rows (0: enough for 2h)
      character(len=name_len) :: core = 'impermeable'   !< 'impermeable' | 'porous'
      integer :: core_id = core_impermeable  !< core as its value in options (core_*)
      real(rp) :: core_porosity = 0.4_rp    !< porous core: porosity [-]
      real(rp) :: core_d50 = 0.0_rp         !< porous core: stone size [m] (0: 0.4 underlayer_d50)
      real(rp) :: underlayer_porosity = 0.4_rp   !< porous core: porosity of the underlayer [-]
      real(rp) :: underlayer_d50 = 0.0_rp   !< porous core: underlayer stone size [m] (0: 0.4 &armour dn)
      real(rp) :: underlayer_thickness = 0.0_rp  !< porous core: normal to the slope [m] (0: 2 underlayer_d50)
   end type breakwater_cfg

   type :: armour_cfg
      logical :: on = .false.
      character(len=name_len) :: placement = 'regular'   !< 'regular' | 'irregular'
      integer :: placement_id = placement_regular         !< placement as its value in options (placement_*)
      real(rp) :: dn = 0.02_rp              !< cube side (nominal diameter) [m]
      real(rp) :: density = 2200.0_rp       !< concrete density [kg/m3]
      real(rp) :: porosity = 0.0_rp         !< layer porosity [-] (0: 0.21 regular, 0.25 irregular)
      real(rp) :: mu = 0.8_rp               !< friction with the underlayer and between units [-]
      integer :: seed = 1                   !< irregular: gaps and tilts
      real(rp) :: max_tilt = 5.0_rp         !< irregular: largest tilt from the slope [deg]
      real(rp) :: gap_spread = 0.5_rp       !< irregular: gaps vary by +- this fraction of their mean [-]
      integer :: n_units = 0                !< units (0: as many as fit from the toe to the crest)
      real(rp) :: threshold = 1.0_rp        !< a unit is displaced beyond threshold*dn [-]
      logical :: toe_block = .true.         !< a fixed unit at the toe holds the layer
      integer :: n_across = 0               !< 3D: rows side by side across the width (0: equal gaps both ways)
      real(rp) :: max_turn = 5.0_rp         !< 3D, irregular: largest turn about the slope's normal [deg]
   end type armour_cfg

   real(rp) :: x_start, depth, toe_depth, flat_length, foreshore_angle, slope_cot, rc, crest_width, rear_cot
   integer :: layers
   character(len=name_len) :: core
   real(rp) :: core_porosity, core_d50, underlayer_porosity, underlayer_d50, underlayer_thickness
   namelist /breakwater/ x_start, depth, toe_depth, flat_length, foreshore_angle, slope_cot, rc, crest_width, &
      rear_cot, layers, core, core_porosity, core_d50, underlayer_porosity, underlayer_d50, underlayer_thickness
   character(len=name_len) :: placement
   real(rp) :: dn, density, porosity, mu, max_tilt, gap_spread, threshold, max_turn
   integer :: seed, n_units, n_across
   logical :: toe_block
   namelist /armour/ placement, dn, density, porosity, mu, seed, max_tilt, gap_spread, n_units, threshold, toe_block, &
      n_across, max_turn

contains

   subroutine bw_to_vars(c)
      type(breakwater_cfg), intent(in) :: c
      x_start = c%x_start; depth = c%depth; toe_depth = c%toe_depth; flat_length = c%flat_length
      foreshore_angle = c%foreshore_angle; slope_cot = c%slope_cot; rc = c%rc; crest_width = c%crest_width
      rear_cot = c%rear_cot; layers = c%layers
      core = c%core; core_porosity = c%core_porosity; core_d50 = c%core_d50
      underlayer_porosity = c%underlayer_porosity; underlayer_d50 = c%underlayer_d50
      underlayer_thickness = c%underlayer_thickness
   end subroutine bw_to_vars

   subroutine read_breakwater(file, c)
      character(len=*), intent(in) :: file
      type(breakwater_cfg), intent(out) :: c
      integer :: u, ios, n
      character(len=msg_len) :: msg
      character(len=*), parameter :: g = 'breakwater'
      n = group_count(file, g)
      if (n > 1) call input_error(file, g, '', 'group appears more than once')
      if (n == 0) return
      call bw_to_vars(c)
      u = open_case(file)
      read (u, nml=breakwater, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, g, ios, msg)) return
      c%on = .true.
      c%x_start = x_start; c%depth = depth; c%toe_depth = toe_depth; c%flat_length = flat_length
      c%foreshore_angle = foreshore_angle; c%slope_cot = slope_cot; c%rc = rc; c%crest_width = crest_width
      c%rear_cot = rear_cot; c%layers = layers
      c%core = core; c%core_porosity = core_porosity; c%core_d50 = core_d50
      c%underlayer_porosity = underlayer_porosity; c%underlayer_d50 = underlayer_d50
      c%underlayer_thickness = underlayer_thickness
      call check_real(file, g, 'depth', c%depth, 0.0_rp, 100.0_rp, lo_open=.true.)
      call check_real(file, g, 'toe_depth', c%toe_depth, 0.0_rp, c%depth, lo_open=.true.)
      call check_real(file, g, 'flat_length', c%flat_length, 0.0_rp, 1.0e4_rp)
      if (c%toe_depth < c%depth) then
         call check_real(file, g, 'foreshore_angle', c%foreshore_angle, 0.0_rp, 45.0_rp, lo_open=.true.)
      end if
      call check_real(file, g, 'slope_cot', c%slope_cot, 0.5_rp, 10.0_rp)
      call check_real(file, g, 'rc', c%rc, 0.0_rp, 100.0_rp, lo_open=.true.)
      call check_real(file, g, 'crest_width', c%crest_width, 0.0_rp, 1.0e4_rp, lo_open=.true.)
      call check_real(file, g, 'rear_cot', c%rear_cot, 0.5_rp, 10.0_rp)
      call check_int(file, g, 'layers', c%layers, 0, 100)
      c%core_id = option_index(file, g, 'core', c%core, core_names)
      c%core = core_names(c%core_id)
      if (c%core_id == core_porous) call check_porous_core(file, c)
   end subroutine read_breakwater

   !> The stones of a porous core: porosities in (0, 1), sizes and thickness
   !> positive or 0 for the default; the underlayer's default size needs the
   !> armour's dn, so without &armour it must be given.
   subroutine check_porous_core(file, c)
      character(len=*), intent(in) :: file
      type(breakwater_cfg), intent(inout) :: c
      character(len=*), parameter :: g = 'breakwater'
      call check_real(file, g, 'core_porosity', c%core_porosity, 0.0_rp, 1.0_rp, lo_open=.true., hi_open=.true.)
      call check_real(file, g, 'underlayer_porosity', c%underlayer_porosity, 0.0_rp, 1.0_rp, lo_open=.true., &
                      hi_open=.true.)
      call check_real(file, g, 'core_d50', c%core_d50, 0.0_rp, 10.0_rp)
      call check_real(file, g, 'underlayer_d50', c%underlayer_d50, 0.0_rp, 10.0_rp)
      call check_real(file, g, 'underlayer_thickness', c%underlayer_thickness, 0.0_rp, 100.0_rp)
      if (c%underlayer_d50 > 0.0_rp) return
      if (group_count(file, 'armour') == 0) call input_error(file, g, 'underlayer_d50', &
         "a porous core (core = 'porous') without &armour needs the underlayer's stone size: "// &
         '(0, 10] m (its default is 0.4 of the armour unit dn)')
   end subroutine check_porous_core

   subroutine write_breakwater(u, c)
      integer, intent(in) :: u
      type(breakwater_cfg), intent(in) :: c
      if (.not. c%on) return
      call bw_to_vars(c)
      write (u, nml=breakwater)
   end subroutine write_breakwater

   subroutine ar_to_vars(c)
      type(armour_cfg), intent(in) :: c
      placement = c%placement; dn = c%dn; density = c%density; porosity = c%porosity; mu = c%mu
      seed = c%seed; max_tilt = c%max_tilt; gap_spread = c%gap_spread; n_units = c%n_units
      threshold = c%threshold; toe_block = c%toe_block; n_across = c%n_across; max_turn = c%max_turn
   end subroutine ar_to_vars

   subroutine read_armour(file, dp, c)
      character(len=*), intent(in) :: file
      real(rp), intent(in) :: dp
      type(armour_cfg), intent(out) :: c
      integer :: u, ios, n
      character(len=msg_len) :: msg
      character(len=*), parameter :: g = 'armour'
      n = group_count(file, g)
      if (n > 1) call input_error(file, g, '', 'group appears more than once (one layer per case)')
      if (n == 0) return
      if (group_count(file, 'breakwater') == 0) call input_error(file, g, '', &
                                                                 'the armour layer needs a &breakwater group')
      call ar_to_vars(c)
      u = open_case(file)
      read (u, nml=armour, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, g, ios, msg)) return
      c%on = .true.
      c%placement = placement; c%dn = dn; c%density = density; c%porosity = porosity; c%mu = mu
      c%seed = seed; c%max_tilt = max_tilt; c%gap_spread = gap_spread; c%n_units = n_units
      c%threshold = threshold; c%toe_block = toe_block; c%n_across = n_across; c%max_turn = max_turn
      c%placement_id = option_index(file, g, 'placement', c%placement, placement_names)
      c%placement = placement_names(c%placement_id)
      call check_real(file, g, 'dn', c%dn, 3.0_rp*dp, 100.0_rp)
      call check_real(file, g, 'density', c%density, 1.0_rp, 1.0e5_rp)
      call check_real(file, g, 'porosity', c%porosity, 0.0_rp, 0.6_rp)
      if (c%porosity <= 0.0_rp) c%porosity = merge(0.21_rp, 0.25_rp, c%placement_id == placement_regular)
      call check_real(file, g, 'mu', c%mu, 0.0_rp, 10.0_rp)
      call check_int(file, g, 'seed', c%seed, 0, huge(1))
      call check_real(file, g, 'max_tilt', c%max_tilt, 0.0_rp, 30.0_rp)
      call check_real(file, g, 'gap_spread', c%gap_spread, 0.0_rp, 1.0_rp)
      ! a cube turned by more than 45 degrees is one turned by less the other way
      call check_real(file, g, 'max_turn', c%max_turn, 0.0_rp, 45.0_rp)
      call check_int(file, g, 'n_units', c%n_units, 0, 100000)
      call check_real(file, g, 'threshold', c%threshold, 0.0_rp, 100.0_rp, lo_open=.true.)
      call check_int(file, g, 'n_across', c%n_across, 0, 100000)
      if (ndim == 2 .and. c%n_across /= 0) call input_error(file, g, 'n_across', &
         'rows across the width are for the 3D build (build/mbsph3d); leave it out in 2D')
   end subroutine read_armour

   subroutine write_armour(u, c)
      integer, intent(in) :: u
      type(armour_cfg), intent(in) :: c
      if (.not. c%on) return
      call ar_to_vars(c)
      write (u, nml=armour)
   end subroutine write_armour
end module input_breakwater

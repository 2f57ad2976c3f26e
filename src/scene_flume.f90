!> Flume generators: the wavemaker paddle, the breakwater (bed, foreshore,
!> core and still water) and its armour layer of cubes. They make geometry
!> objects and body groups like those a user writes, marked `generated`,
!> so the rest of the code treats them as any other object or body.
module scene_flume
   use kinds, only: rp
   use constants, only: pi, name_len, ndim
   use input_geometry, only: geom_object
   use input_body, only: body_cfg
   use input_wave, only: wavemaker_cfg
   use input_breakwater, only: breakwater_cfg, armour_cfg
   use input_porous, only: porous_cfg
   use input_check, only: int_str, real_str
   use errors, only: input_error, alloc_check, fatal
   use wave_paddle, only: paddle_t
   use wave_theory, only: wave_number, piston_transfer, flap_transfer, piston_second_order
   use wave_spectrum, only: jonswap_paddle_signal, signal_hm0
   use wave_signal, only: signal_read
   use options, only: role_solid, role_fluid, role_filter, core_porous, wall_wavemaker, motion_fixed, motion_floating, shape_box, &
                      placement_irregular, wave_regular, wave_irregular, wave_file, paddle_piston, paddle_flap
   implicit none
   private
   public :: armour_layer_t, paddle_object, breakwater_objects, breakwater_porous, armour_units, scene_paddle, &
             armour_csv_header

   !> What the armour generator achieved; the solver writes it to armour.csv.
   type :: armour_layer_t
      integer :: n_units = 0
      integer :: first = 0                 !< index in the case's bodies of the first unit
      real(rp) :: porosity = 0.0_rp        !< achieved [-]
      real(rp) :: alpha = 0.0_rp           !< slope angle [rad]
      real(rp) :: width = 0.0_rp           !< the width across the layer (3D) [m]
      real(rp) :: turn_max = 0.0_rp        !< 3D, irregular: the largest turn about the slope's normal drawn [deg]
      !> (npose, n_units) at the start: x [m], y [m], angle [deg] in 2D; x, y, z [m], angle, turn [deg] in 3D
      real(rp), allocatable :: pose(:, :)
   end type armour_layer_t

   !> A row of units along the slope while it is being laid out. A unit is
   !> turned by turn about the slope's normal (3D), then tilted by tilt in the
   !> section; foot is its length along the slope, rise its height above it.
   type :: row_t
      real(rp) :: dn = 0.0_rp, target = 0.0_rp, s0 = 0.0_rp
      real(rp), allocatable :: tilt(:), turn(:), wgt(:), foot(:), rise(:), sc(:)
   end type row_t

   integer, parameter :: npose = 2*ndim - 1   !< rows of armour_layer_t%pose

   real(rp), parameter :: deg = pi/180.0_rp
   integer, parameter :: max_parts = 10    !< objects of a breakwater: 6 bed lines, 2 walls, the water (twice)

contains

   !> The paddle: a wall of particles behind the face x0, from the bed up.
   function paddle_object(wm, dp, h) result(o)
      type(wavemaker_cfg), intent(in) :: wm
      real(rp), intent(in) :: dp, h
      type(geom_object) :: o
      real(rp) :: thick, top
      integer :: layers
      integer :: ist
      character(len=200) :: emsg
      layers = wm%layers
      if (layers == 0) layers = max(1, ceiling(2.0_rp*h/dp - 1.0e-9_rp))
      thick = layers*dp
      top = wm%top
      if (top <= 0.0_rp) top = wm%y_bed + 1.5_rp*wm%depth
      o%group = 'wavemaker'
      o%index = 1
      o%generated = .true.
      o%role = 'solid'
      o%role_id = role_solid
      o%motion = 'wavemaker'
      o%motion_id = wall_wavemaker
      o%hinge_depth = wm%depth
      o%box = [wm%x0 - thick, wm%x0, wm%y_bed, top]
      o%nv = 4
      allocate (o%v(2, 4), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'o%v in paddle_object')
      o%v = reshape([o%box(1), o%box(3), o%box(2), o%box(3), o%box(2), o%box(4), o%box(1), o%box(4)], [2, 4])
   end function paddle_object

   !> Key points of the profile: x of the foreshore start, toe, front crest
   !> edge, rear crest edge, rear foot; y of the toe and the crest.
   subroutine breakwater_levels(bw, x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c)
      type(breakwater_cfg), intent(in) :: bw
      real(rp), intent(out) :: x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c
      x_fs = bw%x_start + bw%flat_length
      y_toe = bw%depth - bw%toe_depth
      x_toe = x_fs
      if (y_toe > 0.0_rp) x_toe = x_fs + y_toe/tan(bw%foreshore_angle*deg)
      y_c = bw%depth + bw%rc
      x_cf = x_toe + (y_c - y_toe)*bw%slope_cot
      x_cb = x_cf + bw%crest_width
      x_rf = x_cb + (y_c - y_toe)*bw%rear_cot
   end subroutine breakwater_levels

   !> The bed as a chain of slopes (particle rows below each line), an end
   !> wall, and the still water. An impermeable core is one solid under the
   !> breakwater's outline and the water ends at the front slope; a porous
   !> core (breakwater_porous gives its stones) has the bed run on under it
   !> to the end wall, a filter along its outline for the armour to rest on,
   !> and the still water fills the flume to the end wall, pores included.
   subroutine breakwater_objects(file, bw, paddle, xmin, xmax, ymin, dp, h, objs)
      character(len=*), intent(in) :: file
      type(breakwater_cfg), intent(in) :: bw
      logical, intent(in) :: paddle          !< a wavemaker closes the flume at x_start; else a wall does
      real(rp), intent(in) :: xmin, xmax, ymin, dp, h
      type(geom_object), allocatable, intent(out) :: objs(:)
      real(rp) :: x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c, thick, x_swl, xw
      integer :: layers, n
      logical :: porous
      type(geom_object) :: tmp(max_parts)
      character(len=*), parameter :: g = 'breakwater'
      layers = bw%layers
      if (layers == 0) layers = max(1, ceiling(2.0_rp*h/dp - 1.0e-9_rp))
      thick = layers*dp
      call breakwater_levels(bw, x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c)
      if (ymin > -thick + 1.0e-9_rp) call input_error(file, g, 'layers', 'the bed (y = 0) is '// &
         int_str(layers)//' rows = '//real_str(thick)//' m thick: &domain ymin must be <= '//real_str(-thick))
      if (bw%x_start < xmin + thick) call input_error(file, g, 'x_start', 'must leave room for the paddle: >= '// &
                                                      real_str(xmin + thick)//' (&domain xmin + wall thickness)')
      xw = xmax - thick
      if (x_rf > xw - dp) call input_error(file, g, 'crest_width', 'the breakwater ends at x = '// &
         real_str(x_rf)//' m, beyond the end wall at '//real_str(xw)//' m: make &domain xmax larger')
      n = 0
      call add_line(xmin, 0.0_rp, x_fs, 0.0_rp)
      if (y_toe > 0.0_rp) call add_line(x_fs, 0.0_rp, x_toe, y_toe)
      porous = bw%core_id == core_porous
      call add_line(x_toe, y_toe, x_cf, y_c, porous)
      call add_line(x_cf, y_c, x_cb, y_c, porous)
      call add_line(x_cb, y_c, x_rf, y_toe, porous)
      if (porous) then
         call add_line(x_toe, y_toe, xw, y_toe)
      else if (xw - x_rf > dp) then
         call add_line(x_rf, y_toe, xw, y_toe)
      end if
      ! end wall, so overtopping water stays in the flume
      n = n + 1
      tmp(n)%group = 'box'
      tmp(n)%box = [xw, xmax, y_toe - thick, y_c + bw%rc]
      tmp(n)%v = reshape([xw, y_toe - thick, xmax, y_toe - thick, xmax, y_c + bw%rc, xw, y_c + bw%rc], [2, 4])
      tmp(n)%nv = 4
      if (.not. paddle) then
         n = n + 1
         tmp(n)%group = 'box'
         tmp(n)%box = [bw%x_start - thick, bw%x_start, 0.0_rp, y_c + bw%rc]
         tmp(n)%v = reshape([bw%x_start - thick, 0.0_rp, bw%x_start, 0.0_rp, bw%x_start, y_c + bw%rc, &
                             bw%x_start - thick, y_c + bw%rc], [2, 4])
         tmp(n)%nv = 4
      end if
      ! still water up to the front slope, or through the porous core to the end wall
      x_swl = x_toe + bw%toe_depth*bw%slope_cot
      n = n + 1
      tmp(n)%group = 'polygon'
      tmp(n)%role = 'fluid'
      tmp(n)%role_id = role_fluid
      if (y_toe > 0.0_rp) then
         tmp(n)%v = reshape([bw%x_start, 0.0_rp, x_fs, 0.0_rp, x_toe, y_toe, x_swl, bw%depth, &
                             bw%x_start, bw%depth], [2, 5])
      else
         tmp(n)%v = reshape([bw%x_start, 0.0_rp, x_toe, 0.0_rp, x_swl, bw%depth, bw%x_start, bw%depth], [2, 4])
      end if
      tmp(n)%nv = size(tmp(n)%v, 2)
      if (porous) then
         ! the water behind the front slope, in the pores and beyond: a second
         ! object, so that the pore water's lattice is fitted between the bed
         ! under the breakwater and the still-water level (scene's add_pore_water)
         n = n + 1
         tmp(n)%group = 'polygon'
         tmp(n)%role = 'fluid'
         tmp(n)%role_id = role_fluid
         tmp(n)%v = reshape([x_toe, y_toe, xw, y_toe, xw, bw%depth, x_swl, bw%depth], [2, 4])
         tmp(n)%nv = 4
      end if
      tmp(1:n)%generated = .true.
      tmp(1:n)%index = 1
      objs = tmp(1:n)
   contains
      !> A slope below the line from a to b; a filter (one row) when filter is set.
      subroutine add_line(xa, ya, xb, yb, filter)
         real(rp), intent(in) :: xa, ya, xb, yb
         logical, intent(in), optional :: filter
         real(rp) :: t(2), nrm(2), w
         n = n + 1
         tmp(n)%group = 'slope'
         tmp(n)%line = [xa, ya, xb, yb]
         tmp(n)%layers = layers
         if (present(filter)) then
            if (filter) then
               tmp(n)%layers = 1
               tmp(n)%role = 'filter'
               tmp(n)%role_id = role_filter
            end if
         end if
         w = tmp(n)%layers*dp
         t = [xb - xa, yb - ya]/hypot(xb - xa, yb - ya)
         nrm = [-t(2), t(1)]
         tmp(n)%v = reshape([xa - w*nrm(1), ya - w*nrm(2), xb - w*nrm(1), yb - w*nrm(2), &
                             xb, yb, xa, ya], [2, 4])
         tmp(n)%nv = 4
      end subroutine add_line
   end subroutine breakwater_objects

   !> The stones of a porous core (&breakwater core = 'porous'): an underlayer
   !> of thickness t normal to the front slope, from the toe to the crest, and
   !> the core behind it under the crest and the rear slope. Their outer
   !> outlines lie half the porosity's transition (width) inside the
   !> breakwater's surface, so that the stones begin at the filter the armour
   !> rests on (the porosity is 1 there and above: the armour layer's voids are
   !> open water). Both reach a bed thickness (thick) down into the bed, so
   !> that the porosity is uniform down to the bed. Defaults where the case
   !> gives 0: the underlayer's stones of 0.4 of the armour's dn, two stones
   !> thick, the core's 0.4 of the underlayer's (doc/porous.md: the Rock
   !> Manual's filter rule, a mass ratio of 10 to 15).
   subroutine breakwater_porous(file, bw, dn, dp, h, width, regions)
      character(len=*), intent(in) :: file
      type(breakwater_cfg), intent(in) :: bw
      real(rp), intent(in) :: dn                 !< armour unit size [m] (0: no &armour)
      real(rp), intent(in) :: dp, h
      real(rp), intent(in) :: width              !< the porosity's transition [m]
      type(porous_cfg), allocatable, intent(out) :: regions(:)
      real(rp) :: x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c, thick, du, dc, t, sx, yb, df, dr, yc, xf, xi, xr
      integer :: layers, ist
      character(len=200) :: emsg
      character(len=*), parameter :: g = 'breakwater'
      allocate (regions(0), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'regions in breakwater_porous')
      if (bw%core_id /= core_porous) return
      layers = bw%layers
      if (layers == 0) layers = max(1, ceiling(2.0_rp*h/dp - 1.0e-9_rp))
      thick = layers*dp
      call breakwater_levels(bw, x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c)
      du = bw%underlayer_d50
      if (du <= 0.0_rp) du = 0.4_rp*dn
      dc = bw%core_d50
      if (dc <= 0.0_rp) dc = 0.4_rp*du
      t = bw%underlayer_thickness
      if (t <= 0.0_rp) t = 2.0_rp*du
      if (t <= 0.5_rp*width + dp) call input_error(file, g, 'underlayer_thickness', 'the underlayer ('// &
         real_str(t)//' m thick) must be thicker than half the transition of the porosity and a spacing: > '// &
         real_str(0.5_rp*width + dp)//' m (the transition is 2h = '//real_str(width)//' m wide)')
      ! horizontal distances behind the front slope line: the underlayer's inner
      ! edge (sx) and the stones' outer outline (df); dr before the rear slope line
      sx = t*sqrt(1.0_rp + bw%slope_cot**2)
      df = 0.5_rp*width*sqrt(1.0_rp + bw%slope_cot**2)
      dr = 0.5_rp*width*sqrt(1.0_rp + bw%rear_cot**2)
      yc = y_c - 0.5_rp*width
      xf = x_toe + df + (yc - y_toe)*bw%slope_cot
      xi = x_toe + sx + (yc - y_toe)*bw%slope_cot
      xr = x_rf - dr - (yc - y_toe)*bw%rear_cot
      if (xi > xr - dp) call input_error(file, g, 'underlayer_thickness', 'the underlayer ('// &
         real_str(t)//' m thick) reaches past the crest: make it thinner or crest_width (now '// &
         real_str(bw%crest_width)//' m) wider')
      yb = y_toe - thick
      deallocate (regions)
      allocate (regions(2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'regions in breakwater_porous')
      regions%generated = .true.
      regions%is_box = .false.
      regions%width = width
      regions(1)%porosity = bw%underlayer_porosity
      regions(1)%d50 = du
      regions(1)%v = reshape([x_toe + df, yb, x_toe + sx, yb, xi, yc, xf, yc, x_toe + df, y_toe], [2, 5])
      regions(2)%porosity = bw%core_porosity
      regions(2)%d50 = dc
      regions(2)%v = reshape([x_toe + sx, yb, x_rf - dr, yb, x_rf - dr, y_toe, xr, yc, xi, yc], [2, 5])
      regions(1)%nv = 5
      regions(2)%nv = 5
   end subroutine breakwater_porous

   !> A single layer of cubes (squares in 2D) on the front slope, from the
   !> toe up to the crest. Each unit lies on the underlayer; the gaps between
   !> units give the layer its porosity, measured in a band of thickness dn
   !> above the slope from the toe unit to the end of the last unit.
   !> Regular: equal gaps, no tilt. Irregular: gaps and tilts drawn from the
   !> seed, gaps scaled so the measured porosity meets the target.
   !> In 3D the layer is ncol such rows side by side across the width zdom,
   !> one every pitch = width/ncol: the rows along the slope take the
   !> porosity that gives the layer its target with the gaps across, each
   !> irregular row its own draws, its units shifted across at random within
   !> the gap (gap_spread of it).
   subroutine armour_units(file, bw, ar, zdom, bodies, layer)
      character(len=*), intent(in) :: file
      type(breakwater_cfg), intent(in) :: bw
      type(armour_cfg), intent(in) :: ar
      real(rp), intent(in) :: zdom(2)           !< the width across (3D)
      type(body_cfg), allocatable, intent(out) :: bodies(:)
      type(armour_layer_t), intent(out) :: layer
      real(rp) :: x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c, s_max, t(2), nrm(2), p0(2), pitch, target, zc, &
                  por_sum, turn_max
      type(row_t) :: r
      type(body_cfg), allocatable :: units(:), toes(:)
      integer :: n, k, j, ncol, zstate, m
      call breakwater_levels(bw, x_fs, x_toe, x_cf, x_cb, x_rf, y_toe, y_c)
      layer%alpha = atan(1.0_rp/bw%slope_cot)
      t = [cos(layer%alpha), sin(layer%alpha)]
      nrm = [-t(2), t(1)]
      p0 = [x_toe, y_toe]
      s_max = (y_c - y_toe)/sin(layer%alpha)
      ncol = 1
      pitch = 0.0_rp
      target = ar%porosity
      if (ndim == 3) call columns_across(file, ar, zdom, ncol, pitch, target)
      turn_max = 0.0_rp
      if (ndim == 3 .and. ar%placement_id == placement_irregular) turn_max = fitting_turn(ar, pitch)
      layer%turn_max = turn_max/deg
      allocate (units(0), toes(0))
      por_sum = 0.0_rp
      do j = 1, ncol
         call fit_row(file, ar, target, s_max, stream(ar%seed, (j - 1)*7919), turn_max, r, n)
         if (n > 1) por_sum = por_sum + row_porosity(r, n)
         zc = zdom(1) + (j - 0.5_rp)*pitch
         zstate = stream(ar%seed, 104729*j)
         if (ar%toe_block) then
            toes = [toes, unit_cfg(ar, p0, t, nrm, layer%alpha, 0.5_rp*ar%dn, 0.0_rp, ar%dn, 0.0_rp)]
            m = size(toes)
            toes(m)%motion = 'fixed'
            toes(m)%motion_id = motion_fixed
            if (ndim == 3) call across(toes(m), zc)
         end if
         do k = 1, n
            units = [units, unit_cfg(ar, p0, t, nrm, layer%alpha, r%sc(k), r%tilt(k), r%rise(k), r%turn(k))]
            if (ndim == 3) then
               if (ar%placement_id == placement_irregular) then
                  ! the play across is what the turned unit's span leaves of the pitch
                  call across(units(size(units)), zc + (2.0_rp*uniform(zstate) - 1.0_rp)*0.5_rp* &
                              (pitch - ar%dn*turned_span(r%turn(k)))*ar%gap_spread)
               else
                  call across(units(size(units)), zc)
               end if
            end if
         end do
      end do
      n = size(units)
      layer%n_units = n
      layer%porosity = por_sum/ncol
      if (ndim == 3) layer%porosity = 1.0_rp - (1.0_rp - layer%porosity)*ar%dn/pitch
      layer%width = zdom(2) - zdom(1)
      bodies = [toes, units]
      layer%first = size(toes) + 1       ! relative to these bodies; the caller shifts it
      allocate (layer%pose(npose, n))
      do k = 1, n
         layer%pose(1:2, k) = [units(k)%x, units(k)%y]
         if (ndim == 3) layer%pose(3, k) = units(k)%z
         layer%pose(ndim + 1, k) = units(k)%angle
         if (ndim == 3) layer%pose(npose, k) = units(k)%angle_y
      end do
   contains
      !> Unit b across the width: a cube centred at z.
      subroutine across(b, z)
         type(body_cfg), intent(inout) :: b
         real(rp), intent(in) :: z
         b%z = z
         b%depth = ar%dn
      end subroutine across
   end subroutine armour_units

   !> 3D, irregular: the largest turn about the slope's normal a unit may take,
   !> max_turn or less: a turned cube spans dn turned_span(turn) across, and
   !> that must fit within the pitch, so that neighbours across never meet.
   real(rp) function fitting_turn(ar, pitch) result(tm)
      type(armour_cfg), intent(in) :: ar
      real(rp), intent(in) :: pitch
      ! turned_span(turn) = sqrt(2) sin(turn + pi/4), rising from 1 at 0 to sqrt(2) at pi/4
      tm = min(ar%max_turn*deg, asin(min(1.0_rp, pitch/(sqrt(2.0_rp)*ar%dn))) - 0.25_rp*pi)
      tm = max(0.0_rp, tm)
   end function fitting_turn

   !> The span of a cube of side 1 turned by turn about one of its axes, along
   !> another of them.
   elemental real(rp) function turned_span(turn) result(w)
      real(rp), intent(in) :: turn
      w = abs(cos(turn)) + abs(sin(turn))
   end function turned_span

   !> 3D: the rows across the width, their pitch and the porosity a row along
   !> the slope must have for the layer to reach its target: the units take dn
   !> of each pitch across. ncol: n_across, or by default as many as give equal
   !> gaps along and across, (dn/(dn + gap))^2 = 1 - porosity.
   subroutine columns_across(file, ar, zdom, ncol, pitch, target)
      character(len=*), intent(in) :: file
      type(armour_cfg), intent(in) :: ar
      real(rp), intent(in) :: zdom(2)
      integer, intent(out) :: ncol
      real(rp), intent(out) :: pitch, target
      real(rp) :: width
      width = zdom(2) - zdom(1)
      ncol = ar%n_across
      if (ncol == 0) ncol = max(1, nint(width*sqrt(1.0_rp - ar%porosity)/ar%dn))
      pitch = width/ncol
      if (pitch < ar%dn) call input_error(file, 'armour', 'n_across', int_str(ncol)//' units of side '// &
         real_str(ar%dn)//' m do not fit across the width '//real_str(width)//' m: at most '// &
         int_str(floor(width/ar%dn)))
      target = 1.0_rp - (1.0_rp - ar%porosity)*pitch/ar%dn
      if (target < 0.0_rp .or. target > 0.6_rp) call input_error(file, 'armour', 'n_across', 'with '// &
         int_str(ncol)//' units across the width '//real_str(width)//' m the rows along the slope would need '// &
         'porosity '//real_str(target)//' (from 0 to 0.6) to give the layer '//real_str(ar%porosity)// &
         ': choose about '//int_str(max(1, nint(width*sqrt(1.0_rp - ar%porosity)/ar%dn)))//' units across')
   end subroutine columns_across

   !> One row along the slope: the draws of the seed, the most units that fit
   !> below the crest at the target porosity (or n_units), their places.
   subroutine fit_row(file, ar, target, s_max, seed, turn_max, r, n)
      character(len=*), intent(in) :: file
      type(armour_cfg), intent(in) :: ar
      real(rp), intent(in) :: target, s_max
      integer, intent(in) :: seed
      real(rp), intent(in) :: turn_max          !< largest turn about the slope's normal [rad] (3D)
      type(row_t), intent(out) :: r
      integer, intent(out) :: n
      integer :: ncap, k
      real(rp) :: por
      character(len=*), parameter :: g = 'armour'
      r%dn = ar%dn
      r%target = target
      r%s0 = merge(ar%dn, 0.0_rp, ar%toe_block)
      ncap = max(0, floor((s_max - r%s0)/ar%dn))
      call draw_units(ar, seed, ncap, turn_max, r)
      n = 0
      fit: do k = ncap, 1, -1
         call solve_gaps(r, k)
         if (r%sc(k) + 0.5_rp*r%foot(k) <= s_max + 1.0e-12_rp) then
            n = k
            exit fit
         end if
      end do fit
      if (n < 1) call input_error(file, g, 'dn', 'no unit of side '//real_str(ar%dn)// &
         ' m fits on the front slope (length '//real_str(s_max)//' m from the toe to the crest)')
      if (ar%n_units > n) call input_error(file, g, 'n_units', 'at most '//int_str(n)//' units of side '// &
         real_str(ar%dn)//' m fit on the front slope at porosity '//real_str(ar%porosity)//' (got '// &
         int_str(ar%n_units)//')')
      if (ar%n_units > 0) then
         n = ar%n_units
         call solve_gaps(r, n)
      end if
      if (n > 1) then
         por = row_porosity(r, n)
         ! said of the layer: in 3D a row's voids are a share of the layer's (columns_across)
         if (abs(por - target) > 0.02_rp) call input_error(file, g, 'porosity', &
            'the layer cannot reach porosity '//real_str(ar%porosity)//' with these tilts'// &
            turns_note(turn_max > 0.0_rp, 1.0_rp - (1.0_rp - por)*(1.0_rp - ar%porosity)/(1.0_rp - target)))
      end if
   end subroutine fit_row

   !> The end of fit_row's message: the turns named where there are any.
   function turns_note(turned, por) result(t)
      logical, intent(in) :: turned
      real(rp), intent(in) :: por
      character(len=:), allocatable :: t
      if (turned) then
         t = ' and turns (reached '//real_str(por)//'; a smaller max_turn or a larger porosity)'
      else
         t = ' (reached '//real_str(por)//')'
      end if
   end function turns_note

   !> Tilts, turns and gap weights of up to ncap units, from the seed; the
   !> draws do not depend on how many units fit, so a longer slope extends
   !> the same row. The turns (3D) have a stream of their own, so that the
   !> tilts and gaps of a seed are the same with and without them.
   subroutine draw_units(ar, seed, ncap, turn_max, r)
      type(armour_cfg), intent(in) :: ar
      integer, intent(in) :: seed, ncap
      real(rp), intent(in) :: turn_max
      type(row_t), intent(inout) :: r
      integer :: i, state
      integer :: ist
      character(len=200) :: emsg
      real(rp) :: span(ncap)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (r%tilt(ncap), r%turn(ncap), r%wgt(ncap), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'r%tilt, r%turn, r%wgt in draw_units')
      r%tilt = 0.0_rp
      r%turn = 0.0_rp
      r%wgt = 1.0_rp
      state = seed
      if (ar%placement_id == placement_irregular) then
         do i = 1, ncap
            r%tilt(i) = (2.0_rp*uniform(state) - 1.0_rp)*ar%max_tilt*deg
            r%wgt(i) = 1.0_rp + (2.0_rp*uniform(state) - 1.0_rp)*ar%gap_spread
         end do
      end if
      if (turn_max > 0.0_rp) then
         state = stream(seed, 15485863)
         do i = 1, ncap
            r%turn(i) = (2.0_rp*uniform(state) - 1.0_rp)*turn_max
         end do
      end if
      ! the extents along the slope and normal to it of the turned, then tilted cube
      span = turned_span(r%turn)
      r%foot = ar%dn*(span*abs(cos(r%tilt)) + abs(sin(r%tilt)))
      r%rise = ar%dn*(span*abs(sin(r%tilt)) + abs(cos(r%tilt)))
   end subroutine draw_units

   !> Gaps of the first m units that meet the target porosity (bisection:
   !> the porosity grows with the gaps).
   subroutine solve_gaps(r, m)
      type(row_t), intent(inout) :: r
      integer, intent(in) :: m
      real(rp) :: glo, ghi, gmid
      integer :: it
      if (m == 1) then
         call place_units(r, 1, 0.0_rp)
         return
      end if
      glo = 0.0_rp
      ghi = 4.0_rp*r%dn
      do it = 1, 50
         gmid = 0.5_rp*(glo + ghi)
         call place_units(r, m, gmid)
         if (row_porosity(r, m) < r%target) then
            glo = gmid
         else
            ghi = gmid
         end if
      end do
      call place_units(r, m, 0.5_rp*(glo + ghi))
   end subroutine solve_gaps

   !> Positions along the slope of the first m unit centres, with gaps
   !> proportional to wgt scaled by gs; the first unit rests on the toe.
   subroutine place_units(r, m, gs)
      type(row_t), intent(inout) :: r
      integer, intent(in) :: m
      real(rp), intent(in) :: gs
      real(rp) :: s
      integer :: k
      integer :: ist
      character(len=200) :: emsg
      if (allocated(r%sc)) deallocate (r%sc)
      allocate (r%sc(m), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'r%sc in place_units')
      s = r%s0
      do k = 1, m
         if (k > 1) s = s + gs*r%wgt(k)
         r%sc(k) = s + 0.5_rp*r%foot(k)
         s = s + r%foot(k)
      end do
   end subroutine place_units

   !> Void fraction of the band s0 <= s <= end of unit m, 0 <= nu <= dn,
   !> sampled on a grid of dn/40.
   real(rp) function row_porosity(r, m) result(pr)
      type(row_t), intent(in) :: r
      integer, intent(in) :: m
      integer, parameter :: nn = 40
      integer :: ns, a, b, k0
      real(rp) :: len, ds, s, nu, ct(m), st(m), cw(m), sw(m), inside
      ! each unit's rotation once, not once per sample point
      ct = cos(r%tilt(1:m))
      st = sin(r%tilt(1:m))
      cw = cos(r%turn(1:m))
      sw = sin(r%turn(1:m))
      len = r%sc(m) + 0.5_rp*r%foot(m) - r%s0
      ns = max(1, nint(len/(r%dn/nn)))
      ds = len/ns
      inside = 0.0_rp
      k0 = 1
      do a = 1, ns
         s = r%s0 + (a - 0.5_rp)*ds
         first_near: do while (k0 < m)
            if (r%sc(k0) + 0.5_rp*r%foot(k0) >= s - r%dn) exit first_near
            k0 = k0 + 1
         end do first_near
         do b = 1, nn
            nu = (b - 0.5_rp)*r%dn/nn
            inside = inside + unit_depth(r, ct, st, cw, sw, k0, min(m, k0 + 3), s, nu)
         end do
      end do
      pr = 1.0_rp - inside/real(ns*nn, rp)
   end function row_porosity

   !> How deep across, in dn, one of units k0..k1 holds the line across the
   !> width through the point (s along the slope, nu above it): 1 inside an
   !> unturned unit, the chord of the turned square otherwise (ct, st: the
   !> cosine and sine of each unit's tilt; cw, sw: of its turn). Summed over
   !> the section, it gives the units' volume in the band.
   pure real(rp) function unit_depth(r, ct, st, cw, sw, k0, k1, s, nu) result(d)
      type(row_t), intent(in) :: r
      real(rp), intent(in) :: ct(:), st(:), cw(:), sw(:)
      integer, intent(in) :: k0, k1
      real(rp), intent(in) :: s, nu
      integer :: k
      real(rp) :: c, sn, u, v, a, z1, z2, lo, hi
      d = 0.0_rp
      a = 0.5_rp*r%dn
      do k = k0, k1
         c = ct(k)
         sn = st(k)
         ! the point in the frame of the unit turned about its normal (its tilt undone)
         u = c*(s - r%sc(k)) + sn*(nu - 0.5_rp*r%rise(k))
         v = -sn*(s - r%sc(k)) + c*(nu - 0.5_rp*r%rise(k))
         if (abs(v) > a) cycle
         if (abs(sw(k)) <= 0.0_rp) then
            if (abs(u) <= a) then
               d = 1.0_rp
               return
            end if
            cycle
         end if
         ! the line (u, z) in the unit's frame: |cw u - sw z| <= a and |sw u + cw z| <= a (|turn| <= pi/4: cw > 0)
         z1 = (cw(k)*u - a)/sw(k)
         z2 = (cw(k)*u + a)/sw(k)
         lo = max(min(z1, z2), (-a - sw(k)*u)/cw(k))
         hi = min(max(z1, z2), (a - sw(k)*u)/cw(k))
         if (hi > lo) then
            d = (hi - lo)/r%dn
            return
         end if
      end do
   end function unit_depth

   !> A unit centred s along the slope from the toe p0, turned by psi about
   !> the slope's normal (3D), then tilted by phi from the slope, its lowest
   !> corner (or face) on the slope: its centre rise/2 above it.
   type(body_cfg) function unit_cfg(ar, p0, t, nrm, alpha, s, phi, rise, psi) result(b)
      type(armour_cfg), intent(in) :: ar
      real(rp), intent(in) :: p0(2), t(2), nrm(2), alpha, s, phi, rise, psi
      real(rp) :: c(2)
      c = p0 + s*t + 0.5_rp*rise*nrm
      b%shape = 'box'
      b%shape_id = shape_box
      b%width = ar%dn
      b%height = ar%dn
      b%x = c(1)
      b%y = c(2)
      b%angle = (alpha + phi)/deg
      ! R = Rz(alpha + phi) Ry(psi): turned about its own normal, then laid on the slope
      if (ndim == 3) b%angle_y = psi/deg
      b%density = ar%density
      b%mu = ar%mu
      b%motion = 'floating'
      b%motion_id = motion_floating
      b%generated = .true.
   end function unit_cfg

   !> The start of a stream of uniform: seed + offset, kept within the
   !> generator's range (a seed near huge(1) would overflow the sum).
   integer function stream(seed, offset) result(state)
      integer, intent(in) :: seed, offset
      integer, parameter :: i8 = selected_int_kind(18)
      state = int(mod(int(seed, i8) + int(offset, i8), 2147483646_i8))
   end function stream

   !> Uniform number in [0, 1) from a 31-bit Park-Miller generator: the same
   !> layer from the same seed on every machine and compiler.
   real(rp) function uniform(state) result(u)
      integer, intent(inout) :: state
      integer, parameter :: i8 = selected_int_kind(18)
      integer(i8) :: s
      s = mod(int(state, i8), 2147483646_i8) + 1_i8
      s = mod(16807_i8*s, 2147483647_i8)
      state = int(s - 1_i8)
      u = real(s - 1_i8, rp)/2147483646.0_rp
   end function uniform

   !> The paddle's law of motion from the &wavemaker group (nothing without one);
   !> report what it makes in lines.
   !> A signal that exceeds the stroke stops here, before any particle is made.
   subroutine scene_paddle(file, c, g, t_end, pad, lines)
      character(len=*), intent(in) :: file
      type(wavemaker_cfg), intent(in) :: c
      real(rp), intent(in) :: g, t_end
      type(paddle_t), intent(out) :: pad
      character(len=:), allocatable, intent(out) :: lines
      real(rp) :: k, kd, dur, dt, nwaves, xmax, hm0
      real(rp), allocatable :: ts(:), xs(:), eta(:)
      integer :: i
      lines = ''
      if (.not. c%on) return
      pad%on = .true.
      pad%flap = c%paddle_id == paddle_flap
      pad%wave = c%wave_id
      pad%t_start = c%t_start
      associate (wm => c, omega => pad%omega, amp1 => pad%amp1, amp2 => pad%amp2, t_ramp => pad%t_ramp, &
                 sig => pad%sig)
         select case (wm%wave_id)
         case (wave_regular)
            omega = 2.0_rp*pi/wm%period
            k = wave_number(omega, wm%depth, g)
            kd = k*wm%depth
            if (wm%paddle_id == paddle_piston) then
               amp1 = 0.5_rp*wm%height/piston_transfer(kd)
            else
               amp1 = 0.5_rp*wm%height/flap_transfer(kd)
            end if
            if (wm%second_order) amp2 = piston_second_order(wm%height, kd, wm%depth)
            t_ramp = wm%ramp_periods*wm%period
            pad%eta1 = 0.5_rp*wm%height
            pad%t_stop = wm%duration
            lines = '  wavemaker: '//trim(wm%paddle)//', regular H = '//real_str(wm%height)//' m, T = '// &
                    real_str(wm%period)//' s, depth '//real_str(wm%depth)//' m: L = '//real_str(2.0_rp*pi/k)// &
                    ' m, kd = '//real_str(kd)//', stroke '//real_str(2.0_rp*amp1)//' m'
            if (wm%second_order) lines = lines//' + second order '//real_str(amp2)//' m'
         case (wave_irregular)
            dur = wm%duration
            if (dur <= 0.0_rp) dur = max(t_end - wm%t_start, 20.0_rp*wm%tp)
            dt = min(wm%tp/200.0_rp, 0.01_rp)
            call jonswap_paddle_signal(wm%hs, wm%tp, wm%gamma, wm%depth, g, wm%paddle_id, wm%seed, dur, dt, ts, xs, eta, &
                                       nwaves, wm%f_lo, wm%f_hi)
            sig%t = ts
            sig%x = xs
            if (wm%absorb) then
               pad%sig_eta%t = ts
               pad%sig_eta%x = eta
            end if
            ! a wave with a set length ends at rest with its signal
            if (wm%duration > 0.0_rp) pad%t_stop = ts(size(ts))
            t_ramp = wm%ramp_periods*wm%tp
            hm0 = signal_hm0(eta, ts(2) - ts(1))
            lines = '  wavemaker: '//trim(wm%paddle)//', irregular JONSWAP Hs = '//real_str(wm%hs)//' m, Tp = '// &
                    real_str(wm%tp)//' s, gamma = '//real_str(wm%gamma)//', seed '//int_str(wm%seed)// &
                    ': signal of '//real_str(ts(size(ts)) - ts(1))//' s, about '//real_str(nwaves)// &
                    ' waves, Hm0 of the target elevation '//real_str(hm0)//' m'
         case (wave_file)
            call signal_read(trim(wm%signal_file), 'wavemaker', sig, file, 'signal_file')
            t_ramp = 0.0_rp
            lines = '  wavemaker: '//trim(wm%paddle)//', signal from '//trim(wm%signal_file)//' ('// &
                    int_str(size(sig%t))//' samples, '//real_str(sig%t(1))//' to '//real_str(sig%t(size(sig%t)))//' s)'
         case default
            call fatal('scene_paddle: unknown wave '//int_str(wm%wave_id))
         end select
         if (wm%ramp_time > 0.0_rp) t_ramp = wm%ramp_time
         if (wm%wave_id /= wave_regular) then
            xmax = 0.0_rp
            do i = 1, size(sig%x)
               xmax = max(xmax, abs(sig%x(i)))
            end do
            if (2.0_rp*xmax > wm%max_stroke) then
               call fatal(trim(file)//': &wavemaker: the paddle signal moves +-'//real_str(xmax)// &
                          ' m, beyond max_stroke/2 = '//real_str(0.5_rp*wm%max_stroke)// &
                          ' m: lower hs (or the signal), or raise max_stroke', 2)
            end if
         end if
         if (t_ramp > 0.0_rp) lines = lines//', ramp '//real_str(t_ramp)//' s'
         if (wm%t_start > 0.0_rp) lines = lines//', starting at t = '//real_str(wm%t_start)//' s'
         if (pad%t_stop > 0.0_rp) then
            if (t_ramp <= 0.0_rp) call input_error(file, 'wavemaker', 'duration', 'a wave with an end needs a '// &
               'ramp to end at rest: set ramp_periods or ramp_time above 0')
            if (pad%t_stop < 2.0_rp*t_ramp) call input_error(file, 'wavemaker', 'duration', 'the wave of '// &
               real_str(pad%t_stop)//' s is shorter than its two ramps ('//real_str(2.0_rp*t_ramp)// &
               ' s): lengthen duration or shorten the ramp')
            lines = lines//', ending (at rest) at t = '//real_str(wm%t_start + pad%t_stop)//' s'
         end if
      end associate
      if (c%absorb) call absorber(c, g, pad, lines)
   end subroutine scene_paddle

   !> The active absorber of the paddle: its frequency and time scale, and
   !> the Biesel gain G = omega / (H/S) that would absorb a wave of the (peak)
   !> period at the face (sqrt(g/d) for a piston in shallow water); the run's
   !> set-up tunes gain and delay to the gauge (paddle_absorb_tune).
   subroutine absorber(wm, g, pad, lines)
      type(wavemaker_cfg), intent(in) :: wm
      real(rp), intent(in) :: g
      type(paddle_t), intent(inout) :: pad
      character(len=:), allocatable, intent(inout) :: lines
      real(rp) :: period, omega, kd, tra
      period = wm%period
      if (wm%wave_id == wave_irregular) period = wm%tp
      omega = 2.0_rp*pi/period
      kd = wave_number(omega, wm%depth, g)*wm%depth
      if (wm%paddle_id == paddle_piston) then
         tra = piston_transfer(kd)
      else
         tra = flap_transfer(kd)
      end if
      pad%absorb = .true.
      pad%gain = omega/tra
      pad%depth = wm%depth
      pad%tau = wm%absorb_time
      if (pad%tau <= 0.0_rp) pad%tau = 5.0_rp*period
      pad%omega_abs = omega
      pad%x_face = wm%x0
      pad%x_max = 0.5_rp*wm%max_stroke
      lines = lines//new_line('a')//'  absorbing paddle: Biesel gain '//real_str(pad%gain)//' 1/s (sqrt(g/d) = '// &
              real_str(sqrt(g/wm%depth))//'), drift and mean-level time '//real_str(pad%tau)//' s'
   end subroutine absorber

   !> The parameters of the armour layer for the '#' line of OUT/armour.csv.
   function armour_csv_header(a, layer, rho_water) result(line)
      type(armour_cfg), intent(in) :: a
      type(armour_layer_t), intent(in) :: layer
      real(rp), intent(in) :: rho_water
      character(len=:), allocatable :: line
      character(len=512) :: buf
      write (buf, '("dn=",f0.6,",density=",f0.6,",rho_water=",f0.6,",placement=",a,",porosity_target=",f0.6, &
            &",porosity=",f0.6,",threshold=",f0.6,",slope_angle_deg=",f0.6,",seed=",i0)') a%dn, &
         a%density, rho_water, trim(a%placement), a%porosity, layer%porosity, a%threshold, layer%alpha*180.0_rp/pi, &
         a%seed
      line = trim(buf)
      ! 3D: the width of the strip, for Nod per dn of width
      if (ndim == 3) line = line//',width='//trim(real_str(layer%width))
      ! 3D, irregular: the bound of the turns drawn about the slope's normal, max_turn or what a slot leaves
      if (ndim == 3) line = line//',turn_max_deg='//trim(real_str(layer%turn_max))
   end function armour_csv_header
end module scene_flume

!> Reads and validates a whole case file; writes the effective namelist.
!> Every check happens here, before any particle is made.
module input
   use kinds, only: rp
   use constants, only: path_len, msg_len, ndim
   use input_check, only: scan_groups, real_str, int_str, group_count
   use input_run, only: run_cfg, read_run, write_run
   use input_domain, only: domain_cfg, read_domain, write_domain
   use input_fluid, only: fluid_cfg, read_fluid, write_fluid
   use input_numerics, only: numerics_cfg, read_numerics, write_numerics
   use input_geometry, only: geom_object, read_geometry, write_geometry, geom_zrange, geom_join_slopes
   use input_body, only: body_cfg, body_zrange, contact_cfg, read_bodies, write_bodies, read_contact, write_contact
   use input_wave, only: wavemaker_cfg, gauge_cfg, damping_cfg, read_wavemaker, write_wavemaker, read_gauges, &
                         write_gauges, read_damping, write_damping, z_left_out
   use input_porous, only: porous_cfg, read_porous, write_porous
   use input_mesh, only: mesh_cfg, read_meshes, write_meshes
   use input_breakwater, only: breakwater_cfg, armour_cfg, read_breakwater, write_breakwater, read_armour, &
                               write_armour
   use porous, only: max_regions
   use scene_flume, only: armour_layer_t, paddle_object, breakwater_objects, breakwater_porous, armour_units
   use wave_theory, only: wave_number, piston_transfer, flap_transfer, miche_limit, piston_second_order
   use constants, only: pi
   use body_shapes, only: body_outline
   use geom, only: polygons_overlap
   use errors, only: input_error, fatal, alloc_check
   use options, only: role_fluid, role_filter, model_dynamic, wall_wavemaker, wave_regular, wave_file, paddle_piston, &
                      gauge_pressure, &
                      integ_verlet, kgc_shepard, kgc_gradient, bnd_repulsive, bnd_mdbc, visc_laminar_sps, shift_none, &
                      bnd_dynamic, core_porous, shape_stl
   implicit none
   private
   public :: case_cfg, read_case, write_case

   type :: case_cfg
      character(len=path_len) :: file = ''
      type(run_cfg) :: run
      type(domain_cfg) :: domain
      type(fluid_cfg) :: fluid
      type(numerics_cfg) :: numerics
      type(geom_object), allocatable :: objs(:)
      type(mesh_cfg), allocatable :: meshes(:)     !< &stl: 3D fixed solids from triangle meshes
      type(body_cfg), allocatable :: bodies(:)
      type(contact_cfg) :: contact
      type(wavemaker_cfg) :: wavemaker
      type(gauge_cfg), allocatable :: gauges(:)
      type(damping_cfg) :: damping
      type(porous_cfg), allocatable :: porous(:)
      type(breakwater_cfg) :: breakwater
      type(armour_cfg) :: armour
      type(armour_layer_t) :: layer           !< the armour layer as generated
      !> the &numerics variables that took the wave defaults (a case with a
      !> wavemaker that leaves them out), 'name = value, ...'; '' for none
      character(len=:), allocatable :: wave_defaults
   end type case_cfg

contains

   subroutine read_case(file, c)
      character(len=*), intent(in) :: file
      type(case_cfg), intent(out) :: c
      integer :: i, k
      real(rp) :: tol
      character(len=:), allocatable :: gi, gk
      c%file = file
      call scan_groups(file)
      call read_run(file, c%run)
      call read_domain(file, c%domain)
      call read_fluid(file, c%fluid)
      ! a wave flume (a wavemaker, neither bodies nor pores) takes the wave
      ! defaults for what its &numerics leaves out (input_numerics)
      call read_contact(file, c%contact)
      call read_breakwater(file, c%breakwater)
      call read_wavemaker(file, c%wavemaker, c%breakwater)
      call read_case_numerics(file, c)
      call read_geometry(file, c%numerics%dp, c%numerics%h_over_dp*c%numerics%dp, c%objs)
      call read_meshes(file, c%numerics%dp, c%meshes)
      call read_bodies(file, c%numerics%dp, c%bodies)
      call read_armour(file, c%numerics%dp, c%armour)
      call read_gauges(file, c%gauges)
      ! 3D: a gauge without z at mid-width
      if (ndim == 3) where (z_left_out(c%gauges%z)) c%gauges%z = 0.5_rp*(c%domain%zmin + c%domain%zmax)
      call read_damping(file, c%damping)
      call read_porous(file, c%numerics%h_over_dp*c%numerics%dp, c%porous)
      if (ndim == 3) call refuse_in_3d(c)
      call expand_flume(c)

      tol = 1.0e-9_rp*max(abs(c%domain%xmax - c%domain%xmin), abs(c%domain%ymax - c%domain%ymin))
      do i = 1, size(c%objs)
         if (c%objs(i)%generated) cycle     ! their generators check them (scene_flume, check_waves)
         gi = obj_name(c%objs(i))
         associate (v => c%objs(i)%v)
            if (minval(v(1, :)) < c%domain%xmin - tol .or. maxval(v(1, :)) > c%domain%xmax + tol .or. &
                minval(v(2, :)) < c%domain%ymin - tol .or. maxval(v(2, :)) > c%domain%ymax + tol) then
               call input_error(file, gi, '', 'the '//trim(c%objs(i)%role)//' object reaches outside the &domain ['// &
                                real_str(c%domain%xmin)//', '//real_str(c%domain%xmax)//'] x ['// &
                                real_str(c%domain%ymin)//', '//real_str(c%domain%ymax)//']')
            end if
            call check_width_in_domain(c, c%objs(i), gi, tol)
         end associate
      end do
      do i = 1, size(c%objs)
         if (c%objs(i)%role_id /= role_fluid) cycle
         others: do k = 1, size(c%objs)
            if (k == i) cycle others
            if (c%objs(k)%role_id == role_fluid .and. k < i) cycle others
            if (c%objs(k)%role_id == role_filter) cycle others   ! the water flows through a filter
            if (.not. widths_overlap(c, c%objs(i), c%objs(k))) cycle others
            if (polygons_overlap(c%objs(i)%v, c%objs(k)%v, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
               gi = obj_name(c%objs(i))
               gk = obj_name(c%objs(k))
               call input_error(file, gi, '', 'the fluid overlaps '//trim(c%objs(k)%role)//' object &'//gk// &
                                ' (fluid and walls must not share area)')
            end if
         end do others
      end do
      call check_meshes(c, tol)
      call check_bodies(c, tol)
      call check_waves(c)
      call check_porous(c, tol)
      call check_filters(c)
      call check_mdbc(c)
      call check_periodic(c)
   end subroutine read_case

   !> &numerics, with the wave defaults where the case is a wave flume. An
   !> absorbing paddle keeps the dynamic boundary: under mDBC it returns ten
   !> times more of the wave (doc/input.md, "Wave defaults").
   subroutine read_case_numerics(file, c)
      character(len=*), intent(in) :: file
      type(case_cfg), intent(inout) :: c
      call read_numerics(file, c%numerics, wave_flume(file, c), &
                         c%contact%model_id == model_dynamic .or. c%wavemaker%absorb, c%wave_defaults)
   end subroutine read_case_numerics

   !> Whether the case is a wave flume, which takes the wave defaults for the
   !> numerics it leaves out: a wavemaker, neither bodies nor pores (the
   !> contact is validated with the general defaults, the pores need h = 2 dp
   !> without the gradient correction), in 2D (in 3D the periodic strip's wave
   !> came out 10 % below the 2D flume's with them). c holds the groups read so far.
   logical function wave_flume(file, c) result(flume)
      character(len=*), intent(in) :: file
      type(case_cfg), intent(in) :: c
      flume = c%wavemaker%on .and. ndim == 2
      if (group_count(file, 'body') + group_count(file, 'armour') + group_count(file, 'porous') > 0) flume = .false.
      if (c%breakwater%on .and. c%breakwater%core_id == core_porous) flume = .false.
   end function wave_flume

   !> Periodic sides: the lattices across the width continue over the side
   !> (the width a whole number of spacings), one cell column at least 2h
   !> wide fits, and every body is narrower than the width.
   subroutine check_periodic(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: w, n, h, d
      integer :: k
      if (.not. c%domain%periodic_z) return
      w = c%domain%zmax - c%domain%zmin
      n = w/c%numerics%dp
      if (abs(n - nint(n)) > 1.0e-6_rp*n) call input_error(c%file, 'domain', 'zmax', &
         'with periodic_z the width zmax - zmin must be a whole number of spacings dp = '//real_str(c%numerics%dp)// &
         ' m (got '//real_str(w)//' m, '//real_str(n)//' spacings)')
      h = c%numerics%h_over_dp*c%numerics%dp
      if (w < 2.0_rp*h*(1.0_rp - 1.0e-9_rp)) call input_error(c%file, 'domain', 'zmax', &
         'with periodic_z the width zmax - zmin must be at least the kernel support 2h = '//real_str(2.0_rp*h)// &
         ' m (got '//real_str(w)//' m)')
      do k = 1, size(c%bodies)
         ! a body's arms are those of the images of its particles nearest its centre: turned
         ! any way, it must stay narrower than the width
         associate (b => c%bodies(k))
            d = sqrt(b%width**2 + b%height**2 + b%depth**2) + c%numerics%dp
            ! a mesh: twice its farthest vertex from the centroid
            if (b%shape_id == shape_stl) d = 2.0_rp*maxval(norm2(b%mesh%v, dim=1)) + c%numerics%dp
            if (d >= w) call input_error(c%file, 'body #'//int_str(k), 'width, height, depth', &
               'with periodic_z a body must be narrower than the width turned any way: its diagonal plus dp, '// &
               real_str(d)//' m, must be less than zmax - zmin = '//real_str(w)//' m')
         end associate
      end do
   end subroutine check_periodic

   !> The modified dynamic boundary sets the solids' density from the water
   !> beyond them: what acts through the solids' own continuity equation (the
   !> contact model 'dynamic') and the pores' terms are not written for it.
   subroutine check_mdbc(c)
      type(case_cfg), intent(in) :: c
      if (c%numerics%boundary_id /= bnd_mdbc) return
      if (size(c%bodies) > 0 .and. c%contact%model_id == model_dynamic) call input_error(c%file, 'contact', 'model', &
         "'dynamic' acts through the solids' own density, which boundary = 'mdbc' takes from the water: use "// &
         "'noncohesive_spring', 'noncohesive', 'repulsive' or 'hertz'")
   end subroutine check_mdbc

   !> A filter is massless to the water: it stops bodies through their
   !> contact, so a model that acts through the water's terms cannot use it.
   subroutine check_filters(c)
      type(case_cfg), intent(in) :: c
      integer :: k
      do k = 1, size(c%objs)
         if (c%objs(k)%role_id /= role_filter) cycle
         if (c%numerics%boundary_id == bnd_repulsive) call input_error(c%file, 'numerics', 'boundary', &
            "'repulsive' cannot have a filter (&"//obj_name(c%objs(k))//" role = 'filter'): use 'dynamic'")
         if (c%contact%model_id == model_dynamic) call input_error(c%file, 'contact', 'model', &
            "'dynamic' cannot stop bodies on a filter (&"//obj_name(c%objs(k))// &
            " role = 'filter'), which carries no water: use 'noncohesive_spring', 'noncohesive', 'repulsive' or 'hertz'")
         return
      end do
   end subroutine check_filters

   !> Porous regions inside the domain, not overlapping each other (sharing
   !> an edge is allowed: a core under its filter layer), and an integrator
   !> that damps: the leapfrog's spurious mode grows under the resistance.
   subroutine check_porous(c, tol)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: tol
      integer :: i, k
      character(len=:), allocatable :: gi
      do i = 1, size(c%porous)
         gi = 'porous #'//int_str(i)
         if (c%porous(i)%generated) gi = 'breakwater'   ! its core or underlayer
         associate (v => c%porous(i)%v)
            if (minval(v(1, :)) < c%domain%xmin - tol .or. maxval(v(1, :)) > c%domain%xmax + tol .or. &
                minval(v(2, :)) < c%domain%ymin - tol .or. maxval(v(2, :)) > c%domain%ymax + tol) then
               call input_error(c%file, gi, merge('xmin, xmax, ymin, ymax', 'x, y                  ', &
                                c%porous(i)%is_box), 'the region reaches outside the &domain ['// &
                                real_str(c%domain%xmin)//', '//real_str(c%domain%xmax)//'] x ['// &
                                real_str(c%domain%ymin)//', '//real_str(c%domain%ymax)//']')
            end if
         end associate
         do k = 1, i - 1
            if (polygons_overlap(c%porous(i)%v, c%porous(k)%v, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
               call input_error(c%file, gi, '', 'the region overlaps &porous #'//int_str(k)// &
                                ' (regions may share an edge, not area)')
            end if
         end do
      end do
      if (size(c%porous) == 0) return
      if (size(c%porous) > max_regions) call input_error(c%file, 'porous', '', 'at most '//int_str(max_regions)// &
         ' porous regions (&porous groups and a porous &breakwater core), got '//int_str(size(c%porous)))
      if (c%numerics%integrator_id == integ_verlet) then
         call input_error(c%file, 'numerics', 'integrator', "the porous regions' resistance needs a two-stage "// &
                          "integrator: 'symplectic' or 'predictor_corrector' (Verlet's leapfrog mode grows under it)")
      end if
      ! not yet for the pores (doc/porous.md): the Shepard filter averages
      ! superficial densities of unlike porosity; with the gradient correction
      ! the water at the edge of a region goes unstable; the SPS stress and the
      ! repulsive force are written for open water only
      if (c%numerics%kgc_id == kgc_shepard .or. c%numerics%kgc_id == kgc_gradient) call input_error(c%file, &
         'numerics', 'kernel_correction', "'"//trim(c%numerics%kernel_correction)// &
         "' does not work with porous regions (&porous, &breakwater core = 'porous') yet: use 'none' "// &
         '(doc/porous.md)')
      if (c%numerics%viscosity_id == visc_laminar_sps) call input_error(c%file, 'numerics', 'viscosity', &
         "'laminar_sps' does not work with porous regions (&porous, &breakwater core = 'porous') yet: "// &
         "use 'artificial' (doc/porous.md)")
      if (c%numerics%boundary_id == bnd_repulsive) call input_error(c%file, 'numerics', 'boundary', &
         "'repulsive' does not work with porous regions (&porous, &breakwater core = 'porous') yet: use 'dynamic'")
      if (c%numerics%shift_id /= shift_none) call input_error(c%file, 'numerics', 'shifting', &
         "'"//trim(c%numerics%shifting)//"' does not work with porous regions (&porous, &breakwater core = "// &
         "'porous') yet: use 'none' (the pore water's lattice is looser by n^(-1/d))")
   end subroutine check_porous

   !> The breakwater, its armour and the paddle become objects and bodies
   !> like any other (after the user's own, so the user's solids come first).
   subroutine expand_flume(c)
      type(case_cfg), intent(inout) :: c
      type(geom_object), allocatable :: more(:)
      type(body_cfg), allocatable :: units(:)
      type(porous_cfg), allocatable :: stones(:)
      real(rp) :: h
      integer :: ist
      character(len=200) :: emsg
      h = c%numerics%h_over_dp*c%numerics%dp
      allocate (more(0), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'more in expand_flume')
      if (c%breakwater%on) then
         call breakwater_objects(c%file, c%breakwater, c%wavemaker%on, c%domain%xmin, c%domain%xmax, c%domain%ymin, &
                                 c%numerics%dp, h, more)
         call append_objects(c%objs, more)
         call breakwater_porous(c%file, c%breakwater, merge(c%armour%dn, 0.0_rp, c%armour%on), c%numerics%dp, h, &
                                2.0_rp*h, stones)
         c%porous = [c%porous, stones]
      end if
      if (c%wavemaker%on) then
         if (allocated(more)) deallocate (more)
         allocate (more(1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'more in expand_flume')
         more(1) = paddle_object(c%wavemaker, c%numerics%dp, h)
         call append_objects(c%objs, more)
      end if
      if (c%armour%on) then
         call armour_units(c%file, c%breakwater, c%armour, [c%domain%zmin, c%domain%zmax], units, c%layer)
         c%layer%first = c%layer%first + size(c%bodies)
         c%bodies = [c%bodies, units]
      end if
      call geom_join_slopes(c%objs, c%numerics%dp)
   end subroutine expand_flume

   !> a = [a, b]; b is consumed.
   subroutine append_objects(a, b)
      type(geom_object), allocatable, intent(inout) :: a(:), b(:)
      type(geom_object), allocatable :: t(:)
      integer :: na
      integer :: ist
      character(len=200) :: emsg
      na = size(a)
      allocate (t(na + size(b)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 't in append_objects')
      t(1:na) = a
      t(na + 1:) = b
      call move_alloc(t, a)
      deallocate (b)
   end subroutine append_objects

   !> Every gauge inside the domain (y: pressure gauges; z: 3D).
   subroutine check_gauges(c)
      type(case_cfg), intent(in) :: c
      integer :: i
      character(len=:), allocatable :: gi
      associate (d => c%domain)
         do i = 1, size(c%gauges)
            gi = 'gauge #'//int_str(i)
            if (c%gauges(i)%x < d%xmin .or. c%gauges(i)%x > d%xmax) call input_error(c%file, gi, 'x', &
               'the gauge is outside the &domain: x must be in ['//real_str(d%xmin)//', '//real_str(d%xmax)//'] m')
            if (ndim == 3) then
               if (c%gauges(i)%z < d%zmin .or. c%gauges(i)%z > d%zmax) call input_error(c%file, gi, 'z', &
                  'the gauge is outside the &domain: z must be in ['//real_str(d%zmin)//', '//real_str(d%zmax)//'] m')
            end if
            if (c%gauges(i)%kind_id == gauge_pressure .and. (c%gauges(i)%y < d%ymin .or. c%gauges(i)%y > d%ymax)) then
               call input_error(c%file, gi, 'y', 'the gauge is outside the &domain: y must be in ['// &
                                real_str(d%ymin)//', '//real_str(d%ymax)//'] m')
            end if
         end do
      end associate
   end subroutine check_gauges

   !> Waves that the paddle can make and the flume can hold; gauges and the
   !> damping zone inside the domain.
   subroutine check_waves(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: k, kd, hmax, stroke, thick, per, hh
      integer :: ip
      character(len=*), parameter :: g = 'wavemaker'
      associate (wm => c%wavemaker, d => c%domain)
         ip = paddle_index(c%objs)
         if (wm%on) then
            if (ip == 0) call input_error(c%file, g, '', 'internal: the wavemaker paddle was not generated')
            thick = c%objs(ip)%box(2) - c%objs(ip)%box(1)
            if (wm%x0 - thick - 0.5_rp*wm%max_stroke < d%xmin) call input_error(c%file, g, 'x0', &
               'the paddle (thickness '//real_str(thick)//' m) moving +-'//real_str(0.5_rp*wm%max_stroke)// &
               ' m (max_stroke/2) leaves the &domain: x0 must be >= '//real_str(d%xmin + thick + 0.5_rp*wm%max_stroke))
            if (c%objs(ip)%box(4) > d%ymax) call input_error(c%file, g, 'top', 'the paddle reaches y = '// &
               real_str(c%objs(ip)%box(4))//' m, above the &domain ymax = '//real_str(d%ymax)// &
               ' m (top defaults to 1.5 depth above the bed)')
            if (wm%wave_id /= wave_file) then
               if (wm%wave_id == wave_regular) then
                  per = wm%period
                  hh = wm%height
               else
                  per = wm%tp
                  hh = wm%hs
               end if
               k = wave_number(2.0_rp*pi/per, wm%depth, c%fluid%gravity)
               kd = k*wm%depth
               hmax = miche_limit(k, wm%depth)
               if (hh > hmax) call input_error(c%file, g, merge('height', 'hs    ', wm%wave_id == wave_regular), &
                  'the wave breaks at the paddle: H/L = '//real_str(hh*k/(2.0_rp*pi))//' above the limit '// &
                  real_str(hmax*k/(2.0_rp*pi))//' (0.142 tanh kd, kd = '//real_str(kd)//'): H must be below '// &
                  real_str(hmax)//' m at this period and depth')
               if (wm%paddle_id == paddle_piston) then
                  stroke = hh/piston_transfer(kd)
               else
                  stroke = hh/flap_transfer(kd)
               end if
               if (wm%second_order) stroke = stroke + 2.0_rp*abs(piston_second_order(hh, kd, wm%depth))
               if (stroke > wm%max_stroke) call input_error(c%file, g, merge('height', 'hs    ', &
                  wm%wave_id == wave_regular), 'the paddle stroke '//real_str(stroke)//' m (peak to peak) exceeds '// &
                  'max_stroke = '//real_str(wm%max_stroke)//' m: lower the height or shorten the period')
            end if
         end if
         call check_gauges(c)
         if (c%damping%on) then
            if (min(c%damping%x0, c%damping%x1) < d%xmin .or. max(c%damping%x0, c%damping%x1) > d%xmax) then
               call input_error(c%file, 'damping', 'x0, x1', 'the zone must lie inside the &domain ['// &
                                real_str(d%xmin)//', '//real_str(d%xmax)//'] m')
            end if
         end if
      end associate
   end subroutine check_waves

   !> The paddle: the object that moves as the wavemaker, wherever the scene
   !> put it (0: none).
   pure integer function paddle_index(objs) result(ip)
      type(geom_object), intent(in) :: objs(:)
      integer :: k
      ip = 0
      do k = 1, size(objs)
         if (objs(k)%motion_id == wall_wavemaker) ip = k
      end do
   end function paddle_index

   !> Bodies inside the domain, not overlapping a wall or another body
   !> (touching is allowed; fluid is carved around them).
   subroutine check_bodies(c, tol)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: tol
      integer :: i, k
      real(rp), allocatable :: vi(:, :), vk(:, :)
      real(rp) :: zi(2)
      character(len=16) :: bi, bk
      integer :: ist
      character(len=200) :: emsg
      do i = 1, size(c%bodies)
         write (bi, '(i0)') i
         if (allocated(vi)) deallocate (vi)
         allocate (vi, source=body_outline(c%bodies(i)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'vi in check_bodies')
         if (minval(vi(1, :)) < c%domain%xmin - tol .or. maxval(vi(1, :)) > c%domain%xmax + tol .or. &
             minval(vi(2, :)) < c%domain%ymin - tol .or. maxval(vi(2, :)) > c%domain%ymax + tol) then
            call input_error(c%file, 'body #'//trim(bi), '', 'the body reaches outside the &domain')
         end if
         zi = body_width(c, c%bodies(i))
         if (zi(1) < c%domain%zmin - tol .or. zi(2) > c%domain%zmax + tol) then
            call input_error(c%file, 'body #'//trim(bi), 'z, depth', 'the body reaches outside the &domain across the width')
         end if
         walls: do k = 1, size(c%objs)
            if (c%objs(k)%role_id == role_fluid) cycle walls
            if (.not. spans_overlap(zi, object_span(c, c%objs(k)), 0.5_rp*c%numerics%dp)) cycle walls
            if (polygons_overlap(vi, c%objs(k)%v, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
               call input_error(c%file, 'body #'//trim(bi), '', 'the body overlaps the '//trim(c%objs(k)%role)//' &'// &
                                obj_name(c%objs(k))//' (bodies may touch walls, not cut into them)')
            end if
         end do walls
         earlier: do k = 1, i - 1
            write (bk, '(i0)') k
            if (allocated(vk)) deallocate (vk)
            allocate (vk, source=body_outline(c%bodies(k)), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 'vk in check_bodies')
            if (.not. spans_overlap(zi, body_width(c, c%bodies(k)), 0.5_rp*c%numerics%dp)) cycle earlier
            if (polygons_overlap(vi, vk, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
              call input_error(c%file, 'body #'//trim(bi), '', 'the body overlaps &body #'//trim(bk))
            end if
         end do earlier
      end do
   end subroutine check_bodies

   function obj_name(o) result(s)
      type(geom_object), intent(in) :: o
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i0)') o%index
      s = trim(o%group)//' #'//trim(b)
   end function obj_name

   !> The effective namelist: every group with every value, defaults filled in.
   subroutine write_case(path, c)
      character(len=*), intent(in) :: path
      type(case_cfg), intent(in) :: c
      integer :: u, ios
      character(len=msg_len) :: msg
      open (newunit=u, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//trim(path)//': '//trim(msg))
      write (u, '(a)') "! Effective input of MBSPH case '"//trim(c%run%case_name)//"' read from "//trim(c%file)
      call write_run(u, c%run)
      call write_domain(u, c%domain)
      call write_fluid(u, c%fluid)
      call write_numerics(u, c%numerics)
      call write_geometry(u, c%objs)
      call write_meshes(u, c%meshes)
      call write_bodies(u, c%bodies)
      call write_contact(u, c%contact)
      call write_breakwater(u, c%breakwater)
      call write_armour(u, c%armour)
      call write_wavemaker(u, c%wavemaker)
      call write_gauges(u, c%gauges)
      call write_damping(u, c%damping)
      call write_porous(u, c%porous)
      close (u)
   end subroutine write_case

   !> Every &stl mesh lies in the domain, and with mDBC is deep enough behind
   !> its faces (the rows for 2h - dp/2, as check_mdbc asks of the walls).
   subroutine check_meshes(c, tol)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: tol
      integer :: k
      real(rp) :: dlo(3), dhi(3)
      character(len=:), allocatable :: g
      dlo = [c%domain%xmin, c%domain%ymin, c%domain%zmin]
      dhi = [c%domain%xmax, c%domain%ymax, c%domain%zmax]
      do k = 1, size(c%meshes)
         g = 'stl #'//int_str(k)
         associate (m => c%meshes(k))
            if (any(m%lo < dlo - tol) .or. any(m%hi > dhi + tol)) call input_error(c%file, g, &
               'stl_file', 'the mesh reaches outside the &domain: it spans ['//real_str(m%lo(1))//', '// &
               real_str(m%hi(1))//'] x ['//real_str(m%lo(2))//', '//real_str(m%hi(2))//'] x ['// &
               real_str(m%lo(3))//', '//real_str(m%hi(3))//'] (move it with x, y, z or scale it with stl_scale)')
            if (c%numerics%boundary_id == bnd_mdbc .and. m%layers > 0 .and. &
                m%layers < ceiling(2.0_rp*c%numerics%h_over_dp - 0.5_rp - 1.0e-9_rp)) call input_error(c%file, g, &
               'layers', "'mdbc' needs a solid 2h - dp/2 deep behind its faces: at least "// &
               int_str(ceiling(2.0_rp*c%numerics%h_over_dp - 0.5_rp - 1.0e-9_rp))//' rows (got '// &
               int_str(m%layers)//'; 0 takes enough for 2h)')
         end associate
      end do
   end subroutine check_meshes

   !> An object's own extent across the width (3D) lies in the domain's.
   subroutine check_width_in_domain(c, o, gi, tol)
      type(case_cfg), intent(in) :: c
      type(geom_object), intent(in) :: o
      character(len=*), intent(in) :: gi
      real(rp), intent(in) :: tol
      if (ndim == 2 .or. .not. o%zr(2) > o%zr(1)) return
      if (o%zr(1) >= c%domain%zmin - tol .and. o%zr(2) <= c%domain%zmax + tol) return
      call input_error(c%file, gi, 'zmin, zmax', 'the '//trim(o%role)//' object reaches outside the &domain '// &
                       'across the width ['//real_str(c%domain%zmin)//', '//real_str(c%domain%zmax)//']')
   end subroutine check_width_in_domain

   !> Whether two objects share some of the width (3D; always in 2D): their
   !> extents across it overlap by more than half a spacing.
   pure logical function widths_overlap(c, a, b) result(yes)
      type(case_cfg), intent(in) :: c
      type(geom_object), intent(in) :: a, b
      yes = spans_overlap(object_span(c, a), object_span(c, b), 0.5_rp*c%numerics%dp)
   end function widths_overlap

   !> Whether two extents across the width overlap by more than gap (always in 2D).
   pure logical function spans_overlap(za, zb, gap) result(yes)
      real(rp), intent(in) :: za(2), zb(2), gap
      yes = ndim == 2
      if (ndim == 3) yes = min(za(2), zb(2)) - max(za(1), zb(1)) > gap
   end function spans_overlap

   !> An object's extent across the width: its own, or the domain's.
   pure function object_span(c, o) result(z)
      type(case_cfg), intent(in) :: c
      type(geom_object), intent(in) :: o
      real(rp) :: z(2)
      z = geom_zrange(o, [c%domain%zmin, c%domain%zmax])
   end function object_span

   !> A body's extent across the width (3D; the domain's in 2D).
   pure function body_width(c, b) result(z)
      type(case_cfg), intent(in) :: c
      type(body_cfg), intent(in) :: b
      real(rp) :: z(2)
      z = [c%domain%zmin, c%domain%zmax]
      if (ndim == 3) z = body_zrange(b)
   end function body_width

   !> What the 3D build does not model yet stops at input, by name (doc/3d.md):
   !> water, boxes, polygons and slopes between walls of particles are there.
   subroutine refuse_in_3d(c)
      type(case_cfg), intent(in) :: c
      ! the breakwater is a strip of an infinitely long one: no side walls are built
      if (c%breakwater%on .and. .not. c%domain%periodic_z) call input_error(c%file, 'breakwater', '', &
         'in the 3D build the breakwater is a strip with periodic sides: set &domain periodic_z = .true.')
      ! the repulsive force is spread over a wall's lattice along the axes an
      ! extruded wall has; a body's or a mesh's lattice turns with it, which the
      ! fluid's pair loop does not know yet
      if (c%numerics%boundary_id == bnd_repulsive .and. (size(c%bodies) > 0 .or. size(c%meshes) > 0 .or. &
                                                         c%armour%on)) call input_error(c%file, 'numerics', &
         'boundary', "'repulsive' in the 3D build is for walls drawn as &box, &polygon and &slope; bodies "// &
         "(&body, &armour) and &stl solids need 'dynamic' or 'mdbc' (doc/3d.md)")
   end subroutine refuse_in_3d
end module input

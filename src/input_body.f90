!> &body (repeatable): rigid bodies; &contact: the contact model between
!> bodies and between a body and a wall.
module input_body
   use kinds, only: rp
   use constants, only: name_len, msg_len, path_len, pi, ndim
   use geom_stl, only: stl_t, stl_read, stl_props, stl_bounds, stl_inside
   use input_check, only: case_path, open_case, read_failed, read_failed_open, check_real, check_int, group_count, &
                          int_str, real_str
   use errors, only: input_error, alloc_check
   use geom, only: polygon_area, polygon_self_intersects
   use options, only: contact_names, model_spring, model_noncohesive, model_hertz, model_dynamic, option_index, &
                      shape_names, shape_circle, &
                      shape_box, shape_wedge, shape_polygon, shape_stl, &
                      body_motion_names, motion_floating, motion_prescribed
   implicit none
   private
   public :: body_zrange, body_turn, body_tilted, body_cfg, contact_cfg, read_bodies, write_bodies, read_contact, write_contact

   integer, parameter :: body_max_vert = 100

   type :: body_cfg
      character(len=name_len) :: shape = 'box'        !< 'circle' | 'box' | 'wedge' | 'polygon'
      integer :: shape_id = shape_box                  !< shape as its value in options (shape_*)
      real(rp) :: x = 0.0_rp, y = 0.0_rp               !< centre (circle, box) [m]
      real(rp) :: radius = 0.0_rp                      !< circle radius [m]
      real(rp) :: width = 0.0_rp, height = 0.0_rp      !< box sides [m]
      real(rp) :: z = 0.0_rp                           !< 3D: centre across the width [m]
      real(rp) :: depth = 0.0_rp                       !< 3D: box side across the width [m]
      real(rp) :: angle = 0.0_rp                       !< initial rotation [deg], counter-clockwise
      !> 3D: initial turns about x and about y [deg], taken before angle (about z): R = Rz Ry Rx
      real(rp) :: angle_x = 0.0_rp, angle_y = 0.0_rp
      real(rp) :: omega_x = 0.0_rp, omega_y = 0.0_rp   !< 3D, floating: initial angular velocity about x and y [rad/s]
      !> 3D, shape = 'stl': the mesh's file (stl_file, relative to the case file's folder), its
      !> coordinates' unit in metres (stl_scale), and the mesh itself, read at input, in its own frame
      !> with its centroid at the origin (the centroid goes to (x, y, z))
      character(len=path_len) :: file = ''
      real(rp) :: scale = 1.0_rp
      type(stl_t) :: mesh
      integer :: nvert = 0                             !< polygon / wedge vertices
      real(rp) :: vx(body_max_vert) = 0.0_rp, vy(body_max_vert) = 0.0_rp
      real(rp) :: density = 0.0_rp                     !< [kg/m3]; or
      real(rp) :: mass = 0.0_rp                        !< [kg/m] in 2D (per metre of width), [kg] in 3D
      character(len=name_len) :: motion = 'floating'   !< 'floating' | 'fixed' | 'prescribed'
      integer :: motion_id = motion_floating           !< motion as its value in options (motion_*)
      real(rp) :: u = 0.0_rp, v = 0.0_rp               !< initial (or prescribed) velocity [m/s]
      real(rp) :: w = 0.0_rp                           !< initial velocity across the width (3D, floating) [m/s]
      real(rp) :: omega = 0.0_rp                       !< initial (or prescribed) angular velocity [rad/s]
      real(rp) :: amplitude_x = 0.0_rp, amplitude_y = 0.0_rp  !< prescribed oscillation of the centre [m]
      real(rp) :: amplitude_angle = 0.0_rp             !< prescribed oscillation of the angle [rad]
      real(rp) :: period = 0.0_rp                      !< period of the oscillation [s]
      real(rp) :: phase = 0.0_rp                       !< phase of the oscillation at t = 0 [rad]
      real(rp) :: mu = 0.0_rp                          !< Coulomb friction coefficient [-]
      real(rp) :: restitution = 0.5_rp                 !< restitution coefficient (hertz) [-]
      real(rp) :: young = 2.0e10_rp                    !< Young's modulus (hertz) [Pa]
      real(rp) :: poisson = 0.2_rp                     !< Poisson ratio (hertz) [-]
      integer :: layers = 0                            !< particle layers inward (0: enough for 2h)
      logical :: generated = .false.                   !< an armour unit made by &armour, not written back
   end type body_cfg

   type :: contact_cfg
      character(len=name_len) :: model = 'noncohesive_spring'  !< 'dynamic' | 'repulsive' | 'noncohesive' |
                                                               !< 'noncohesive_spring' | 'hertz'
      integer :: model_id = model_spring     !< model as its value in options (model_*)
      real(rp) :: r_f = 0.5_rp               !< damping coefficient r_f of Eq. 4-6 [-] (doc/contact.md)
      real(rp) :: b = 0.0_rp                 !< sound coefficient B of Eq. 4-6 (0: &fluid coef) [-]
      real(rp) :: c0 = 0.0_rp                !< reference speed of Eq. 4-6 (0: from the static load, doc/contact.md) [m/s]
      real(rp) :: q0 = 0.001_rp              !< regularisation of 1/sqrt(q): bounds R at q = 0 [-]
      real(rp) :: stick_velocity = 1.0e-3_rp  !< slip speed below which friction is proportional [m/s]
      real(rp) :: stick_length = 0.01_rp     !< slip at which the friction spring gives mu f_n, in dp [-]; 0: off
      real(rp) :: impact = 20.0_rp           !< K of the approach term K u_L^2 / h of eps (Eq. 2) [-]; 0: off
      real(rp) :: barrier = 2.0_rp           !< barrier of R: q_b in units of dp/(8h) (2: touching) [-]; 0: off
      real(rp) :: core = -huge(1.0_rp)       !< overlap of the stiff core under a body's weight on one pair, in dp [-];
                                             !< 0: off; left out: 0.01 for the non-cohesive models, 0 for 'repulsive'
   end type contact_cfg

   type(body_cfg) :: dflt
   character(len=name_len) :: shape, motion, model
   real(rp) :: x, y, radius, width, height, angle, density, mass, u, v, omega, mu, restitution, young, poisson
   real(rp) :: z, depth, w, angle_x, angle_y, omega_x, omega_y, stl_scale
   character(len=path_len) :: stl_file
   real(rp) :: amplitude_x, amplitude_y, amplitude_angle, period, phase
   real(rp) :: vx(body_max_vert), vy(body_max_vert)
   integer :: nvert, layers
   namelist /body/ shape, x, y, radius, width, height, angle, nvert, vx, vy, density, mass, motion, u, v, &
      omega, amplitude_x, amplitude_y, amplitude_angle, period, phase, mu, restitution, young, poisson, layers, z, depth, w, &
      angle_x, angle_y, omega_x, omega_y, stl_file, stl_scale
   real(rp) :: r_f, b, c0, q0, stick_velocity, stick_length, impact, barrier, core_overlap
   namelist /contact/ model, r_f, b, c0, q0, stick_velocity, stick_length, impact, barrier, core_overlap

contains

   subroutine to_vars(c)
      type(body_cfg), intent(in) :: c
      shape = c%shape; x = c%x; y = c%y; radius = c%radius; width = c%width; height = c%height
      angle = c%angle; nvert = c%nvert; vx = c%vx; vy = c%vy; density = c%density; mass = c%mass
      motion = c%motion; u = c%u; v = c%v; omega = c%omega; mu = c%mu; restitution = c%restitution
      young = c%young; poisson = c%poisson; layers = c%layers
      amplitude_x = c%amplitude_x; amplitude_y = c%amplitude_y; amplitude_angle = c%amplitude_angle
      period = c%period; phase = c%phase; z = c%z; depth = c%depth; w = c%w
      angle_x = c%angle_x; angle_y = c%angle_y; omega_x = c%omega_x; omega_y = c%omega_y
      stl_file = c%file; stl_scale = c%scale
   end subroutine to_vars

   subroutine from_vars(c)
      type(body_cfg), intent(out) :: c
      c%shape = shape; c%x = x; c%y = y; c%radius = radius; c%width = width; c%height = height
      c%angle = angle; c%nvert = nvert; c%vx = vx; c%vy = vy; c%density = density; c%mass = mass
      c%motion = motion; c%u = u; c%v = v; c%omega = omega; c%mu = mu; c%restitution = restitution
      c%young = young; c%poisson = poisson; c%layers = layers
      c%amplitude_x = amplitude_x; c%amplitude_y = amplitude_y; c%amplitude_angle = amplitude_angle
      c%period = period; c%phase = phase; c%z = z; c%depth = depth; c%w = w
      c%angle_x = angle_x; c%angle_y = angle_y; c%omega_x = omega_x; c%omega_y = omega_y
      c%file = stl_file; c%scale = stl_scale
   end subroutine from_vars

   subroutine read_bodies(file, dp, bodies)
      character(len=*), intent(in) :: file
      real(rp), intent(in) :: dp
      type(body_cfg), allocatable, intent(out) :: bodies(:)
      integer :: nb, k, u_, ios
      character(len=msg_len) :: msg
      character(len=:), allocatable :: g
      integer :: ist
      character(len=200) :: emsg
      nb = group_count(file, 'body')
      allocate (bodies(nb), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'bodies in read_bodies')
      if (nb == 0) return
      u_ = open_case(file)
      do k = 1, nb
         call to_vars(dflt)
         read (u_, nml=body, iostat=ios, iomsg=msg)
         if (read_failed_open(u_, file, 'body', ios, msg)) return
         call from_vars(bodies(k))
         g = 'body #'//int_str(k)
         associate (c => bodies(k))
            c%shape_id = option_index(file, g, 'shape', c%shape, shape_names)
            c%shape = shape_names(c%shape_id)
            c%motion_id = option_index(file, g, 'motion', c%motion, body_motion_names)
            c%motion = body_motion_names(c%motion_id)
            select case (c%shape_id)
            case (shape_circle)
               call check_real(file, g, 'radius', c%radius, 2.0_rp*dp, 1.0e4_rp)
            case (shape_box)
               call check_real(file, g, 'width', c%width, 2.0_rp*dp, 1.0e4_rp)
               call check_real(file, g, 'height', c%height, 2.0_rp*dp, 1.0e4_rp)
            case (shape_wedge, shape_polygon)
               if (c%shape_id == shape_wedge) then
                  call check_int(file, g, 'nvert', c%nvert, 3, 3)
               else
                  call check_int(file, g, 'nvert', c%nvert, 3, body_max_vert)
               end if
               block
                  real(rp) :: vv(2, c%nvert)
                  vv(1, :) = c%vx(1:c%nvert)
                  vv(2, :) = c%vy(1:c%nvert)
                  if (abs(polygon_area(vv)) < 4.0_rp*dp*dp) call input_error(file, g, 'vx, vy', &
                     'the outline has (almost) no area: at least 4 dp^2 is needed')
                  if (polygon_self_intersects(vv)) call input_error(file, g, 'vx, vy', 'the outline crosses itself')
               end block
            case (shape_stl)
               call read_mesh(file, g, dp, c)
            case default
               call input_error(file, g, 'shape', 'no checks for shape '//trim(c%shape))
            end select
            if (c%shape_id /= shape_stl .and. len_trim(c%file) > 0) call input_error(file, g, 'stl_file', &
               "a mesh's file is for shape = 'stl' (this body is '"//trim(c%shape)//"')")
            call check_real(file, g, 'angle', c%angle, -360.0_rp, 360.0_rp)
            if (c%motion_id == motion_floating .or. c%mass > 0.0_rp .or. c%density > 0.0_rp) then
               if (c%mass > 0.0_rp) then
                  call check_real(file, g, 'mass', c%mass, 0.0_rp, 1.0e9_rp, lo_open=.true.)
               else
                  call check_real(file, g, 'density', c%density, 1.0_rp, 1.0e5_rp)
               end if
            end if
            call check_real(file, g, 'mu', c%mu, 0.0_rp, 10.0_rp)
            call check_real(file, g, 'restitution', c%restitution, 0.01_rp, 1.0_rp)
            call check_real(file, g, 'young', c%young, 1.0e3_rp, 1.0e13_rp)
            call check_real(file, g, 'poisson', c%poisson, 0.0_rp, 0.5_rp, hi_open=.true.)
            call check_int(file, g, 'layers', c%layers, 0, 100)
            if (max(abs(c%u), abs(c%v), abs(c%w)) > 1.0e3_rp) call input_error(file, g, 'u, v, w', &
               'speeds above 1000 m/s ('//real_str(max(abs(c%u), abs(c%v), abs(c%w)))//') are not meant')
            if (abs(c%omega) > 1.0e3_rp*pi) call input_error(file, g, 'omega', 'above 1000 pi rad/s')
            call check_oscillation(file, g, c)
            call check_width(file, g, c, dp)
         end associate
      end do
      close (u_)
   end subroutine read_bodies

   !> A body's extent across the width in 3D: its depth about z.
   pure function body_zrange(b) result(z)
      type(body_cfg), intent(in) :: b
      real(rp) :: z(2), r(3, 3), e
      integer :: t, k
      if (b%shape_id == shape_stl) then
         ! the turned mesh's extent across the width
         r = body_turn(b)
         z = [huge(1.0_rp), -huge(1.0_rp)]
         if (.not. allocated(b%mesh%v)) return
         do t = 1, b%mesh%nt
            do k = 1, 3
               e = dot_product(r(3, :), b%mesh%v(:, k, t))
               z = [min(z(1), e), max(z(2), e)]
            end do
         end do
         z = b%z + z
         return
      end if
      if (body_tilted(b)) then
         ! the turned box's extent across the width
         r = body_turn(b)
         e = 0.5_rp*(abs(r(3, 1))*b%width + abs(r(3, 2))*b%height + abs(r(3, 3))*b%depth)
         z = b%z + [-e, e]
         return
      end if
      z = b%z + 0.5_rp*[-b%depth, b%depth]
   end function body_zrange

   !> The mesh of an STL body (3D), read and checked, moved to its own frame:
   !> its centroid at the origin. It must hold at least the layers of particles
   !> of a small body: 2 dp across its bounding box each way.
   subroutine read_mesh(file, g, dp, c)
      character(len=*), intent(in) :: file, g
      real(rp), intent(in) :: dp
      type(body_cfg), intent(inout) :: c
      character(len=:), allocatable :: path
      real(rp) :: vol, cen(3), inertia(3, 3), lo(3), hi(3)
      integer :: t, k
      if (ndim == 2) call input_error(file, g, 'shape', 'an STL body is for the 3D build (build/mbsph3d)')
      if (len_trim(c%file) == 0) call input_error(file, g, 'stl_file', "shape = 'stl' needs the mesh's file")
      call check_real(file, g, 'stl_scale', c%scale, 1.0e-9_rp, 1.0e9_rp)
      ! a relative path from the case file's folder, kept absolute (OUT/case.nml names the same file)
      path = case_path(file, c%file)
      if (len(path) > len(c%file)) call input_error(file, g, 'stl_file', 'the path '//path//' is longer than '// &
                                                     int_str(len(c%file))//' characters')
      c%file = path
      call stl_read(path, c%scale, file, g, 'stl_file', c%mesh)
      call stl_props(c%mesh, vol, cen, inertia)
      do t = 1, c%mesh%nt
         do k = 1, 3
            c%mesh%v(:, k, t) = c%mesh%v(:, k, t) - cen
         end do
      end do
      call stl_bounds(c%mesh, lo, hi)
      if (minval(hi - lo) < 2.0_rp*dp) call input_error(file, g, 'stl_file', "the mesh of '"//trim(path)// &
         "' is "//real_str(minval(hi - lo))//' m across at its thinnest: at least 2 dp = '//real_str(2.0_rp*dp)// &
         ' m is needed (stl_scale: its unit in metres)')
      if (.not. lattice_meets_mesh(c%mesh, lo, hi, dp)) call input_error(file, g, 'stl_file', 'no particle of '// &
         "the lattice dp apart falls inside the mesh of '"//trim(path)//"': it is too thin for dp = "// &
         real_str(dp)//' m')
      if (max(c%width, c%height, c%depth) > 0.0_rp) call input_error(file, g, 'width, height, depth', &
         "an STL body's size is its mesh's (stl_scale scales it): leave them out")
   end subroutine read_mesh

   !> Whether a point of the body lattice (body_shapes: mesh_particles) lies inside the mesh.
   logical function lattice_meets_mesh(mesh, lo, hi, dp) result(meets)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(in) :: lo(3), hi(3), dp
      integer :: nn(3), i, j, k
      real(rp) :: sp(3)
      nn = max(1, nint((hi - lo)/dp))
      sp = (hi - lo)/nn
      meets = .true.
      do k = 1, nn(3)
         do j = 1, nn(2)
            do i = 1, nn(1)
               if (stl_inside(mesh, lo + ([i, j, k] - 0.5_rp)*sp)) return
            end do
         end do
      end do
      meets = .false.
   end function lattice_meets_mesh

   !> Whether a body is turned about x or y at the start (3D).
   pure logical function body_tilted(b)
      type(body_cfg), intent(in) :: b
      ! written so that a NaN counts as a turn (and is refused)
      body_tilted = .not. (abs(b%angle_x) <= 0.0_rp .and. abs(b%angle_y) <= 0.0_rp)
   end function body_tilted

   !> The start orientation of a body as a 3 x 3 rotation from its own frame:
   !> about x by angle_x, then about y by angle_y, then about z by angle
   !> (R = Rz Ry Rx; in 2D only angle counts).
   pure function body_turn(b) result(r)
      type(body_cfg), intent(in) :: b
      real(rp) :: r(3, 3), ax, ay, az
      ax = b%angle_x*pi/180.0_rp
      ay = b%angle_y*pi/180.0_rp
      az = b%angle*pi/180.0_rp
      r = matmul(reshape([cos(az), sin(az), 0.0_rp, -sin(az), cos(az), 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3]), &
                 matmul(reshape([cos(ay), 0.0_rp, -sin(ay), 0.0_rp, 1.0_rp, 0.0_rp, sin(ay), 0.0_rp, cos(ay)], [3, 3]), &
                        reshape([1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, cos(ax), sin(ax), 0.0_rp, -sin(ax), cos(ax)], [3, 3])))
   end function body_turn

   !> The body across the width: in 3D a box of side depth, centred at z; in 2D
   !> neither is given.
   subroutine check_width(file, g, c, dp)
      character(len=*), intent(in) :: file, g
      type(body_cfg), intent(in) :: c
      real(rp), intent(in) :: dp
      if (ndim == 2) then
         if (abs(c%z) > 0.0_rp .or. abs(c%depth) > 0.0_rp) call input_error(file, g, &
            trim(merge('z    ', 'depth', abs(c%z) > 0.0_rp)), 'a body across the width is for the 3D build (build/mbsph3d); '// &
            'leave it out in 2D')
         if (abs(c%w) > 0.0_rp) call input_error(file, g, 'w', 'a velocity across the width is for the 3D build '// &
                                                 '(build/mbsph3d); leave it out in 2D')
         call check_turns(file, g, c)
         return
      end if
      if (abs(c%w) > 0.0_rp .and. c%motion_id /= motion_floating) call input_error(file, g, 'w', &
         'a velocity across the width is for a floating body (a prescribed one moves in the section)')
      if (c%shape_id /= shape_box .and. c%shape_id /= shape_stl) call input_error(file, g, 'shape', &
         "the 3D build has box and STL bodies (doc/3d.md): 'box' or 'stl'; got '"//trim(c%shape)//"'")
      if (c%shape_id == shape_box) call check_real(file, g, 'depth', c%depth, 2.0_rp*dp, 1.0e4_rp)
      call check_turns(file, g, c)
   end subroutine check_width

   !> The turns and spins out of the section (angle_x, angle_y, omega_x,
   !> omega_y): refused in 2D; in 3D within range, a spin for a floating body.
   subroutine check_turns(file, g, c)
      character(len=*), intent(in) :: file, g
      type(body_cfg), intent(in) :: c
      logical :: spins
      ! written so that a NaN counts as given
      spins = .not. (abs(c%omega_x) <= 0.0_rp .and. abs(c%omega_y) <= 0.0_rp)
      if (ndim == 2) then
         if (body_tilted(c)) call input_error(file, g, trim(merge('angle_x', 'angle_y', .not. abs(c%angle_x) <= 0.0_rp)), &
            'a turn out of the section is for the 3D build (build/mbsph3d); leave it out in 2D')
         if (spins) call input_error(file, g, trim(merge('omega_x', 'omega_y', .not. abs(c%omega_x) <= 0.0_rp)), &
            'a spin out of the section is for the 3D build (build/mbsph3d); leave it out in 2D')
         return
      end if
      call check_real(file, g, 'angle_x', c%angle_x, -360.0_rp, 360.0_rp)
      call check_real(file, g, 'angle_y', c%angle_y, -360.0_rp, 360.0_rp)
      call check_real(file, g, 'omega_x', c%omega_x, -1.0e3_rp*pi, 1.0e3_rp*pi)
      call check_real(file, g, 'omega_y', c%omega_y, -1.0e3_rp*pi, 1.0e3_rp*pi)
      if (spins .and. c%motion_id /= motion_floating) then
         call input_error(file, g, trim(merge('omega_x', 'omega_y', .not. abs(c%omega_x) <= 0.0_rp)), &
                          "a spin out of the section is for a floating body (this one is '"//trim(c%motion)//"')")
      end if
   end subroutine check_turns

   !> The oscillation of a prescribed body: amplitudes, period and phase.
   subroutine check_oscillation(file, g, c)
      character(len=*), intent(in) :: file, g
      type(body_cfg), intent(in) :: c
      integer, parameter :: nvar = 5
      character(len=*), parameter :: names(nvar) = [character(len=15) :: 'amplitude_x', 'amplitude_y', &
                                                    'amplitude_angle', 'period', 'phase']
      real(rp) :: vals(nvar), speed
      integer :: k
      vals = [c%amplitude_x, c%amplitude_y, c%amplitude_angle, c%period, c%phase]
      if (c%motion_id /= motion_prescribed) then
         do k = 1, nvar
            ! written so that a NaN is refused too
            if (.not. abs(vals(k)) <= 0.0_rp) then
               call input_error(file, g, trim(names(k)), &
                                "only a body with motion = 'prescribed' oscillates; this one is '"//trim(c%motion)//"'")
            end if
         end do
         return
      end if
      call check_real(file, g, 'amplitude_x', c%amplitude_x, -1.0e4_rp, 1.0e4_rp)
      call check_real(file, g, 'amplitude_y', c%amplitude_y, -1.0e4_rp, 1.0e4_rp)
      call check_real(file, g, 'amplitude_angle', c%amplitude_angle, -2.0_rp*pi, 2.0_rp*pi)
      call check_real(file, g, 'phase', c%phase, -2.0_rp*pi, 2.0_rp*pi)
      if (maxval(abs(vals(1:3))) <= 0.0_rp) then
         call check_real(file, g, 'period', c%period, 0.0_rp, 1.0e4_rp)
         return
      end if
      if (c%period <= 0.0_rp) call input_error(file, g, 'period', 'a non-zero amplitude needs a period in (0, 1e4] s')
      call check_real(file, g, 'period', c%period, 0.0_rp, 1.0e4_rp, lo_open=.true.)
      ! the peak speeds 2 pi a / period, under the same bounds as u, v and omega
      speed = 2.0_rp*pi*max(abs(c%amplitude_x), abs(c%amplitude_y))/c%period
      if (speed > 1.0e3_rp) then
         call input_error(file, g, 'amplitude_x, amplitude_y, period', 'peak speed 2 pi amplitude / period '// &
                          real_str(speed)//' m/s is above 1000 m/s')
      end if
      if (2.0_rp*pi*abs(c%amplitude_angle)/c%period > 1.0e3_rp*pi) then
         call input_error(file, g, 'amplitude_angle, period', &
                          'peak angular speed 2 pi amplitude_angle / period is above 1000 pi rad/s')
      end if
   end subroutine check_oscillation

   subroutine write_bodies(u_, bodies)
      integer, intent(in) :: u_
      type(body_cfg), intent(in) :: bodies(:)
      integer :: k
      do k = 1, size(bodies)
         if (bodies(k)%generated) cycle
         call to_vars(bodies(k))
         write (u_, nml=body)
      end do
   end subroutine write_bodies

   subroutine read_contact(file, c)
      character(len=*), intent(in) :: file
      type(contact_cfg), intent(out) :: c
      integer :: u_, ios
      character(len=msg_len) :: msg
      type(contact_cfg) :: d
      if (group_count(file, 'contact') > 1) call input_error(file, 'contact', '', 'group appears more than once')
      model = d%model; r_f = d%r_f; b = d%b; c0 = d%c0; q0 = d%q0; stick_velocity = d%stick_velocity
      impact = d%impact; barrier = d%barrier; stick_length = d%stick_length; core_overlap = d%core
      if (group_count(file, 'contact') == 1) then
         u_ = open_case(file)
         read (u_, nml=contact, iostat=ios, iomsg=msg)
         close (u_)
         if (read_failed(file, 'contact', ios, msg)) return
      end if
      c%model = model; c%r_f = r_f; c%b = b; c%c0 = c0; c%q0 = q0; c%stick_velocity = stick_velocity
      c%impact = impact; c%barrier = barrier; c%stick_length = stick_length; c%core = core_overlap
      c%model_id = option_index(file, 'contact', 'model', c%model, contact_names)
      c%model = contact_names(c%model_id)
      ! the stiff core under the non-cohesive models by default; Eq. 4 keeps
      ! its soft, cohesive form, whose artefact that model is there to show;
      ! Hertz and the dynamic boundary have no use for it (left out: -huge)
      if (c%core < -1.0e30_rp) then
         c%core = merge(0.01_rp, 0.0_rp, c%model_id == model_noncohesive .or. c%model_id == model_spring)
      else if (abs(c%core) > 0.0_rp .and. (c%model_id == model_hertz .or. c%model_id == model_dynamic)) then
         call input_error(file, 'contact', 'core_overlap', "the stiff core belongs to the models of Eq. 2-6 ('repulsive', "// &
                          "'noncohesive', 'noncohesive_spring'); model '"//trim(c%model)//"' has no use for it: leave it out")
         return
      end if
      call check_real(file, 'contact', 'r_f', c%r_f, 0.0_rp, 1.0e3_rp)
      call check_real(file, 'contact', 'b', c%b, 0.0_rp, 100.0_rp)
      call check_real(file, 'contact', 'c0', c%c0, 0.0_rp, 1.0e4_rp)
      call check_real(file, 'contact', 'q0', c%q0, 1.0e-6_rp, 0.1_rp)
      call check_real(file, 'contact', 'stick_velocity', c%stick_velocity, 1.0e-7_rp, 1.0_rp)
      call check_real(file, 'contact', 'stick_length', c%stick_length, 0.0_rp, 1.0_rp)
      call check_real(file, 'contact', 'impact', c%impact, 0.0_rp, 1.0e4_rp)
      call check_real(file, 'contact', 'barrier', c%barrier, 0.0_rp, 2.0_rp)
      if (abs(c%core) > 0.0_rp) call check_real(file, 'contact', 'core_overlap', c%core, 1.0e-4_rp, 0.5_rp)
   end subroutine read_contact

   subroutine write_contact(u_, c)
      integer, intent(in) :: u_
      type(contact_cfg), intent(in) :: c
      model = c%model; r_f = c%r_f; b = c%b; c0 = c%c0; q0 = c%q0; stick_velocity = c%stick_velocity
      impact = c%impact; barrier = c%barrier; stick_length = c%stick_length; core_overlap = c%core
      write (u_, nml=contact)
   end subroutine write_contact
end module input_body

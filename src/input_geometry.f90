!> Geometry groups, each repeatable: &box, &polygon, &slope. Every object
!> becomes a polygon with a role (solid wall, fluid, or for a slope a
!> permeable filter) and a motion.
module input_geometry
   use kinds, only: rp
   use constants, only: name_len, msg_len, ndim
   use input_check, only: open_case, read_failed, read_failed_open, check_real, check_int, checked_outline, &
                          group_count, int_str, real_str
   use errors, only: input_error, alloc_check, fatal
   use options, only: option_index, role_names, role_solid, role_fluid, role_filter, wall_motion_names, wall_fixed, &
                      wall_oscillate
   implicit none
   private
   public :: geom_zrange, geom_object, read_geometry, write_geometry, geom_join_slopes, max_vert

   integer, parameter :: max_vert = 100

   type :: geom_object
      character(len=name_len) :: group = ''         !< 'box' | 'polygon' | 'slope'
      integer :: index = 0                          !< 1 for the first group of its name, ...
      character(len=name_len) :: role = 'solid'     !< 'solid' | 'fluid' (&box, &polygon) | 'filter' (&slope)
      character(len=name_len) :: motion = 'fixed'   !< 'fixed' | 'oscillate' | 'wavemaker'
      integer :: role_id = role_solid               !< role as its value in options (role_*)
      integer :: motion_id = wall_fixed             !< motion as its value in options (wall_*)
      logical :: generated = .false.                !< made by &wavemaker or &breakwater, not written back
      real(rp) :: amplitude(2) = 0.0_rp             !< oscillation amplitude [m]
      real(rp) :: period = 1.0_rp                   !< oscillation period [s]
      real(rp) :: hinge_depth = 0.0_rp              !< wavemaker: still-water depth above the flap hinge [m]
      integer :: nv = 0
      real(rp), allocatable :: v(:, :)              !< outline vertices (2, nv), counter-clockwise
      ! input values kept for the effective namelist
      real(rp) :: box(4) = 0.0_rp                   !< xmin, xmax, ymin, ymax
      real(rp) :: line(4) = 0.0_rp                  !< slope x0, y0, x1, y1
      integer :: layers = 0                         !< slope thickness in particle rows
      !> slope: half the angle it turns by from the solid slope it continues and into the one
      !> continuing it (> 0 toward the water; 0 for none): its rows end at those mitres [rad]
      real(rp) :: mitre(2) = 0.0_rp
      !> 3D: the extent across the width (zmin, zmax) [m]; zmax <= zmin (both left out): the domain's width
      real(rp) :: zr(2) = 0.0_rp
   end type geom_object

   ! &box
   character(len=name_len) :: role, motion
   real(rp) :: xmin, xmax, ymin, ymax, amplitude(2), period, zmin, zmax
   namelist /box/ role, xmin, xmax, ymin, ymax, motion, amplitude, period, zmin, zmax
   ! &polygon
   integer :: nvert
   real(rp) :: x(max_vert), y(max_vert)
   namelist /polygon/ role, nvert, x, y, motion, amplitude, period, zmin, zmax
   ! &slope
   real(rp) :: x0, y0, x1, y1
   integer :: layers
   namelist /slope/ role, x0, y0, x1, y1, layers, zmin, zmax

contains

   subroutine defaults()
      type(geom_object) :: d
      role = d%role; motion = d%motion; amplitude = d%amplitude; period = d%period
      xmin = 0.0_rp; xmax = 0.0_rp; ymin = 0.0_rp; ymax = 0.0_rp; zmin = d%zr(1); zmax = d%zr(2)
      nvert = 0; x = 0.0_rp; y = 0.0_rp
      x0 = 0.0_rp; y0 = 0.0_rp; x1 = 0.0_rp; y1 = 0.0_rp; layers = 0
   end subroutine defaults

   !> Read every geometry group. dp fixes the default slope thickness.
   subroutine read_geometry(file, dp, h, objs)
      character(len=*), intent(in) :: file
      real(rp), intent(in) :: dp, h
      type(geom_object), allocatable, intent(out) :: objs(:)
      integer :: nbox, npoly, nslope, u, ios, k, n
      character(len=msg_len) :: msg
      character(len=:), allocatable :: g
      integer :: ist
      character(len=200) :: emsg
      nbox = group_count(file, 'box')
      npoly = group_count(file, 'polygon')
      nslope = group_count(file, 'slope')
      allocate (objs(nbox + npoly + nslope), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'objs in read_geometry')
      n = 0
      u = open_case(file)
      do k = 1, nbox
         call defaults()
         read (u, nml=box, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'box', ios, msg)) return
         n = n + 1
         g = 'box #'//int_str(k)
         if (.not. (xmax > xmin)) call input_error(file, g, 'xmax', 'must be greater than xmin = '// &
                                                   real_str(xmin)//' (got '//real_str(xmax)//')')
         if (.not. (ymax > ymin)) call input_error(file, g, 'ymax', 'must be greater than ymin = '// &
                                                   real_str(ymin)//' (got '//real_str(ymax)//')')
         objs(n)%group = 'box'
         objs(n)%index = k
         objs(n)%box = [xmin, xmax, ymin, ymax]
         objs(n)%nv = 4
         objs(n)%v = reshape([xmin, ymin, xmax, ymin, xmax, ymax, xmin, ymax], [2, 4])
         call set_common(objs(n), g)
      end do
      rewind (u)
      do k = 1, npoly
         call defaults()
         read (u, nml=polygon, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'polygon', ios, msg)) return
         n = n + 1
         g = 'polygon #'//int_str(k)
         call check_int(file, g, 'nvert', nvert, 3, max_vert)
         objs(n)%group = 'polygon'
         objs(n)%index = k
         objs(n)%nv = nvert
         objs(n)%v = checked_outline(file, g, 'polygon', nvert, x, y)
         call set_common(objs(n), g)
      end do
      rewind (u)
      do k = 1, nslope
         call defaults()
         read (u, nml=slope, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'slope', ios, msg)) return
         n = n + 1
         g = 'slope #'//int_str(k)
         call check_int(file, g, 'layers', layers, 0, 100)
         call slope_role(file, g, objs(n))
         if (layers == 0) layers = max(1, ceiling(2.0_rp*h/dp - 1.0e-9_rp))
         if (.not. (x1 > x0)) call input_error(file, g, 'x1', 'must be greater than x0 = '//real_str(x0)// &
                                               ' (the solid lies below the line from (x0,y0) to (x1,y1))')
         if (hypot(x1 - x0, y1 - y0) < dp) call input_error(file, g, 'x1, y1', 'the slope is shorter than dp')
         objs(n)%group = 'slope'
         objs(n)%index = k
         objs(n)%line = [x0, y0, x1, y1]
         objs(n)%layers = layers
         call set_width(file, objs(n), g)
         objs(n)%nv = 4
         block
            real(rp) :: t(2), nrm(2), thick
            t = [x1 - x0, y1 - y0]/hypot(x1 - x0, y1 - y0)
            nrm = [-t(2), t(1)]                      ! points up since x1 > x0
            thick = layers*dp
            objs(n)%v = reshape([x0 - thick*nrm(1), y0 - thick*nrm(2), x1 - thick*nrm(1), y1 - thick*nrm(2), &
                                 x1, y1, x0, y0], [2, 4])
         end block
      end do
      close (u)
   contains
      subroutine set_common(o, gname)
         type(geom_object), intent(inout) :: o
         character(len=*), intent(in) :: gname
         o%role = role
         o%motion = motion
         o%amplitude = amplitude
         o%period = period
         o%role_id = option_index(file, gname, 'role', o%role, role_names(role_solid:role_fluid))
         o%role = role_names(o%role_id)
         ! 'wavemaker' is the flume builder's, not a case file's
         o%motion_id = option_index(file, gname, 'motion', o%motion, wall_motion_names(wall_fixed:wall_oscillate))
         o%motion = wall_motion_names(o%motion_id)
         if (o%motion_id == wall_oscillate) then
            if (o%role_id == role_fluid) call input_error(file, gname, 'motion', "only a solid can move (role = 'solid')")
            call check_real(file, gname, 'period', o%period, 0.0_rp, 1.0e6_rp, lo_open=.true.)
         end if
         call set_width(file, o, gname)
      end subroutine set_common
   end subroutine read_geometry

   !> An object's extent across the width (3D): its own, or the domain's zdom.
   pure function geom_zrange(o, zdom) result(z)
      type(geom_object), intent(in) :: o
      real(rp), intent(in) :: zdom(2)
      real(rp) :: z(2)
      z = zdom
      if (o%zr(2) > o%zr(1)) z = o%zr
   end function geom_zrange

   !> The extent across the width of the group just read (3D only): zmin and zmax
   !> both left out for the domain's width.
   subroutine set_width(file, o, gname)
      character(len=*), intent(in) :: file, gname
      type(geom_object), intent(inout) :: o
      if (abs(zmin) <= 0.0_rp .and. abs(zmax) <= 0.0_rp) return
      if (ndim == 2) call input_error(file, gname, merge('zmin', 'zmax', abs(zmin) > 0.0_rp), &
                                      'a width across the section is for the 3D build (build/mbsph3d); leave it out in 2D')
      if (.not. (zmax > zmin)) call input_error(file, gname, 'zmax', 'must be greater than zmin = '// &
                                                real_str(zmin)//' (got '//real_str(zmax)//')')
      o%zr = [zmin, zmax]
   end subroutine set_width

   !> The role of a &slope from the namelist's role and layers: a solid, or a
   !> filter of one row (what the bodies touch is the outer row; the water needs none).
   subroutine slope_role(file, g, o)
      character(len=*), intent(in) :: file, g
      type(geom_object), intent(inout) :: o
      o%role_id = role_filter
      if (option_index(file, g, 'role', role, [role_names(role_solid), role_names(role_filter)]) == 1) o%role_id = role_solid
      o%role = role_names(o%role_id)
      if (o%role_id /= role_filter) return
      if (layers > 1) call input_error(file, g, 'layers', "a filter (role = 'filter') is one row: [0, 1] (got "// &
                                       int_str(layers)//')')
      layers = 1
   end subroutine slope_role

   subroutine write_geometry(u, objs)
      integer, intent(in) :: u
      type(geom_object), intent(in) :: objs(:)
      integer :: k
      do k = 1, size(objs)
         if (objs(k)%generated) cycle
         call defaults()
         role = objs(k)%role; motion = objs(k)%motion
         amplitude = objs(k)%amplitude; period = objs(k)%period
         zmin = objs(k)%zr(1); zmax = objs(k)%zr(2)
         select case (objs(k)%group)
         case ('box')
            xmin = objs(k)%box(1); xmax = objs(k)%box(2); ymin = objs(k)%box(3); ymax = objs(k)%box(4)
            write (u, nml=box)
         case ('polygon')
            nvert = objs(k)%nv
            x(1:nvert) = objs(k)%v(1, :)
            y(1:nvert) = objs(k)%v(2, :)
            write (u, nml=polygon)
         case ('slope')
            x0 = objs(k)%line(1); y0 = objs(k)%line(2); x1 = objs(k)%line(3); y1 = objs(k)%line(4)
            layers = objs(k)%layers
            write (u, nml=slope)
         case default
            call fatal('write_geometry: an object of group '//trim(objs(k)%group)//' is not from the case file')
         end select
      end do
   end subroutine write_geometry

   !> Slopes that continue one another (the end of one the start of the next,
   !> both solid, as many rows, the same width and motion: the breakwater's
   !> bed, foreshore and core) meet at a mitre: each row runs to the bisector
   !> of the bend and each outline ends there, so that the solids tile the
   !> bend. Without it a bend toward the water leaves a wedge open below it
   !> (1.2 dp between the first rows at a 10 degree foreshore, which the water
   !> finds under mDBC). Bends sharper than a right angle, and a slope too
   !> short for its mitres, keep their square ends.
   subroutine geom_join_slopes(objs, dp)
      type(geom_object), intent(inout) :: objs(:)
      real(rp), intent(in) :: dp
      integer :: k, e, next(size(objs)), prev(size(objs))
      real(rp) :: half
      next = 0
      prev = 0
      slopes: do k = 1, size(objs)
         if (.not. solid_slope(objs(k))) cycle slopes
         followers: do e = 1, size(objs)
            if (e == k .or. prev(e) /= 0 .or. .not. solid_slope(objs(e))) cycle followers
            if (.not. continues(objs(k), objs(e))) cycle followers
            half = 0.5_rp*turn_angle(along(objs(k)%line), along(objs(e)%line))
            if (abs(half) > 0.25_rp*acos(-1.0_rp)) cycle followers
            next(k) = e
            prev(e) = k
            objs(k)%mitre(2) = half
            objs(e)%mitre(1) = half
            exit followers
         end do followers
      end do slopes
      ! a slope whose deepest row would not reach past its mitres keeps square ends
      do k = 1, size(objs)
         if (.not. solid_slope(objs(k))) cycle
         if (row_length(objs(k), objs(k)%layers*dp) >= dp) cycle
         if (prev(k) /= 0) objs(prev(k))%mitre(2) = 0.0_rp
         if (next(k) /= 0) objs(next(k))%mitre(1) = 0.0_rp
         objs(k)%mitre = 0.0_rp
      end do
      do k = 1, size(objs)
         if (solid_slope(objs(k))) call slope_outline(objs(k), objs(k)%layers*dp)
      end do
   end subroutine geom_join_slopes

   pure logical function solid_slope(o)
      type(geom_object), intent(in) :: o
      solid_slope = o%group == 'slope' .and. o%role_id == role_solid
   end function solid_slope

   !> Whether slope b starts where slope a ends, with as many rows, the same
   !> width and the same motion.
   pure logical function continues(a, b)
      type(geom_object), intent(in) :: a, b
      real(rp) :: tol
      tol = 1.0e-9_rp*max(1.0_rp, maxval(abs(a%line)))
      continues = b%layers == a%layers .and. b%motion_id == a%motion_id .and. &
                  all(abs(b%zr - a%zr) <= tol) .and. all(abs(b%line(1:2) - a%line(3:4)) <= tol)
   end function continues

   !> The signed angle from direction t to direction u (> 0 counter-clockwise) [rad].
   pure real(rp) function turn_angle(t, u) result(a)
      real(rp), intent(in) :: t(2), u(2)
      a = atan2(t(1)*u(2) - t(2)*u(1), dot_product(t, u))
   end function turn_angle

   pure function along(line) result(t)
      real(rp), intent(in) :: line(4)
      real(rp) :: t(2)
      t = (line(3:4) - line(1:2))/norm2(line(3:4) - line(1:2))
   end function along

   !> The length of slope o's row at depth d below its line, from mitre to mitre.
   pure real(rp) function row_length(o, d) result(l)
      type(geom_object), intent(in) :: o
      real(rp), intent(in) :: d
      l = norm2(o%line(3:4) - o%line(1:2)) + d*(tan(o%mitre(1)) + tan(o%mitre(2)))
   end function row_length

   !> Slope o's outline: the band of thickness w below its line, ended at its mitres.
   subroutine slope_outline(o, w)
      type(geom_object), intent(inout) :: o
      real(rp), intent(in) :: w
      real(rp) :: t(2), nrm(2), a(2), b(2)
      t = along(o%line)
      nrm = [-t(2), t(1)]
      a = o%line(1:2) - w*nrm - w*tan(o%mitre(1))*t
      b = o%line(3:4) - w*nrm + w*tan(o%mitre(2))*t
      o%nv = 4
      o%v = reshape([a, b, o%line(3:4), o%line(1:2)], [2, 4])
   end subroutine slope_outline
end module input_geometry

!> Rigid-body shapes: outline, mass properties from the geometry, and the
!> boundary particles (shells of `layers` rows along the outline, solid where
!> the rows meet before that). In
!> 3D a body is a box: the section's rectangle times its depth across the
!> width, turned by angle_x about x, angle_y about y and angle about z; its
!> outline is the section's (of a box turned out of the section, the outline
!> of its shadow on the section).
module body_shapes
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use kinds, only: rp
   use constants, only: pi, ndim, nsec
   use rigid, only: nrot
   use input_body, only: body_cfg, body_turn, body_tilted
   use options, only: shape_circle, shape_box, shape_wedge, shape_polygon, shape_stl
   use geom, only: point_in_polygon, distance_to_polygon, nearest_edge_normal, polygon_area
   use geom_stl, only: stl_t, stl_props, stl_inside, stl_nearest, stl_bounds, stl_triangle_point, stl_sort_points
   implicit none
   private
   public :: body_outline, body_mass_properties, body_particles, mesh_shell

   integer, parameter :: circle_sides = 64   !< polygon drawn for a circle outline

contains

   pure function rot(a) result(r)
      real(rp), intent(in) :: a
      real(rp) :: r(2, 2)
      r = reshape([cos(a), sin(a), -sin(a), cos(a)], [2, 2])
   end function rot

   !> World outline at the start (counter-clockwise vertices); a circle as a polygon.
   function body_outline(c) result(v)
      type(body_cfg), intent(in) :: c
      real(rp), allocatable :: v(:, :)
      real(rp) :: a, cen(2), area
      integer :: k
      integer :: ist
      character(len=200) :: emsg
      a = c%angle*pi/180.0_rp
      select case (c%shape_id)
      case (shape_circle)
         allocate (v(2, circle_sides), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'v in body_outline')
         do k = 1, circle_sides
            v(:, k) = [c%x, c%y] + c%radius*[cos(2*pi*(k - 1)/circle_sides), sin(2*pi*(k - 1)/circle_sides)]
         end do
      case (shape_stl)
         v = mesh_shadow(c)
      case (shape_box)
         if (ndim == 3 .and. body_tilted(c)) then
            v = box_shadow(c)
            return
         end if
         allocate (v(2, 4), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'v in body_outline')
         v = 0.5_rp*reshape([-c%width, -c%height, c%width, -c%height, c%width, c%height, -c%width, c%height], [2, 4])
         v = matmul(rot(a), v)
         v(1, :) = v(1, :) + c%x
         v(2, :) = v(2, :) + c%y
      case (shape_wedge, shape_polygon)
         allocate (v(2, c%nvert), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'v in body_outline')
         v(1, :) = c%vx(1:c%nvert)
         v(2, :) = c%vy(1:c%nvert)
         call polygon_props(v, area, cen)
         if (area < 0.0_rp) then
            v = v(:, c%nvert:1:-1)
            call polygon_props(v, area, cen)
         end if
         do k = 1, c%nvert
            v(:, k) = cen + matmul(rot(a), v(:, k) - cen)
         end do
      case default
         call fatal('body_outline: unknown shape '//int_str(c%shape_id))
      end select
   end function body_outline

   !> The outline (counter-clockwise) of the shadow of a turned box on the
   !> section: the convex hull of its eight corners' (x, y).
   function box_shadow(c) result(v)
      type(body_cfg), intent(in) :: c
      real(rp), allocatable :: v(:, :)
      integer, parameter :: ncorner = 8           !< a box's corners
      real(rp) :: r(3, 3), p(2, ncorner)
      integer :: i
      r = body_turn(c)
      do i = 0, ncorner - 1
         p(:, i + 1) = [c%x, c%y] + matmul(r(1:2, :), 0.5_rp*[c%width*merge(1, -1, btest(i, 0)), &
                                                              c%height*merge(1, -1, btest(i, 1)), &
                                                              c%depth*merge(1, -1, btest(i, 2))])
      end do
      v = convex_hull(p)
   end function box_shadow

   !> The outline (counter-clockwise) of the shadow of a turned mesh on the
   !> section: the convex hull of its vertices' (x, y).
   function mesh_shadow(c) result(v)
      type(body_cfg), intent(in) :: c
      real(rp), allocatable :: v(:, :), p(:, :)
      real(rp) :: r(3, 3)
      integer :: t, k, ist
      character(len=200) :: emsg
      r = body_turn(c)
      allocate (p(2, 3*c%mesh%nt), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the shadow of a mesh')
      do t = 1, c%mesh%nt
         do k = 1, 3
            p(:, 3*(t - 1) + k) = [c%x, c%y] + matmul(r(1:2, :), c%mesh%v(:, k, t))
         end do
      end do
      v = convex_hull(p)
   end function mesh_shadow

   !> The convex hull (counter-clockwise, no point twice) of the points p(2, n), by the
   !> monotone chain.
   function convex_hull(p0) result(v)
      real(rp), intent(in) :: p0(:, :)
      real(rp), allocatable :: v(:, :)
      real(rp), allocatable :: p(:, :), hull(:, :)
      integer, allocatable :: order(:)
      integer :: i, k, n, np, ist
      character(len=200) :: emsg
      np = size(p0, 2)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (p(2, np), hull(2, 2*np), stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
         call alloc_check(ist, emsg, 'a convex hull')
         error stop
      end if
      ! sorted by x, then y
      call stl_sort_points(p0, order)
      do i = 1, np
         p(:, i) = p0(:, order(i))
      end do
      n = 0
      do i = 1, np                                 ! the lower hull
         call push(p(:, i), 1)
      end do
      k = n
      do i = np - 1, 1, -1                         ! the upper hull
         call push(p(:, i), k)
      end do
      v = hull(:, 1:n - 1)                         ! its last point is its first
   contains
      !> p1 onto the hull, after dropping the points that would make a clockwise turn
      !> (the chain being built starts at n0).
      subroutine push(p1, n0)
         real(rp), intent(in) :: p1(2)
         integer, intent(in) :: n0
         do while (n >= n0 + 1)
            if ((hull(1, n) - hull(1, n - 1))*(p1(2) - hull(2, n - 1)) - &
                (hull(2, n) - hull(2, n - 1))*(p1(1) - hull(1, n - 1)) > 0.0_rp) exit
            n = n - 1
         end do
         n = n + 1
         hull(:, n) = p1
      end subroutine push
   end function convex_hull

   !> Signed area and centroid of a polygon.
   pure subroutine polygon_props(v, area, cen)
      real(rp), intent(in) :: v(:, :)
      real(rp), intent(out) :: area, cen(2)
      integer :: i, j, n
      real(rp) :: cr
      n = size(v, 2)
      area = 0.0_rp
      cen = 0.0_rp
      do i = 1, n
         j = modulo(i, n) + 1
         cr = v(1, i)*v(2, j) - v(1, j)*v(2, i)
         area = area + 0.5_rp*cr
         cen = cen + (v(:, i) + v(:, j))*cr
      end do
      cen = cen/(6.0_rp*area)
   end subroutine polygon_props

   !> Mass [kg/m in 2D, kg in 3D], centre [m] and inertia tensor about the
   !> centre at the start pose [kg m in 2D, kg m2 in 3D] from the shape: the
   !> particles carry no mass of their own.
   subroutine body_mass_properties(c, mass, cen, inertia)
      type(body_cfg), intent(in) :: c
      real(rp), intent(out) :: mass, cen(ndim), inertia(nrot, nrot)
      real(rp) :: area, j0, rho
      if (ndim == 3) then
         if (c%shape_id == shape_stl) then
            call mesh_mass_properties(c, mass, cen, inertia)
         else
            call box_mass_properties(c, mass, cen, inertia)
         end if
         return
      end if
      if (c%shape_id == shape_circle) then
         area = pi*c%radius**2
         cen(1:nsec) = [c%x, c%y]
         j0 = 0.5_rp*area*c%radius**2
      else
         call polygon_moments(body_outline(c), area, cen(1:nsec), j0)
      end if
      rho = c%density
      if (c%mass > 0.0_rp) rho = c%mass/area
      mass = rho*area
      inertia(1, 1) = rho*j0
   end subroutine body_mass_properties

   !> A mesh in 3D (its own frame: the centroid at the origin), turned by the
   !> start angles: mass from the density (or given) and the enclosed volume,
   !> centre (x, y, z), the inertia tensor R I R^T of the solid the mesh encloses.
   subroutine mesh_mass_properties(c, mass, cen, inertia)
      type(body_cfg), intent(in) :: c
      real(rp), intent(out) :: mass, cen(ndim), inertia(nrot, nrot)
      real(rp) :: vol, rho, c3(3), j(3, 3), r3(3, 3), cen3(3)
      call stl_props(c%mesh, vol, c3, j)
      rho = c%density
      if (c%mass > 0.0_rp) rho = c%mass/vol
      mass = rho*vol
      cen3 = [c%x, c%y, c%z]
      cen = cen3(1:ndim)
      r3 = body_turn(c)
      j = rho*matmul(r3, matmul(j, transpose(r3)))
      inertia = j(1:nrot, 1:nrot)
   end subroutine mesh_mass_properties

   !> A box in 3D: width along x, height along y, depth along z in its own frame,
   !> turned by its angle about z; mass from the density (or given), the centre
   !> (x, y, z), the inertia tensor R diag(m (h^2 + d^2)/12, m (w^2 + d^2)/12,
   !> m (w^2 + h^2)/12) R^T.
   subroutine box_mass_properties(c, mass, cen, inertia)
      type(body_cfg), intent(in) :: c
      real(rp), intent(out) :: mass, cen(ndim), inertia(nrot, nrot)
      real(rp) :: vol, rho, r3(3, 3), ib(3, 3), i3(3, 3), cen3(3)
      vol = c%width*c%height*c%depth
      rho = c%density
      if (c%mass > 0.0_rp) rho = c%mass/vol
      mass = rho*vol
      cen3 = [c%x, c%y, c%z]
      cen = cen3(1:ndim)
      ib = 0.0_rp
      ib(1, 1) = mass*(c%height**2 + c%depth**2)/12.0_rp
      ib(2, 2) = mass*(c%width**2 + c%depth**2)/12.0_rp
      ib(3, 3) = mass*(c%width**2 + c%height**2)/12.0_rp
      r3 = body_turn(c)
      i3 = matmul(r3, matmul(ib, transpose(r3)))
      inertia = i3(1:nrot, 1:nrot)
   end subroutine box_mass_properties

   !> The boundary particles of a 3D box in its own frame (centre at the origin,
   !> the start angle applied): the points of a lattice of about dp fitted to the
   !> box (a whole number of spacings along each side) at most layers spacings in
   !> from its faces; the normal, the outward normal of the nearest face (the mean
   !> of two or three at an edge or a corner); surf 1 on a face, 2 on an edge or a
   !> corner (outer layer only), 0 inside.
   subroutine box_particles(c, dp, layers, xb, nb, surf)
      type(body_cfg), intent(in) :: c
      real(rp), intent(in) :: dp
      integer, intent(in) :: layers
      real(rp), allocatable, intent(out) :: xb(:, :), nb(:, :)
      integer, allocatable, intent(out) :: surf(:)
      integer :: nn(3), i, j, k, m, a, depth_in, n, faces, idx(3), ist
      real(rp) :: side(3), s(3), pos(3), nrm(3), r3(3, 3)
      character(len=200) :: emsg
      side = [c%width, c%height, c%depth]
      nn = max(1, nint(side/dp))
      s = side/nn
      r3 = body_turn(c)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (xb(ndim, product(nn)), nb(ndim, product(nn)), surf(product(nn)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'xb, nb, surf in box_particles')
      m = 0
      do k = 1, nn(3)
         do j = 1, nn(2)
            lattice: do i = 1, nn(1)
               idx = [i, j, k]
               ! layers in from the nearest face: 1 on the outside
               depth_in = minval(min(idx, nn + 1 - idx))
               if (depth_in > layers) cycle lattice
               pos = -0.5_rp*side + (idx - 0.5_rp)*s
               nrm = 0.0_rp
               faces = 0
               do a = 1, 3
                  n = min(idx(a), nn(a) + 1 - idx(a))
                  if (n == depth_in) then
                     faces = faces + 1
                     nrm(a) = merge(-1.0_rp, 1.0_rp, idx(a) <= nn(a) + 1 - idx(a))
                  end if
               end do
               m = m + 1
               xb(:, m) = matmul(r3(1:ndim, :), pos)
               nb(:, m) = matmul(r3(1:ndim, :), nrm/norm2(nrm))
               surf(m) = 0
               if (depth_in == 1) surf(m) = merge(1, 2, faces == 1)
            end do lattice
         end do
      end do
      xb = xb(:, 1:m)
      nb = nb(:, 1:m)
      surf = surf(1:m)
   end subroutine box_particles

   !> The boundary particles of an STL body in its own frame turned by the start
   !> angles (centre at the origin): the points of a lattice of about dp along the
   !> mesh's own axes, fitted to its bounding box as a box's lattice is to the box
   !> (a whole number of spacings along each side, half a spacing in), inside the mesh
   !> and less than layers spacings from its surface; the normal, that of the
   !> nearest triangle, or at an edge or a corner (triangles within dp/2 of the
   !> particle whose normals differ by more than 30 degrees) the mean of their
   !> normals; surf 1 on a face, 2 on an edge or a corner (outer layer: within
   !> dp of the surface), 0 deeper.
   subroutine mesh_particles(c, dp, layers, xb, nb, surf)
      type(body_cfg), intent(in) :: c
      real(rp), intent(in) :: dp
      integer, intent(in) :: layers
      real(rp), allocatable, intent(out) :: xb(:, :), nb(:, :)
      integer, allocatable, intent(out) :: surf(:)
      real(rp) :: lo(3), hi(3), sp(3), r3(3, 3)
      real(rp), allocatable :: xs(:, :), ns(:, :)
      integer :: nn(3), m
      call stl_bounds(c%mesh, lo, hi)
      nn = max(1, nint((hi - lo)/dp))
      sp = (hi - lo)/nn
      call mesh_shell(c%mesh, lo, sp, nn, dp, layers, xs, ns, surf)
      m = size(surf)
      if (m == 0) then
         ! read_mesh (input_body) refuses a mesh whose lattice holds no particle
         call fatal('mesh_particles: no lattice point inside the mesh (internal error)')
      end if
      r3 = body_turn(c)
      xb = matmul(r3(1:ndim, :), xs)
      nb = matmul(r3(1:ndim, :), ns)
   end subroutine mesh_particles

   !> The points x0 + (i - 1/2, j - 1/2, k - 1/2) sp, i, j, k up to nn, inside the
   !> closed mesh and less than layers dp from its surface (xs), with their
   !> normals (ns) and surface flags (surf: 1 within dp of the surface, 2 there
   !> on an edge or a corner, 0 deeper). The normal is that of the nearest
   !> triangle; at an edge or a corner (faces more than 30 degrees apart within
   !> dp/2 of the nearest) the mean of the faces' normals (the nearest face's
   !> where two opposite faces are as near: the middle of a thin wall).
   subroutine mesh_shell(mesh, x0, sp, nn, dp, layers, xs, ns, surf)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(in) :: x0(3), sp(3), dp
      integer, intent(in) :: nn(3), layers
      real(rp), allocatable, intent(out) :: xs(:, :), ns(:, :)
      integer, allocatable, intent(out) :: surf(:)
      real(rp) :: pos(3), q(3), nrm(3), d, nsum(3)
      integer :: i, j, k, m, ist, nfaces
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (xs(3, product(nn)), ns(3, product(nn)), surf(product(nn)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'xs, ns, surf in mesh_shell')
      m = 0
      do k = 1, nn(3)
         do j = 1, nn(2)
            lattice: do i = 1, nn(1)
               pos = x0 + ([i, j, k] - 0.5_rp)*sp
               call stl_nearest(mesh, pos, q, nrm)
               d = norm2(q - pos)
               if (d >= layers*dp) cycle lattice
               if (.not. stl_inside(mesh, pos)) cycle lattice
               call edge_normals(pos, nrm, nsum, nfaces)
               if (norm2(nsum) < 0.5_rp) nsum = nrm
               m = m + 1
               xs(:, m) = pos
               ns(:, m) = nsum/norm2(nsum)
               surf(m) = 0
               if (d < dp) surf(m) = merge(1, 2, nfaces == 1)
            end do lattice
         end do
      end do
      xs = xs(:, 1:m)
      ns = ns(:, 1:m)
      surf = surf(1:m)
   contains
      !> The sum of the distinct normals (more than 30 degrees apart) of the
      !> triangles within dp/2 of the nearest one's distance from x, and how many.
      subroutine edge_normals(x, n0, nsm, nf)
         real(rp), intent(in) :: x(3), n0(3)
         real(rp), intent(out) :: nsm(3)
         integer, intent(out) :: nf
         real(rp) :: y(3), n1(3), dist0, e(3, 3)
         integer :: t
         nsm = n0
         nf = 1
         e(:, 1) = n0
         dist0 = d
         do t = 1, mesh%nt
            call stl_triangle_point(mesh%v(:, :, t), x, y, n1)
            if (.not. norm2(n1) > 0.0_rp .or. norm2(y - x) > dist0 + 0.5_rp*dp) cycle
            if (any(matmul(n1, e(:, 1:nf)) > cos(pi/6.0_rp))) cycle
            if (nf == 3) cycle
            nf = nf + 1
            e(:, nf) = n1
            nsm = nsm + n1
         end do
      end subroutine edge_normals
   end subroutine mesh_shell

   !> Area, centroid and polar second moment of area about the centroid.
   pure subroutine polygon_moments(v, area, cen, j0)
      real(rp), intent(in) :: v(:, :)
      real(rp), intent(out) :: area, cen(2), j0
      integer :: i, k, n
      real(rp) :: a(2), b(2), cr
      call polygon_props(v, area, cen)
      n = size(v, 2)
      j0 = 0.0_rp
      do i = 1, n
         k = modulo(i, n) + 1
         a = v(:, i) - cen
         b = v(:, k) - cen
         cr = a(1)*b(2) - b(1)*a(2)
         j0 = j0 + cr*(a(1)**2 + a(1)*b(1) + b(1)**2 + a(2)**2 + a(2)*b(2) + b(2)**2)/12.0_rp
      end do
   end subroutine polygon_moments

   !> Boundary particles of a body in its own frame (centre at the origin,
   !> the start angle already applied): rows at (l - 1/2) dp inside the
   !> outline, l = 1 .. layers. surf: 1 on a flat face, 2 at a vertex or on
   !> a circle (outer row only), 0 inside.
   subroutine body_particles(c, dp, layers, xb, nb, surf)
      type(body_cfg), intent(in) :: c
      real(rp), intent(in) :: dp
      integer, intent(in) :: layers
      real(rp), allocatable, intent(out) :: xb(:, :), nb(:, :)
      integer, allocatable, intent(out) :: surf(:)
      real(rp) :: mass, cen(ndim), inertia(nrot, nrot), r, a, ang
      real(rp), allocatable :: v(:, :), w(:, :), en(:, :), off(:, :), core(:, :)
      integer :: l, k, m, n, ns, nv, j, cap
      integer :: ist
      character(len=200) :: emsg
      if (ndim == 3) then
         if (c%shape_id == shape_stl) then
            call mesh_particles(c, dp, layers, xb, nb, surf)
         else
            call box_particles(c, dp, layers, xb, nb, surf)
         end if
         return
      end if
      call body_mass_properties(c, mass, cen, inertia)
      cap = 64
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (xb(ndim, cap), nb(ndim, cap), surf(cap), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'xb, nb, surf in body_particles')
      n = 0
      if (c%shape_id == shape_circle) then
         ang = c%angle*pi/180.0_rp
         do l = 1, layers
            r = c%radius - (l - 0.5_rp)*dp
            if (r < 0.25_rp*dp) exit
            ns = max(3, nint(2.0_rp*pi*r/dp))
            do k = 1, ns
               a = 2.0_rp*pi*(k - 1 + 0.5_rp*mod(l + 1, 2))/ns + ang
               call push([cos(a), sin(a)]*r, [cos(a), sin(a)], merge(2, 0, l == 1))
            end do
         end do
      else
         v = body_outline(c)
         nv = size(v, 2)
         do k = 1, nv
            v(:, k) = v(:, k) - cen(1:nsec)
         end do
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (en(2, nv), off(2, nv), w(2, nv), stat=ist, errmsg=emsg)
         if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
            call alloc_check(ist, emsg, 'en, off, w in body_particles')
            error stop
         end if
         do k = 1, nv                          ! outward normal of edge k (from vertex k to k+1)
            j = modulo(k, nv) + 1
            en(:, k) = [v(2, j) - v(2, k), -(v(1, j) - v(1, k))]
            en(:, k) = en(:, k)/norm2(en(:, k))
         end do
         do l = 1, layers
            ! inset outline: edge lines moved inward by (l - 1/2) dp, neighbours intersected
            do k = 1, nv
               j = modulo(k - 2, nv) + 1       ! edge before vertex k
               w(:, k) = inset_vertex(v(:, k), en(:, j), en(:, k), (l - 0.5_rp)*dp)
            end do
            if (.not. inset_valid(v, w, dp)) then
               ! the rows have met before all layers were laid: a sliver left in
               ! the middle (the mid-line of a box with an odd number of rows)
               ! gets the points of the body's lattice, so that the body has no
               ! hollow the water can fill (with mDBC, which does not repel, it
               ! did, and the buoyancy fell to that of the particles' volume)
               core = core_points(v, dp, (l - 0.75_rp)*dp, c%angle*pi/180.0_rp)
               do k = 1, size(core, 2)
                  call push(core(:, k), nearest_edge_normal(core(:, k), v), 0)
               end do
               exit
            end if
            do k = 1, nv
               j = modulo(k, nv) + 1
               m = max(1, nint(norm2(w(:, j) - w(:, k))/dp))
               do ns = 0, m - 1
                  if (ns == 0) then
                     off(:, 1) = en(:, k) + en(:, modulo(k - 2, nv) + 1)
                     call push(w(:, k), off(:, 1)/norm2(off(:, 1)), merge(2, 0, l == 1))
                  else
                     call push(w(:, k) + (w(:, j) - w(:, k))*real(ns, rp)/m, en(:, k), merge(1, 0, l == 1))
                  end if
               end do
            end do
         end do
      end if
      xb = xb(:, 1:n)
      nb = nb(:, 1:n)
      surf = surf(1:n)
   contains
      subroutine push(pos, nrm, s)
         real(rp), intent(in) :: pos(2), nrm(2)
         integer, intent(in) :: s
         real(rp), allocatable :: t2(:, :)
         integer, allocatable :: t1(:)
         integer :: ist
         character(len=200) :: emsg
         if (n == cap) then
            cap = 2*cap
            allocate (t2(ndim, cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't2 in push')
            t2(:, 1:n) = xb(:, 1:n); call move_alloc(t2, xb)
            allocate (t2(ndim, cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't2 in push')
            t2(:, 1:n) = nb(:, 1:n); call move_alloc(t2, nb)
            allocate (t1(cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't1 in push')
            t1(1:n) = surf(1:n); call move_alloc(t1, surf)
         end if
         n = n + 1
         xb(:, n) = 0.0_rp
         nb(:, n) = 0.0_rp
         xb(1:nsec, n) = pos
         nb(1:nsec, n) = nrm
         surf(n) = s
      end subroutine push
   end subroutine body_particles

   !> Vertex p moved so that it lies at distance d inside both edge lines
   !> (outward normals n1, n2).
   pure function inset_vertex(p, n1, n2, d) result(q)
      real(rp), intent(in) :: p(2), n1(2), n2(2), d
      real(rp) :: q(2), m(2), c
      m = n1 + n2
      c = 1.0_rp + dot_product(n1, n2)
      if (c < 1.0e-6_rp) then
         q = p - d*n1                  ! a hairpin: no proper intersection
      else
         q = p - d*m/c                 ! m/c has unit projection on both normals
      end if
   end function inset_vertex

   !> The points of a lattice of about dp over the bounding box of outline v
   !> turned back by ang (the body's start angle: the lattice the rows along a
   !> box's sides lie on), at least dmin inside the outline, turned with it.
   pure function core_points(v, dp, dmin, ang) result(pts)
      real(rp), intent(in) :: v(:, :), dp, dmin, ang
      real(rp), allocatable :: pts(:, :)
      real(rp) :: lo(2), hi(2), turn(2, 2)
      integer :: i, j, nx, ny
      logical, allocatable :: keep(:, :)
      real(rp), allocatable :: pos(:, :, :)
      turn = reshape([cos(ang), sin(ang), -sin(ang), cos(ang)], [2, 2])
      lo = minval(matmul(transpose(turn), v), dim=2)
      hi = maxval(matmul(transpose(turn), v), dim=2)
      nx = max(1, nint((hi(1) - lo(1))/dp))
      ny = max(1, nint((hi(2) - lo(2))/dp))
      allocate (keep(nx, ny), pos(2, nx, ny))
      do j = 1, ny
         do i = 1, nx
            pos(:, i, j) = matmul(turn, lo + ([i, j] - 0.5_rp)*(hi - lo)/[nx, ny])
            keep(i, j) = point_in_polygon(pos(:, i, j), v) .and. distance_to_polygon(pos(:, i, j), v) >= dmin
         end do
      end do
      pts = reshape(pack(pos, spread(keep, 1, 2)), [2, count(keep)])
   end function core_points

   !> The inset polygon still has the outline's orientation, every edge points
   !> the same way as the original one, and it is at least dp/2 wide on the
   !> mean (its area over its longest side): a thinner row would crowd its
   !> particles within half a spacing of each other (the mid-line of a box with
   !> an odd number of rows, whose area rounding may leave just above zero, the
   !> tip of a wedge), and the core's lattice points take its place.
   pure logical function inset_valid(v, w, dp) result(ok)
      real(rp), intent(in) :: v(:, :), w(:, :), dp
      integer :: k, j, n
      real(rp) :: longest, area
      n = size(v, 2)
      ! the area alone (an inset that collapsed onto a line has no centroid)
      area = polygon_area(w)
      ok = area > 0.0_rp
      longest = 0.0_rp
      do k = 1, n
         j = modulo(k, n) + 1
         ok = ok .and. dot_product(w(:, j) - w(:, k), v(:, j) - v(:, k)) > 0.0_rp
         longest = max(longest, norm2(w(:, j) - w(:, k)))
      end do
      ok = ok .and. area >= 0.5_rp*dp*longest
   end function inset_valid
end module body_shapes

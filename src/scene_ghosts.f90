!> The ghost points of the modified dynamic boundary (bc_mdbc): for every
!> solid particle within 2h of a face the water can touch, the offset gof
!> from the particle to its mirror across that face (twice the way to the
!> nearest point of the face). The faces of fixed and moving walls are the
!> parts of the solids' surfaces with no other solid and no domain edge
!> beyond them; of those, a particle takes the nearest that looks towards
!> the water (its outward normal towards the fluid particle nearest to the
!> particle), so that the middle row of a wall with free space behind it
!> mirrors into the tank and not out of it, nor through the wall's top. Near a corner of the water the nearest point is the
!> corner, and the ghost point lies on its bisector (as in DualSPHysics).
!> A body's particles mirror across its own outline. Particles farther
!> than 2h from every face, and the particles of filters (massless to the
!> water), get no ghost point (gof = 0).
!>
!> In 3D a solid is its section's outline extruded over its z range. Its
!> surface is the outline's edges extruded (side faces) and two end faces,
!> the outline at either end of the z range. The side faces are found in
!> slabs across the width between the z ends of all solids, each slab with
!> the solids that span it, as the 2D faces are; an end face strictly inside
!> the domain's width is open where no solid lies just beyond it, and its
!> open part is a plane region whose edges (stretches of the outline's and
!> of the solids' beyond) are faces of their own, so that the nearest point
!> of the open part is the point straight across (when it is open) or the
!> nearest of those edges.
module scene_ghosts
   use kinds, only: rp
   use constants, only: kind_fluid, kind_filter, ndim, nsec
   use input, only: case_cfg
   use input_mesh, only: mesh_holding
   use input_body, only: body_cfg
   use geom_stl, only: stl_nearest, stl_triangle_point
   use input_geometry, only: geom_zrange
   use options, only: role_solid, shape_stl
   use particles, only: particles_t
   use body_dynamics, only: body_t
   use geom, only: point_in_polygon, polygon_area
   use errors, only: alloc_check, input_error
   use input_check, only: int_str, real_str
   implicit none
   private
   public :: scene_ghost_offsets

   !> A part of a solid's surface that the water can touch, with its outward
   !> normal n: in the section the stretch a-b of an edge, across the width
   !> (3D) from z0 to z1 (a side face; z0 = z1 on an edge of an end face's open
   !> part); or, cap > 0, the plane z = z0 of an end face of objs(cap), where
   !> it is open; or (tri) a triangle of an &stl solid.
   type :: face_t
      real(rp) :: a(nsec) = 0.0_rp, b(nsec) = 0.0_rp, z0 = 0.0_rp, z1 = 0.0_rp, n(ndim) = 0.0_rp
      integer :: cap = 0
      !> a triangle of an &stl solid's mesh (3D): its vertices v(:, 1:3)
      logical :: tri = .false.
      real(rp) :: v(3, 3) = 0.0_rp
   end type face_t

   !> Where a point of the section counts as open: across the width at z
   !> (3D), the solids that span z are looked for; own > 0: the point must
   !> also lie in objs(own)'s outline (the open part of its end face), and
   !> that solid itself does not count.
   type :: probe_t
      real(rp) :: z = 0.0_rp
      integer :: own = 0
   end type probe_t

   !> The fluid particles binned in cubic cells, for the nearest one to a
   !> point: cell i (its indices ix(d) along each axis d, i = 1 + sum (ix(d) -
   !> 1) stride(d)) holds idx(start(i) : start(i + 1) - 1), in increasing
   !> particle order.
   type :: bins_t
      real(rp) :: x0(ndim) = 0.0_rp, cs = 1.0_rp
      integer :: nc(ndim) = 0, stride(ndim) = 0
      integer, allocatable :: start(:), idx(:)
   end type bins_t

contains

   !> gof and gob (equal at the start) of every particle of p; h the smoothing length.
   subroutine scene_ghost_offsets(c, p, bodies, h)
      type(case_cfg), intent(in) :: c
      type(particles_t), intent(inout) :: p
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(in) :: h
      type(face_t), allocatable :: faces(:)
      type(bins_t) :: bins
      integer :: i, b, nobj
      real(rp) :: u(ndim), q(ndim)
      logical :: found
      if (.not. p%mdbc) return
      nobj = size(c%objs)
      call exposed_faces(c, faces)
      call bin_fluid(p, 2.0_rp*h, bins)
      do i = 1, p%n
         p%gof(:, i) = 0.0_rp
         if (p%kind(i) == kind_fluid .or. p%kind(i) == kind_filter) cycle
         b = p%body(i) - nobj
         if (b >= 1 .and. b <= size(bodies)) then
            ! a body: its own outline, in the body frame
            q = nearest_on_body(p%xb(:, i), bodies(b), c%bodies(b))
            if (norm2(q - p%xb(:, i)) < 2.0_rp*h) p%gof(:, i) = 2.0_rp*(q - p%xb(:, i))
         else
            ! too deep for any water to see it: no ghost (and no search)
            u = 0.0_rp
            q = nearest_on_faces(c, p%x(:, i), u, faces, found)
            if (.not. found .or. norm2(q - p%x(:, i)) >= 2.0_rp*h) cycle
            call toward_water(p, bins, i, u, found)
            if (.not. found) cycle
            q = nearest_on_faces(c, p%x(:, i), u, faces, found)
            if (.not. found .or. norm2(q - p%x(:, i)) >= 2.0_rp*h) cycle
            p%gof(:, i) = 2.0_rp*(q - p%x(:, i))
            if (norm2(q - p%x(:, i)) < 0.6_rp*c%numerics%dp) call check_thick(c, p%x(:, i), q, h)
         end if
      end do
      ! the body frame is the start pose: bodies_place turns gob into gof
      p%gob(:, 1:p%n) = p%gof(:, 1:p%n)
   end subroutine scene_ghost_offsets

   !> Whether point x lies in solid o (in 3D: its outline extruded over its z range).
   logical function in_solid(c, o, x) result(inside)
      type(case_cfg), intent(in) :: c
      integer, intent(in) :: o
      real(rp), intent(in) :: x(ndim)
      real(rp) :: zr(2)
      inside = point_in_polygon(x(1:nsec), c%objs(o)%v)
      if (ndim == 3 .and. inside) then
         zr = geom_zrange(c%objs(o), [c%domain%zmin, c%domain%zmax])
         inside = x(ndim) > zr(1) .and. x(ndim) < zr(2)
      end if
   end function in_solid

   !> A solid behind a wetted face must be 2h - dp/2 thick at least: the water
   !> half a spacing from the face has then the whole kernel's support of
   !> solid particles; a thinner wall lets it through (the dynamic boundary's
   !> own continuity makes a thin wall stiffer, mDBC's extrapolated pressure
   !> does not). x: a particle of the solid's first row, q: its face point.
   subroutine check_thick(c, x, q, h)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: x(ndim), q(ndim), h
      real(rp) :: deep(ndim), need
      integer :: o, k, m
      character(len=:), allocatable :: which
      need = 2.0_rp*h - 0.5_rp*c%numerics%dp
      deep = q + need*(x - q)/norm2(x - q)
      k = 0
      m = 0
      if (ndim == 3) then
         if (in_mesh(c, pad3(deep), 0)) return
         m = mesh_holding(c%meshes, pad3(x), 0)
      end if
      do o = 1, size(c%objs)
         if (c%objs(o)%role_id /= role_solid) cycle
         if (in_solid(c, o, deep)) return
         if (k == 0 .and. in_solid(c, o, x)) k = o
      end do
      if (m > 0 .and. k == 0) then
         which = '&stl #'//int_str(m)
      else
         k = max(k, 1)
         which = '&'//trim(c%objs(k)%group)//' #'//int_str(c%objs(k)%index)
      end if
      call input_error(c%file, 'numerics', 'boundary', "'mdbc' needs the solids at least 2h - dp/2 = "// &
                       real_str(need)//' m thick behind every face the water can touch ('// &
                       int_str(ceiling(2.0_rp*h/c%numerics%dp - 1.0e-9_rp))//' rows); behind the face at '// &
                       point_str(q)//' '//which//' is thinner: make it thicker (with the &domain room '// &
                       "behind it) or use 'dynamic'")
   end subroutine check_thick

   !> '(x, y)' or '(x, y, z)'.
   function point_str(x) result(s)
      real(rp), intent(in) :: x(:)
      character(len=:), allocatable :: s
      integer :: d
      s = '('//real_str(x(1))
      do d = 2, size(x)
         s = s//', '//real_str(x(d))
      end do
      s = s//')'
   end function point_str

   !> The parts of the solids' surfaces with neither another solid nor the
   !> domain's edge just outside them.
   subroutine exposed_faces(c, faces)
      type(case_cfg), intent(in) :: c
      type(face_t), allocatable, intent(out) :: faces(:)
      integer :: k, nf, ist, s, m
      real(rp), allocatable :: zb(:)
      real(rp) :: zr(2), zdom(2), eps
      character(len=200) :: emsg
      allocate (faces(64), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'faces in exposed_faces')
      nf = 0
      if (ndim == 2) then
         call side_faces(c, probe_t(), 0.0_rp, 0.0_rp, faces, nf)
      else
         ! slabs across the width between the z ends of the solids
         zdom = [c%domain%zmin, c%domain%zmax]
         zb = [zdom]
         do k = 1, size(c%objs)
            if (c%objs(k)%role_id /= role_solid) cycle
            zr = geom_zrange(c%objs(k), zdom)
            zb = [zb, max(min(zr, zdom(2)), zdom(1))]
         end do
         ! and of the meshes (exact for a mesh whose section is the same across its width)
         do k = 1, size(c%meshes)
            zb = [zb, max(min([c%meshes(k)%lo(3), c%meshes(k)%hi(3)], zdom(2)), zdom(1))]
         end do
         call sort_unique(zb, 1.0e-9_rp*c%numerics%dp)
         do m = 1, size(zb) - 1
            call side_faces(c, probe_t(0.5_rp*(zb(m) + zb(m + 1)), 0), zb(m), zb(m + 1), faces, nf)
         end do
         ! the end faces inside the domain's width
         eps = 1.0e-3_rp*c%numerics%dp
         do k = 1, size(c%objs)
            if (c%objs(k)%role_id /= role_solid) cycle
            zr = geom_zrange(c%objs(k), zdom)
            ends: do s = 1, 2
               if (.not. (zr(s) > zdom(1) + eps .and. zr(s) < zdom(2) - eps)) cycle ends
               call end_face(c, k, zr(s), real(2*s - 3, rp), faces, nf)
            end do ends
         end do
      end if
      do k = 1, size(c%meshes)
         call mesh_faces(c, k, faces, nf)
      end do
      faces = faces(1:nf)
   end subroutine exposed_faces

   !> The side faces of the solids that the probe pr's width (its z) finds,
   !> open where pr finds free space, each spanning z0 to z1 across the width.
   subroutine side_faces(c, pr, z0, z1, faces, nf)
      type(case_cfg), intent(in) :: c
      type(probe_t), intent(in) :: pr
      real(rp), intent(in) :: z0, z1
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(inout) :: nf
      integer :: k, e
      real(rp) :: a(nsec), d(nsec), en(nsec), nrm(ndim)
      logical :: ok
      do k = 1, size(c%objs)
         if (c%objs(k)%role_id /= role_solid) cycle
         if (.not. spans(c, k, pr%z)) cycle
         edges: do e = 1, size(c%objs(k)%v, 2)
            call outline_edge(c%objs(k)%v, e, a, d, en, ok)
            if (.not. ok) cycle edges
            nrm = 0.0_rp
            nrm(1:nsec) = en
            call open_runs(c, pr, a, d, en, nrm, z0, z1, faces, nf)
         end do edges
      end do
   end subroutine side_faces

   !> The end face of solid o at z = zc whose outward normal is s along z
   !> (3D): the plane itself, open where no solid lies just beyond it, and the
   !> edges of its open part: the stretches of o's outline with the open part
   !> just inside, and of the solids' outlines beyond it with the open part
   !> just outside.
   subroutine end_face(c, o, zc, s, faces, nf)
      type(case_cfg), intent(in) :: c
      integer, intent(in) :: o
      real(rp), intent(in) :: zc, s
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(inout) :: nf
      type(probe_t) :: pr
      integer :: k, e
      real(rp) :: a(nsec), d(nsec), nrm(ndim), en(nsec)
      logical :: ok
      nrm = 0.0_rp
      nrm(ndim) = s
      pr = probe_t(zc + s*1.0e-3_rp*c%numerics%dp, o)
      call grow(faces, nf)
      nf = nf + 1
      faces(nf) = face_t(z0=zc, z1=zc, n=nrm, cap=o)
      do k = 1, size(c%objs)
         if (c%objs(k)%role_id /= role_solid) cycle
         if (k /= o .and. .not. spans(c, k, pr%z)) cycle
         edges: do e = 1, size(c%objs(k)%v, 2)
            call outline_edge(c%objs(k)%v, e, a, d, en, ok)
            if (.not. ok) cycle edges
            ! o's own edges: the open part lies inside o; another's: outside it
            if (k == o) en = -en
            call open_runs(c, pr, a, d, en, nrm, zc, zc, faces, nf)
         end do edges
      end do
      ! and the outlines of the &stl solids beyond: their cuts by the probe's plane
      do k = 1, size(c%meshes)
         if (pr%z <= c%meshes(k)%lo(3) .or. pr%z >= c%meshes(k)%hi(3)) cycle
         cuts: do e = 1, c%meshes(k)%mesh%nt
            call plane_cut(c%meshes(k)%mesh%v(:, :, e), pr%z, a, d, en, ok)
            if (.not. ok) cycle cuts
            call open_runs(c, pr, a, d, en, nrm, zc, zc, faces, nf)
         end do cuts
      end do
   end subroutine end_face

   !> Where the triangle v(:, 1:3) crosses the plane z = zp (3D): the segment
   !> from a to a + d in the section, with the triangle's outward normal in the
   !> section en (a unit vector); ok false where it does not cross, or lies
   !> (almost) in the plane.
   pure subroutine plane_cut(v, zp, a, d, en, ok)
      real(rp), intent(in) :: v(3, 3), zp
      real(rp), intent(out) :: a(nsec), d(nsec), en(nsec)
      logical, intent(out) :: ok
      real(rp) :: n(3), pts(2, 2), s(3)
      integer :: i, j, m
      a = 0.0_rp; d = 0.0_rp; en = 0.0_rp
      n = [(v(2, 2) - v(2, 1))*(v(3, 3) - v(3, 1)) - (v(3, 2) - v(3, 1))*(v(2, 3) - v(2, 1)), &
           (v(3, 2) - v(3, 1))*(v(1, 3) - v(1, 1)) - (v(1, 2) - v(1, 1))*(v(3, 3) - v(3, 1)), &
           (v(1, 2) - v(1, 1))*(v(2, 3) - v(2, 1)) - (v(2, 2) - v(2, 1))*(v(1, 3) - v(1, 1))]
      ok = norm2(n(1:2)) > 1.0e-9_rp*norm2(n)
      if (.not. ok) return
      s = v(3, :) - zp
      m = 0
      do i = 1, 3
         j = modulo(i, 3) + 1
         if ((s(i) < 0.0_rp .neqv. s(j) < 0.0_rp) .and. m < 2) then
            m = m + 1
            pts(:, m) = v(1:2, i) + s(i)/(s(i) - s(j))*(v(1:2, j) - v(1:2, i))
         end if
      end do
      ok = m == 2
      if (.not. ok) return
      a = pts(:, 1)
      d = pts(:, 2) - pts(:, 1)
      en = n(1:2)/norm2(n(1:2))
      ok = norm2(d) > 0.0_rp
   end subroutine plane_cut

   !> Edge e of the outline v: from a to a + d, its outward unit normal en;
   !> ok false for an edge of no length.
   pure subroutine outline_edge(v, e, a, d, en, ok)
      real(rp), intent(in) :: v(:, :)
      integer, intent(in) :: e
      real(rp), intent(out) :: a(nsec), d(nsec), en(nsec)
      logical, intent(out) :: ok
      a = v(:, e)
      d = v(:, modulo(e, size(v, 2)) + 1) - a
      en = 0.0_rp
      ok = norm2(d) > 0.0_rp
      if (ok) en = sign(1.0_rp, polygon_area(v))*[d(2), -d(1)]/norm2(d)
   end subroutine outline_edge

   !> Whether solid k spans z across the width (always in 2D).
   logical function spans(c, k, z)
      type(case_cfg), intent(in) :: c
      integer, intent(in) :: k
      real(rp), intent(in) :: z
      real(rp) :: zr(2)
      spans = .true.
      if (ndim == 2) return
      zr = geom_zrange(c%objs(k), [c%domain%zmin, c%domain%zmax])
      spans = z > zr(1) .and. z < zr(2)
   end function spans

   !> x sorted in increasing order, values within tol of the one before dropped.
   subroutine sort_unique(x, tol)
      real(rp), allocatable, intent(inout) :: x(:)
      real(rp), intent(in) :: tol
      integer :: i, j, n
      real(rp) :: t
      n = size(x)
      do i = 2, n
         t = x(i)
         j = i - 1
         shift: do while (j >= 1)
            if (x(j) <= t) exit shift
            x(j + 1) = x(j)
            j = j - 1
         end do shift
         x(j + 1) = t
      end do
      j = min(n, 1)
      do i = 2, n
         if (x(i) - x(j) > tol) then
            j = j + 1
            x(j) = x(i)
         end if
      end do
      x = x(1:j)
   end subroutine sort_unique

   !> Room for one more face in faces(1:nf).
   subroutine grow(faces, nf)
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(in) :: nf
      type(face_t), allocatable :: tmp(:)
      integer :: ist
      character(len=200) :: emsg
      if (nf < size(faces)) return
      allocate (tmp(2*nf), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'faces in scene_ghosts')
      tmp(1:nf) = faces
      call move_alloc(tmp, faces)
   end subroutine grow

   !> The open stretches of the edge from a to a + d, appended to faces(1:nf)
   !> with the face normal nrm and the extent z0 to z1 across the width: open
   !> where the probe pr finds free space just off the edge along tdir. The
   !> edge is sampled every dp/4 between its vertices (at a vertex the test
   !> point lies on the next solid's edge, where point_in_polygon may go either
   !> way), the ends of each open run found by bisection.
   subroutine open_runs(c, pr, a, d, tdir, nrm, z0, z1, faces, nf)
      type(case_cfg), intent(in) :: c
      type(probe_t), intent(in) :: pr
      real(rp), intent(in) :: a(nsec), d(nsec), tdir(nsec), nrm(ndim), z0, z1
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(inout) :: nf
      integer :: m, s
      real(rp) :: t0, t1
      logical :: prev, now
      m = max(2, ceiling(4.0_rp*norm2(d)/c%numerics%dp))
      prev = .false.
      t0 = 0.0_rp
      do s = 1, m
         now = open_at(c, pr, a, d, tdir, (s - 0.5_rp)/m)
         if (now .and. .not. prev) then
            t0 = 0.0_rp
            if (s > 1) t0 = edge_of_run(c, pr, a, d, tdir, (s - 1.5_rp)/m, (s - 0.5_rp)/m)
         else if (prev .and. .not. now) then
            t1 = edge_of_run(c, pr, a, d, tdir, (s - 1.5_rp)/m, (s - 0.5_rp)/m)
            call add(a + t0*d, a + t1*d)
         end if
         prev = now
      end do
      if (prev) call add(a + t0*d, a + d)
   contains
      subroutine add(x0, x1)
         real(rp), intent(in) :: x0(nsec), x1(nsec)
         call grow(faces, nf)
         nf = nf + 1
         faces(nf) = face_t(x0, x1, z0, z1, nrm, 0)
      end subroutine add
   end subroutine open_runs

   !> Whether the point at t along the edge from a to a + d has free space
   !> just off it along tdir, as the probe pr sees it.
   logical function open_at(c, pr, a, d, tdir, t) result(op)
      type(case_cfg), intent(in) :: c
      type(probe_t), intent(in) :: pr
      real(rp), intent(in) :: a(nsec), d(nsec), tdir(nsec), t
      op = open_point(c, pr, a + t*d + 1.0e-3_rp*c%numerics%dp*tdir)
   end function open_at

   !> Whether the section's point x is free space for the probe pr: inside
   !> the domain (own = 0) or in objs(own)'s outline, and in no solid that
   !> spans pr's z (own excepted).
   logical function open_point(c, pr, x) result(op)
      type(case_cfg), intent(in) :: c
      type(probe_t), intent(in) :: pr
      real(rp), intent(in) :: x(nsec)
      integer :: o
      if (pr%own > 0) then
         op = point_in_polygon(x, c%objs(pr%own)%v)
      else
         op = x(1) > c%domain%xmin .and. x(1) < c%domain%xmax .and. x(2) > c%domain%ymin .and. x(2) < c%domain%ymax
      end if
      solids: do o = 1, size(c%objs)
         if (.not. op) return
         if (c%objs(o)%role_id /= role_solid .or. o == pr%own) cycle solids
         if (.not. spans(c, o, pr%z)) cycle solids
         if (point_in_polygon(x, c%objs(o)%v)) op = .false.
      end do solids
      if (op .and. ndim == 3) op = .not. in_mesh(c, [x, pr%z], 0)
   end function open_point

   !> Whether the point x (3D) lies inside an &stl solid's mesh other than
   !> mesh skip.
   logical function in_mesh(c, x, skip) result(inside)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: x(3)
      integer, intent(in) :: skip
      inside = mesh_holding(c%meshes, x, skip) > 0
   end function in_mesh

   !> The triangles of &stl solid k with free space just outside their
   !> centroid (inside the domain, in no other solid: a box, a polygon, a slope
   !> across that z, or another mesh), appended to faces(1:nf). A triangle
   !> counts whole: a mesh should meet the other solids at their faces.
   subroutine mesh_faces(c, k, faces, nf)
      type(case_cfg), intent(in) :: c
      integer, intent(in) :: k
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(inout) :: nf
      integer :: t, o
      real(rp) :: y(3), n(3), x(3), lo(3), hi(3)
      logical :: on
      lo = [c%domain%xmin, c%domain%ymin, c%domain%zmin]
      hi = [c%domain%xmax, c%domain%ymax, c%domain%zmax]
      associate (m => c%meshes(k)%mesh)
         triangles: do t = 1, m%nt
            x = sum(m%v(:, :, t), dim=2)/3.0_rp
            call stl_triangle_point(m%v(:, :, t), x, y, n)
            x = x + 1.0e-3_rp*c%numerics%dp*n
            on = norm2(n) > 0.0_rp .and. all(x > lo) .and. all(x < hi)
            if (on) on = .not. in_mesh(c, x, k)
            solids: do o = 1, size(c%objs)
               if (.not. on) cycle triangles
               if (c%objs(o)%role_id /= role_solid) cycle solids
               if (in_solid(c, o, x(1:ndim))) on = .false.
            end do solids
            if (.not. on) cycle triangles
            call grow(faces, nf)
            nf = nf + 1
            faces(nf)%tri = .true.
            faces(nf)%v = m%v(:, :, t)
            faces(nf)%n = n(1:ndim)
         end do triangles
      end associate
   end subroutine mesh_faces


   !> Where open_at changes between ta and tb along the edge (it differs at the two).
   real(rp) function edge_of_run(c, pr, a, d, tdir, ta, tb) result(t)
      type(case_cfg), intent(in) :: c
      type(probe_t), intent(in) :: pr
      real(rp), intent(in) :: a(nsec), d(nsec), tdir(nsec), ta, tb
      real(rp) :: lo, hi
      logical :: at_lo
      integer :: it
      lo = ta
      hi = tb
      at_lo = open_at(c, pr, a, d, tdir, lo)
      do it = 1, 50
         t = 0.5_rp*(lo + hi)
         if (open_at(c, pr, a, d, tdir, t) .eqv. at_lo) then
            lo = t
         else
            hi = t
         end if
      end do
      t = 0.5_rp*(lo + hi)
   end function edge_of_run

   !> The fluid particles of p in cells of size cs over their bounding box.
   subroutine bin_fluid(p, cs, bins)
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: cs
      type(bins_t), intent(out) :: bins
      integer :: i, c, d, nf, ist
      integer, allocatable :: cell(:)
      character(len=200) :: emsg
      real(rp) :: lo(ndim), hi(ndim)
      lo = huge(1.0_rp)
      hi = -huge(1.0_rp)
      nf = 0
      do i = 1, p%n
         if (p%kind(i) /= kind_fluid) cycle
         nf = nf + 1
         lo = min(lo, p%x(:, i))
         hi = max(hi, p%x(:, i))
      end do
      if (nf == 0) then
         lo = 0.0_rp
         hi = 0.0_rp
      end if
      bins%x0 = lo
      bins%cs = cs
      bins%nc = int((hi - lo)/cs) + 1
      bins%stride(1) = 1
      do d = 2, ndim
         bins%stride(d) = bins%stride(d - 1)*bins%nc(d - 1)
      end do
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (bins%start(product(bins%nc) + 1), bins%idx(nf), cell(p%n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the fluid bins of scene_ghost_offsets')
      bins%start = 0
      do i = 1, p%n
         cell(i) = 0
         if (p%kind(i) /= kind_fluid) cycle
         cell(i) = bin_of(bins, p%x(:, i))
         bins%start(cell(i) + 1) = bins%start(cell(i) + 1) + 1
      end do
      bins%start(1) = 1
      do c = 2, size(bins%start)
         bins%start(c) = bins%start(c) + bins%start(c - 1)
      end do
      ! cell(i)'s next free slot; particles in increasing order within a cell
      do i = 1, p%n
         if (cell(i) == 0) cycle
         bins%idx(bins%start(cell(i))) = i
         bins%start(cell(i)) = bins%start(cell(i)) + 1
      end do
      do c = size(bins%start), 2, -1
         bins%start(c) = bins%start(c - 1)
      end do
      bins%start(1) = 1
   end subroutine bin_fluid

   !> The cell of a point inside the bins' box.
   pure integer function bin_of(bins, x) result(c)
      type(bins_t), intent(in) :: bins
      real(rp), intent(in) :: x(ndim)
      integer :: d
      c = 1
      do d = 1, ndim
         c = c + (min(max(int((x(d) - bins%x0(d))/bins%cs) + 1, 1), bins%nc(d)) - 1)*bins%stride(d)
      end do
   end function bin_of

   !> Unit vector from particle i to the nearest fluid particle (found:
   !> there is one; of equally near ones the first in p). The cells are
   !> searched in shells around the particle's (the cells r cells away along
   !> some axis and no more along any), until the next shell cannot hold a
   !> nearer one.
   subroutine toward_water(p, bins, i, u, found)
      type(particles_t), intent(in) :: p
      type(bins_t), intent(in) :: bins
      integer, intent(in) :: i
      real(rp), intent(out) :: u(ndim)
      logical, intent(out) :: found
      integer :: jmin, ci(ndim), r, rmax, d
      real(rp) :: dmin
      dmin = huge(1.0_rp)
      jmin = 0
      ! the particle's cell, possibly outside the box
      rmax = 0
      do d = 1, ndim
         ci(d) = floor((p%x(d, i) - bins%x0(d))/bins%cs) + 1
         rmax = max(rmax, abs(ci(d) - 1), abs(ci(d) - bins%nc(d)))
      end do
      do r = 0, rmax
         call visit_shell(p, bins, i, ci, r, dmin, jmin)
         ! every point of shell r + 1 is at least r cells away
         if (jmin > 0 .and. (real(r, rp)*bins%cs)**2 > dmin) exit
      end do
      found = jmin > 0
      u = 0.0_rp
      if (found) u = (p%x(:, jmin) - p%x(:, i))/sqrt(dmin)
   end subroutine toward_water

   !> The cells of shell r around cell ci inside the box (rows along x where y,
   !> or z, is r cells away; the two ends of the others), for the fluid
   !> particle nearest to particle i so far: jmin at the squared distance dmin.
   subroutine visit_shell(p, bins, i, ci, r, dmin, jmin)
      type(particles_t), intent(in) :: p
      type(bins_t), intent(in) :: bins
      integer, intent(in) :: i, ci(ndim), r
      real(rp), intent(inout) :: dmin
      integer, intent(inout) :: jmin
      integer :: lo(3), hi(3), ix, iy, iz, d
      lo = 1
      hi = 1
      do d = 1, ndim
         lo(d) = max(ci(d) - r, 1)
         hi(d) = min(ci(d) + r, bins%nc(d))
      end do
      do iz = lo(3), hi(3)
         do iy = lo(2), hi(2)
            if (abs(iy - ci(2)) == r .or. (ndim == 3 .and. abs(iz - ci(ndim)) == r)) then
               do ix = lo(1), hi(1)
                  call visit_cell(p, bins, i, [ix, iy, iz], dmin, jmin)
               end do
            else
               call visit_cell(p, bins, i, [ci(1) - r, iy, iz], dmin, jmin)
               if (r > 0) call visit_cell(p, bins, i, [ci(1) + r, iy, iz], dmin, jmin)
            end if
         end do
      end do
   end subroutine visit_shell

   !> The particles of cell ix(1:ndim), if it is one of the box.
   pure subroutine visit_cell(p, bins, i, ix, dmin, jmin)
      type(particles_t), intent(in) :: p
      type(bins_t), intent(in) :: bins
      integer, intent(in) :: i, ix(3)
      real(rp), intent(inout) :: dmin
      integer, intent(inout) :: jmin
      integer :: k, j, c, d
      real(rp) :: d2
      c = 1
      do d = 1, ndim
         if (ix(d) < 1 .or. ix(d) > bins%nc(d)) return
         c = c + (ix(d) - 1)*bins%stride(d)
      end do
      do k = bins%start(c), bins%start(c + 1) - 1
         j = bins%idx(k)
         d2 = sum((p%x(:, j) - p%x(:, i))**2)
         if (d2 < dmin .or. (.not. d2 > dmin .and. j < jmin)) then
            dmin = d2
            jmin = j
         end if
      end do
   end subroutine visit_cell

   !> The nearest point to x of the faces that look towards u (outward
   !> normal . u > 0; found: one does); u = 0: of all faces.
   function nearest_on_faces(c, x, u, faces, found) result(q)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: x(ndim), u(ndim)
      type(face_t), intent(in) :: faces(:)
      logical, intent(out) :: found
      real(rp) :: q(ndim), y(ndim), dmin, dd, y3(3), n3(3)
      integer :: k
      q = x
      dmin = huge(1.0_rp)
      found = .false.
      do k = 1, size(faces)
         if (dot_product(faces(k)%n, u) <= 0.0_rp .and. dot_product(u, u) > 0.0_rp) cycle
         if (faces(k)%tri) then
            call stl_triangle_point(faces(k)%v, pad3(x), y3, n3)
            y = y3(1:ndim)
         else if (faces(k)%cap > 0) then
            ! straight across to the plane of an end face, where it is open
            if (.not. open_point(c, probe_t(faces(k)%z0 + faces(k)%n(ndim)*1.0e-3_rp*c%numerics%dp, faces(k)%cap), &
                                 x(1:nsec))) cycle
            y = x
            y(ndim) = faces(k)%z0
         else
            y(1:nsec) = nearest_on_segment(x(1:nsec), faces(k)%a, faces(k)%b)
            if (ndim == 3) y(ndim) = min(max(x(ndim), faces(k)%z0), faces(k)%z1)
         end if
         dd = norm2(y - x)
         if (dd < dmin) then
            dmin = dd
            q = y
            found = .true.
         end if
      end do
   end function nearest_on_faces

   !> A point of ndim components as three.
   pure function pad3(x) result(y)
      real(rp), intent(in) :: x(ndim)
      real(rp) :: y(3)
      y = 0.0_rp
      y(1:ndim) = x
   end function pad3

   !> The nearest point to x (in the body frame) of a body's surface: its
   !> outline; in 3D the faces of its box, from the box's own frame (of faces
   !> equally near, the first along x, y, z), or its mesh.
   pure function nearest_on_body(x, b, bc) result(q)
      real(rp), intent(in) :: x(ndim)
      type(body_t), intent(in) :: b
      type(body_cfg), intent(in) :: bc
      real(rp) :: q(ndim), y(3), gap(3), w(3), nw(3)
      integer :: a
      if (ndim == 2) then
         q(1:nsec) = nearest_on_outline(x(1:nsec), b%outline)
         return
      end if
      y = 0.0_rp
      y(1:ndim) = x
      y = matmul(y, b%turn)
      if (bc%shape_id == shape_stl) then
         ! the mesh's nearest point, in its own frame
         call stl_nearest(bc%mesh, y, w, nw)
         y = matmul(b%turn, w)
         q = y(1:ndim)
         return
      end if
      gap = b%half - abs(y)
      a = minloc(gap, dim=1)
      y(a) = sign(b%half(a), y(a))
      y = matmul(b%turn, y)
      q = y(1:ndim)
   end function nearest_on_body

   !> The nearest point to x of a closed outline.
   pure function nearest_on_outline(x, v) result(q)
      real(rp), intent(in) :: x(nsec), v(:, :)
      real(rp) :: q(nsec), y(nsec), dmin
      integer :: k, nv
      nv = size(v, 2)
      dmin = huge(1.0_rp)
      q = x
      do k = 1, nv
         y = nearest_on_segment(x, v(:, k), v(:, modulo(k, nv) + 1))
         if (norm2(y - x) < dmin) then
            dmin = norm2(y - x)
            q = y
         end if
      end do
   end function nearest_on_outline

   pure function nearest_on_segment(x, a, b) result(y)
      real(rp), intent(in) :: x(nsec), a(nsec), b(nsec)
      real(rp) :: y(nsec), e(nsec), t
      e = b - a
      t = max(0.0_rp, min(1.0_rp, dot_product(x - a, e)/max(dot_product(e, e), tiny(1.0_rp))))
      y = a + t*e
   end function nearest_on_segment
end module scene_ghosts

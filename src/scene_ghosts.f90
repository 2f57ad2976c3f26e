!> The ghost points of the modified dynamic boundary (bc_mdbc): for every
!> solid particle within 2h of a face the water can touch, the offset gof
!> from the particle to its mirror across that face (twice the way to the
!> nearest point of the face). The faces of fixed and moving walls are the
!> stretches of the solids' edges with no other solid and no domain edge
!> beyond them; of those, a particle takes the nearest that looks towards
!> the water (its outward normal towards the fluid particle nearest to the
!> particle), so that the middle row of a wall with free space behind it
!> mirrors into the tank and not out of it, nor through the wall's top. Near a corner of the water the nearest point is the
!> corner, and the ghost point lies on its bisector (as in DualSPHysics).
!> A body's particles mirror across its own outline. Particles farther
!> than 2h from every face, and the particles of filters (massless to the
!> water), get no ghost point (gof = 0).
module scene_ghosts
   use kinds, only: rp
   use constants, only: kind_fluid, kind_filter
   use input, only: case_cfg
   use options, only: role_solid
   use particles, only: particles_t
   use body_dynamics, only: body_t
   use geom, only: point_in_polygon, polygon_area
   use errors, only: alloc_check, input_error
   use input_check, only: int_str, real_str
   implicit none
   private
   public :: scene_ghost_offsets

   !> a stretch of a solid's edge that the water can touch, and its outward normal
   type :: face_t
      real(rp) :: a(2), b(2), n(2)
   end type face_t

   !> The fluid particles binned in square cells, for the nearest one to a
   !> point: cell (ix, iy) holds idx(start(c) : start(c + 1) - 1), c = ix +
   !> (iy - 1) nx, in increasing particle order.
   type :: bins_t
      real(rp) :: x0(2) = 0.0_rp, cs = 1.0_rp
      integer :: nx = 0, ny = 0
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
      real(rp) :: u(2), q(2)
      logical :: found
      if (.not. p%mdbc) return
      nobj = size(c%objs)
      call exposed_faces(c, faces)
      call bin_fluid(p, 2.0_rp*h, bins)
      do i = 1, p%n
         p%gof(:, i) = 0.0_rp
         if (p%kind(i) == kind_fluid .or. p%kind(i) == kind_filter) cycle
         b = p%body(i) - nobj
         if (b >= 1) then
            ! a body: its own outline, in the body frame
            q = nearest_on_outline(p%xb(:, i), bodies(b)%outline)
            if (norm2(q - p%xb(:, i)) < 2.0_rp*h) p%gof(:, i) = 2.0_rp*(q - p%xb(:, i))
         else
            ! too deep for any water to see it: no ghost (and no search)
            q = nearest_on_faces(p%x(:, i), [0.0_rp, 0.0_rp], faces, found)
            if (.not. found .or. norm2(q - p%x(:, i)) >= 2.0_rp*h) cycle
            call toward_water(p, bins, i, u, found)
            if (.not. found) cycle
            q = nearest_on_faces(p%x(:, i), u, faces, found)
            if (.not. found .or. norm2(q - p%x(:, i)) >= 2.0_rp*h) cycle
            p%gof(:, i) = 2.0_rp*(q - p%x(:, i))
            if (norm2(q - p%x(:, i)) < 0.6_rp*c%numerics%dp) call check_thick(c, p%x(:, i), q, h)
         end if
      end do
      ! the body frame is the start pose: bodies_place turns gob into gof
      p%gob(:, 1:p%n) = p%gof(:, 1:p%n)
   end subroutine scene_ghost_offsets

   !> A solid behind a wetted face must be 2h - dp/2 thick at least: the water
   !> half a spacing from the face has then the whole kernel's support of
   !> solid particles; a thinner wall lets it through (the dynamic boundary's
   !> own continuity makes a thin wall stiffer, mDBC's extrapolated pressure
   !> does not). x: a particle of the solid's first row, q: its face point.
   subroutine check_thick(c, x, q, h)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: x(2), q(2), h
      real(rp) :: deep(2), need
      integer :: o, k
      need = 2.0_rp*h - 0.5_rp*c%numerics%dp
      deep = q + need*(x - q)/norm2(x - q)
      k = 0
      do o = 1, size(c%objs)
         if (c%objs(o)%role_id /= role_solid) cycle
         if (point_in_polygon(deep, c%objs(o)%v)) return
         if (k == 0 .and. point_in_polygon(x, c%objs(o)%v)) k = o
      end do
      if (k == 0) k = 1
      call input_error(c%file, 'numerics', 'boundary', "'mdbc' needs the solids at least 2h - dp/2 = "// &
                       real_str(need)//' m thick behind every face the water can touch ('// &
                       int_str(ceiling(2.0_rp*h/c%numerics%dp - 1.0e-9_rp))//' rows); behind the face at ('// &
                       real_str(q(1))//', '//real_str(q(2))//') &'//trim(c%objs(k)%group)//' #'// &
                       int_str(c%objs(k)%index)//' is thinner: make it thicker (with the &domain room '// &
                       "behind it) or use 'dynamic'")
   end subroutine check_thick

   !> The stretches of the solids' edges with neither another solid nor the
   !> domain's edge just outside them.
   subroutine exposed_faces(c, faces)
      type(case_cfg), intent(in) :: c
      type(face_t), allocatable, intent(out) :: faces(:)
      integer :: k, e, nv, nf, ist
      real(rp) :: a(2), d(2)
      character(len=200) :: emsg
      allocate (faces(64), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'faces in exposed_faces')
      nf = 0
      do k = 1, size(c%objs)
         if (c%objs(k)%role_id /= role_solid) cycle
         associate (v => c%objs(k)%v)
            nv = size(v, 2)
            edges: do e = 1, nv
               a = v(:, e)
               d = v(:, modulo(e, nv) + 1) - a
               if (norm2(d) <= 0.0_rp) cycle edges
               call open_runs(c, a, d, sign(1.0_rp, polygon_area(v))*[d(2), -d(1)]/norm2(d), faces, nf)
            end do edges
         end associate
      end do
      faces = faces(1:nf)
   end subroutine exposed_faces

   !> The open stretches of the edge from a to a + d (outward normal nrm),
   !> appended to faces(1:nf): the edge sampled every dp/4 between its
   !> vertices (at a vertex the test point lies on the next solid's edge,
   !> where point_in_polygon may go either way), the ends of each open run
   !> found by bisection.
   subroutine open_runs(c, a, d, nrm, faces, nf)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: a(2), d(2), nrm(2)
      type(face_t), allocatable, intent(inout) :: faces(:)
      integer, intent(inout) :: nf
      type(face_t), allocatable :: tmp(:)
      integer :: m, s, ist
      real(rp) :: t0, t1
      logical :: prev, now
      character(len=200) :: emsg
      m = max(2, ceiling(4.0_rp*norm2(d)/c%numerics%dp))
      prev = .false.
      t0 = 0.0_rp
      do s = 1, m
         now = open_at(c, a, d, nrm, (s - 0.5_rp)/m)
         if (now .and. .not. prev) then
            t0 = 0.0_rp
            if (s > 1) t0 = edge_of_run(c, a, d, nrm, (s - 1.5_rp)/m, (s - 0.5_rp)/m)
         else if (prev .and. .not. now) then
            t1 = edge_of_run(c, a, d, nrm, (s - 1.5_rp)/m, (s - 0.5_rp)/m)
            call add(a + t0*d, a + t1*d)
         end if
         prev = now
      end do
      if (prev) call add(a + t0*d, a + d)
   contains
      subroutine add(x0, x1)
         real(rp), intent(in) :: x0(2), x1(2)
         if (nf == size(faces)) then
            allocate (tmp(2*nf), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 'faces in open_runs')
            tmp(1:nf) = faces
            call move_alloc(tmp, faces)
         end if
         nf = nf + 1
         faces(nf) = face_t(x0, x1, nrm)
      end subroutine add
   end subroutine open_runs

   !> Whether the point at t along the edge from a to a + d (outward normal
   !> nrm) has free space just outside it: inside the domain, in no solid.
   logical function open_at(c, a, d, nrm, t) result(op)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: a(2), d(2), nrm(2), t
      real(rp) :: x(2)
      integer :: o
      x = a + t*d + 1.0e-3_rp*c%numerics%dp*nrm
      op = x(1) > c%domain%xmin .and. x(1) < c%domain%xmax .and. x(2) > c%domain%ymin .and. x(2) < c%domain%ymax
      solids: do o = 1, size(c%objs)
         if (.not. op) return
         if (c%objs(o)%role_id /= role_solid) cycle solids
         if (point_in_polygon(x, c%objs(o)%v)) op = .false.
      end do solids
   end function open_at

   !> Where open_at changes between ta and tb along the edge (it differs at the two).
   real(rp) function edge_of_run(c, a, d, nrm, ta, tb) result(t)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: a(2), d(2), nrm(2), ta, tb
      real(rp) :: lo, hi
      logical :: at_lo
      integer :: it
      lo = ta
      hi = tb
      at_lo = open_at(c, a, d, nrm, lo)
      do it = 1, 50
         t = 0.5_rp*(lo + hi)
         if (open_at(c, a, d, nrm, t) .eqv. at_lo) then
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
      integer :: i, c, nf, ist
      integer, allocatable :: cell(:)
      character(len=200) :: emsg
      real(rp) :: lo(2), hi(2)
      lo = huge(1.0_rp)
      hi = -huge(1.0_rp)
      nf = 0
      do i = 1, p%n
         if (p%kind(i) /= kind_fluid) cycle
         nf = nf + 1
         lo = min(lo, p%x(1:2, i))
         hi = max(hi, p%x(1:2, i))
      end do
      if (nf == 0) then
         lo = 0.0_rp
         hi = 0.0_rp
      end if
      bins%x0 = lo
      bins%cs = cs
      bins%nx = int((hi(1) - lo(1))/cs) + 1
      bins%ny = int((hi(2) - lo(2))/cs) + 1
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (bins%start(bins%nx*bins%ny + 1), bins%idx(nf), cell(p%n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the fluid bins of scene_ghost_offsets')
      bins%start = 0
      do i = 1, p%n
         cell(i) = 0
         if (p%kind(i) /= kind_fluid) cycle
         cell(i) = bin_of(bins, p%x(1, i), p%x(2, i))
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
   pure integer function bin_of(bins, x, y) result(c)
      type(bins_t), intent(in) :: bins
      real(rp), intent(in) :: x, y
      integer :: ix, iy
      ix = min(max(int((x - bins%x0(1))/bins%cs) + 1, 1), bins%nx)
      iy = min(max(int((y - bins%x0(2))/bins%cs) + 1, 1), bins%ny)
      c = ix + (iy - 1)*bins%nx
   end function bin_of

   !> Unit vector from particle i to the nearest fluid particle (found:
   !> there is one; of equally near ones the first in p). The cells are
   !> searched in square rings around the particle's, until the next ring
   !> cannot hold a nearer one.
   subroutine toward_water(p, bins, i, u, found)
      type(particles_t), intent(in) :: p
      type(bins_t), intent(in) :: bins
      integer, intent(in) :: i
      real(rp), intent(out) :: u(2)
      logical, intent(out) :: found
      integer :: jmin, cx, cy, r, rmax, ix, iy
      real(rp) :: dmin
      dmin = huge(1.0_rp)
      jmin = 0
      ! the particle's cell, possibly outside the box
      cx = floor((p%x(1, i) - bins%x0(1))/bins%cs) + 1
      cy = floor((p%x(2, i) - bins%x0(2))/bins%cs) + 1
      rmax = max(abs(cx - 1), abs(cx - bins%nx), abs(cy - 1), abs(cy - bins%ny))
      do r = 0, rmax
         do ix = max(cx - r, 1), min(cx + r, bins%nx)
            call visit(ix, cy - r)
            if (r > 0) call visit(ix, cy + r)
         end do
         do iy = max(cy - r + 1, 1), min(cy + r - 1, bins%ny)
            call visit(cx - r, iy)
            if (r > 0) call visit(cx + r, iy)
         end do
         ! every point of ring r + 1 is at least r cells away
         if (jmin > 0 .and. (real(r, rp)*bins%cs)**2 > dmin) exit
      end do
      found = jmin > 0
      u = 0.0_rp
      if (found) u = (p%x(:, jmin) - p%x(:, i))/sqrt(dmin)
   contains
      !> The particles of cell (ix, iy), if it is one of the box.
      subroutine visit(ix, iy)
         integer, intent(in) :: ix, iy
         integer :: k, j, c
         real(rp) :: d2
         if (ix < 1 .or. ix > bins%nx .or. iy < 1 .or. iy > bins%ny) return
         c = ix + (iy - 1)*bins%nx
         do k = bins%start(c), bins%start(c + 1) - 1
            j = bins%idx(k)
            d2 = (p%x(1, j) - p%x(1, i))**2 + (p%x(2, j) - p%x(2, i))**2
            if (d2 < dmin .or. (.not. d2 > dmin .and. j < jmin)) then
               dmin = d2
               jmin = j
            end if
         end do
      end subroutine visit
   end subroutine toward_water

   !> The nearest point to x of the faces that look towards u (outward
   !> normal . u > 0; found: one does); u = 0: of all faces.
   function nearest_on_faces(x, u, faces, found) result(q)
      real(rp), intent(in) :: x(2), u(2)
      type(face_t), intent(in) :: faces(:)
      logical, intent(out) :: found
      real(rp) :: q(2), y(2), dmin, dd
      integer :: k
      q = x
      dmin = huge(1.0_rp)
      found = .false.
      do k = 1, size(faces)
         y = nearest_on_segment(x, faces(k)%a, faces(k)%b)
         if (dot_product(faces(k)%n, u) <= 0.0_rp .and. dot_product(u, u) > 0.0_rp) cycle
         dd = norm2(y - x)
         if (dd < dmin) then
            dmin = dd
            q = y
            found = .true.
         end if
      end do
   end function nearest_on_faces

   !> The nearest point to x of a closed outline.
   pure function nearest_on_outline(x, v) result(q)
      real(rp), intent(in) :: x(2), v(:, :)
      real(rp) :: q(2), y(2), dmin
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
      real(rp), intent(in) :: x(2), a(2), b(2)
      real(rp) :: y(2), e(2), t
      e = b - a
      t = max(0.0_rp, min(1.0_rp, dot_product(x - a, e)/max(dot_product(e, e), tiny(1.0_rp))))
      y = a + t*e
   end function nearest_on_segment
end module scene_ghosts

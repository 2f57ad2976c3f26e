!> Triangle meshes from STL files (3D solids and bodies): a small reader of
!> both STL forms, binary (80-byte header, a 4-byte triangle count, then per
!> triangle a normal and three vertices as 4-byte reals and a 2-byte
!> attribute) and ASCII (solid / facet normal / outer loop / vertex x y z /
!> endloop / endfacet / endsolid), and what the scene needs of a closed
!> mesh: its volume, centroid and inertia tensor (the divergence theorem over
!> the tetrahedra from the origin to each triangle, Tonon 2004), whether a
!> point is inside (the winding number: the solid angles of the triangles
!> seen from the point, summed; 4 pi inside a closed mesh, 0 outside), and the
!> nearest point of the surface with its triangle's normal. A mesh must be
!> closed (every edge shared by exactly two triangles, once each way) and is
!> turned outward when its triangles are wound inward.
module geom_stl
   use, intrinsic :: iso_fortran_env, only: int16, int32, int64, real32
   use kinds, only: rp
   use constants, only: pi, path_len
   use errors, only: alloc_check, input_error
   use input_check, only: int_str
   implicit none
   private
   public :: stl_t, stl_read, stl_props, stl_inside, stl_nearest, stl_bounds, stl_triangle_point, stl_sort_points

   !> A triangle mesh: v(:, k, t) is vertex k (1 to 3) of triangle t, wound
   !> counter-clockwise seen from outside.
   type :: stl_t
      integer :: nt = 0
      real(rp), allocatable :: v(:, :, :)
   end type stl_t

contains

   !> The mesh of the STL file path, its coordinates times scale; file, group
   !> and var name the case file, its group and the variable in the messages of
   !> a bad mesh.
   subroutine stl_read(path, scale, file, group, var, mesh)
      character(len=*), intent(in) :: path, file, group, var
      real(rp), intent(in) :: scale
      type(stl_t), intent(out) :: mesh
      integer :: u, ios, nt
      integer(int32) :: count
      character(len=80) :: header
      character(len=256) :: msg
      integer(int64) :: bytes
      logical :: there
      inquire (file=path, exist=there, size=bytes)
      if (.not. there) call input_error(file, group, var, "no such file: '"//trim(path)//"'")
      open (newunit=u, file=path, access='stream', form='unformatted', status='old', action='read', &
            iostat=ios, iomsg=msg)
      if (ios /= 0) call input_error(file, group, var, "cannot open '"//trim(path)//"': "//trim(msg))
      header = ''
      count = -1
      read (u, iostat=ios, iomsg=msg) header, count
      close (u)
      ! binary when the size is that of its triangle count; ASCII otherwise (some
      ! binary files start with 'solid' too, so the size decides)
      if (ios == 0 .and. count >= 0) then
         if (bytes == 84_int64 + 50_int64*int(count, int64)) then
            nt = count
            call read_binary(path, nt, file, group, var, mesh)
            call finish(mesh, scale, path, file, group, var)
            return
         end if
      end if
      call read_ascii(path, file, group, var, mesh)
      call finish(mesh, scale, path, file, group, var)
   end subroutine stl_read

   subroutine read_binary(path, nt, file, group, var, mesh)
      character(len=*), intent(in) :: path, file, group, var
      integer, intent(in) :: nt
      type(stl_t), intent(inout) :: mesh
      integer :: u, ios, t, ist
      character(len=80) :: header
      integer(int32) :: count
      integer, parameter :: nreal = 12              !< a binary triangle: its normal and three vertices
      real(real32) :: f(nreal)
      integer(int16) :: attr
      character(len=256) :: msg
      character(len=200) :: emsg
      allocate (mesh%v(3, 3, nt), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the triangles of '//trim(path), nt)
      mesh%nt = nt
      open (newunit=u, file=path, access='stream', form='unformatted', status='old', action='read')
      read (u) header, count
      do t = 1, nt
         read (u, iostat=ios, iomsg=msg) f, attr
         if (ios /= 0) call input_error(file, group, var, "'"//trim(path)//"': triangle "//int_str(t)//': '//trim(msg))
         mesh%v(:, :, t) = reshape(real(f(4:12), rp), [3, 3])
      end do
      close (u)
   end subroutine read_binary

   !> The ASCII form: every 'vertex' line, three to a facet.
   subroutine read_ascii(path, file, group, var, mesh)
      character(len=*), intent(in) :: path, file, group, var
      type(stl_t), intent(inout) :: mesh
      integer :: u, ios, nv, line, ist, k
      character(len=path_len) :: text
      character(len=16) :: word
      character(len=256) :: msg
      real(rp) :: x(3)
      real(rp), allocatable :: tmp(:, :, :)
      character(len=200) :: emsg
      open (newunit=u, file=path, status='old', action='read', form='formatted', iostat=ios, iomsg=msg)
      if (ios /= 0) call input_error(file, group, var, "cannot open '"//trim(path)//"': "//trim(msg))
      read (u, '(a)', iostat=ios, iomsg=msg) text
      if (ios /= 0 .or. index(adjustl(text), 'solid') /= 1) call input_error(file, group, var, &
         "'"//trim(path)//"' is neither a binary STL (its size is not 84 + 50 x its triangle count) nor an "// &
         "ASCII one (it does not start with 'solid')")
      allocate (mesh%v(3, 3, 64), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the triangles of '//trim(path))
      nv = 0
      line = 1
      do
         read (u, '(a)', iostat=ios, iomsg=msg) text
         if (ios /= 0) exit
         line = line + 1
         ! tabs as blanks, the keyword in any case
         do k = 1, len_trim(text)
            if (text(k:k) == achar(9)) text(k:k) = ' '
         end do
         text = adjustl(text)
         k = index(text, ' ')
         word = lower(text(1:max(k - 1, 1)))
         if (word /= 'vertex') cycle
         read (text(k:), *, iostat=ios, iomsg=msg) x
         if (ios /= 0) call input_error(file, group, var, "'"//trim(path)//"' line "//int_str(line)// &
                                        ': a vertex needs three numbers')
         nv = nv + 1
         if ((nv - 1)/3 + 1 > size(mesh%v, 3)) then
            allocate (tmp(3, 3, 2*size(mesh%v, 3)), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 'the triangles of '//trim(path))
            tmp(:, :, 1:size(mesh%v, 3)) = mesh%v
            call move_alloc(tmp, mesh%v)
         end if
         mesh%v(:, modulo(nv - 1, 3) + 1, (nv - 1)/3 + 1) = x
      end do
      close (u)
      if (nv == 0) call input_error(file, group, var, "'"//trim(path)//"' has no 'vertex' lines: if it is a "// &
         'binary STL, its size is not 84 + 50 x the triangle count in its header (a file cut short?)')
      if (modulo(nv, 3) /= 0) call input_error(file, group, var, "'"//trim(path)//"': "//int_str(nv)// &
                                               ' vertices, not three to each facet')
      mesh%nt = nv/3
      mesh%v = mesh%v(:, :, 1:mesh%nt)
   end subroutine read_ascii

   !> Scaled; checked for triangles, closedness and volume; wound outward.
   subroutine finish(mesh, scale, path, file, group, var)
      type(stl_t), intent(inout) :: mesh
      real(rp), intent(in) :: scale
      character(len=*), intent(in) :: path, file, group, var
      real(rp) :: vol, c(3), j(3, 3), t(3)
      integer :: open_edges, k
      if (mesh%nt < 4) call input_error(file, group, var, "'"//trim(path)//"' has "//int_str(mesh%nt)// &
                                        ' triangles: a closed solid has at least 4')
      if (.not. all(abs(mesh%v) < huge(1.0_rp))) call input_error(file, group, var, "'"//trim(path)// &
                                                                  "' has a coordinate that is not a number")
      mesh%v = scale*mesh%v
      open_edges = unmatched_edges(mesh)
      if (open_edges > 0) call input_error(file, group, var, "'"//trim(path)//"' is not a closed surface: "// &
         int_str(open_edges)//' edges are not shared by exactly two triangles, once each way (the mesh has a hole, '// &
         'or triangles wound both ways)')
      call stl_props(mesh, vol, c, j)
      if (abs(vol) <= 0.0_rp) call input_error(file, group, var, "'"//trim(path)//"' encloses no volume")
      if (vol < 0.0_rp) then
         ! wound inward: turn every triangle
         do k = 1, mesh%nt
            t = mesh%v(:, 2, k)
            mesh%v(:, 2, k) = mesh%v(:, 3, k)
            mesh%v(:, 3, k) = t
         end do
      end if
   end subroutine finish

   !> The number of directed edges (a, b) without the edge (b, a) of another
   !> triangle, or with more than one: 0 for a closed, consistently wound mesh.
   !> Vertices are the same where their coordinates are.
   function unmatched_edges(mesh) result(nbad)
      type(stl_t), intent(in) :: mesh
      integer :: nbad
      integer, allocatable :: id(:), order(:), e(:, :)
      real(rp), allocatable :: key(:, :)
      integer :: n, k, t, m, ist
      character(len=200) :: emsg
      n = 3*mesh%nt
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (key(3, n), id(n), e(2, n), stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
         call alloc_check(ist, emsg, 'the edges of a mesh', n)
         error stop
      end if
      key = reshape(mesh%v, [3, n])
      call stl_sort_points(key, order)
      ! the vertices numbered in sorted order, equal coordinates one number
      m = 1
      id(order(1)) = 1
      do k = 2, n
         if (any(abs(key(:, order(k)) - key(:, order(k - 1))) > 0.0_rp)) m = m + 1
         id(order(k)) = m
      end do
      ! each triangle's three directed edges, (low, high) with the sign of the direction in e(1)
      do t = 1, mesh%nt
         do k = 1, 3
            associate (a => id(3*(t - 1) + k), b => id(3*(t - 1) + modulo(k, 3) + 1))
               e(:, 3*(t - 1) + k) = [merge(1, -1, a < b)*min(a, b), max(a, b)]
            end associate
         end do
      end do
      nbad = count_unpaired(e)
   end function unmatched_edges

   !> Directed edges (sign of e(1): the direction) that do not come as exactly one
   !> pair of opposite directions.
   function count_unpaired(e) result(nbad)
      integer, intent(in) :: e(:, :)
      integer :: nbad, n, k, l, up, down
      integer, allocatable :: order(:)
      real(rp), allocatable :: key(:, :)
      integer :: ist
      character(len=200) :: emsg
      n = size(e, 2)
      allocate (key(3, n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the edges of a mesh', n)
      key(1, :) = real(abs(e(1, :)), rp)
      key(2, :) = real(e(2, :), rp)
      key(3, :) = 0.0_rp
      call stl_sort_points(key, order)
      nbad = 0
      k = 1
      do while (k <= n)
         l = k
         same: do while (l < n)
            if (abs(e(1, order(l + 1))) /= abs(e(1, order(k))) .or. e(2, order(l + 1)) /= e(2, order(k))) exit same
            l = l + 1
         end do same
         up = count(e(1, order(k:l)) > 0)
         down = (l - k + 1) - up
         if (.not. (up == 1 .and. down == 1)) nbad = nbad + (l - k + 1)
         k = l + 1
      end do
   end function count_unpaired

   !> The order of the points x(:, k) sorted by their first coordinate, then the
   !> second, and so on (merge sort).
   subroutine stl_sort_points(x, order)
      real(rp), intent(in) :: x(:, :)
      integer, allocatable, intent(out) :: order(:)
      integer, allocatable :: tmp(:)
      integer :: n, w, lo, mid, hi, i, j, k, ist
      character(len=200) :: emsg
      n = size(x, 2)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (order(n), tmp(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the sort of a mesh', n)
      order = [(k, k = 1, n)]
      w = 1
      do while (w < n)
         lo = 1
         do while (lo <= n - w)
            mid = lo + w - 1
            hi = min(lo + 2*w - 1, n)
            i = lo
            j = mid + 1
            k = lo
            do while (i <= mid .and. j <= hi)
               if (.not. before(order(j), order(i))) then
                  tmp(k) = order(i)
                  i = i + 1
               else
                  tmp(k) = order(j)
                  j = j + 1
               end if
               k = k + 1
            end do
            tmp(k:k + mid - i) = order(i:mid)
            k = k + mid - i + 1
            tmp(k:k + hi - j) = order(j:hi)
            order(lo:hi) = tmp(lo:hi)
            lo = lo + 2*w
         end do
         w = 2*w
      end do
   contains
      logical function before(a, b)
         integer, intent(in) :: a, b
         integer :: d
         before = .false.
         do d = 1, size(x, 1)
            if (x(d, a) < x(d, b)) then
               before = .true.
               return
            end if
            if (x(d, a) > x(d, b)) return
         end do
      end function before
   end subroutine stl_sort_points

   !> Volume, centroid and the inertia tensor about the centroid per unit
   !> density of the solid the mesh encloses: sums over the tetrahedra from the
   !> origin to each triangle (signed by its winding; Tonon 2004, J. Math.
   !> Stat. 1, 8-11, for the second moments).
   pure subroutine stl_props(mesh, vol, cen, inertia)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(out) :: vol, cen(3), inertia(3, 3)
      real(rp) :: a(3), b(3), c(3), dv, s(3, 3)
      integer :: t, p, q
      vol = 0.0_rp
      cen = 0.0_rp
      s = 0.0_rp          ! the second moments: the integral of x_p x_q
      do t = 1, mesh%nt
         a = mesh%v(:, 1, t)
         b = mesh%v(:, 2, t)
         c = mesh%v(:, 3, t)
         dv = dot_product(a, cross(b, c))/6.0_rp
         vol = vol + dv
         cen = cen + dv*(a + b + c)/4.0_rp
         ! over a tetrahedron (0, a, b, c): dv/20 (sum of the vertices' products + the
         ! product of their sums)
         do q = 1, 3
            do p = 1, 3
               s(p, q) = s(p, q) + dv/20.0_rp*(a(p)*a(q) + b(p)*b(q) + c(p)*c(q) + (a(p) + b(p) + c(p))*(a(q) + b(q) + c(q)))
            end do
         end do
      end do
      if (abs(vol) > 0.0_rp) cen = cen/vol
      ! about the centroid: I = trace(S) 1 - S, S taken about the centroid
      s = s - vol*spread(cen, 2, 3)*spread(cen, 1, 3)
      inertia = -s
      do p = 1, 3
         inertia(p, p) = inertia(p, p) + (s(1, 1) + s(2, 2) + s(3, 3))
      end do
   end subroutine stl_props

   !> Whether x is inside the closed mesh: the winding number, the sum of the
   !> solid angles of the triangles seen from x (Van Oosterom and Strackee 1983)
   !> over 4 pi, is 1 inside and 0 outside.
   pure logical function stl_inside(mesh, x) result(inside)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(in) :: x(3)
      real(rp) :: a(3), b(3), c(3), la, lb, lc, omega
      integer :: t
      omega = 0.0_rp
      do t = 1, mesh%nt
         a = mesh%v(:, 1, t) - x
         b = mesh%v(:, 2, t) - x
         c = mesh%v(:, 3, t) - x
         la = norm2(a); lb = norm2(b); lc = norm2(c)
         omega = omega + 2.0_rp*atan2(dot_product(a, cross(b, c)), &
                                      la*lb*lc + dot_product(a, b)*lc + dot_product(a, c)*lb + dot_product(b, c)*la)
      end do
      inside = omega > 2.0_rp*pi
   end function stl_inside

   !> The nearest point q of the mesh's surface to x, and the outward unit
   !> normal n of its triangle.
   pure subroutine stl_nearest(mesh, x, q, n)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(in) :: x(3)
      real(rp), intent(out) :: q(3), n(3)
      real(rp) :: y(3), c(3), d2, best
      integer :: t
      best = huge(1.0_rp)
      q = x
      n = 0.0_rp
      do t = 1, mesh%nt
         call stl_triangle_point(mesh%v(:, :, t), x, y, c)
         ! a triangle of no area has no normal: its points are its neighbours' too
         if (.not. norm2(c) > 0.0_rp) cycle
         d2 = sum((y - x)**2)
         if (d2 < best) then
            best = d2
            q = y
            n = c
         end if
      end do
   end subroutine stl_nearest

   !> The nearest point y of the triangle v(:, 1:3) to x, and its outward unit
   !> normal n (0 for a triangle of no area).
   pure subroutine stl_triangle_point(v, x, y, n)
      real(rp), intent(in) :: v(3, 3), x(3)
      real(rp), intent(out) :: y(3), n(3)
      y = nearest_on_triangle(x, v(:, 1), v(:, 2), v(:, 3))
      n = cross(v(:, 2) - v(:, 1), v(:, 3) - v(:, 1))
      if (norm2(n) > 0.0_rp) n = n/norm2(n)
   end subroutine stl_triangle_point

   !> The smallest box (lo, hi) around the mesh.
   pure subroutine stl_bounds(mesh, lo, hi)
      type(stl_t), intent(in) :: mesh
      real(rp), intent(out) :: lo(3), hi(3)
      lo = minval(minval(mesh%v, dim=3), dim=2)
      hi = maxval(maxval(mesh%v, dim=3), dim=2)
   end subroutine stl_bounds

   !> The nearest point of the triangle (a, b, c) to x (Ericson 2005, 5.1.5).
   pure function nearest_on_triangle(x, a, b, c) result(q)
      real(rp), intent(in) :: x(3), a(3), b(3), c(3)
      real(rp) :: q(3), ab(3), ac(3), ap(3), bp(3), cp(3), d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, den
      ab = b - a; ac = c - a; ap = x - a
      d1 = dot_product(ab, ap); d2 = dot_product(ac, ap)
      if (d1 <= 0.0_rp .and. d2 <= 0.0_rp) then
         q = a
         return
      end if
      bp = x - b
      d3 = dot_product(ab, bp); d4 = dot_product(ac, bp)
      if (d3 >= 0.0_rp .and. d4 <= d3) then
         q = b
         return
      end if
      vc = d1*d4 - d3*d2
      if (vc <= 0.0_rp .and. d1 >= 0.0_rp .and. d3 <= 0.0_rp) then
         q = a + d1/(d1 - d3)*ab
         return
      end if
      cp = x - c
      d5 = dot_product(ab, cp); d6 = dot_product(ac, cp)
      if (d6 >= 0.0_rp .and. d5 <= d6) then
         q = c
         return
      end if
      vb = d5*d2 - d1*d6
      if (vb <= 0.0_rp .and. d2 >= 0.0_rp .and. d6 <= 0.0_rp) then
         q = a + d2/(d2 - d6)*ac
         return
      end if
      va = d3*d6 - d5*d4
      if (va <= 0.0_rp .and. d4 - d3 >= 0.0_rp .and. d5 - d6 >= 0.0_rp) then
         q = b + (d4 - d3)/((d4 - d3) + (d5 - d6))*(c - b)
         return
      end if
      den = 1.0_rp/(va + vb + vc)
      v = vb*den
      w = vc*den
      q = a + v*ab + w*ac
   end function nearest_on_triangle

   !> s in lower case (ASCII).
   pure function lower(s) result(t)
      character(len=*), intent(in) :: s
      character(len=len(s)) :: t
      integer :: k
      t = s
      do k = 1, len(s)
         if (s(k:k) >= 'A' .and. s(k:k) <= 'Z') t(k:k) = achar(iachar(s(k:k)) + 32)
      end do
   end function lower

   pure function cross(a, b) result(c)
      real(rp), intent(in) :: a(3), b(3)
      real(rp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
   end function cross
end module geom_stl

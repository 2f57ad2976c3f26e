!> Plane geometry of polygons: area, point inclusion, overlap, edge normals.
!> Polygons are vertex lists (2, nv), closed implicitly, either orientation.
module geom
   use kinds, only: rp
   implicit none
   private
   public :: polygon_area, point_in_polygon, polygons_overlap, nearest_edge_normal, &
             polygon_self_intersects, distance_to_polygon

contains

   !> Signed area (positive for counter-clockwise vertices).
   pure real(rp) function polygon_area(v) result(a)
      real(rp), intent(in) :: v(:, :)
      integer :: i, j, nv
      nv = size(v, 2)
      a = 0.0_rp
      do i = 1, nv
         j = modulo(i, nv) + 1
         a = a + v(1, i)*v(2, j) - v(1, j)*v(2, i)
      end do
      a = 0.5_rp*a
   end function polygon_area

   !> Crossing-number test; points on an edge may go either way.
   pure logical function point_in_polygon(p, v) result(inside)
      real(rp), intent(in) :: p(2), v(:, :)
      integer :: i, j, nv
      nv = size(v, 2)
      inside = .false.
      j = nv
      do i = 1, nv
         if ((v(2, i) > p(2)) .neqv. (v(2, j) > p(2))) then
            if (p(1) < (v(1, j) - v(1, i))*(p(2) - v(2, i))/(v(2, j) - v(2, i)) + v(1, i)) inside = .not. inside
         end if
         j = i
      end do
   end function point_in_polygon

   pure real(rp) function cross(o, a, b)
      real(rp), intent(in) :: o(2), a(2), b(2)
      cross = (a(1) - o(1))*(b(2) - o(2)) - (a(2) - o(2))*(b(1) - o(1))
   end function cross

   !> Proper crossing of segments ab and cd (touching or collinear does not count).
   pure logical function segments_cross(a, b, c, d, tol) result(x)
      real(rp), intent(in) :: a(2), b(2), c(2), d(2), tol
      real(rp) :: d1, d2, d3, d4
      d1 = cross(c, d, a); d2 = cross(c, d, b)
      d3 = cross(a, b, c); d4 = cross(a, b, d)
      x = ((d1 > tol .and. d2 < -tol) .or. (d1 < -tol .and. d2 > tol)) .and. &
          ((d3 > tol .and. d4 < -tol) .or. (d3 < -tol .and. d4 > tol))
   end function segments_cross

   !> Distance from point p to the outline of polygon v.
   pure real(rp) function distance_to_polygon(p, v) result(dmin)
      real(rp), intent(in) :: p(2), v(:, :)
      integer :: i, j, nv
      real(rp) :: e(2), w(2), t, d
      nv = size(v, 2)
      dmin = huge(1.0_rp)
      do i = 1, nv
         j = modulo(i, nv) + 1
         e = v(:, j) - v(:, i)
         w = p - v(:, i)
         t = max(0.0_rp, min(1.0_rp, dot_product(w, e)/max(dot_product(e, e), tiny(1.0_rp))))
         d = norm2(w - t*e)
         dmin = min(dmin, d)
      end do
   end function distance_to_polygon

   !> True when the interiors of two polygons overlap by more than a
   !> tolerance (polygons that only share an edge or a vertex do not).
   pure logical function polygons_overlap(a, b, tol, step) result(ov)
      real(rp), intent(in) :: a(:, :), b(:, :), tol, step
      integer :: i, j, k, l, na, nb, nx, ny
      real(rp) :: c(2), scale, lo(2), hi(2)
      na = size(a, 2); nb = size(b, 2)
      ov = .false.
      scale = tol*max(maxval(abs(a)), maxval(abs(b)), 1.0_rp)
      do i = 1, na
         j = modulo(i, na) + 1
         do k = 1, nb
            l = modulo(k, nb) + 1
            ! cross products are lengths squared: the tolerance is scale times a length
            if (segments_cross(a(:, i), a(:, j), b(:, k), b(:, l), scale*max(maxval(abs(a)), maxval(abs(b)), 1.0_rp))) then
               ov = .true.
               return
            end if
         end do
      end do
      ! no proper crossing: one may contain the other (a vertex strictly
      ! inside), or they share area along collinear edges; sample the common
      ! bounding box at spacing step for a point strictly inside both
      do i = 1, na
         if (point_in_polygon(a(:, i), b) .and. distance_to_polygon(a(:, i), b) > scale) then
            ov = .true.; return
         end if
      end do
      do k = 1, nb
         if (point_in_polygon(b(:, k), a) .and. distance_to_polygon(b(:, k), a) > scale) then
            ov = .true.; return
         end if
      end do
      lo = max(minval(a, dim=2), minval(b, dim=2))
      hi = min(maxval(a, dim=2), maxval(b, dim=2))
      if (any(hi - lo <= scale)) return
      nx = max(1, ceiling((hi(1) - lo(1))/step))
      ny = max(1, ceiling((hi(2) - lo(2))/step))
      do j = 1, ny
         samples: do i = 1, nx
            c = lo + ([real(i, rp), real(j, rp)] - 0.5_rp)*(hi - lo)/[real(nx, rp), real(ny, rp)]
            if (.not. (point_in_polygon(c, a) .and. point_in_polygon(c, b))) cycle samples
            if (distance_to_polygon(c, a) > scale .and. distance_to_polygon(c, b) > scale) then
               ov = .true.; return
            end if
         end do samples
      end do
   end function polygons_overlap

   !> Any two non-adjacent edges crossing.
   pure logical function polygon_self_intersects(v) result(x)
      real(rp), intent(in) :: v(:, :)
      integer :: i, j, k, l, nv
      real(rp) :: scale
      nv = size(v, 2)
      scale = 1.0e-12_rp*max(maxval(abs(v)), 1.0_rp)
      x = .false.
      do i = 1, nv
         j = modulo(i, nv) + 1
         edges: do k = i + 2, nv
            l = modulo(k, nv) + 1
            if (l == i) cycle edges
            if (segments_cross(v(:, i), v(:, j), v(:, k), v(:, l), scale*scale)) then
               x = .true.; return
            end if
         end do edges
      end do
   end function polygon_self_intersects

   !> Outward unit normal of the polygon edge nearest to p.
   pure function nearest_edge_normal(p, v) result(n)
      real(rp), intent(in) :: p(2), v(:, :)
      real(rp) :: n(2)
      integer :: i, j, nv
      real(rp) :: e(2), w(2), t, d, dmin, s
      nv = size(v, 2)
      s = sign(1.0_rp, polygon_area(v))     ! outward side depends on orientation
      dmin = huge(1.0_rp)
      n = [0.0_rp, 1.0_rp]
      do i = 1, nv
         j = modulo(i, nv) + 1
         e = v(:, j) - v(:, i)
         w = p - v(:, i)
         t = max(0.0_rp, min(1.0_rp, dot_product(w, e)/max(dot_product(e, e), tiny(1.0_rp))))
         d = norm2(w - t*e)
         if (d < dmin - 1.0e-12_rp*max(dmin, 1.0e-300_rp)) then
            dmin = d
            n = s*[e(2), -e(1)]/norm2(e)
         end if
      end do
   end function nearest_edge_normal
end module geom

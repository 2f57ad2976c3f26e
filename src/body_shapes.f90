!> Rigid-body shapes: outline, mass properties from the geometry, and the
!> boundary particles (hollow shells of `layers` rows along the outline).
module body_shapes
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use kinds, only: rp
   use constants, only: pi
   use input_body, only: body_cfg
   use options, only: shape_circle, shape_box, shape_wedge, shape_polygon
   implicit none
   private
   public :: body_outline, body_mass_properties, body_particles

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
      case (shape_box)
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

   !> Mass [kg/m], centre [m] and moment of inertia about the centre
   !> [kg m] from the shape: the particles carry no mass of their own.
   subroutine body_mass_properties(c, mass, cen, inertia)
      type(body_cfg), intent(in) :: c
      real(rp), intent(out) :: mass, cen(2), inertia
      real(rp) :: area, j0, rho
      if (c%shape_id == shape_circle) then
         area = pi*c%radius**2
         cen = [c%x, c%y]
         j0 = 0.5_rp*area*c%radius**2
      else
         call polygon_moments(body_outline(c), area, cen, j0)
      end if
      rho = c%density
      if (c%mass > 0.0_rp) rho = c%mass/area
      mass = rho*area
      inertia = rho*j0
   end subroutine body_mass_properties

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
      real(rp) :: mass, cen(2), inertia, r, a, ang
      real(rp), allocatable :: v(:, :), w(:, :), en(:, :), off(:, :)
      integer :: l, k, m, n, ns, nv, j, cap
      integer :: ist
      character(len=200) :: emsg
      call body_mass_properties(c, mass, cen, inertia)
      cap = 64
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (xb(2, cap), nb(2, cap), surf(cap), stat=ist, errmsg=emsg)
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
            v(:, k) = v(:, k) - cen
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
            if (.not. inset_valid(v, w)) exit
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
            allocate (t2(2, cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't2 in push')
            t2(:, 1:n) = xb(:, 1:n); call move_alloc(t2, xb)
            allocate (t2(2, cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't2 in push')
            t2(:, 1:n) = nb(:, 1:n); call move_alloc(t2, nb)
            allocate (t1(cap), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 't1 in push')
            t1(1:n) = surf(1:n); call move_alloc(t1, surf)
         end if
         n = n + 1
         xb(:, n) = pos
         nb(:, n) = nrm
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

   !> The inset polygon still has the outline's orientation and every edge
   !> points the same way as the original one.
   pure logical function inset_valid(v, w) result(ok)
      real(rp), intent(in) :: v(:, :), w(:, :)
      integer :: k, j, n
      real(rp) :: area, cen(2)
      n = size(v, 2)
      call polygon_props(w, area, cen)
      ok = area > 0.0_rp
      do k = 1, n
         j = modulo(k, n) + 1
         ok = ok .and. dot_product(w(:, j) - w(:, k), v(:, j) - v(:, k)) > 0.0_rp
      end do
   end function inset_valid
end module body_shapes

!> Builds the particles of a case: fluid lattices, wall lattices and slope
!> layers from the geometry objects; hydrostatic density to start from.
module scene
   use kinds, only: rp
   use constants, only: kind_fluid, kind_fixed, kind_moving
   use input, only: case_cfg
   use input_geometry, only: geom_object
   use particles, only: particles_t, particles_grow
   use params, only: params_t, params_init
   use eos, only: eos_density_at_depth
   use geom, only: point_in_polygon, nearest_edge_normal
   use errors, only: fatal
   implicit none
   private
   public :: scene_build

contains

   subroutine scene_build(c, p, prm)
      type(case_cfg), intent(in) :: c
      type(particles_t), intent(inout) :: p
      type(params_t), intent(out) :: prm
      integer :: k, i, nf
      real(rp) :: dp, ybed, ytop
      dp = c%numerics%dp
      p%n = 0
      p%n_id = 0
      do k = 1, size(c%objs)
         if (c%objs(k)%group == 'slope') then
            call add_slope(c%objs(k), k, dp, p, c%objs(1:k - 1))
         else
            call add_lattice(c%objs(k), k, dp, p, c%objs(1:k - 1))
         end if
      end do
      nf = count(p%kind(1:p%n) == kind_fluid)
      ybed = 0.0_rp
      ytop = 0.0_rp
      if (nf > 0) then
         ybed = minval(p%x(2, 1:p%n), mask=p%kind(1:p%n) == kind_fluid) - 0.5_rp*dp
         ytop = maxval(p%x(2, 1:p%n), mask=p%kind(1:p%n) == kind_fluid) + 0.5_rp*dp
      end if
      call params_init(c, ybed, ytop, prm)
      do i = 1, p%n
         p%id(i) = i
         p%v(:, i) = 0.0_rp
         p%mass(i) = prm%rho0*dp*dp
         ! still water: hydrostatic density below the surface, rho0 above
         p%rho(i) = eos_density_at_depth(prm, max(prm%y_surface - p%x(2, i), 0.0_rp))
         p%vm1(:, i) = p%v(:, i)
         p%rhom1(i) = p%rho(i)
         p%p(i) = 0.0_rp
      end do
      p%n_id = p%n
      if (p%n == 0) call fatal(trim(c%file)//': the case makes no particles (add &box, &polygon or &slope groups)', 2)
   end subroutine scene_build

   !> Lattice points (spacing dp, half a spacing in from the bounding box)
   !> inside the object's polygon.
   subroutine add_lattice(o, obj, dp, p, earlier)
      type(geom_object), intent(in) :: o, earlier(:)
      integer, intent(in) :: obj
      real(rp), intent(in) :: dp
      type(particles_t), intent(inout) :: p
      integer :: i, j, nx, ny, k
      real(rp) :: x0, y0, pt(2)
      x0 = minval(o%v(1, :))
      y0 = minval(o%v(2, :))
      nx = nint((maxval(o%v(1, :)) - x0)/dp)
      ny = nint((maxval(o%v(2, :)) - y0)/dp)
      call particles_grow(p, nx*ny)
      do j = 1, ny
         columns: do i = 1, nx
            pt = [x0 + (i - 0.5_rp)*dp, y0 + (j - 0.5_rp)*dp]
            if (.not. point_in_polygon(pt, o%v)) cycle columns
            if (o%role == 'solid') then
               if (inside_earlier_solid(pt, earlier)) cycle columns
            end if
            p%n = p%n + 1
            k = p%n
            p%x(:, k) = pt
            p%xb(:, k) = pt
            if (o%role == 'fluid') then
               p%kind(k) = kind_fluid
               p%body(k) = 0
               p%nrm(:, k) = 0.0_rp
            else
               p%kind(k) = merge(kind_moving, kind_fixed, o%motion /= 'fixed')
               p%body(k) = obj
               p%nrm(:, k) = nearest_edge_normal(pt, o%v)
            end if
         end do columns
      end do
   end subroutine add_lattice

   !> Rows of particles parallel to the slope line, below it.
   subroutine add_slope(o, obj, dp, p, earlier)
      type(geom_object), intent(in) :: o, earlier(:)
      integer, intent(in) :: obj
      real(rp), intent(in) :: dp
      type(particles_t), intent(inout) :: p
      real(rp) :: a(2), b(2), t(2), nrm(2), len, ds, pt(2)
      integer :: i, l, ns, k
      a = o%line(1:2)
      b = o%line(3:4)
      len = norm2(b - a)
      t = (b - a)/len
      nrm = [-t(2), t(1)]
      ns = max(1, nint(len/dp))
      ds = len/ns
      call particles_grow(p, ns*o%layers)
      do l = 1, o%layers
         along: do i = 1, ns
            pt = a + (i - 0.5_rp)*ds*t - (l - 0.5_rp)*dp*nrm
            if (inside_earlier_solid(pt, earlier)) cycle along
            p%n = p%n + 1
            k = p%n
            p%x(:, k) = pt
            p%xb(:, k) = pt
            p%kind(k) = kind_fixed
            p%body(k) = obj
            p%nrm(:, k) = nrm
         end do along
      end do
   end subroutine add_slope

   !> Solids may overlap (a slope resting on a floor, boxes sharing a corner):
   !> where they do, the earlier object keeps its particles and the later one
   !> leaves the shared area empty, so no two wall particles sit together.
   logical function inside_earlier_solid(pt, earlier) result(inside)
      real(rp), intent(in) :: pt(2)
      type(geom_object), intent(in) :: earlier(:)
      integer :: e
      inside = .false.
      do e = 1, size(earlier)
         if (earlier(e)%role /= 'solid') cycle
         if (point_in_polygon(pt, earlier(e)%v)) then
            inside = .true.
            return
         end if
      end do
   end function inside_earlier_solid
end module scene

!> Porous regions: the porosity a fluid particle sees where it is, and the
!> volume-averaged momentum of the water in the pores (doc/porous.md). In a
!> region of porosity n the particles move with the pore (seepage) velocity
!> V; the density the continuity equation integrates is the superficial one,
!> n rho, and the pressure comes from the pore water's density rho. The pair
!> loop gives each particle -(1/rho_i) sum_j V_j (p_i + p_j) grad W_ij, the
!> open water's pressure term with the pore water's density for the particle
!> and the partner's volume V_j = m_j / (n_j rho_j): an estimate of -grad p /
!> rho that needs no gradient of the porosity, so that nothing but the
!> pressure varies where water crosses the stones' edge. Where the porosities
!> of a pair differ its two forces differ: the difference is what the stones
!> give back. The stones resist by the Forchheimer law of Van Gent (1995) in
!> the Darcy velocity u = n V, and their added mass makes the water heavier to
!> accelerate by 1 + c_A.
module porous
   use kinds, only: rp
   use constants, only: kind_fluid, kind_floating, nsec
   use geom, only: point_in_polygon
   implicit none
   private
   public :: porous_region_t, porous_t, porous_point, porous_field, porous_accel, porous_rate_max, porous_lookup, &
             n_por, max_regions

   !> Rows of the per-particle porous properties (porous_field): the porosity,
   !> the linear resistance rate, the quadratic resistance factor, the added
   !> mass.
   integer, parameter :: n_por = 4
   !> the most porous regions of a case (the input refuses more)
   integer, parameter :: max_regions = 100

   type :: porous_region_t
      real(rp), allocatable :: v(:, :)   !< outline (2, nv), counter-clockwise [m]
      real(rp) :: bb(4) = 0.0_rp          !< bounding box grown by half the width: xmin, xmax, ymin, ymax [m]
      real(rp) :: n = 1.0_rp              !< porosity [-]
      real(rp) :: d50 = 1.0_rp            !< nominal stone diameter [m]
      real(rp) :: alpha = 0.0_rp          !< linear resistance coefficient [-]
      real(rp) :: beta = 0.0_rp           !< quadratic resistance coefficient [-]
      real(rp) :: gamma = 0.0_rp          !< added-mass coefficient [-]
      real(rp) :: nu = 1.0e-6_rp          !< kinematic viscosity of the pore water [m2/s]
      real(rp) :: width = 0.0_rp          !< width of the transition from 1 to n across the outline [m]
   end type porous_region_t

   type :: porous_t
      logical :: on = .false.
      type(porous_region_t), allocatable :: r(:)
      ! a grid of cells over the regions (porous_lookup): where a whole cell lies
      ! deep in one region or out of every region's reach, its porous properties
      ! are those of every point in it, and porous_field takes them from here
      real(rp) :: lo(nsec) = 0.0_rp          !< lower corner of the grid [m]
      real(rp) :: cell = 0.0_rp              !< cell size [m]; 0: no grid
      integer :: nc(nsec) = 0                !< cells along each axis
      integer, allocatable :: code(:, :)     !< 0: compute; -1: out of reach; r: deep in region r
      real(rp), allocatable :: deep(:, :)    !< (n_por, regions): the properties deep in each region
   end type porous_t

contains

   !> The porous properties at a point: porosity n, linear rate kl [1/s],
   !> quadratic factor kq [1/m] and added mass ca, so that the stones'
   !> resistance per unit mass of pore water is (kl + kq |V|) V. Each region
   !> weighs in by a smooth step s of the signed distance to its outline (0 a
   !> half width outside, 1 a half width inside);
   !> n = 1 - sum s (1 - n_r), and the coefficients take the local n.
   pure function porous_point(por, x) result(f)
      type(porous_t), intent(in) :: por
      real(rp), intent(in) :: x(nsec)
      real(rp) :: f(n_por)
      real(rp) :: s(max_regions), n, t, d
      integer :: k
      s = 0.0_rp
      do k = 1, size(por%r)
         associate (r => por%r(k))
            if (x(1) < r%bb(1) .or. x(1) > r%bb(2) .or. x(2) < r%bb(3) .or. x(2) > r%bb(4)) cycle
            d = signed_distance(x, r%v)
            if (r%width > 0.0_rp) then
               t = min(max(d/r%width + 0.5_rp, 0.0_rp), 1.0_rp)
               s(k) = t*t*(3.0_rp - 2.0_rp*t)
            else
               s(k) = merge(1.0_rp, 0.0_rp, d > 0.0_rp)
            end if
         end associate
      end do
      f = 0.0_rp
      f(1) = 1.0_rp
      if (all(s(1:size(por%r)) <= 0.0_rp)) return
      n = 1.0_rp - sum(s(1:size(por%r))*(1.0_rp - por%r%n))
      f(1) = n
      do k = 1, size(por%r)
         if (s(k) <= 0.0_rp) cycle
         associate (r => por%r(k))
            ! Van Gent (1995): I = a u + b u|u| with a = alpha (1-n)^2/n^3 nu/(g D^2),
            ! b = beta (1-n)/n^3 /(g D); per unit mass g I, in V = u/n
            f(2) = f(2) + s(k)*r%alpha*r%nu*(1.0_rp - n)**2/(n*n*r%d50*r%d50)
            f(3) = f(3) + s(k)*r%beta*(1.0_rp - n)/(n*r%d50)
            f(4) = f(4) + s(k)*r%gamma*(1.0_rp - n)/n
         end associate
      end do
   end function porous_point

   !> Signed distance from x to the outline v (> 0 inside).
   pure real(rp) function signed_distance(x, v) result(d)
      real(rp), intent(in) :: x(nsec), v(:, :)
      integer :: e, f, nv
      real(rp) :: a(nsec), w(nsec), t
      nv = size(v, 2)
      d = huge(1.0_rp)
      do e = 1, nv
         f = modulo(e, nv) + 1
         a = v(:, f) - v(:, e)
         w = x - v(:, e)
         t = max(0.0_rp, min(1.0_rp, dot_product(w, a)/max(dot_product(a, a), tiny(1.0_rp))))
         d = min(d, norm2(w - t*a))
      end do
      if (.not. point_in_polygon(x(1:2), v)) d = -d
   end function signed_distance

   !> The porous properties of particles 1..n, where they are: the fluid's
   !> pores, and the porosity every particle takes part in the pairs with
   !> (walls and fixed or moving bodies inside a region too, as pore water).
   !> A floating body is never among the stones (it rests on them, on a
   !> filter): its particles are open water to the pores' terms, so that the
   !> water in the pores under it presses on it with its own pressure.
   subroutine porous_field(por, n, x, kind, f)
      type(porous_t), intent(in) :: por
      integer, intent(in) :: n, kind(:)
      real(rp), intent(in) :: x(:, :)
      real(rp), intent(inout) :: f(:, :)
      integer :: i, c(nsec), code
      do i = 1, n
         code = 0
         if (kind(i) == kind_floating) code = -1
         if (por%cell > 0.0_rp .and. code == 0) then
            c = floor((x(1:nsec, i) - por%lo)/por%cell) + 1
            if (any(c < 1) .or. any(c > por%nc)) then
               code = -1
            else
               code = por%code(c(1), c(2))
            end if
         end if
         if (code == -1) then
            f(:, i) = 0.0_rp
            f(1, i) = 1.0_rp
         else if (code > 0) then
            f(:, i) = por%deep(:, code)
         else
            f(:, i) = porous_point(por, x(1:nsec, i))
         end if
      end do
   end subroutine porous_field

   !> The lookup grid of porous_field, cells of size cell over the regions'
   !> reach: a cell whose every point lies at least half a transition inside
   !> one region (where its smooth step is 1) and out of every other's reach
   !> takes that region's properties; one whose every point lies out of every
   !> region's reach the open water's; the others are computed point by point.
   !> Exact: the properties at every point of such a cell are those stored.
   subroutine porous_lookup(por, cell)
      type(porous_t), intent(inout) :: por
      real(rp), intent(in) :: cell
      integer :: i, j, code, ist
      real(rp) :: hi(nsec), c(nsec)
      logical :: found(max_regions)
      character(len=200) :: emsg
      if (.not. por%on .or. size(por%r) == 0 .or. cell <= 0.0_rp) return
      por%lo = [minval(por%r%bb(1)), minval(por%r%bb(3))]
      hi = [maxval(por%r%bb(2)), maxval(por%r%bb(4))]
      por%cell = cell
      por%nc = max(1, ceiling((hi - por%lo)/cell))
      if (allocated(por%code)) deallocate (por%code)
      if (allocated(por%deep)) deallocate (por%deep)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (por%code(por%nc(1), por%nc(2)), por%deep(n_por, size(por%r)), stat=ist, errmsg=emsg)
      if (ist /= 0) then
         por%cell = 0.0_rp                         ! no grid: every point computed
         return
      end if
      por%deep = 0.0_rp
      found = .false.
      do j = 1, por%nc(2)
         do i = 1, por%nc(1)
            c = por%lo + ([i, j] - 0.5_rp)*cell
            code = cell_code(por, c, 0.5_rp*sqrt(2.0_rp)*cell)
            por%code(i, j) = code
            if (code > 0) then
               if (.not. found(code)) por%deep(:, code) = porous_point(por, c)
               found(code) = .true.
            end if
         end do
      end do
   end subroutine porous_lookup

   !> The code of the cell of centre c and half-diagonal half (porous_lookup):
   !> -1 when all of it is out of every region's reach, r when all of it lies
   !> at least half a transition inside region r and out of every other's
   !> reach, 0 otherwise.
   pure integer function cell_code(por, c, half) result(code)
      type(porous_t), intent(in) :: por
      real(rp), intent(in) :: c(nsec), half
      integer :: k, deep_in, reached
      real(rp) :: d, w
      deep_in = 0
      reached = 0
      do k = 1, size(por%r)
         d = signed_distance(c, por%r(k)%v)
         w = 0.5_rp*por%r(k)%width
         if (d + half > -w) reached = reached + 1
         if (d - half >= w) deep_in = k
      end do
      code = 0
      if (reached == 0) then
         code = -1
      else if (reached == 1 .and. deep_in > 0) then
         code = deep_in
      end if
   end function cell_code

   !> The acceleration of the pore water of the fluid particles among 1..n
   !> from acc, which holds the pair sums (-grad p / rho) and gravity: minus
   !> the resistance, all over 1 + c_A; the rates of wall and body particles
   !> among the pores back to their own mass and density. Outside the regions
   !> nothing changes.
   subroutine porous_accel(n, kind, f, v, acc, drho)
      integer, intent(in) :: n, kind(:)
      real(rp), intent(in) :: f(:, :), v(:, :)
      real(rp), intent(inout) :: acc(:, :), drho(:)
      integer :: i
      do i = 1, n
         if (f(1, i) >= 1.0_rp) cycle
         if (kind(i) /= kind_fluid) then
            ! a wall or body particle among the pores took part in the pairs as
            ! pore water of mass n m and density n rho: its own density rate and
            ! its share of the force on its body, per unit of its true mass
            drho(i) = drho(i)/f(1, i)
            acc(:, i) = f(1, i)*acc(:, i)
            cycle
         end if
         acc(:, i) = (acc(:, i) - (f(2, i) + f(3, i)*norm2(v(:, i)))*v(:, i))/(1.0_rp + f(4, i))
      end do
   end subroutine porous_accel

   !> The largest rate of the resistance's linearisation, (kl + 2 kq |V|)/(1 + c_A),
   !> over the fluid particles among 1..n [1/s]: an explicit step must stay below its inverse.
   real(rp) function porous_rate_max(n, kind, f, v) result(k)
      integer, intent(in) :: n, kind(:)
      real(rp), intent(in) :: f(:, :), v(:, :)
      integer :: i
      k = 0.0_rp
      do i = 1, n
         if (f(1, i) >= 1.0_rp .or. kind(i) /= kind_fluid) cycle
         k = max(k, (f(2, i) + 2.0_rp*f(3, i)*norm2(v(:, i)))/(1.0_rp + f(4, i)))
      end do
   end function porous_rate_max
end module porous

!> The boundary particles of 2D bodies (body_shapes: body_particles): a box of
!> nx by ny spacings asked for as many rows as reach its middle is its whole
!> lattice, every site once, whether its number of rows is odd or even (the rows
!> meet on a mid-line that gets its own points, so no hollow is left for the water);
!> with fewer rows it is a shell of that many; no two particles of a box or a wedge
!> closer than half a spacing; every particle inside the outline.
program test_bodies
   use kinds, only: rp
   use options, only: shape_box, shape_wedge
   use input_body, only: body_cfg
   use body_shapes, only: body_particles
   use geom, only: point_in_polygon
   use testing, only: check, test_summary
   implicit none
   real(rp), parameter :: dp = 0.01_rp
   integer :: nx, ny
   character(len=60) :: name

   do nx = 4, 11
      do ny = 4, 7
         write (name, '("box ",i0," x ",i0," spacings, full")') nx, ny
         call box_case(nx, ny, (min(nx, ny) + 1)/2, nx*ny, name)
      end do
   end do
   ! a shell of two rows: 2 (nx + ny) - 4 and 2 (nx + ny) - 12 particles
   call box_case(10, 9, 2, 2*(10 + 9) - 4 + 2*(10 + 9) - 12, 'box 10 x 9 spacings, shell of 2 rows')
   call thin_cases()
   call wedge_case()
   call test_summary('test_bodies')

contains

   subroutine box_case(nx, ny, layers, expected, name)
      integer, intent(in) :: nx, ny, layers, expected
      character(len=*), intent(in) :: name
      type(body_cfg) :: c
      real(rp), allocatable :: xb(:, :), nb(:, :)
      integer, allocatable :: surf(:)
      integer :: i, j, sites
      logical :: once
      c%shape_id = shape_box
      c%width = nx*dp
      c%height = ny*dp
      call body_particles(c, dp, layers, xb, nb, surf)
      call check(size(xb, 2) == expected, trim(name)//': particle count')
      call check(closest(xb) > 0.99_rp*dp, trim(name)//': no two particles closer than dp')
      if (expected == nx*ny) then
         ! every site of the box's lattice holds exactly one particle
         once = .true.
         do j = 1, ny
            do i = 1, nx
               sites = count(norm2(xb - spread([(i - 0.5_rp*(nx + 1))*dp, (j - 0.5_rp*(ny + 1))*dp], 2, &
                                                size(xb, 2)), dim=1) < 0.01_rp*dp)
               once = once .and. sites == 1
            end do
         end do
         call check(once, trim(name)//': every lattice site once')
      end if
   end subroutine box_case

   !> A box 10 x 5 spacings turned by 30 degrees (its mid-line's inset may keep a
   !> sliver of area from rounding), and a box 10 x 3.4 spacings (its second row
   !> would be two lines 0.4 dp apart): no two particles within 0.75 dp, and the
   !> turned box's 50 sites all held.
   subroutine thin_cases()
      type(body_cfg) :: c
      real(rp), allocatable :: xb(:, :), nb(:, :)
      integer, allocatable :: surf(:)
      integer :: a
      do a = 0, 90, 15
         c%shape_id = shape_box
         c%width = 10*dp
         c%height = 5*dp
         c%angle = real(a, rp)
         call body_particles(c, dp, 4, xb, nb, surf)
         write (name, '("box 10 x 5 spacings turned ",i0," deg")') a
         call check(size(xb, 2) == 50, trim(name)//': 50 particles')
         call check(closest(xb) > 0.99_rp*dp, trim(name)//': no two particles closer than dp')
      end do
      c%angle = 0.0_rp
      c%height = 3.4_rp*dp
      call body_particles(c, dp, 4, xb, nb, surf)
      call check(closest(xb) > 0.75_rp*dp, 'box 10 x 3.4 spacings: no two particles within 0.75 dp')
   end subroutine thin_cases

   subroutine wedge_case()
      type(body_cfg) :: c
      real(rp), allocatable :: xb(:, :), nb(:, :), v(:, :)
      integer, allocatable :: surf(:)
      integer :: k
      logical :: inside
      c%shape_id = shape_wedge
      c%nvert = 3
      c%vx(1:3) = [0.0_rp, 0.12_rp, 0.0_rp]
      c%vy(1:3) = [0.0_rp, 0.0_rp, 0.07_rp]
      call body_particles(c, dp, 6, xb, nb, surf)
      call check(closest(xb) > 0.5_rp*dp, 'wedge: no two particles closer than dp/2')
      ! in the body frame the outline is centred on its centroid
      v = reshape([0.0_rp, 0.0_rp, 0.12_rp, 0.0_rp, 0.0_rp, 0.07_rp], [2, 3])
      v = v - spread(sum(v, dim=2)/3.0_rp, 2, 3)
      inside = .true.
      do k = 1, size(xb, 2)
         inside = inside .and. point_in_polygon(xb(:, k), v)
      end do
      call check(inside, 'wedge: every particle inside the outline')
      call check(size(xb, 2) >= nint(0.5_rp*0.12_rp*0.07_rp/dp**2) - 6, 'wedge: about its area over dp^2')
   end subroutine wedge_case

   real(rp) function closest(x) result(d)
      real(rp), intent(in) :: x(:, :)
      integer :: i, j
      d = huge(1.0_rp)
      do j = 2, size(x, 2)
         do i = 1, j - 1
            d = min(d, norm2(x(:, i) - x(:, j)))
         end do
      end do
   end function closest
end program test_bodies

!> The STL reader and mesh properties (geom_stl) against what they must be: a
!> cube written as ASCII STL (its triangles wound inward, which the reader turns)
!> has volume a^3, its centroid at its centre and the inertia tensor a^5/6 times
!> the identity, exactly; an icosphere of radius r (1280 triangles) written as
!> binary STL has the volume of the polyhedron (the same sum about its own
!> centre) and, within the polyhedron's deficit (1.5 %), 4/3 pi r^3 and
!> 2/5 V r^2; points inside and outside are told apart, and the nearest point
!> of the surface and its normal are those of the face. The files are written
!> under build/ (the unit tests run from the repository's root) and removed.
program test_stl
   use, intrinsic :: iso_fortran_env, only: int16, int32, real32
   use kinds, only: rp
   use constants, only: pi
   use geom_stl, only: stl_t, stl_read, stl_props, stl_inside, stl_nearest, stl_bounds
   use testing, only: check, check_close, test_summary
   implicit none
   type(stl_t) :: m
   real(rp) :: vol, cen(3), jj(3, 3), q(3), n(3), lo(3), hi(3), c0(3), r, poly
   real(rp), allocatable :: tri(:, :, :)
   integer :: k
   real(rp), parameter :: a = 0.2_rp

   ! the cube [0.1, 0.3] x [-0.1, 0.1] x [0, 0.2], its triangles wound inward
   call cube_triangles(a, [0.1_rp, -0.1_rp, 0.0_rp], tri)
   tri = tri(:, [1, 3, 2], :)
   call write_ascii('build/test_stl_cube.stl', tri)
   call stl_read('build/test_stl_cube.stl', 1.0_rp, 'case.nml', 'body #1', 'stl_file', m)
   call check(m%nt == 12, 'cube: 12 triangles read')
   call stl_props(m, vol, cen, jj)
   call check_close(vol, a**3, 1.0e-13_rp, 'cube: volume a^3 (wound inward, turned outward)')
   call check(maxval(abs(cen - [0.2_rp, 0.0_rp, 0.1_rp])) <= 1.0e-14_rp, 'cube: centroid at its centre')
   call check(maxval(abs(jj - a**5/6.0_rp*identity())) <= 1.0e-12_rp*a**5, 'cube: inertia a^5/6 I about the centroid')
   call check(stl_inside(m, [0.2_rp, 0.0_rp, 0.1_rp]) .and. stl_inside(m, [0.29_rp, 0.09_rp, 0.01_rp]), 'cube: inside')
   call check(.not. stl_inside(m, [0.31_rp, 0.0_rp, 0.1_rp]) .and. .not. stl_inside(m, [0.2_rp, 0.0_rp, -0.01_rp]), &
              'cube: outside')
   call stl_nearest(m, [0.2_rp, 0.05_rp, 0.19_rp], q, n)
   call check(maxval(abs(q - [0.2_rp, 0.05_rp, 0.2_rp])) <= 1.0e-15_rp .and. maxval(abs(n - [0.0_rp, 0.0_rp, 1.0_rp])) &
              <= 1.0e-15_rp, 'cube: nearest point and normal of the top face')
   call stl_bounds(m, lo, hi)
   call check(maxval(abs(lo - [0.1_rp, -0.1_rp, 0.0_rp])) + maxval(abs(hi - [0.3_rp, 0.1_rp, 0.2_rp])) <= 1.0e-15_rp, &
              'cube: bounds')
   ! the same file scaled by 10
   call stl_read('build/test_stl_cube.stl', 10.0_rp, 'case.nml', 'body #1', 'stl_file', m)
   call stl_props(m, vol, cen, jj)
   call check_close(vol, (10.0_rp*a)**3, 1.0e-13_rp, 'cube: scaled volume')

   ! an icosphere of radius r about c0, binary
   r = 0.05_rp
   c0 = [1.0_rp, 2.0_rp, -0.5_rp]
   call icosphere(3, r, c0, tri)
   call write_binary('build/test_stl_sphere.stl', tri)
   call stl_read('build/test_stl_sphere.stl', 1.0_rp, 'case.nml', 'body #1', 'stl_file', m)
   call check(m%nt == 1280, 'sphere: 1280 triangles read')
   call stl_props(m, vol, cen, jj)
   ! the polyhedron's volume summed about its own centre, as pyramids
   poly = 0.0_rp
   do k = 1, m%nt
      poly = poly + dot_product(m%v(:, 1, k) - c0, cross(m%v(:, 2, k) - c0, m%v(:, 3, k) - c0))/6.0_rp
   end do
   ! the same vertices summed about another origin: round-off apart
   call check_close(vol, poly, 1.0e-10_rp, 'sphere: volume = the polyhedron''s, about any origin')
   call check(abs(vol/(4.0_rp/3.0_rp*pi*r**3) - 1.0_rp) <= 0.015_rp .and. vol < 4.0_rp/3.0_rp*pi*r**3, &
              'sphere: volume within the polyhedron''s 1.5 % below 4/3 pi r^3')
   call check(maxval(abs(cen - c0)) <= 1.0e-6_rp*r, 'sphere: centroid at the centre')
   call check(maxval(abs(jj - 0.4_rp*vol*r**2*identity())) <= 0.03_rp*0.4_rp*vol*r**2, &
              'sphere: inertia 2/5 V r^2 I within 3 %')
   call check(stl_inside(m, c0) .and. stl_inside(m, c0 + [0.0_rp, 0.0_rp, 0.95_rp*r]), 'sphere: inside')
   call check(.not. stl_inside(m, c0 + [0.0_rp, 1.01_rp*r, 0.0_rp]) .and. .not. stl_inside(m, c0 + 2.0_rp*r), &
              'sphere: outside')
   call stl_nearest(m, c0 + [0.5_rp*r, 0.0_rp, 0.0_rp], q, n)
   call check(abs(norm2(q - c0) - r) <= 0.02_rp*r .and. n(1) > 0.97_rp, 'sphere: nearest point on the surface, normal out')
   call remove('build/test_stl_cube.stl')
   call remove('build/test_stl_sphere.stl')
   call test_summary('test_stl')

contains

   !> The file at path deleted.
   subroutine remove(path)
      character(len=*), intent(in) :: path
      integer :: u, ios
      open (newunit=u, file=path, status='old', iostat=ios)
      if (ios == 0) close (u, status='delete')
   end subroutine remove

   function identity() result(e)
      real(rp) :: e(3, 3)
      e = reshape([1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3])
   end function identity

   pure function cross(x, y) result(z)
      real(rp), intent(in) :: x(3), y(3)
      real(rp) :: z(3)
      z = [x(2)*y(3) - x(3)*y(2), x(3)*y(1) - x(1)*y(3), x(1)*y(2) - x(2)*y(1)]
   end function cross

   !> The 12 triangles of the cube [o, o + s]^3, wound outward.
   subroutine cube_triangles(s, o, t)
      real(rp), intent(in) :: s, o(3)
      real(rp), allocatable, intent(out) :: t(:, :, :)
      real(rp) :: p(3, 8)
      integer :: f(4, 6), k
      do k = 0, 7
         p(:, k + 1) = o + s*[merge(1.0_rp, 0.0_rp, btest(k, 0)), merge(1.0_rp, 0.0_rp, btest(k, 1)), &
                              merge(1.0_rp, 0.0_rp, btest(k, 2))]
      end do
      ! faces as corners counter-clockwise seen from outside (corner k + 1 = bits x, y, z of k)
      f = reshape([1, 3, 4, 2, 5, 6, 8, 7, 1, 2, 6, 5, 3, 7, 8, 4, 1, 5, 7, 3, 2, 4, 8, 6], [4, 6])
      allocate (t(3, 3, 12))
      do k = 1, 6
         t(:, :, 2*k - 1) = p(:, f([1, 2, 3], k))
         t(:, :, 2*k) = p(:, f([1, 3, 4], k))
      end do
   end subroutine cube_triangles

   !> An icosahedron subdivided level times, its vertices on the sphere (r, c).
   subroutine icosphere(level, r, c, t)
      integer, intent(in) :: level
      real(rp), intent(in) :: r, c(3)
      real(rp), allocatable, intent(out) :: t(:, :, :)
      real(rp), allocatable :: s(:, :, :)
      real(rp) :: g, v(3, 12), m12(3), m23(3), m31(3)
      integer :: f(3, 20), k, l, n
      g = 0.5_rp*(1.0_rp + sqrt(5.0_rp))
      v = reshape([-1.0_rp, g, 0.0_rp, 1.0_rp, g, 0.0_rp, -1.0_rp, -g, 0.0_rp, 1.0_rp, -g, 0.0_rp, &
                   0.0_rp, -1.0_rp, g, 0.0_rp, 1.0_rp, g, 0.0_rp, -1.0_rp, -g, 0.0_rp, 1.0_rp, -g, &
                   g, 0.0_rp, -1.0_rp, g, 0.0_rp, 1.0_rp, -g, 0.0_rp, -1.0_rp, -g, 0.0_rp, 1.0_rp], [3, 12])
      f = reshape([1, 12, 6, 1, 6, 2, 1, 2, 8, 1, 8, 11, 1, 11, 12, 2, 6, 10, 6, 12, 5, 12, 11, 3, 11, 8, 7, &
                   8, 2, 9, 4, 10, 5, 4, 5, 3, 4, 3, 7, 4, 7, 9, 4, 9, 10, 5, 10, 6, 3, 5, 12, 7, 3, 11, &
                   9, 7, 8, 10, 9, 2], [3, 20])
      allocate (t(3, 3, 20))
      do k = 1, 20
         t(:, :, k) = v(:, f(:, k))
      end do
      do l = 1, level
         n = size(t, 3)
         allocate (s(3, 3, 4*n))
         do k = 1, n
            m12 = 0.5_rp*(t(:, 1, k) + t(:, 2, k))
            m23 = 0.5_rp*(t(:, 2, k) + t(:, 3, k))
            m31 = 0.5_rp*(t(:, 3, k) + t(:, 1, k))
            s(:, :, 4*k - 3) = reshape([t(:, 1, k), m12, m31], [3, 3])
            s(:, :, 4*k - 2) = reshape([m12, t(:, 2, k), m23], [3, 3])
            s(:, :, 4*k - 1) = reshape([m31, m23, t(:, 3, k)], [3, 3])
            s(:, :, 4*k) = reshape([m12, m23, m31], [3, 3])
         end do
         call move_alloc(s, t)
      end do
      do k = 1, size(t, 3)
         do l = 1, 3
            t(:, l, k) = c + r*t(:, l, k)/norm2(t(:, l, k))
         end do
      end do
   end subroutine icosphere

   subroutine write_ascii(path, t)
      character(len=*), intent(in) :: path
      real(rp), intent(in) :: t(:, :, :)
      integer :: u, k, l
      open (newunit=u, file=path, status='replace', action='write')
      write (u, '(a)') 'solid cube'
      do k = 1, size(t, 3)
         write (u, '(a)') '  facet normal 0 0 0'
         write (u, '(a)') '    outer loop'
         do l = 1, 3
            write (u, '(a, 3es24.16)') '      vertex ', t(:, l, k)
         end do
         write (u, '(a)') '    endloop'
         write (u, '(a)') '  endfacet'
      end do
      write (u, '(a)') 'endsolid cube'
      close (u)
   end subroutine write_ascii

   subroutine write_binary(path, t)
      character(len=*), intent(in) :: path
      real(rp), intent(in) :: t(:, :, :)
      integer :: u, k
      character(len=80) :: header
      header = 'solid written by test_stl (binary)'
      open (newunit=u, file=path, access='stream', form='unformatted', status='replace', action='write')
      write (u) header, int(size(t, 3), int32)
      do k = 1, size(t, 3)
         write (u) [0.0_real32, 0.0_real32, 0.0_real32], real(reshape(t(:, :, k), [9]), real32), 0_int16
      end do
      close (u)
   end subroutine write_binary
end program test_stl

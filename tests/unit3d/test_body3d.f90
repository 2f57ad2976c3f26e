!> A box body in 3D (body_shapes built with ndim = 3: make unit-3d) against what
!> it must be, turned about z only and turned about x, y and z: its mass is
!> density times volume; its inertia tensor, turned by the start angles, equals
!> the sum m (|r|^2 I - r r^T) over a fine lattice of point masses filling the
!> turned box; its particles lie inside the box, the outer layer within half a
!> spacing of a face, with unit normals pointing out of the box; the shell is
!> the layers asked for, no deeper. The turn R = Rz Ry Rx is written here from
!> the three angles on its own; the start pose's quaternion turns the box the
!> same way; the extent across the width and the outline of the box's shadow
!> on the section are those of its eight corners.
program test_body3d
   use kinds, only: rp
   use constants, only: ndim, pi
   use rigid, only: nrot, pose_t, rigid_set_angle_z, rigid_tilt, rigid_rotation
   use input_body, only: body_cfg, body_zrange
   use options, only: shape_box
   use body_shapes, only: body_mass_properties, body_particles, body_outline
   use geom, only: point_in_polygon, distance_to_polygon, polygon_area
   use testing, only: check, check_close, test_summary
   implicit none
   type(body_cfg) :: c
   real(rp), parameter :: dp = 0.01_rp

   call check(ndim == 3 .and. nrot == 3, 'a 3D build (ndim = 3, nrot = 3)')
   c%shape_id = shape_box
   c%x = 0.4_rp; c%y = 0.2_rp; c%z = 0.15_rp
   c%width = 0.12_rp; c%height = 0.08_rp; c%depth = 0.1_rp
   c%angle = 30.0_rp
   c%density = 2400.0_rp
   call check_box(c, 'turned about z')
   c%angle_x = 40.0_rp; c%angle_y = 15.0_rp
   call check_box(c, 'turned about x, y and z')
   call test_summary('test_body3d')

contains

   !> Rz(angle) Ry(angle_y) Rx(angle_x).
   function turn(c) result(r)
      type(body_cfg), intent(in) :: c
      real(rp) :: r(3, 3), x, y, z, rx(3, 3), ry(3, 3), rz(3, 3)
      x = c%angle_x*pi/180.0_rp; y = c%angle_y*pi/180.0_rp; z = c%angle*pi/180.0_rp
      rx = transpose(reshape([1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, cos(x), -sin(x), 0.0_rp, sin(x), cos(x)], [3, 3]))
      ry = transpose(reshape([cos(y), 0.0_rp, sin(y), 0.0_rp, 1.0_rp, 0.0_rp, -sin(y), 0.0_rp, cos(y)], [3, 3]))
      rz = transpose(reshape([cos(z), -sin(z), 0.0_rp, sin(z), cos(z), 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3]))
      r = matmul(rz, matmul(ry, rx))
   end function turn

   subroutine check_box(c, label)
      type(body_cfg), intent(in) :: c
      character(len=*), intent(in) :: label
      real(rp) :: mass, cen(ndim), inertia(nrot, nrot), ref(3, 3), r(3), dm, side(3), rot(3, 3), q(3), zr(2)
      real(rp) :: corner(2, 8), e
      real(rp), allocatable :: xb(:, :), nb(:, :), v(:, :)
      integer, allocatable :: surf(:)
      integer :: i, j, k, n, m, nout, nbad_in, nbad_n, nbad_face, deepest, nv, matched
      type(pose_t) :: pose, ref_pose
      side = [c%width, c%height, c%depth]
      rot = turn(c)
      call body_mass_properties(c, mass, cen, inertia)
      call check_close(mass, 2400.0_rp*product(side), 1.0e-14_rp, label//': mass = density x volume')
      call check(all(abs(cen - [c%x, c%y, c%z]) < 1.0e-15_rp), label//': centre at (x, y, z)')

      ! the inertia tensor of point masses on a fine lattice filling the turned box
      n = 60
      dm = mass/n**3
      ref = 0.0_rp
      do k = 1, n
         do j = 1, n
            do i = 1, n
               r = matmul(rot, -0.5_rp*side + ([i, j, k] - 0.5_rp)*side/n)
               ref = ref - dm*spread(r, 2, 3)*spread(r, 1, 3)
               do m = 1, 3
                  ref(m, m) = ref(m, m) + dm*dot_product(r, r)
               end do
            end do
         end do
      end do
      ! the midpoint lattice misses the second moment of each cell, (side/n)^2/12 of it: 3e-4 relative at n = 60
      call check(maxval(abs(inertia - ref)) <= 5.0e-4_rp*maxval(abs(ref)), label//': inertia tensor = point-mass sum')
      call check(abs(inertia(1, 2) - inertia(2, 1)) <= 1.0e-15_rp*maxval(abs(inertia)) .and. &
                 abs(inertia(1, 2)) > 1.0e-3_rp*inertia(1, 1), label//': inertia symmetric, coupled in x-y by the turn')

      ! the start pose turns the box's own frame as R does
      call rigid_set_angle_z(pose, c%angle*pi/180.0_rp)
      call rigid_tilt(pose, c%angle_x*pi/180.0_rp, c%angle_y*pi/180.0_rp)
      call check(maxval(abs(rigid_rotation(pose, ref_pose) - rot)) <= 1.0e-14_rp, label//': the start quaternion is R')

      ! the particles: two layers in from every face
      call body_particles(c, dp, 2, xb, nb, surf)
      nout = 0; nbad_in = 0; nbad_n = 0; nbad_face = 0; deepest = 0
      do m = 1, size(xb, 2)
         q = matmul(transpose(rot), xb(:, m))              ! in the box's own frame
         if (any(abs(q) > 0.5_rp*side)) nbad_in = nbad_in + 1
         if (abs(norm2(nb(:, m)) - 1.0_rp) > 1.0e-12_rp .or. dot_product(nb(:, m), xb(:, m)) <= 0.0_rp) &
            nbad_n = nbad_n + 1
         if (surf(m) > 0) then
            nout = nout + 1
            if (minval(0.5_rp*side - abs(q)) > 0.5_rp*dp + 1.0e-12_rp) nbad_face = nbad_face + 1
         end if
         ! how many spacings in from the nearest face
         deepest = max(deepest, nint(minval(0.5_rp*side - abs(q))/dp + 0.5_rp))
      end do
      call check(nbad_in == 0, label//': every particle inside the box')
      call check(nbad_n == 0, label//': unit normals pointing out of the box')
      call check(nbad_face == 0, label//': the outer layer within dp/2 of a face')
      call check(deepest == 2, label//': the shell is two layers deep')
      ! the outer layer of a 12 x 8 x 10 lattice: all of it less the 10 x 6 x 8 inside
      call check(nout == 12*8*10 - 10*6*8, label//': the outer layer holds every surface point of the lattice')
      call check(size(xb, 2) == 12*8*10 - 8*4*6, label//': two layers: all of the lattice less the 8 x 4 x 6 core')

      ! its corners: the extent across the width, and the shadow on the section
      e = 0.0_rp
      do m = 0, 7
         r = 0.5_rp*side*[merge(1, -1, btest(m, 0)), merge(1, -1, btest(m, 1)), merge(1, -1, btest(m, 2))]
         r = matmul(rot, r)
         e = max(e, abs(r(3)))
         corner(:, m + 1) = [c%x, c%y] + r(1:2)
      end do
      zr = body_zrange(c)
      call check(abs(zr(1) - (c%z - e)) <= 1.0e-15_rp .and. abs(zr(2) - (c%z + e)) <= 1.0e-15_rp, &
                 label//': the extent across the width is the corners''')
      v = body_outline(c)
      nv = size(v, 2)
      matched = 0
      do k = 1, nv
         if (minval(norm2(corner - spread(v(:, k), 2, 8), dim=1)) <= 1.0e-15_rp) matched = matched + 1
      end do
      call check(matched == nv .and. polygon_area(v) > 0.0_rp, &
                 label//': the outline of the shadow: counter-clockwise, through corners')
      call check(all([(point_in_polygon(corner(:, m), v) .or. distance_to_polygon(corner(:, m), v) <= 1.0e-15_rp, &
                       m = 1, 8)]), label//': every corner in the shadow''s outline')
   end subroutine check_box
end program test_body3d

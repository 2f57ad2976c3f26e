!> The 3D forms of rigid (built with ndim = 3: make unit-3d) against what they
!> must be: the rotation of a unit quaternion is orthonormal with determinant 1,
!> a turn by omega dt is Rodrigues' rotation about omega by |omega| dt and stays
!> a unit quaternion over many turns; the velocity of a point and the moment of a
!> force equal the finite-difference derivatives of the placed point (in time) and
!> of the virtual work (in angle about each axis); the inertia tensor turned with
!> the body keeps its trace; the angular acceleration solves Euler's equations;
!> the rotational energy equals that of a set of point masses turning with the body.
program test_rigid3d
   use kinds, only: rp
   use constants, only: ndim
   use rigid, only: pose_t, nrot, npose, rigid_rotation, rigid_rotate, rigid_point_velocity, rigid_moment, &
                    rigid_moment_add, rigid_moment_sub, rigid_angular_accel, rigid_inertia_inverse, rigid_turn, &
                    rigid_angle, rigid_rot_energy, rigid_world_inertia, rigid_pose_pack, rigid_pose_unpack
   use testing, only: check, check_close, test_summary
   implicit none
   type(pose_t) :: ref, now, p1, p2
   real(rp) :: r(3, 3), rod(3, 3), k(3), a, xb(3), omega(3), u(3), ufd(3), x(3), f(3), t(3), t0(3), tfd
   real(rp) :: inertia(3, 3), iw(3, 3), alpha(3), m(8), xs(3, 8), e_part, e0(3), pk(npose)
   real(rp), parameter :: dt = 1.0e-5_rp, dphi = 1.0e-6_rp
   integer :: j, n

   call check(ndim == 3 .and. nrot == 3, 'a 3D build (ndim = 3, nrot = 3)')
   ref%c = [0.3_rp, -0.2_rp, 0.1_rp]
   call rigid_turn(ref, [0.2_rp, -0.5_rp, 0.4_rp], 1.0_rp)
   now = ref
   now%c = [1.1_rp, 0.7_rp, -0.4_rp]
   omega = [0.3_rp, 0.8_rp, -0.6_rp]
   call rigid_turn(now, omega, 1.0_rp)
   call check_close(rigid_angle(now, ref), norm2(omega), 1.0e-14_rp, 'angle turned = |omega| dt')

   ! orthonormal, determinant 1, and Rodrigues' rotation about omega
   r = rigid_rotation(now, ref)
   call check_close(maxval(abs(matmul(transpose(r), r) - eye())), 0.0_rp, 1.0_rp, 'R^T R = I', floor=1.0e-14_rp)
   call check_close(det3(r), 1.0_rp, 1.0e-14_rp, 'det R = 1')
   k = omega/norm2(omega)
   a = norm2(omega)
   rod = cos(a)*eye() + sin(a)*skew(k) + (1.0_rp - cos(a))*spread(k, 2, 3)*spread(k, 1, 3)
   call check_close(maxval(abs(r - rod)), 0.0_rp, 1.0_rp, 'a turn is Rodrigues'' rotation', floor=1.0e-14_rp)

   ! unit length kept over many turns; the pose's numbers round trip
   p1 = now
   do n = 1, 100000
      call rigid_turn(p1, [0.7_rp, -1.3_rp, 2.1_rp], 1.0e-3_rp)
   end do
   call check_close(norm2(p1%q), 1.0_rp, 1.0e-14_rp, 'unit quaternion after 1e5 turns')
   pk = rigid_pose_pack(now)
   p2 = rigid_pose_unpack(pk)
   call check(npose == 7 .and. maxval(abs(p2%c - now%c)) <= 0.0_rp .and. maxval(abs(p2%q - now%q)) <= 0.0_rp, &
              'pose packed and unpacked: centre and quaternion')

   ! the velocity of a point: central difference of its placement
   xb = [0.05_rp, -0.12_rp, 0.08_rp]
   p1 = now
   p2 = now
   call rigid_turn(p1, omega, -dt)
   call rigid_turn(p2, omega, dt)
   ufd = (rigid_rotate(rigid_rotation(p2, ref), xb) - rigid_rotate(rigid_rotation(p1, ref), xb))/(2.0_rp*dt)
   x = rigid_rotate(r, xb)
   u = rigid_point_velocity([0.0_rp, 0.0_rp, 0.0_rp], omega, x)
   call check_close(maxval(abs(u - ufd)), 0.0_rp, 1.0_rp, 'omega x r = d(R xb)/dt', floor=1.0e-9_rp)

   ! the moment of a force: the virtual work of f under a small turn about each axis
   f = [1.5_rp, -0.7_rp, 0.4_rp]
   t = rigid_moment(x, f)
   do j = 1, 3
      e0 = 0.0_rp
      e0(j) = 1.0_rp
      p1 = now
      p2 = now
      call rigid_turn(p1, e0, -dphi)
      call rigid_turn(p2, e0, dphi)
      tfd = dot_product(f, rigid_rotate(rigid_rotation(p2, ref), xb) - rigid_rotate(rigid_rotation(p1, ref), xb))/(2.0_rp*dphi)
      call check_close(t(j), tfd, 1.0e-8_rp, 'moment = virtual work, axis', floor=1.0e-8_rp)
   end do
   t0 = [0.1_rp, 0.2_rp, 0.3_rp]
   call rigid_moment_add(t0, x, f)
   call rigid_moment_sub(t0, x, f)
   call check_close(maxval(abs(t0 - [0.1_rp, 0.2_rp, 0.3_rp])), 0.0_rp, 1.0_rp, 'add then subtract a moment', floor=1.0e-15_rp)

   ! point masses: the tensor, its turn, Euler's equations and the energy
   m = [1.0_rp, 2.0_rp, 0.5_rp, 1.5_rp, 0.7_rp, 1.2_rp, 0.9_rp, 1.1_rp]
   do j = 1, 8
      xs(:, j) = [0.1_rp*mod(j, 3) - 0.1_rp, 0.07_rp*mod(j, 4) - 0.1_rp, 0.05_rp*mod(j, 5) - 0.1_rp]
   end do
   inertia = 0.0_rp
   do j = 1, 8
      inertia = inertia + m(j)*(dot_product(xs(:, j), xs(:, j))*eye() - spread(xs(:, j), 2, 3)*spread(xs(:, j), 1, 3))
   end do
   iw = rigid_world_inertia(inertia, now, ref)
   call check_close(iw(1, 1) + iw(2, 2) + iw(3, 3), inertia(1, 1) + inertia(2, 2) + inertia(3, 3), 1.0e-14_rp, &
                    'turned inertia keeps its trace')
   call check_close(maxval(abs(iw - transpose(iw))), 0.0_rp, 1.0_rp, 'turned inertia symmetric', floor=1.0e-15_rp)
   call check_close(maxval(abs(matmul(iw, rigid_inertia_inverse(iw)) - eye())), 0.0_rp, 1.0_rp, 'I I^-1 = I', &
                    floor=1.0e-13_rp)
   alpha = rigid_angular_accel(iw, f, omega)
   call check_close(maxval(abs(matmul(iw, alpha) + cross(omega, matmul(iw, omega)) - f)), 0.0_rp, 1.0_rp, &
                    'I alpha + omega x I omega = t', floor=1.0e-13_rp)
   e_part = 0.0_rp
   do j = 1, 8
      x = rigid_rotate(r, xs(:, j))
      e_part = e_part + 0.5_rp*m(j)*sum(rigid_point_velocity([0.0_rp, 0.0_rp, 0.0_rp], omega, x)**2)
   end do
   call check_close(rigid_rot_energy(iw, omega), e_part, 1.0e-13_rp, 'rotational energy of the point masses')
   call test_summary('test_rigid3d')
contains
   pure function eye() result(e)
      real(rp) :: e(3, 3)
      integer :: i
      e = 0.0_rp
      do i = 1, 3
         e(i, i) = 1.0_rp
      end do
   end function eye
   pure function skew(v) result(s)
      real(rp), intent(in) :: v(3)
      real(rp) :: s(3, 3)
      s = reshape([0.0_rp, v(3), -v(2), -v(3), 0.0_rp, v(1), v(2), -v(1), 0.0_rp], [3, 3])
   end function skew
   pure function cross(a, b) result(c)
      real(rp), intent(in) :: a(3), b(3)
      real(rp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
   end function cross
   pure real(rp) function det3(q) result(d)
      real(rp), intent(in) :: q(3, 3)
      d = dot_product(q(:, 1), cross(q(:, 2), q(:, 3)))
   end function det3
end program test_rigid3d

!> Rigid-body kinematics (module rigid) against what they must be: the rotation
!> is orthonormal with determinant 1 and two turns compose; the velocity of a
!> point and the moment of a force equal the finite-difference derivatives of
!> the placed point (in time) and of the virtual work (in angle); the angular
!> acceleration solves I alpha = t; the rotational energy equals the kinetic
!> energy of a set of point masses turning with the body, its tensor summed from them.
program test_rigid
   use kinds, only: rp
   use constants, only: ndim
   use rigid, only: pose_t, nrot, rigid_rotation, rigid_rotate, rigid_point_velocity, rigid_moment, &
                    rigid_moment_add, rigid_moment_sub, rigid_angular_accel, rigid_turn, rigid_angle, &
                    rigid_rot_energy
   use testing, only: check, check_close, test_summary
   implicit none
   type(pose_t) :: ref, now, p1, p2
   real(rp) :: r(ndim, ndim), rr(ndim, ndim), xb(ndim), v(ndim), omega(nrot), u(ndim), ufd(ndim)
   real(rp) :: f(ndim), t(nrot), t0(nrot), tfd, inertia(nrot, nrot), alpha(nrot), e_part, m, x(ndim)
   real(rp), parameter :: dt = 1.0e-5_rp, dphi = 1.0e-6_rp
   integer :: k

   ref%c = [0.3_rp, -0.2_rp]
   ref%theta = 0.4_rp
   now = ref
   now%c = [1.1_rp, 0.7_rp]
   call rigid_turn(now, [0.9_rp], 1.0_rp)
   call check_close(rigid_angle(now, ref), 0.9_rp, 1.0e-15_rp, 'angle turned')

   ! orthonormal, determinant 1
   r = rigid_rotation(now, ref)
   rr = matmul(transpose(r), r)
   call check_close(rr(1, 1), 1.0_rp, 1.0e-15_rp, 'R^T R (1,1)')
   call check_close(rr(2, 2), 1.0_rp, 1.0e-15_rp, 'R^T R (2,2)')
   call check(abs(rr(1, 2)) < 1.0e-15_rp .and. abs(rr(2, 1)) < 1.0e-15_rp, 'R^T R off-diagonal')
   call check_close(r(1, 1)*r(2, 2) - r(1, 2)*r(2, 1), 1.0_rp, 1.0e-15_rp, 'det R')
   xb = [0.25_rp, -0.6_rp]
   call check_close(norm2(rigid_rotate(r, xb)), norm2(xb), 1.0e-15_rp, 'rotation keeps length')

   ! two turns compose: R(a then b) x = R(b) R(a) x
   p1 = ref
   call rigid_turn(p1, [0.6_rp], 0.5_rp)
   p2 = p1
   call rigid_turn(p2, [-1.2_rp], 1.0_rp)
   u = rigid_rotate(rigid_rotation(p2, p1), rigid_rotate(rigid_rotation(p1, ref), xb))
   ufd = rigid_rotate(rigid_rotation(p2, ref), xb)
   do k = 1, ndim
      call check_close(u(k), ufd(k), 1.0e-14_rp, 'turns compose', floor=1.0_rp)
   end do

   ! velocity of a point: the time derivative of x(t) = c + v t + R(omega t) R0 xb
   v = [0.8_rp, -0.3_rp]
   omega = [2.5_rp]
   u = rigid_point_velocity(v, omega, rigid_rotate(rigid_rotation(now, ref), xb))
   ufd = (placed(dt) - placed(-dt))/(2.0_rp*dt)
   do k = 1, ndim
      call check_close(u(k), ufd(k), 1.0e-8_rp, 'point velocity = dx/dt', floor=1.0_rp)
   end do

   ! moment of a force: the derivative of its virtual work in the angle
   f = [-1.7_rp, 0.45_rp]
   x = rigid_rotate(rigid_rotation(now, ref), xb)
   t = rigid_moment(x, f)
   tfd = (work(dphi) - work(-dphi))/(2.0_rp*dphi)
   call check_close(t(1), tfd, 1.0e-8_rp, 'moment = d(work)/d(angle)', floor=1.0_rp)
   ! a running sum and the reaction: added then taken away, the sum is back
   t0 = [0.125_rp]
   t = t0
   call rigid_moment_add(t, x, f)
   alpha = rigid_moment(x, f)
   call check_close(t(1) - t0(1), alpha(1), 1.0e-14_rp, 'moment added', floor=1.0_rp)
   call rigid_moment_sub(t, x, f)
   call check_close(t(1), t0(1), 1.0e-14_rp, 'moment added and taken away', floor=1.0_rp)

   ! a set of point masses turning with the body: its inertia tensor summed
   ! from them, energy and angular acceleration
   inertia = 0.0_rp
   e_part = 0.0_rp
   do k = 1, 7
      m = 0.1_rp*k
      x = [cos(0.9_rp*k), sin(1.3_rp*k)]*(0.2_rp + 0.05_rp*k)
      inertia(1, 1) = inertia(1, 1) + m*sum(x**2)
      u = rigid_point_velocity([0.0_rp, 0.0_rp], omega, x)
      e_part = e_part + 0.5_rp*m*sum(u**2)
   end do
   call check_close(rigid_rot_energy(inertia, omega), e_part, 1.0e-13_rp, 'rotational energy of the point masses')
   t = [3.2_rp]
   alpha = rigid_angular_accel(inertia, t, [0.3_rp])
   call check_close(inertia(1, 1)*alpha(1), t(1), 1.0e-14_rp, 'I alpha = t')

   call test_summary('test_rigid')
contains
   !> The body's point xb at time s, the body moving with v and turning with omega from now.
   function placed(s) result(y)
      real(rp), intent(in) :: s
      real(rp) :: y(ndim)
      type(pose_t) :: ps
      ps = now
      ps%c = now%c + v*s
      call rigid_turn(ps, omega, s)
      y = ps%c + rigid_rotate(rigid_rotation(ps, ref), xb)
   end function placed

   !> Work of the force f at the point x when the body turns by a about its centre.
   real(rp) function work(a)
      real(rp), intent(in) :: a
      type(pose_t) :: ps
      ps = now
      call rigid_turn(ps, [a], 1.0_rp)
      work = dot_product(f, rigid_rotate(rigid_rotation(ps, now), x) - x)
   end function work
end program test_rigid

!> Rigid-body kinematics, the one place that knows how a body turns: its pose
!> (centre and orientation), the rotation from its reference orientation, the
!> velocity of a point of the body, the moment of a force about the centre,
!> the angular acceleration from a torque and the inertia tensor, and the
!> orientation advanced by an angular velocity over a time. Angular velocity, torque and rotation
!> increments are vectors of nrot components, inertia an nrot x nrot tensor.
!> In 2D (ndim = 2) nrot = 1: the one component is about z, the orientation is
!> the angle theta about z and the tensor is 1 x 1; in 3D the same procedures
!> take three components, a unit quaternion and a 3 x 3 tensor. The 2D forms
!> below keep the order of every product and sum of the formulas they replaced,
!> so the results did not change by a bit.
module rigid
   use kinds, only: rp
   use constants, only: ndim
   implicit none
   private
   public :: pose_t, nrot, ndof, rigid_rotation, rigid_rotate, rigid_point_velocity, rigid_moment, &
             rigid_moment_add, rigid_moment_sub, rigid_angular_accel, rigid_inertia_inverse, rigid_turn, &
             rigid_angle, rigid_rot_energy, npose, rigid_pose_pack, rigid_pose_unpack

   integer, parameter :: nrot = ndim*(ndim - 1)/2   !< rotational degrees of freedom: 1 in 2D, 3 in 3D
   integer, parameter :: ndof = ndim + nrot         !< degrees of freedom of a body
   integer, parameter :: nori = merge(1, 4, ndim == 2)   !< numbers of an orientation: an angle in 2D, a quaternion in 3D
   integer, parameter :: npose = ndim + nori        !< numbers of a pose (rigid_pose_pack)

   !> Where a body is: its centre and its orientation.
   type :: pose_t
      real(rp) :: c(ndim) = 0.0_rp      !< centre [m]
      real(rp) :: theta = 0.0_rp        !< orientation: angle about z [rad] (2D)
   end type pose_t

contains

   !> A pose as npose numbers (the checkpoint): the centre, then the orientation.
   pure function rigid_pose_pack(pose) result(v)
      type(pose_t), intent(in) :: pose
      real(rp) :: v(npose)
      v(1:ndim) = pose%c
      v(ndim + 1:npose) = pose%theta
   end function rigid_pose_pack

   !> The pose of npose numbers written by rigid_pose_pack.
   pure function rigid_pose_unpack(v) result(pose)
      real(rp), intent(in) :: v(npose)
      type(pose_t) :: pose
      pose%c = v(1:ndim)
      pose%theta = v(npose)
   end function rigid_pose_unpack

   !> The rotation matrix that takes the body's particles from the pose ref
   !> (their frame) to the pose now: x = c + R xb.
   pure function rigid_rotation(now, ref) result(r)
      type(pose_t), intent(in) :: now, ref
      real(rp) :: r(ndim, ndim), cs, sn
      cs = cos(now%theta - ref%theta)
      sn = sin(now%theta - ref%theta)
      r(:, 1) = [cs, sn]
      r(:, 2) = [-sn, cs]
   end function rigid_rotation

   !> R x.
   pure function rigid_rotate(r, x) result(y)
      real(rp), intent(in) :: r(ndim, ndim), x(ndim)
      real(rp) :: y(ndim)
      y = [r(1, 1)*x(1) - r(2, 1)*x(2), r(2, 1)*x(1) + r(1, 1)*x(2)]
   end function rigid_rotate

   !> Velocity of the point at r from the centre of a body moving with v and
   !> turning with omega: v + omega x r.
   pure function rigid_point_velocity(v, omega, r) result(u)
      real(rp), intent(in) :: v(ndim), omega(nrot), r(ndim)
      real(rp) :: u(ndim)
      u = v + omega(1)*[-r(2), r(1)]
   end function rigid_point_velocity

   !> Moment about the centre of a force f at r from it: r x f.
   pure function rigid_moment(r, f) result(t)
      real(rp), intent(in) :: r(ndim), f(ndim)
      real(rp) :: t(nrot)
      t = [r(1)*f(2) - r(2)*f(1)]
   end function rigid_moment

   !> t + r x f, summed in the order of a running sum of moments.
   pure subroutine rigid_moment_add(t, r, f)
      real(rp), intent(inout) :: t(nrot)
      real(rp), intent(in) :: r(ndim), f(ndim)
      t(1) = t(1) + r(1)*f(2) - r(2)*f(1)
   end subroutine rigid_moment_add

   !> t - r x f (the reaction on the other body of a pair).
   pure subroutine rigid_moment_sub(t, r, f)
      real(rp), intent(inout) :: t(nrot)
      real(rp), intent(in) :: r(ndim), f(ndim)
      t(1) = t(1) - (r(1)*f(2) - r(2)*f(1))
   end subroutine rigid_moment_sub

   !> The inverse of an inertia tensor.
   pure function rigid_inertia_inverse(inertia) result(iinv)
      real(rp), intent(in) :: inertia(nrot, nrot)
      real(rp) :: iinv(nrot, nrot)
      iinv = 1.0_rp/inertia
   end function rigid_inertia_inverse

   !> Angular acceleration under torque t: I^-1 t (in 2D no gyroscopic term,
   !> omega x I omega is zero about a fixed axis).
   pure function rigid_angular_accel(inertia, t) result(alpha)
      real(rp), intent(in) :: inertia(nrot, nrot), t(nrot)
      real(rp) :: alpha(nrot)
      alpha = t/inertia(1, 1)
   end function rigid_angular_accel

   !> The orientation turned by the angular velocity omega over the time dt
   !> (in 2D the angle grows by omega dt, taken as one fused product and sum).
   pure subroutine rigid_turn(pose, omega, dt)
      type(pose_t), intent(inout) :: pose
      real(rp), intent(in) :: omega(nrot), dt
      pose%theta = pose%theta + dt*omega(1)
   end subroutine rigid_turn

   !> The angle turned from the pose ref to the pose now [rad] (in 3D the angle
   !> of the rotation between them).
   pure real(rp) function rigid_angle(now, ref) result(a)
      type(pose_t), intent(in) :: now, ref
      a = now%theta - ref%theta
   end function rigid_angle

   !> Kinetic energy of the rotation: omega . I omega / 2.
   pure real(rp) function rigid_rot_energy(inertia, omega) result(e)
      real(rp), intent(in) :: inertia(nrot, nrot), omega(nrot)
      e = 0.5_rp*inertia(1, 1)*omega(1)**2
   end function rigid_rot_energy
end module rigid

!> Rigid-body kinematics, the one place that knows how a body turns: its pose
!> (centre and orientation), the rotation from its reference orientation, the
!> velocity of a point of the body, the moment of a force about the centre,
!> the angular acceleration from a torque and the inertia tensor, and the
!> orientation advanced by an angular velocity over a time. Angular velocity, torque and rotation
!> increments are vectors of nrot components, inertia an nrot x nrot tensor.
!> In 2D (ndim = 2) nrot = 1: the one component is about z, the orientation is
!> the angle theta about z and the tensor is 1 x 1; in 3D the same procedures
!> take three components, a unit quaternion and a 3 x 3 tensor (with Euler's
!> gyroscopic term), each procedure a 2D and a 3D form chosen by ndim at
!> compile time; tests/unit3d checks the 3D forms in a 3D build of this module.
!> The 2D forms keep the order of every product and sum of the formulas they
!> replaced, so the results did not change by a bit.
module rigid
   use kinds, only: rp
   use constants, only: ndim
   implicit none
   private
   public :: pose_t, nrot, ndof, rigid_rotation, rigid_rotate, rigid_point_velocity, rigid_moment, &
             rigid_moment_add, rigid_moment_sub, rigid_angular_accel, rigid_inertia_inverse, rigid_turn, &
             rigid_angle, rigid_rot_energy, npose, rigid_pose_pack, rigid_pose_unpack, rigid_world_inertia, &
             rigid_set_angle_z, rigid_tilt

   integer, parameter :: nrot = ndim*(ndim - 1)/2   !< rotational degrees of freedom: 1 in 2D, 3 in 3D
   integer, parameter :: ndof = ndim + nrot         !< degrees of freedom of a body
   integer, parameter :: nori = merge(1, 4, ndim == 2)   !< numbers of an orientation: an angle in 2D, a quaternion in 3D
   integer, parameter :: npose = ndim + nori        !< numbers of a pose (rigid_pose_pack)

   !> Where a body is: its centre and its orientation.
   type :: pose_t
      real(rp) :: c(ndim) = 0.0_rp      !< centre [m]
      real(rp) :: theta = 0.0_rp        !< orientation in 2D: angle about z [rad]
      real(rp) :: q(4) = [1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp]   !< orientation in 3D: unit quaternion (w, x, y, z)
   end type pose_t

contains

   !> Turns a pose to the angle a about z (the axis across a vertical section): the
   !> angle in 2D, the quaternion (cos a/2, 0, 0, sin a/2) in 3D.
   pure subroutine rigid_set_angle_z(pose, a)
      type(pose_t), intent(inout) :: pose
      real(rp), intent(in) :: a
      pose%theta = a
      if (ndim == 3) pose%q = [cos(0.5_rp*a), 0.0_rp, 0.0_rp, sin(0.5_rp*a)]
   end subroutine rigid_set_angle_z

   !> Turns a 3D pose about x by ax, then about y by ay, before its present
   !> orientation (q = q_now q_y q_x, the rotation R_now R_y R_x); in 2D there is
   !> no turn out of the section, and the pose is left as it is.
   pure subroutine rigid_tilt(pose, ax, ay)
      type(pose_t), intent(inout) :: pose
      real(rp), intent(in) :: ax, ay
      if (ndim == 2) return
      pose%q = quat_mul(pose%q, quat_mul([cos(0.5_rp*ay), 0.0_rp, sin(0.5_rp*ay), 0.0_rp], &
                                         [cos(0.5_rp*ax), sin(0.5_rp*ax), 0.0_rp, 0.0_rp]))
   end subroutine rigid_tilt

   !> A pose as npose numbers (the checkpoint): the centre, then the orientation.
   pure function rigid_pose_pack(pose) result(v)
      type(pose_t), intent(in) :: pose
      real(rp) :: v(npose)
      integer :: k
      v(1:ndim) = pose%c
      if (ndim == 2) then
         v(npose) = pose%theta
      else
         do k = 1, nori
            v(ndim + k) = pose%q(k)
         end do
      end if
   end function rigid_pose_pack

   !> The pose of npose numbers written by rigid_pose_pack.
   pure function rigid_pose_unpack(v) result(pose)
      real(rp), intent(in) :: v(npose)
      type(pose_t) :: pose
      integer :: k
      pose%c = v(1:ndim)
      if (ndim == 2) then
         pose%theta = v(npose)
      else
         do k = 1, nori
            pose%q(k) = v(ndim + k)
         end do
      end if
   end function rigid_pose_unpack

   !> The rotation matrix that takes the body's particles from the pose ref
   !> (their frame) to the pose now: x = c + R xb.
   pure function rigid_rotation(now, ref) result(r)
      type(pose_t), intent(in) :: now, ref
      real(rp) :: r(ndim, ndim), cs, sn, m(3, 3), a(3, 3), b(3, 3)
      if (ndim == 2) then
         cs = cos(now%theta - ref%theta)
         sn = sin(now%theta - ref%theta)
         ! element by element (1 and ndim): the 2D form compiles in a 3D build too
         r(1, 1) = cs
         r(ndim, 1) = sn
         r(1, ndim) = -sn
         r(ndim, ndim) = cs
      else
         ! named temporaries: matmul of array results made gfortran -O3 warn of uninitialised descriptors
         a = quat_matrix(now%q)
         b = transpose(quat_matrix(ref%q))
         m = matmul(a, b)
         r = unpad_block(m, ndim)
      end if
   end function rigid_rotation

   !> R x.
   pure function rigid_rotate(r, x) result(y)
      real(rp), intent(in) :: r(ndim, ndim), x(ndim)
      real(rp) :: y(ndim)
      if (ndim == 2) then
         y(1) = r(1, 1)*x(1) - r(ndim, 1)*x(ndim)
         y(ndim) = r(ndim, 1)*x(1) + r(1, 1)*x(ndim)
      else
         y = matmul(r, x)
      end if
   end function rigid_rotate

   !> Velocity of the point at r from the centre of a body moving with v and
   !> turning with omega: v + omega x r.
   pure function rigid_point_velocity(v, omega, r) result(u)
      real(rp), intent(in) :: v(ndim), omega(nrot), r(ndim)
      real(rp) :: u(ndim)
      if (ndim == 2) then
         u(1) = v(1) + omega(1)*(-r(ndim))
         u(ndim) = v(ndim) + omega(1)*r(1)
      else
         u = v + unpad(cross3(pad3(omega), pad3(r)), ndim)
      end if
   end function rigid_point_velocity

   !> Moment about the centre of a force f at r from it: r x f.
   pure function rigid_moment(r, f) result(t)
      real(rp), intent(in) :: r(ndim), f(ndim)
      real(rp) :: t(nrot)
      if (ndim == 2) then
         t(1) = r(1)*f(ndim) - r(ndim)*f(1)
      else
         t = unpad(cross3(pad3(r), pad3(f)), nrot)
      end if
   end function rigid_moment

   !> t + r x f, summed in the order of a running sum of moments.
   pure subroutine rigid_moment_add(t, r, f)
      real(rp), intent(inout) :: t(nrot)
      real(rp), intent(in) :: r(ndim), f(ndim)
      if (ndim == 2) then
         t(1) = t(1) + r(1)*f(ndim) - r(ndim)*f(1)
      else
         t = t + unpad(cross3(pad3(r), pad3(f)), nrot)
      end if
   end subroutine rigid_moment_add

   !> t - r x f (the reaction on the other body of a pair).
   pure subroutine rigid_moment_sub(t, r, f)
      real(rp), intent(inout) :: t(nrot)
      real(rp), intent(in) :: r(ndim), f(ndim)
      if (ndim == 2) then
         t(1) = t(1) - (r(1)*f(ndim) - r(ndim)*f(1))
      else
         t = t - unpad(cross3(pad3(r), pad3(f)), nrot)
      end if
   end subroutine rigid_moment_sub

   !> The inertia tensor of a body at the pose now, given the tensor at the
   !> pose ref: R I R^T (in 2D the same: a turn about z leaves it).
   pure function rigid_world_inertia(inertia, now, ref) result(iw)
      real(rp), intent(in) :: inertia(nrot, nrot)
      type(pose_t), intent(in) :: now, ref
      real(rp) :: iw(nrot, nrot), m(3, 3), rm(3, 3), i3(3, 3)
      if (ndim == 2) then
         iw = inertia
      else
         rm = pad_matrix(rigid_rotation(now, ref))
         i3 = pad_matrix(inertia)
         m = matmul(rm, matmul(i3, transpose(rm)))
         iw = unpad_block(m, nrot)
      end if
   end function rigid_world_inertia

   !> The inverse of an inertia tensor.
   pure function rigid_inertia_inverse(inertia) result(iinv)
      real(rp), intent(in) :: inertia(nrot, nrot)
      real(rp) :: iinv(nrot, nrot)
      if (ndim == 2) then
         iinv = 1.0_rp/inertia
      else
         iinv = unpad_block(inverse3(pad_matrix(inertia)), nrot)
      end if
   end function rigid_inertia_inverse

   !> Angular acceleration under torque t of a body turning with omega, its
   !> inertia tensor taken at the pose now (rigid_world_inertia): Euler's
   !> equations, I alpha = t - omega x I omega (in 2D the last term is zero:
   !> omega and I omega point along z).
   pure function rigid_angular_accel(inertia, t, omega) result(alpha)
      real(rp), intent(in) :: inertia(nrot, nrot), t(nrot), omega(nrot)
      real(rp) :: alpha(nrot), iw(3), i3(3, 3), w3(3), j3(3, 3), r3(3)
      if (ndim == 2) then
         alpha = t/inertia(1, 1)
      else
         i3 = pad_matrix(inertia)
         w3 = pad3(omega)
         iw = matmul(i3, w3)
         j3 = inverse3(i3)
         r3 = pad3(t) - cross3(w3, iw)
         alpha = unpad(matmul(j3, r3), nrot)
      end if
   end function rigid_angular_accel

   !> The orientation turned by the angular velocity omega over the time dt
   !> (in 2D the angle grows by omega dt, taken as one fused product and sum;
   !> in 3D the quaternion is turned by the rotation vector omega dt, exactly,
   !> and kept of unit length).
   pure subroutine rigid_turn(pose, omega, dt)
      type(pose_t), intent(inout) :: pose
      real(rp), intent(in) :: omega(nrot), dt
      real(rp) :: phi(3), a, dq(4)
      if (ndim == 2) then
         pose%theta = pose%theta + dt*omega(1)
      else
         phi = pad3(omega)*dt
         a = norm2(phi)
         if (a > 0.0_rp) then
            dq = [cos(0.5_rp*a), sin(0.5_rp*a)*phi/a]
         else
            dq = [1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp]
         end if
         pose%q = quat_mul(dq, pose%q)
         pose%q = pose%q/norm2(pose%q)
      end if
   end subroutine rigid_turn

   !> The angle turned from the pose ref to the pose now [rad] (in 3D the angle
   !> of the rotation between them, 0 to pi).
   pure real(rp) function rigid_angle(now, ref) result(a)
      type(pose_t), intent(in) :: now, ref
      real(rp) :: d(4)
      if (ndim == 2) then
         a = now%theta - ref%theta
      else
         d = quat_mul(now%q, [ref%q(1), -ref%q(2:4)])
         a = 2.0_rp*atan2(norm2(d(2:4)), abs(d(1)))
      end if
   end function rigid_angle

   !> Kinetic energy of the rotation: omega . I omega / 2.
   pure real(rp) function rigid_rot_energy(inertia, omega) result(e)
      real(rp), intent(in) :: inertia(nrot, nrot), omega(nrot)
      if (ndim == 2) then
         e = 0.5_rp*inertia(1, 1)*omega(1)**2
      else
         e = 0.5_rp*dot_product(omega, matmul(inertia, omega))
      end if
   end function rigid_rot_energy

   ! The 3D forms work on 3-vectors and 3 x 3 matrices, copied from and to the
   ! ndim- and nrot-sized arrays: written so, they compile (and are never run)
   ! in a 2D build.

   !> x (any size up to 3) as a 3-vector, zeros after it.
   pure function pad3(x) result(y)
      real(rp), intent(in) :: x(:)
      real(rp) :: y(3)
      integer :: k
      y = 0.0_rp
      do k = 1, min(size(x), 3)
         y(k) = x(k)
      end do
   end function pad3

   !> The first n components of a 3-vector.
   pure function unpad(y, n) result(x)
      real(rp), intent(in) :: y(3)
      integer, intent(in) :: n
      real(rp) :: x(n)
      integer :: k
      do k = 1, n
         x(k) = y(k)
      end do
   end function unpad

   !> A square matrix (up to 3 x 3) in the top left of a 3 x 3 one.
   pure function pad_matrix(a) result(m)
      real(rp), intent(in) :: a(:, :)
      real(rp) :: m(3, 3)
      integer :: k, l
      m = 0.0_rp
      do l = 1, min(size(a, 2), 3)
         do k = 1, min(size(a, 1), 3)
            m(k, l) = a(k, l)
         end do
      end do
   end function pad_matrix

   !> The top left n x n block of a 3 x 3 matrix (n = ndim or nrot).
   pure function unpad_block(m, n) result(a)
      real(rp), intent(in) :: m(3, 3)
      integer, intent(in) :: n
      real(rp) :: a(n, n)
      integer :: k, l
      do l = 1, n
         do k = 1, n
            a(k, l) = m(k, l)
         end do
      end do
   end function unpad_block

   pure function cross3(a, b) result(c)
      real(rp), intent(in) :: a(3), b(3)
      real(rp) :: c(3)
      c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
   end function cross3

   !> The inverse of a 3 x 3 matrix (its adjugate over its determinant).
   pure function inverse3(m) result(a)
      real(rp), intent(in) :: m(3, 3)
      real(rp) :: a(3, 3)
      a(:, 1) = cross3(m(:, 2), m(:, 3))
      a(:, 2) = cross3(m(:, 3), m(:, 1))
      a(:, 3) = cross3(m(:, 1), m(:, 2))
      a = transpose(a)/dot_product(m(:, 1), a(:, 1))
   end function inverse3

   !> The product of two quaternions (w, x, y, z).
   pure function quat_mul(a, b) result(c)
      real(rp), intent(in) :: a(4), b(4)
      real(rp) :: c(4)
      c(1) = a(1)*b(1) - dot_product(a(2:4), b(2:4))
      c(2:4) = a(1)*b(2:4) + b(1)*a(2:4) + cross3(a(2:4), b(2:4))
   end function quat_mul

   !> The rotation matrix of a unit quaternion (w, x, y, z).
   pure function quat_matrix(q) result(m)
      real(rp), intent(in) :: q(4)
      real(rp) :: m(3, 3)
      associate (w => q(1), x => q(2), y => q(3), z => q(4))
         m(1, :) = [1.0_rp - 2.0_rp*(y*y + z*z), 2.0_rp*(x*y - w*z), 2.0_rp*(x*z + w*y)]
         m(2, :) = [2.0_rp*(x*y + w*z), 1.0_rp - 2.0_rp*(x*x + z*z), 2.0_rp*(y*z - w*x)]
         m(3, :) = [2.0_rp*(x*z - w*y), 2.0_rp*(y*z + w*x), 1.0_rp - 2.0_rp*(x*x + y*y)]
      end associate
   end function quat_matrix
end module rigid

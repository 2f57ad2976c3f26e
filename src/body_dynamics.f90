!> Rigid bodies: state, Newton-Euler time stepping inside every integrator,
!> and the particle positions, velocities and normals taken from the pose
!> every stage, so a body stays exactly rigid.
module body_dynamics
   use errors, only: alloc_check
   use kinds, only: rp
   use constants, only: kind_floating, kind_fixed, kind_moving, pi, ndim, iup
   use rigid, only: pose_t, nrot, ndof, rigid_rotation, rigid_rotate, rigid_point_velocity, rigid_moment, &
                    rigid_moment_add, rigid_angular_accel, rigid_inertia_inverse, rigid_turn, rigid_rot_energy, &
                    rigid_world_inertia
   use particles, only: particles_t
   use options, only: motion_floating, motion_prescribed
   implicit none
   private
   public :: body_t, pose_t, nrot, ndof, bodies_place, bodies_fluid_forces, &
             bodies_damping_reset, bodies_damping_add, &
             bodies_save, bodies_predict, bodies_correct_symplectic, bodies_correct_pc, bodies_verlet, &
             bodies_accel2, body_of, bodies_energy, bodies_pack_sums, bodies_unpack_sums, bodies_prescribe, body_arm


   !> forces and torques of a body summed over the ranks: f_fluid, t_fluid, f_normal, t_normal, f_fric, t_fric
   integer, parameter :: sums_per_body = 3*ndof

   type :: body_t
      integer :: motion = motion_floating
      integer :: id = 0                     !< body number carried by its particles
      real(rp) :: mass = 0.0_rp             !< [kg/m]
      real(rp) :: inertia(nrot, nrot) = 0.0_rp  !< inertia tensor about the centre at pose_start [kg m in 2D]
      type(pose_t) :: pose                  !< centre [m] and orientation now
      real(rp) :: v(ndim) = 0.0_rp          !< velocity of the centre [m/s]
      real(rp) :: omega(nrot) = 0.0_rp      !< angular velocity [rad/s]
      type(pose_t) :: pose_start            !< pose at t = 0, the frame of the particles' xb and nb
      ! prescribed motion: pose(t) = pose_start + rate t + amp sin(2 pi t / period + phase),
      ! the translation's ndim components first, then the rotation's nrot
      real(rp) :: rate(ndof) = 0.0_rp       !< constant rates: velocity [m/s], angular velocity [rad/s]
      real(rp) :: amp(ndof) = 0.0_rp        !< amplitudes [m], [rad]
      real(rp) :: period = 0.0_rp           !< [s]; 0: no oscillation
      real(rp) :: phase = 0.0_rp            !< [rad]
      real(rp) :: m_surf = 0.0_rp           !< body mass per surface particle [kg/m]
      real(rp) :: mu = 0.0_rp, restitution = 0.5_rp, young = 2.0e10_rp, poisson = 0.2_rp
      real(rp) :: rbound = 0.0_rp           !< largest distance of a particle from the centre [m]
      real(rp) :: g = 9.81_rp               !< gravity [m/s2]
      !> the width of periodic sides across (3D) [m], 0 without: a point's arm from the
      !> centre is that of its image nearest the centre (body_arm)
      real(rp) :: period_z = 0.0_rp
      ! forces and torques of the last evaluation, by source
      real(rp) :: f_fluid(ndim) = 0.0_rp, t_fluid(nrot) = 0.0_rp
      real(rp) :: f_normal(ndim) = 0.0_rp, t_normal(nrot) = 0.0_rp
      real(rp) :: f_fric(ndim) = 0.0_rp, t_fric(nrot) = 0.0_rp
      ! velocity-proportional contact terms (damping, sticking friction):
      ! their sum sets the stable time step, an explicit step must stay
      ! below twice mass / coefficient
      ! state at the start of the step
      type(pose_t) :: pose0
      real(rp) :: v0(ndim) = 0.0_rp, omega0(nrot) = 0.0_rp
      real(rp), allocatable :: outline(:, :)  !< outline in the particle frame (centre at 0)
      !> 3D: the box's half sides in its own frame [m], and the rotation from its own frame to
      !> the particle frame (its start orientation)
      real(rp) :: half(3) = 0.0_rp
      real(rp) :: turn(3, 3) = reshape([1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3])
   end type body_t

   !> damping matrix of the velocity-proportional contact forces on the
   !> floating bodies' velocities (u, v, omega of body 1, then body 2, ...)

contains

   !> Body index of particle i, or 0 when it belongs to no body.
   pure integer function body_of(bodies, id) result(b)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: id
      b = 0
      if (size(bodies) == 0) return
      b = id - bodies(1)%id + 1
      if (b < 1 .or. b > size(bodies)) b = 0
   end function body_of

   !> The arm x - c of point x from the centre of body b; with periodic
   !> sides, of the image of x nearest the centre.
   pure function body_arm(b, x) result(r)
      type(body_t), intent(in) :: b
      real(rp), intent(in) :: x(ndim)
      real(rp) :: r(ndim)
      r = x - b%pose%c
      if (b%period_z > 0.0_rp) r(ndim) = r(ndim) - b%period_z*anint(r(ndim)/b%period_z)
   end function body_arm

   !> Particles of every body from its pose: x = c + R xb, R the rotation
   !> from the pose at the start (the particles' frame) to the pose now.
   !> With periodic sides each particle stays on the side of the width where
   !> it was (where the grid sorted it, or its image): the position one
   !> whole number of widths away nearest the old one.
   subroutine bodies_place(bodies, p)
      type(body_t), intent(in) :: bodies(:)
      type(particles_t), intent(inout) :: p
      integer :: i, b
      real(rp) :: rot(ndim, ndim, size(bodies)), r(ndim), xo
      do b = 1, size(bodies)
         rot(:, :, b) = rigid_rotation(bodies(b)%pose, bodies(b)%pose_start)
      end do
      do i = 1, p%n
         b = body_of(bodies, p%body(i))
         if (b == 0) cycle
         r = rigid_rotate(rot(:, :, b), p%xb(:, i))
         xo = p%x(ndim, i)
         p%x(:, i) = bodies(b)%pose%c + r
         if (bodies(b)%period_z > 0.0_rp) p%x(ndim, i) = p%x(ndim, i) - &
            bodies(b)%period_z*anint((p%x(ndim, i) - xo)/bodies(b)%period_z)
         p%v(:, i) = rigid_point_velocity(bodies(b)%v, bodies(b)%omega, r)
         p%nrm(:, i) = rigid_rotate(rot(:, :, b), p%nb(:, i))
         if (p%mdbc) p%gof(:, i) = rigid_rotate(rot(:, :, b), p%gob(:, i))
      end do
   end subroutine bodies_place

   !> Force and torque of the fluid on each floating body: the pair-loop
   !> acceleration of its (owned) particles times their mass.
   subroutine bodies_fluid_forces(bodies, p, acc)
      type(body_t), intent(inout) :: bodies(:)
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: acc(:, :)
      integer :: i, b
      real(rp) :: f(ndim), r(ndim)
      do b = 1, size(bodies)
         bodies(b)%f_fluid = 0.0_rp
         bodies(b)%t_fluid = 0.0_rp
      end do
      do i = 1, p%n_own
         if (p%kind(i) /= kind_floating) cycle
         b = body_of(bodies, p%body(i))
         f = p%mass(i)*acc(:, i)
         r = body_arm(bodies(b), p%x(:, i))
         bodies(b)%f_fluid = bodies(b)%f_fluid + f
         call rigid_moment_add(bodies(b)%t_fluid, r, f)
      end do
   end subroutine bodies_fluid_forces

   !> The forces and torques of every body and the contact damping matrix
   !> as one array, for the sum over the ranks the step makes (each rank
   !> summed its own particles and pairs): bodies_unpack_sums takes it back.
   subroutine bodies_pack_sums(bodies, damp, buf)
      type(body_t), intent(in) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)
      real(rp), allocatable, intent(out) :: buf(:)
      integer :: b, k, nd, ist
      character(len=200) :: emsg
      nd = 0
      if (allocated(damp)) nd = size(damp)
      allocate (buf(sums_per_body*size(bodies) + nd), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the sums of the bodies in bodies_pack_sums')
      do b = 1, size(bodies)
         k = (b - 1)*sums_per_body
         associate (x => bodies(b))
            buf(k + 1:k + sums_per_body) = [x%f_fluid, x%t_fluid, x%f_normal, x%t_normal, x%f_fric, x%t_fric]
         end associate
      end do
      if (nd > 0) buf(sums_per_body*size(bodies) + 1:) = reshape(damp, [nd])
   end subroutine bodies_pack_sums

   !> The forces, torques and damping matrix from the array of bodies_pack_sums.
   subroutine bodies_unpack_sums(buf, bodies, damp)
      real(rp), intent(in) :: buf(:)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), allocatable, intent(inout) :: damp(:, :)
      integer :: b, k
      do b = 1, size(bodies)
         k = (b - 1)*sums_per_body
         associate (x => bodies(b))
            x%f_fluid = buf(k + 1:k + ndim); x%t_fluid = buf(k + ndim + 1:k + ndof)
            x%f_normal = buf(k + ndof + 1:k + ndof + ndim); x%t_normal = buf(k + ndof + ndim + 1:k + 2*ndof)
            x%f_fric = buf(k + 2*ndof + 1:k + 2*ndof + ndim); x%t_fric = buf(k + 2*ndof + ndim + 1:k + 3*ndof)
         end associate
      end do
      if (allocated(damp)) damp = reshape(buf(sums_per_body*size(bodies) + 1:), shape(damp))
   end subroutine bodies_unpack_sums

   !> Linear and angular acceleration of a body from the forces of the last evaluation.
   pure subroutine accel(b, a, alpha)
      type(body_t), intent(in) :: b
      real(rp), intent(out) :: a(ndim), alpha(nrot)
      a = 0.0_rp
      alpha = 0.0_rp
      if (b%motion /= motion_floating) return
      a = (b%f_fluid + b%f_normal + b%f_fric)/b%mass
      a(iup) = a(iup) - b%g                        ! gravity along -y
      alpha = rigid_angular_accel(rigid_world_inertia(b%inertia, b%pose, b%pose_start), &
                                  b%t_fluid + b%t_normal + b%t_fric, b%omega)
   end subroutine accel

   !> Forget the damping matrix of the last evaluation (nb bodies): damp, of
   !> size ndof nb x ndof nb (velocity and angular velocity of each body), zero.
   subroutine bodies_damping_reset(damp, nb)
      real(rp), allocatable, intent(inout) :: damp(:, :)
      integer, intent(in) :: nb
      integer :: ist
      character(len=200) :: emsg
      if (allocated(damp)) then
         if (size(damp, 1) /= ndof*nb) deallocate (damp)
      end if
      if (.not. allocated(damp)) then
         allocate (damp(ndof*nb, ndof*nb), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the contact damping matrix in bodies_damping_reset')
      end if
      damp = 0.0_rp
   end subroutine bodies_damping_reset

   !> A velocity-proportional force -c (e . (v_i - v_j)) e between point xi of
   !> body bi and point xj of body bj (0, or a body that is not floating:
   !> its velocity is given), along the unit vector e. Adds c J^T J to the
   !> damping matrix, J the rates of e . (v_i - v_j) with respect to the
   !> floating bodies' velocities and angular velocities (e . (omega x r) =
   !> omega . (r x e)); the pair's forces stay equal and opposite.
   subroutine bodies_damping_add(damp, bodies, bi, bj, xi, xj, c, e)
      real(rp), intent(inout) :: damp(:, :)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      real(rp), intent(in) :: xi(ndim), xj(ndim), c, e(ndim)
      real(rp) :: ji(ndof), jj(ndof)
      integer :: oi, oj, k
      logical :: fi, fj
      fi = .false.
      fj = .false.
      if (bi > 0) fi = bodies(bi)%motion == motion_floating
      if (bj > 0) fj = bodies(bj)%motion == motion_floating
      oi = ndof*(bi - 1)
      oj = ndof*(bj - 1)
      if (fi) ji = rate(bodies(bi), xi)
      if (fj) jj = -rate(bodies(bj), xj)
      do k = 1, ndof
         if (fi) damp(oi + 1:oi + ndof, oi + k) = damp(oi + 1:oi + ndof, oi + k) + c*ji(k)*ji
         if (fj) damp(oj + 1:oj + ndof, oj + k) = damp(oj + 1:oj + ndof, oj + k) + c*jj(k)*jj
         if (fi .and. fj) then
            damp(oi + 1:oi + ndof, oj + k) = damp(oi + 1:oi + ndof, oj + k) + c*jj(k)*ji
            damp(oj + 1:oj + ndof, oi + k) = damp(oj + 1:oj + ndof, oi + k) + c*ji(k)*jj
         end if
      end do
   contains
      pure function rate(b, x) result(jv)
         type(body_t), intent(in) :: b
         real(rp), intent(in) :: x(ndim)
         real(rp) :: jv(ndof), r(ndim)
         r = body_arm(b, x)
         jv = [e, rigid_moment(r, e)]
      end function rate
   end subroutine bodies_damping_add

   !> Velocities of the floating bodies after a step of length step from
   !> their velocities now, or with from_start those at the start of the step, with the forces of the last evaluation, the
   !> velocity-proportional contact forces (friction below the stick speed,
   !> contact damping: the matrix C) taken implicitly, all bodies together:
   !>    M q_new = M q_start + step (F - C (q_new - q_eval)),  q = (v, omega),
   !> q_eval the velocities the forces were evaluated at. The damping acts on
   !> the slip and approach velocities of the contact points only (a rolling
   !> body is not slowed), equal and opposite between two bodies (momentum is
   !> kept), exact for any step (stiff friction does not limit the step), and
   !> at rest (q_new = q_eval) the forces are those evaluated. A dense solve:
   !> fine for hundreds of bodies.
   subroutine implicit_velocities(bodies, damp, from_start, step, v_new, w_new)
      type(body_t), intent(in) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)
      logical, intent(in) :: from_start
      real(rp), intent(in) :: step
      real(rp), intent(out) :: v_new(:, :), w_new(:, :)
      real(rp), allocatable :: a(:, :), r(:), q(:)
      real(rp) :: acc(ndim), alpha(nrot), iinv(nrot, nrot)
      integer :: nb, b, o, k
      integer :: ist
      character(len=200) :: emsg
      nb = size(bodies)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (a(ndof*nb, ndof*nb), r(ndof*nb), q(ndof*nb), stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
         call alloc_check(ist, emsg, 'a, r, q in implicit_velocities')
         error stop
      end if
      a = 0.0_rp
      if (allocated(damp)) then
         if (size(damp, 1) == ndof*nb) a = step*damp
      end if
      do b = 1, nb
         o = ndof*(b - 1)
         call accel(bodies(b), acc, alpha)
         q(o + 1:o + ndof) = [bodies(b)%v, bodies(b)%omega]
         if (from_start) then
            r(o + 1:o + ndof) = [bodies(b)%v0 + step*acc, bodies(b)%omega0 + step*alpha]
         else
            r(o + 1:o + ndof) = [bodies(b)%v + step*acc, bodies(b)%omega + step*alpha]
         end if
      end do
      r = r + matmul(scaled(a), q)
      a = scaled(a)
      do k = 1, ndof*nb
         a(k, k) = a(k, k) + 1.0_rp
      end do
      call gauss_solve(a, r)
      do b = 1, nb
         o = ndof*(b - 1)
         v_new(:, b) = r(o + 1:o + ndim)
         w_new(:, b) = r(o + ndim + 1:o + ndof)
      end do
   contains
      !> M^-1 c: the rows of a body's velocity divided by its mass, those of
      !> its angular velocity multiplied by the inverse of its inertia tensor.
      function scaled(c) result(m)
         real(rp), intent(in) :: c(:, :)
         real(rp) :: m(size(c, 1), size(c, 2))
         integer :: bb, oo, d
         m = 0.0_rp
         do bb = 1, nb
            oo = ndof*(bb - 1)
            ! a fixed or prescribed body may have no mass; its rows of c are
            ! zero and stay so (0/0 would put NaN into every body's solve)
            if (bodies(bb)%motion /= motion_floating) cycle
            do d = 1, ndim
               m(oo + d, :) = c(oo + d, :)*(1.0_rp/bodies(bb)%mass)
            end do
            iinv = rigid_inertia_inverse(rigid_world_inertia(bodies(bb)%inertia, bodies(bb)%pose, &
                                                             bodies(bb)%pose_start))
            m(oo + ndim + 1:oo + ndof, :) = matmul(iinv, c(oo + ndim + 1:oo + ndof, :))
         end do
      end function scaled
   end subroutine implicit_velocities

   !> Solve a x = r in place (x returned in r) by Gaussian elimination with
   !> partial pivoting; a is destroyed.
   pure subroutine gauss_solve(a, r)
      real(rp), intent(inout) :: a(:, :), r(:)
      integer :: n, k, i, piv
      real(rp) :: f, rowk(size(a, 2)), t
      n = size(r)
      do k = 1, n
         piv = k - 1 + maxloc(abs(a(k:n, k)), 1)
         if (piv /= k) then
            rowk = a(k, :)
            a(k, :) = a(piv, :)
            a(piv, :) = rowk
            t = r(k)
            r(k) = r(piv)
            r(piv) = t
         end if
         do i = k + 1, n
            f = a(i, k)/a(k, k)
            a(i, k:n) = a(i, k:n) - f*a(k, k:n)
            r(i) = r(i) - f*r(k)
         end do
      end do
      do k = n, 1, -1
         r(k) = (r(k) - dot_product(a(k, k + 1:n), r(k + 1:n)))/a(k, k)
      end do
   end subroutine gauss_solve

   !> Largest squared particle acceleration of the bodies (time-step limit).
   real(rp) function bodies_accel2(bodies) result(a2)
      type(body_t), intent(in) :: bodies(:)
      integer :: b
      real(rp) :: a(ndim), alpha(nrot)
      a2 = 0.0_rp
      do b = 1, size(bodies)
         call accel(bodies(b), a, alpha)
         a2 = max(a2, (norm2(a) + norm2(alpha)*bodies(b)%rbound)**2)
      end do
   end function bodies_accel2

   subroutine bodies_save(bodies)
      type(body_t), intent(inout) :: bodies(:)
      integer :: b
      do b = 1, size(bodies)
         bodies(b)%pose0 = bodies(b)%pose
         bodies(b)%v0 = bodies(b)%v
         bodies(b)%omega0 = bodies(b)%omega
      end do
   end subroutine bodies_save

   !> Half a step with the rates at the start (predictor of the two-stage schemes).
   subroutine bodies_predict(bodies, damp, hdt)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)  !< contact damping (bodies_damping_add)
      real(rp), intent(in) :: hdt
      integer :: b
      real(rp) :: vn(ndim, size(bodies)), wn(nrot, size(bodies))
      call implicit_velocities(bodies, damp, .false., hdt, vn, wn)
      do b = 1, size(bodies)
         if (bodies(b)%motion /= motion_floating) cycle
         bodies(b)%pose%c = bodies(b)%pose%c + hdt*bodies(b)%v
         call rigid_turn(bodies(b)%pose, bodies(b)%omega, hdt)
         bodies(b)%v = vn(:, b)
         bodies(b)%omega = wn(:, b)
      end do
   end subroutine bodies_predict

   !> Symplectic corrector: v1 = v0 + dt a(1/2), x1 = x(1/2) + dt/2 v1.
   subroutine bodies_correct_symplectic(bodies, damp, dt)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)  !< contact damping (bodies_damping_add)
      real(rp), intent(in) :: dt
      integer :: b
      real(rp) :: vn(ndim, size(bodies)), wn(nrot, size(bodies))
      call implicit_velocities(bodies, damp, .true., dt, vn, wn)
      do b = 1, size(bodies)
         if (bodies(b)%motion /= motion_floating) cycle
         bodies(b)%v = vn(:, b)
         bodies(b)%omega = wn(:, b)
         bodies(b)%pose%c = bodies(b)%pose%c + 0.5_rp*dt*bodies(b)%v
         call rigid_turn(bodies(b)%pose, bodies(b)%omega, 0.5_rp*dt)
      end do
   end subroutine bodies_correct_symplectic

   !> Predictor-corrector: corrected half step from the start with the
   !> mid-step rates, then extrapolated to the full step.
   subroutine bodies_correct_pc(bodies, damp, dt)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)  !< contact damping (bodies_damping_add)
      real(rp), intent(in) :: dt
      integer :: b
      real(rp) :: vh(ndim, size(bodies)), wh(nrot, size(bodies))
      call implicit_velocities(bodies, damp, .true., 0.5_rp*dt, vh, wh)
      do b = 1, size(bodies)
         if (bodies(b)%motion /= motion_floating) cycle
         bodies(b)%pose = bodies(b)%pose0
         bodies(b)%pose%c = bodies(b)%pose0%c + dt*vh(:, b)
         call rigid_turn(bodies(b)%pose, wh(:, b), dt)
         bodies(b)%v = 2.0_rp*vh(:, b) - bodies(b)%v0
         bodies(b)%omega = 2.0_rp*wh(:, b) - bodies(b)%omega0
      end do
   end subroutine bodies_correct_pc

   !> Verlet step of the bodies: x1 = x0 + dt v0 + dt^2/2 a0, v1 = v0 + dt a0
   !> (exact under a constant force, whatever the step sizes).
   subroutine bodies_verlet(bodies, damp, dt)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), allocatable, intent(in) :: damp(:, :)  !< contact damping (bodies_damping_add)
      real(rp), intent(in) :: dt
      integer :: b
      real(rp) :: a(ndim), alpha(nrot), vn(ndim, size(bodies)), wn(nrot, size(bodies))
      call implicit_velocities(bodies, damp, .false., dt, vn, wn)
      do b = 1, size(bodies)
         if (bodies(b)%motion /= motion_floating) cycle
         call accel(bodies(b), a, alpha)
         bodies(b)%pose%c = bodies(b)%pose%c + dt*bodies(b)%v + 0.5_rp*dt*dt*a
         ! turned by omega dt, then by alpha dt^2/2 (the sum of the angles in 2D)
         call rigid_turn(bodies(b)%pose, bodies(b)%omega, dt)
         call rigid_turn(bodies(b)%pose, alpha, 0.5_rp*dt*dt)
         bodies(b)%v = vn(:, b)
         bodies(b)%omega = wn(:, b)
      end do
   end subroutine bodies_verlet

   !> Pose and velocities of the prescribed bodies at time t, from their
   !> function of time (the integrators step only the floating ones), so a
   !> prescribed body is exactly where its function says at every stage and
   !> a restart needs no state beyond t.
   subroutine bodies_prescribe(bodies, t)
      type(body_t), intent(inout) :: bodies(:)
      real(rp), intent(in) :: t
      real(rp) :: w, s, co
      integer :: b
      do b = 1, size(bodies)
         associate (x => bodies(b))
            if (x%motion /= motion_prescribed) cycle
            s = 0.0_rp
            co = 0.0_rp
            w = 0.0_rp
            if (x%period > 0.0_rp) then
               w = 2.0_rp*pi/x%period
               s = sin(w*t + x%phase)
               co = cos(w*t + x%phase)
            end if
            x%pose = x%pose_start
            x%pose%c = x%pose_start%c + x%rate(1:ndim)*t + x%amp(1:ndim)*s
            ! turned by rate t, then by amp sin(...) (the angle's sum in this order in 2D)
            call rigid_turn(x%pose, x%rate(ndim + 1:ndof), t)
            call rigid_turn(x%pose, x%amp(ndim + 1:ndof), s)
            x%v = x%rate(1:ndim) + x%amp(1:ndim)*w*co
            x%omega = x%rate(ndim + 1:ndof) + x%amp(ndim + 1:ndof)*w*co
         end associate
      end do
   end subroutine bodies_prescribe

   !> Kinetic and potential energy of the floating bodies [J/m].
   subroutine bodies_energy(bodies, ekin, epot)
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(out) :: ekin, epot
      integer :: b
      ekin = 0.0_rp
      epot = 0.0_rp
      do b = 1, size(bodies)
         if (bodies(b)%motion /= motion_floating) cycle
         ekin = ekin + 0.5_rp*bodies(b)%mass*sum(bodies(b)%v**2) + &
                rigid_rot_energy(rigid_world_inertia(bodies(b)%inertia, bodies(b)%pose, bodies(b)%pose_start), bodies(b)%omega)
         epot = epot + bodies(b)%mass*bodies(b)%g*bodies(b)%pose%c(iup)
      end do
   end subroutine bodies_energy
end module body_dynamics

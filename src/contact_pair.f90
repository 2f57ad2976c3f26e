!> What every contact model does with a pair of surface particles i and j
!> of bodies bi and bj (0: a wall particle): apply a force to the two bodies
!> (equal and opposite), add Coulomb friction, add a velocity-proportional
!> force to the bodies' implicit damping; and the properties of a pair of
!> bodies (masses, friction, restitution, elastic constants, the normal).
module contact_pair
   use kinds, only: rp
   use constants, only: ndim, pi
   use tensor, only: tangent_basis, tangent_basis_along
   use particles, only: particles_t
   use body_dynamics, only: body_t, bodies_damping_add, body_arm
   use rigid, only: pose_t, rigid_moment_add, rigid_moment_sub, rigid_point_velocity, rigid_rotation
   use options, only: motion_floating
   use contact_state, only: contact_t
   implicit none
   private
   public :: pair_force, pair_friction, pair_viscous, velocity_at, contact_normal, partition_weight, lattice_share, &
             pair_mass, body_mass, restitution, tau_pair

contains

   !> Force f on particle i, -f on particle j, summed into their bodies: into
   !> f_normal and t_normal when normal, f_fric and t_fric otherwise.
   subroutine pair_force(bodies, p, i, j, bi, bj, f, normal)
      type(body_t), intent(inout) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j, bi, bj
      real(rp), intent(in) :: f(ndim)
      logical, intent(in) :: normal
      real(rp) :: r(ndim)
      if (bi > 0) then
         r = body_arm(bodies(bi), p%x(:, i))
         if (normal) then
            bodies(bi)%f_normal = bodies(bi)%f_normal + f
            call rigid_moment_add(bodies(bi)%t_normal, r, f)
         else
            bodies(bi)%f_fric = bodies(bi)%f_fric + f
            call rigid_moment_add(bodies(bi)%t_fric, r, f)
         end if
      end if
      if (bj > 0) then
         r = body_arm(bodies(bj), p%x(:, j))
         if (normal) then
            bodies(bj)%f_normal = bodies(bj)%f_normal - f
            call rigid_moment_sub(bodies(bj)%t_normal, r, f)
         else
            bodies(bj)%f_fric = bodies(bj)%f_fric - f
            call rigid_moment_sub(bodies(bj)%t_fric, r, f)
         end if
      end if
   end subroutine pair_force

   !> A velocity-proportional force -c (e . v_rel) e between particles i
   !> and j, along the unit vector e (the normal or the slip direction):
   !> its matrix on each body's (u, v, omega), e J^T J with J the rate of
   !> the particle's velocity along e, into the damping the bodies' step
   !> takes implicitly.
   subroutine pair_viscous(ct, bodies, p, i, j, bi, bj, c, e)
      type(contact_t), intent(inout) :: ct
      type(body_t), intent(in) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j, bi, bj
      real(rp), intent(in) :: c, e(ndim)
      call bodies_damping_add(ct%damp, bodies, bi, bj, p%x(:, i), p%x(:, j), c, e)
   end subroutine pair_viscous

   !> Coulomb friction: mu |f_n| against the tangential slip when sliding.
   !> Below it, a viscous term proportional to the slip speed (up to
   !> v_stick) plus a spring on the slip memory xi (up to xi_max): the
   !> spring holds a contact that carries a steady tangential load, where
   !> the viscous term alone would let it creep at v_stick load/(mu f_n).
   subroutine pair_friction(ct, bodies, p, i, j, bi, bj, n, fn, vij, xi)
      type(contact_t), intent(inout) :: ct
      type(body_t), intent(inout) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j, bi, bj
      real(rp), intent(in) :: n(ndim), fn, vij(ndim), xi(ndim)
      real(rp) :: vt(ndim), u(ndim), s, mu, e(ndim, ndim - 1)
      integer :: k
      mu = friction_coef(bodies, bi, bj)
      if (mu <= 0.0_rp .or. fn <= 0.0_rp) return
      vt = vij - dot_product(vij, n)*n
      u = vt/ct%v_stick
      if (ct%xi_max > 0.0_rp) u = u + (xi - dot_product(xi, n)*n)/ct%xi_max
      s = norm2(u)
      if (s < 1.0_rp) then
         ! the viscous term along every direction of the tangent plane
         e = tangent_basis(n)
         do k = 1, ndim - 1
            call pair_viscous(ct, bodies, p, i, j, bi, bj, mu*fn/ct%v_stick, e(:, k))
         end do
      end if
      if (s <= 0.0_rp) return
      call pair_force(bodies, p, i, j, bi, bj, -mu*fn*u/max(s, 1.0_rp), .false.)
   end subroutine pair_friction

   !> P(xi) of Eq. 2: the share of the pair i, j (normal n, tangential
   !> offset t = d - (d . n) n) in its contact, 0.5 (1 + cos(pi s / dp)) of
   !> the offset s along the surface, 0 from dp on. Along a row of particles
   !> dp apart these shares sum to one for any position of the other
   !> particle. In 3D the product of that along the two axes of the lattice
   !> of the face the pair touches (of the particle whose normal n is most
   !> nearly): over a face's particles it sums to one as the 2D weight does
   !> over a row, where a weight of the distance alone would sum to 0.8 to
   !> 1 as a body slides; and a body extruded from a section meets per unit
   !> width the contact it meets in 2D.
   pure real(rp) function partition_weight(bodies, p, i, j, bi, bj, n, t, dp) result(w)
      type(body_t), intent(in) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j, bi, bj
      real(rp), intent(in) :: n(ndim), t(ndim), dp
      real(rp) :: e(ndim, ndim - 1), s
      w = 0.0_rp
      if (ndim == 2) then
         s = norm2(t)
         if (s < dp) w = 0.5_rp*(1.0_rp + cos(pi*s/dp))
         return
      end if
      if (dot_product(n, p%nrm(:, j)) >= -dot_product(n, p%nrm(:, i))) then
         e = tangent_basis_along(n, lattice_axis(bodies, bj, n))
      else
         e = tangent_basis_along(n, lattice_axis(bodies, bi, n))
      end if
      w = lattice_share(t, e, dp)
   end function partition_weight

   !> The 3D weight of partition_weight for the tangential offset t and the
   !> face's lattice axes e: the product of 0.5 (1 + cos(pi s / dp)) over the
   !> offset s along each axis, 0 from dp on.
   pure real(rp) function lattice_share(t, e, dp) result(w)
      real(rp), intent(in) :: t(ndim), e(ndim, ndim - 1), dp
      real(rp) :: s
      integer :: k
      w = 1.0_rp
      do k = 1, ndim - 1
         s = abs(dot_product(t, e(:, k)))
         if (s >= dp) then
            w = 0.0_rp
            return
         end if
         w = w*0.5_rp*(1.0_rp + cos(pi*s/dp))
      end do
   end function lattice_share

   !> An axis of the particle lattice on a face with normal n, in 3D: of a
   !> body, its axis least aligned with n (a box's lattice runs along its
   !> axes); of a wall, the width z (walls are sections extruded over z),
   !> or x on a face across the width.
   pure function lattice_axis(bodies, b, n) result(a)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: b
      real(rp), intent(in) :: n(ndim)
      real(rp) :: a(ndim), r(ndim, ndim)
      a = 0.0_rp
      if (b > 0) then
         r = rigid_rotation(bodies(b)%pose, pose_t())
         a = r(:, minloc(abs(matmul(n, r)), 1))
      else if (abs(n(ndim)) < 0.5_rp) then
         a(ndim) = 1.0_rp
      else
         a(1) = 1.0_rp
      end if
   end function lattice_axis

   !> Velocity at point x of the body b that particle own belongs to; for a
   !> wall particle (b = 0) the particle's own velocity.
   pure function velocity_at(bodies, p, b, x, own) result(v)
      type(body_t), intent(in) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: b, own
      real(rp), intent(in) :: x(ndim)
      real(rp) :: v(ndim)
      if (b > 0) then
         v = rigid_point_velocity(bodies(b)%v, bodies(b)%omega, body_arm(bodies(b), x))
      else
         v = p%v(:, own)
      end if
   end function velocity_at

   !> The normal of the flat side of the pair i, j at offset d = x_i - x_j
   !> (a corner or a curve takes the face's normal); two flats or two curves:
   !> their mean.
   pure function contact_normal(p, i, j, d) result(n)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j
      real(rp), intent(in) :: d(ndim)
      real(rp) :: n(ndim), s
      if (p%surf(j) == 1 .and. p%surf(i) /= 1) then
         n = p%nrm(:, j)
      else if (p%surf(i) == 1 .and. p%surf(j) /= 1) then
         n = -p%nrm(:, i)
      else if (p%surf(i) == 1 .and. dot_product(p%nrm(:, i), p%nrm(:, j)) > -0.866_rp) then
         ! two flat faces that do not face each other (the side of a block
         ! next to the floor): the face the other particle stands in front of
         if (dot_product(d, p%nrm(:, j)) >= -dot_product(d, p%nrm(:, i))) then
            n = p%nrm(:, j)
         else
            n = -p%nrm(:, i)
         end if
      else
         n = p%nrm(:, j) - p%nrm(:, i)
         s = norm2(n)
         if (s < 1.0e-6_rp) then
            n = d/norm2(d)
         else
            n = n/s
         end if
      end if
   end function contact_normal

   !> A floating body (b = 0: a wall particle).
   pure logical function is_floating(bodies, b)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: b
      is_floating = .false.
      if (b > 0) is_floating = bodies(b)%motion == motion_floating
   end function is_floating

   !> Mass that scales the pair force: the lighter floating body's mass per
   !> surface particle (walls, fixed and prescribed bodies count as infinite).
   pure real(rp) function pair_mass(bodies, bi, bj) result(m)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      m = huge(1.0_rp)
      if (is_floating(bodies, bi)) m = min(m, bodies(bi)%m_surf)
      if (is_floating(bodies, bj)) m = min(m, bodies(bj)%m_surf)
   end function pair_mass

   !> Reduced mass of two floating bodies, or the floating one's mass
   !> against a wall, fixed or prescribed body.
   pure real(rp) function body_mass(bodies, bi, bj) result(m)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      if (is_floating(bodies, bi) .and. is_floating(bodies, bj)) then
         m = bodies(bi)%mass*bodies(bj)%mass/(bodies(bi)%mass + bodies(bj)%mass)
      else if (is_floating(bodies, bi)) then
         m = bodies(bi)%mass
      else
         m = bodies(bj)%mass
      end if
   end function body_mass

   !> Between two floating bodies the mean; a wall, a fixed or a prescribed
   !> body takes the floating body's coefficient.
   pure real(rp) function friction_coef(bodies, bi, bj) result(mu)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      if (is_floating(bodies, bi) .and. is_floating(bodies, bj)) then
         mu = 0.5_rp*(bodies(bi)%mu + bodies(bj)%mu)
      else if (is_floating(bodies, bi)) then
         mu = bodies(bi)%mu
      else
         mu = bodies(bj)%mu
      end if
   end function friction_coef

   !> The mean restitution of two bodies; a wall takes the body's.
   pure real(rp) function restitution(bodies, bi, bj) result(e)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      if (bi > 0 .and. bj > 0) then
         e = 0.5_rp*(bodies(bi)%restitution + bodies(bj)%restitution)
      else
         e = bodies(max(bi, bj))%restitution
      end if
   end function restitution

   !> tau_i + tau_j, tau = (1 - nu^2)/E; a wall takes the body's material.
   pure real(rp) function tau_pair(bodies, bi, bj) result(t)
      type(body_t), intent(in) :: bodies(:)
      integer, intent(in) :: bi, bj
      integer :: k1, k2
      k1 = max(bi, bj)
      k2 = k1
      if (bi > 0 .and. bj > 0) k2 = min(bi, bj)
      t = (1.0_rp - bodies(k1)%poisson**2)/bodies(k1)%young + (1.0_rp - bodies(k2)%poisson**2)/bodies(k2)%young
   end function tau_pair
end module contact_pair

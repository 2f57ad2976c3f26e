!> The seed paper's contact force f = n R(psi) P(xi) eps(z, u_L) (Eq. 2-6)
!> with the repulsive (Eq. 4), non-cohesive (Eq. 5) and non-cohesive with a
!> static spring (Eq. 6) coefficients, Coulomb friction with a slip memory,
!> u_L and the slip taken at the contact centre of two touching bodies.
module contact_eq
   use kinds, only: rp
   use constants, only: ndim
   use params, only: params_t
   use particles, only: particles_t
   use body_dynamics, only: body_t, body_arm
   use rigid, only: nrot
   use options, only: model_dynamic, model_repulsive, model_noncohesive, model_spring, model_hertz
   use contact_state, only: contact_t, key_index, store_pair, contact_note_dt
   use contact_pair, only: pair_force, pair_friction, pair_viscous, velocity_at, contact_normal, partition_weight, &
                           pair_mass, body_mass
   implicit none
   private
   public :: eq_gather, eq_apply

contains

   !> First pass over the candidate pairs of the sweep: the geometry of each
   !> pair, and the contact centre of its two bodies.
   subroutine eq_gather(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(in) :: bodies(:)
      integer :: m, i, j, bi, bj, k, b
      real(rp) :: d(ndim), n(ndim), psi_c, pw, psi, q, rq, xm(ndim)
      pairs: do m = 1, ct%nc
         i = ct%cij(1, m); j = ct%cij(2, m); bi = ct%cij(3, m); bj = ct%cij(4, m)
         d = p%x(:, i) - p%x(:, j)
         n = contact_normal(p, i, j, d)
         psi_c = dot_product(d, n)                 ! normal distance of the particle centres
         if (psi_c <= -prm%dp) cycle pairs         ! passed through: never pull back across
         pw = partition_weight(bodies, p, i, j, bi, bj, n, d - psi_c*n, prm%dp)   ! P(xi)
         if (pw <= 0.0_rp) cycle pairs
         psi = psi_c - 0.5_rp*prm%dp               ! distance of particle i from the other surface
         q = max(psi, 0.0_rp)/(2.0_rp*prm%h)
         if (q >= 1.0_rp) cycle pairs
         rq = rhat(ct, q)                          ! R(psi)/A, bounded at contact
         ct%max_penetration = max(ct%max_penetration, prm%dp - psi_c)
         k = key_index(ct, p%body(i), p%body(j))
         ! the pair's midpoint; with periodic sides its image nearest a body's centre (the
         ! pairs of one contact may be met on either side)
         xm = 0.5_rp*(p%x(:, i) + p%x(:, j))
         b = max(bi, bj)
         if (b > 0) then
            if (bodies(b)%period_z > 0.0_rp) xm = bodies(b)%pose%c + body_arm(bodies(b), xm)
         end if
         ct%kx(:, k) = ct%kx(:, k) + rq*pw*xm
         ct%kw(k) = ct%kw(k) + rq*pw
         ct%kt(1:ndim, k) = ct%kt(1:ndim, k) + merge(rq*pw, -rq*pw, p%body(i) < p%body(j))*n
         if (bi == 0) ct%kv(:, k) = ct%kv(:, k) + rq*pw*p%v(:, i)
         if (bj == 0) ct%kv(:, k) = ct%kv(:, k) + rq*pw*p%v(:, j)
         call store_pair(ct, i, j, bi, bj, n, rq*pw, q, pw*max(prm%dp - psi_c, 0.0_rp), k)
      end do pairs
   end subroutine eq_gather

   !> Second pass: u_L, the coefficient A, the normal force and friction.
   !> u_L and the slip are the two bodies' relative motion at the centre of
   !> their contact, so that a rolling disc or a pivoting corner meets no
   !> resistance from the damping; between two flat faces u_L is that of
   !> the particles themselves, so that rocking is damped.
   subroutine eq_apply(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      integer :: m, i, j, bi, bj
      real(rp) :: xc(ndim), vrel(ndim), n(ndim), ul, a, fn, m_ij, rp_w, q, kstiff, aimp, xi(ndim), kc, kc_pair, cc, f_core, mb
      pairs: do m = 1, ct%np
         i = ct%pij(1, m); j = ct%pij(2, m); bi = ct%pb(1, m); bj = ct%pb(2, m)
         n = ct%pn(:, m); rp_w = ct%pw(m); q = ct%pq(m)
         xc = ct%kx(:, ct%pkey(m))/ct%kw(ct%pkey(m))
         vrel = velocity_at(bodies, p, bi, xc, i) - velocity_at(bodies, p, bj, xc, j)
         ! in 3D a body can also spin about the contact's normal, which moves the
         ! contact centre not at all: each pair slips by that spin at its own place
         if (ndim == 3) vrel = vrel + spin_slip(bodies, p, i, j, bi, bj, n, xc)
         if (p%surf(i) == 1 .and. p%surf(j) == 1) then
            ul = dot_product(p%v(:, i) - p%v(:, j), n)
         else
            ul = dot_product(vrel, n)
         end if
         a = coefficient_a(ct, ul, prm%h)
         ! eps of Eq. 2, written as a term added to A: 1 at rest and receding;
         ! approaching, the dynamic head of the relative approach K u_L^2 / h,
         ! so that a fast impact meets a force that grows with its speed
         aimp = 0.0_rp
         if (ul < 0.0_rp) aimp = ct%k_imp*ul*ul/prm%h
         m_ij = pair_mass(bodies, bi, bj)
         fn = m_ij*(a + aimp)*rp_w
         if (ct%core > 0.0_rp .and. ct%po(m) > 0.0_rp) then
            ! the stiff core: where the outlines overlap, a spring that carries
            ! the weight of the floating body (two: their reduced mass) on one pair at an
            ! overlap of ct%core, with a damper critical for that pair alone
            ! under the body (several pairs side by side damp a face's
            ! motion more than critically: a block lands without bouncing);
            ! never pulling (non-cohesive)
            mb = body_mass(bodies, bi, bj)
            kc = mb*prm%g/ct%core
            kc_pair = kc*rp_w/rhat(ct, q)           ! times P(xi): this pair's share
            cc = 2.0_rp*sqrt(kc_pair*sqrt(m_ij*mb))
            f_core = kc*ct%po(m) - cc*ul
            if (f_core > 0.0_rp) then
               fn = fn + f_core
               call pair_viscous(ct, bodies, p, i, j, bi, bj, cc, n)
            end if
            call contact_note_dt(ct, 0.3_rp*sqrt(m_ij/max(kc_pair, tiny(1.0_rp))), bi, bj)
         end if
         if (.not. abs(fn) > 0.0_rp) cycle pairs
         if (ct%model /= model_noncohesive .or. ul <= 0.0_rp) then
            call pair_viscous(ct, bodies, p, i, j, bi, bj, m_ij*(ct%k10b2*ct%r_f*ct%c + &
                              2.0_rp*ct%k_imp*abs(min(ul, 0.0_rp)))*rp_w/prm%h, n)
         end if
         ! stiffness of the static term (and of the approach term, which
         ! multiplies the same R) for the time step: d(R)/d(psi)
         kstiff = m_ij*(ct%k10b2*0.005_rp*ct%c**2/prm%h + aimp)*rp_w/rhat(ct, q)*drhat(ct, q)/(2.0_rp*prm%h)
         call contact_note_dt(ct, 0.3_rp*sqrt(m_ij/max(kstiff, tiny(1.0_rp))), bi, bj)
         ! resolve the approach: at most 0.05 dp of closing per step
         if (ul < 0.0_rp) call contact_note_dt(ct, 0.05_rp*prm%dp/abs(ul), bi, bj)
         call pair_force(bodies, p, i, j, bi, bj, fn*n, .true.)
         ! the slip memory of the contact, as the slip of particle i's body
         xi = 0.0_rp
         if (ct%kmem(ct%pkey(m)) > 0) xi = merge(1.0_rp, -1.0_rp, p%body(i) < p%body(j))*ct%mxi(:, ct%kmem(ct%pkey(m)))
         if (fn > 0.0_rp) call pair_friction(ct, bodies, p, i, j, bi, bj, n, fn, vrel, xi)
      end do pairs
   end subroutine eq_apply

   !> The slip of the pair i, j from the two bodies' relative spin about the
   !> normal n, at the pair's midpoint seen from the contact centre xc (3D:
   !> ndim = nrot = 3; in 2D it is not called).
   pure function spin_slip(bodies, p, i, j, bi, bj, n, xc) result(v)
      type(body_t), intent(in) :: bodies(:)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: i, j, bi, bj
      real(rp), intent(in) :: n(ndim), xc(ndim)
      real(rp) :: v(ndim), xm(ndim), arm(ndim), w3(3), n3(3), a3(3), v3(3)
      integer :: b
      w3 = 0.0_rp
      if (bi > 0) w3(1:nrot) = w3(1:nrot) + bodies(bi)%omega
      if (bj > 0) w3(1:nrot) = w3(1:nrot) - bodies(bj)%omega
      xm = 0.5_rp*(p%x(:, i) + p%x(:, j))
      b = max(bi, bj)
      arm = xm - xc
      ! with periodic sides the arms of the images nearest the body's centre
      if (b > 0) arm = body_arm(bodies(b), xm) - body_arm(bodies(b), xc)
      n3 = 0.0_rp
      n3(1:ndim) = n
      a3 = 0.0_rp
      a3(1:ndim) = arm
      v3 = dot_product(w3, n3)*[n3(2)*a3(3) - n3(3)*a3(2), n3(3)*a3(1) - n3(1)*a3(3), n3(1)*a3(2) - n3(2)*a3(1)]
      v = v3(1:ndim)
   end function spin_slip

   !> R(psi)/A of Eq. 3: (1 - q)/sqrt(q + q0) times the barrier
   !> 1 + (qb/(q + q0))^4, which leaves R as it is at touching distance and
   !> above and makes it rise steeply before the particles reach the other
   !> surface (q = 0), so that loads and impacts stop short of it.
   pure real(rp) function rhat(ct, q) result(r)
      type(contact_t), intent(in) :: ct
      real(rp), intent(in) :: q
      r = (1.0_rp - q)/sqrt(q + ct%q0)*(1.0_rp + (ct%qb/(q + ct%q0))**4)
   end function rhat

   !> -d(rhat)/dq, the stiffness of R for the time step.
   pure real(rp) function drhat(ct, q) result(d)
      type(contact_t), intent(in) :: ct
      real(rp), intent(in) :: q
      real(rp) :: s
      s = q + ct%q0
      d = (1.0_rp/sqrt(s) + 0.5_rp*(1.0_rp - q)/s**1.5_rp)*(1.0_rp + (ct%qb/s)**4) + &
          (1.0_rp - q)/sqrt(s)*4.0_rp*ct%qb**4/s**5
   end function drhat

   !> The coefficient A of Eq. 4 (repulsive), 5 (non-cohesive) or 6
   !> (non-cohesive with a static spring), per unit mass [m/s2].
   pure real(rp) function coefficient_a(ct, ul, h) result(a)
      type(contact_t), intent(in) :: ct
      real(rp), intent(in) :: ul, h
      a = 0.0_rp
      ! allow(missing-default-case): ct%model is one of the five models of options, each a case here
      select case (ct%model)
      case (model_repulsive)                       ! Eq. 4: attractive once u_L > 0.005 c
         if (ul > 0.0_rp) then
            a = ct%k10b2*(0.01_rp*0.5_rp*ct%c**2 - ct%c*ul)/h
         else
            a = -ct%k10b2*ct%r_f*ct%c*ul/h
         end if
      case (model_noncohesive)                     ! Eq. 5
         a = 0.0_rp
         if (ul <= 0.0_rp) a = -ct%k10b2*ct%r_f*ct%c*ul/h
      case (model_spring)                          ! Eq. 6
         ! as Eq. 6 when approaching; when receding, the same expression held
         ! at zero or above: the spring fades out over 0 < u_L < 0.005 c / r_f
         ! instead of dropping at once. Continuous in u_L, never attractive;
         ! over a rolling contact the damping of the approaching and the
         ! receding particles cancels, so rolling meets no resistance.
         a = ct%k10b2*max(0.005_rp*ct%c**2 - ct%r_f*ct%c*ul, 0.0_rp)/h
      case (model_dynamic, model_hertz)            ! these models have no A
         a = 0.0_rp
      end select
   end function coefficient_a

end module contact_eq

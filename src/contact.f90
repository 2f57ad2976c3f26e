!> Contact between bodies, and between a body and a wall: the seed paper's
!> force f = n R(psi) P(xi) eps(z, u_L) (Eq. 2-6) with the repulsive,
!> non-cohesive and non-cohesive-with-spring coefficients, a Hertz DEM
!> contact, and the dynamic-boundary baseline; Coulomb friction on top.
!> Every pair force is applied equal and opposite. doc/contact.md says how
!> each symbol is computed.
module contact
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use kinds, only: rp
   use constants, only: pi, kind_fluid, kind_floating
   use params, only: params_t
   use grid, only: grid_t, grid_ranges
   use particles, only: particles_t
   use body_dynamics, only: body_t, body_of, bodies_damping_reset, bodies_damping_add
   use input_body, only: contact_cfg
   use kernel, only: kernel_gradw
   use options, only: model_dynamic, model_repulsive, model_noncohesive, &
                      model_spring, model_hertz, motion_floating, motion_fixed
   use comm, only: comm_size, comm_allgatherv
   implicit none
   private
   public :: contact_t, contact_init, contact_forces, contact_memory_advance, contact_memory_get, &
             contact_memory_set

   type :: contact_t
      integer :: model = model_spring
      real(rp) :: k10b2 = 1.0_rp      !< (10/B)^2
      real(rp) :: c = 0.0_rp          !< reference speed c0 of Eq. 4-6 [m/s]
      real(rp) :: r_f = 10.0_rp
      real(rp) :: q0 = 0.001_rp
      real(rp) :: qb = 0.0_rp         !< q at which the barrier of R doubles it (0: no barrier)
      real(rp) :: v_stick = 1.0e-3_rp
      real(rp) :: xi_max = 0.0_rp     !< slip held by the static friction spring at mu f_n [m] (0: no spring)
      real(rp) :: k_imp = 0.0_rp      !< K of the approach term K u_L^2 / h (Eq. 2-6 models)
      real(rp) :: max_penetration = 0.0_rp  !< largest overlap of two surfaces in the last evaluation [m]
      real(rp) :: dt_limit = huge(1.0_rp)   !< stable step for the stiffest contact of the last evaluation [s]
      real(rp) :: dt_motion = huge(1.0_rp)  !< step in which no point of a moving body moves more than cfl h [s]
      ! Hertz: restitution e(alpha) of the damped Hertz spring on a grid of the
      ! damping number alpha (tsuji_table), inverted by interpolation
      real(rp), allocatable :: tab_alpha(:), tab_e(:)
      !> damping of the velocity-proportional contact forces between the floating
      !> bodies, taken implicitly in their step (body_dynamics: implicit_velocities)
      real(rp), allocatable :: damp(:, :)
      logical, allocatable :: cand(:)
      ! pairs of the last sweep (Eq. 2-6 models), gathered before the forces
      ! are applied: the slip of the friction is taken at the contact centre
      ! of each pair of touching bodies, so that a rolling body does not slip
      integer :: np = 0, nk = 0
      integer, allocatable :: pij(:, :), pb(:, :), pkey(:)
      real(rp), allocatable :: pn(:, :), pw(:), pq(:)
      integer, allocatable :: kid(:, :)
      real(rp), allocatable :: kx(:, :), kw(:)
      real(rp), allocatable :: kt(:, :)     !< Hertz: sum of sqrt(overlap) n n^T per pair of bodies (xx, xy, yy);
                                            !< Eq. 2-6 models: weighted normal (1:2), from the higher id to the lower
      integer, allocatable :: kmem(:)       !< slip memory of each contact of the sweep (0: none yet)
      real(rp), allocatable :: kv(:, :)     !< Eq. 2-6 models: weighted velocity of the wall's particles (no body)
      ! slip memory of the static friction (Eq. 2-6 models): per pair of
      ! touching bodies (ids lo < hi), the tangential slip xi of body lo
      ! against body hi at their contact centre, accumulated over the steps
      ! the contact has lasted and held at |xi| <= xi_max; kept across steps
      ! and in the checkpoint
      integer :: nm = 0
      integer, allocatable :: mid(:, :)
      real(rp), allocatable :: mxi(:, :)
   end type contact_t

contains

   subroutine contact_init(cfg, prm, coef, ct)
      type(contact_cfg), intent(in) :: cfg
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: coef
      type(contact_t), intent(out) :: ct
      real(rp) :: b
      ct%model = cfg%model_id
      b = cfg%b
      if (b <= 0.0_rp) b = coef
      ct%k10b2 = (10.0_rp/b)**2
      ! default c0 = B sqrt(g h): the static term (10/B)^2 0.005 c0^2 / h equals
      ! g/2, so that a body resting on a face carries its weight inside the
      ! barrier of R, where the contact is stiff enough that a coarse cube does
      ! not tip over on its own compliance (doc/contact.md)
      ct%c = cfg%c0
      if (ct%c <= 0.0_rp) ct%c = sqrt(0.5_rp*max(prm%g, 1.0e-3_rp)*prm%h/(0.005_rp*ct%k10b2))
      ct%r_f = cfg%r_f
      ct%q0 = cfg%q0
      ! q_b = barrier dp/(8h): with the default 2, the touching q_t = dp/(4h)
      ct%qb = cfg%barrier*0.125_rp*prm%dp/prm%h
      ct%v_stick = cfg%stick_velocity
      ct%xi_max = cfg%stick_length*prm%dp
      ct%k_imp = cfg%impact
      if (ct%model == model_hertz) call tsuji_table(ct)
   end subroutine contact_init

   !> Restitution of one Hertz contact with the damping of Tsuji et al.
   !> (1992), m d'' = -k d^(3/2) - alpha sqrt(m k) d^(1/4) d', force never
   !> pulling, for alpha on a grid. In the units m = k = 1 and an impact
   !> speed of 1 the rebound speed is e; e depends on alpha alone, not on
   !> the speed, the mass or the stiffness (the d^(1/4) damping is what makes
   !> it so), so one table serves every contact.
   subroutine tsuji_table(ct)
      type(contact_t), intent(inout) :: ct
      integer, parameter :: na = 400
      real(rp), parameter :: alpha_max = 15.0_rp, ddt = 2.0e-3_rp
      integer :: k, m
      real(rp) :: a, d, v, k1(2), k2(2), k3(2), k4(2)
      integer :: ist
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (ct%tab_alpha(0:na), ct%tab_e(0:na), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ct%tab_alpha, ct%tab_e in tsuji_table')
      do k = 0, na
         ! dense near alpha = 0, where e changes fastest
         a = alpha_max*(real(k, rp)/na)**2
         d = 0.0_rp
         v = 1.0_rp
         steps: do m = 1, 10000000
            k1 = rate(d, v)
            k2 = rate(d + 0.5_rp*ddt*k1(1), v + 0.5_rp*ddt*k1(2))
            k3 = rate(d + 0.5_rp*ddt*k2(1), v + 0.5_rp*ddt*k2(2))
            k4 = rate(d + ddt*k3(1), v + ddt*k3(2))
            d = d + ddt*(k1(1) + 2.0_rp*k2(1) + 2.0_rp*k3(1) + k4(1))/6.0_rp
            v = v + ddt*(k1(2) + 2.0_rp*k2(2) + 2.0_rp*k3(2) + k4(2))/6.0_rp
            if (d < 0.0_rp .and. v < 0.0_rp) exit steps
         end do steps
         ct%tab_alpha(k) = a
         ct%tab_e(k) = -v
      end do
   contains
      pure function rate(d, v) result(r)
         real(rp), intent(in) :: d, v
         real(rp) :: r(2)
         r(1) = v
         r(2) = 0.0_rp
         if (d > 0.0_rp) r(2) = -max(d**1.5_rp + a*d**0.25_rp*v, 0.0_rp)
      end function rate
   end subroutine tsuji_table

   !> Damping number alpha that gives restitution e (the table is monotone).
   pure real(rp) function tsuji_alpha(ct, e) result(a)
      type(contact_t), intent(in) :: ct
      real(rp), intent(in) :: e
      integer :: lo, hi, mid
      real(rp) :: w
      lo = 0
      hi = size(ct%tab_e) - 1
      if (e >= ct%tab_e(lo)) then
         a = 0.0_rp
         return
      end if
      if (e <= ct%tab_e(hi)) then
         a = ct%tab_alpha(hi)
         return
      end if
      do while (hi - lo > 1)                   ! tab_e falls with alpha
         mid = (lo + hi)/2
         if (ct%tab_e(mid) > e) then
            lo = mid
         else
            hi = mid
         end if
      end do
      w = (ct%tab_e(lo) - e)/(ct%tab_e(lo) - ct%tab_e(hi))
      a = (1.0_rp - w)*ct%tab_alpha(lo) + w*ct%tab_alpha(hi)
   end function tsuji_alpha

   !> Contact forces and torques on every body (f_normal, t_normal, f_fric,
   !> t_fric); for the dynamic model also the density rates of the pair.
   ! allow(too-complex): counted with its contained procedures, each of them short; they share the sweep's data
   subroutine contact_forces(ct, prm, g, p, bodies, drho)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      real(rp), intent(inout) :: drho(:)
      integer :: i, j, c, r, jlo(2), jhi(2), bi, bj, k
      real(rp) :: d(2), r2
      do k = 1, size(bodies)
         bodies(k)%f_normal = 0.0_rp; bodies(k)%t_normal = 0.0_rp
         bodies(k)%f_fric = 0.0_rp; bodies(k)%t_fric = 0.0_rp
      end do
      call bodies_damping_reset(ct%damp, size(bodies))
      ct%max_penetration = 0.0_rp
      ct%dt_limit = huge(1.0_rp)
      ct%dt_motion = huge(1.0_rp)
      ct%np = 0
      ct%nk = 0
      call find_candidates(ct, prm, p, bodies)
      ! pairs from the owned particles: every pair is met on one rank only
      do i = 1, p%n_own
         if (.not. ct%cand(i)) cycle
         c = g%icell(i)
         call grid_ranges(g, c, i, jlo, jhi)
         bi = body_of(bodies, p%body(i))
         do r = 1, 2
            partners: do j = jlo(r), jhi(r)
               if (.not. ct%cand(j)) cycle partners
               if (p%body(j) == p%body(i)) cycle partners
               if (p%kind(i) /= kind_floating .and. p%kind(j) /= kind_floating) cycle partners
               d = p%x(:, i) - p%x(:, j)
               r2 = d(1)**2 + d(2)**2
               if (r2 >= prm%support2) cycle partners
               bj = body_of(bodies, p%body(j))
               call pair(i, j, bi, bj, d, r2)
            end do partners
         end do
      end do
      ! a contact split between ranks: its centre and pair count over all of them
      if (ct%model /= model_dynamic .and. comm_size() > 1) call merge_keys(ct)
      if (ct%np > 0) then
         if (ct%model == model_hertz) then
            call apply_hertz_pairs()
         else
            call apply_eq_pairs()
         end if
      end if
      ! no point of a floating or prescribed body moves more than cfl h in a
      ! step, as the fluid's CFL keeps its particles: without water nothing
      ! else limits the step, and two bodies could jump from out of reach into
      ! deep overlap (a prescribed body's velocity is that of its function)
      do k = 1, size(bodies)
         if (bodies(k)%motion == motion_fixed) cycle
         ct%dt_motion = min(ct%dt_motion, prm%cfl*prm%h/max(norm2(bodies(k)%v) + abs(bodies(k)%omega)* &
                                                             bodies(k)%rbound, tiny(1.0_rp)))
      end do
   contains
      !> A velocity-proportional force -c (e . v_rel) e between particles i
      !> and j, along the unit vector e (the normal or the slip direction):
      !> its matrix on each body's (u, v, omega), e J^T J with J the rate of
      !> the particle's velocity along e.
      subroutine viscous(i, j, bi, bj, c, e)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: c, e(2)
         call bodies_damping_add(ct%damp, bodies, bi, bj, p%x(:, i), p%x(:, j), c, e)
      end subroutine viscous

      subroutine pair(i, j, bi, bj, d, r2)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: d(2), r2
         select case (ct%model)
         case (model_dynamic)
            call pair_dynamic(i, j, bi, bj, d)
         case (model_hertz)
            call pair_hertz(i, j, bi, bj, d, r2)
         case (model_repulsive, model_noncohesive, model_spring)
            call pair_eq(i, j, bi, bj, d)
         case default
            call fatal('contact: no pair force for model '//int_str(ct%model))
         end select
      end subroutine pair

      !> Dynamic boundary between bodies: continuity and pressure as for the fluid.
      subroutine pair_dynamic(i, j, bi, bj, d)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: d(2)
         real(rp) :: gw(2), dr, f(2), fn, vij(2)
         vij = p%v(:, i) - p%v(:, j)
         gw = kernel_gradw(prm%kernel, d, prm%h)
         dr = dot_product(vij, gw)
         drho(i) = drho(i) + p%mass(j)*dr
         drho(j) = drho(j) + p%mass(i)*dr
         f = -p%mass(i)*p%mass(j)*(p%p(i) + p%p(j))/(p%rho(i)*p%rho(j))*gw
         fn = norm2(f)
         call apply(i, j, bi, bj, f, .true.)
         if (fn > 0.0_rp) call friction(i, j, bi, bj, f/fn, fn, vij, [0.0_rp, 0.0_rp])
      end subroutine pair_dynamic

      !> Hertz contact of the particles as spheres of diameter dp (Canelas et
      !> al. 2016 form), first pass: the overlapping pairs, and per pair of
      !> touching bodies the sums of sqrt(overlap) n and sqrt(overlap) n n^T,
      !> which give the contact's normal and its stiffness along it.
      subroutine pair_hertz(i, j, bi, bj, d, r2)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: d(2), r2
         real(rp) :: overlap, n(2), w, un, kn, dmax
         integer :: k
         ! resolve the coming impact from before the first touch: its duration
         ! for one pair meeting at the approach speed un (Hertz) is
         ! 2.94 dmax/|un|, dmax = (5/4 M un^2/kn)^(2/5); take 40 steps or more
         un = dot_product(p%v(:, i) - p%v(:, j), d)/sqrt(r2)
         if (un < 0.0_rp) then
            kn = 4.0_rp/(3.0_rp*tau_pair(bi, bj))*sqrt(0.25_rp*prm%dp)
            dmax = (1.25_rp*body_mass(bi, bj)*un*un/kn)**0.4_rp
            ct%dt_limit = min(ct%dt_limit, 2.94_rp*dmax/(40.0_rp*abs(un)))
         end if
         overlap = prm%dp - sqrt(r2)
         if (overlap <= 0.0_rp) return
         ct%max_penetration = max(ct%max_penetration, overlap)
         k = key_index(ct, p%body(i), p%body(j))
         n = d/sqrt(r2)
         w = sqrt(overlap)
         ct%kw(k) = ct%kw(k) + w
         ! oriented from the lower body id to the higher, whichever of the two
         ! particles the sweep calls i
         ct%kx(:, k) = ct%kx(:, k) + merge(w, -w, p%body(i) > p%body(j))*n
         ct%kt(:, k) = ct%kt(:, k) + w*[n(1)*n(1), n(1)*n(2), n(2)*n(2)]
         call store_pair(i, j, bi, bj, n, overlap, 0.0_rp, k)
      end subroutine pair_hertz

      !> Second pass. The contact of two bodies is one damped spring along its
      !> normal N (the sqrt(overlap)-weighted mean of the pair normals): its
      !> tangent stiffness along N is S = sum 3/2 kn sqrt(overlap) (n.N)^2 and
      !> its damping along N is alpha sqrt(M S / (3/2)), Tsuji's form with
      !> alpha for the set restitution (tsuji_table). The damping is shared
      !> among the pairs in proportion to their stiffness 3/2 kn sqrt(overlap),
      !> so that a single pair along N gets Tsuji's damping exactly and pairs
      !> that meet at a slant (particles between two of the other row) damp
      !> the motion along N as much as they resist it.
      subroutine apply_hertz_pairs()
         integer :: m, i, j, bi, bj, k
         real(rp) :: overlap, n(2), ul, kn, gn, mc, fn, sk, sn, nn(2), vij(2)
         do m = 1, ct%np
            i = ct%pij(1, m); j = ct%pij(2, m); bi = ct%pb(1, m); bj = ct%pb(2, m)
            n = ct%pn(:, m); overlap = ct%pw(m); k = ct%pkey(m)
            vij = p%v(:, i) - p%v(:, j)
            ul = dot_product(vij, n)
            kn = 4.0_rp/(3.0_rp*tau_pair(bi, bj))*sqrt(0.25_rp*prm%dp)
            mc = body_mass(bi, bj)
            sk = 1.5_rp*kn*sqrt(overlap)
            nn = ct%kx(:, k)/max(norm2(ct%kx(:, k)), tiny(1.0_rp))
            sn = 1.5_rp*kn*max(ct%kt(1, k)*nn(1)**2 + 2.0_rp*ct%kt(2, k)*nn(1)*nn(2) + ct%kt(3, k)*nn(2)**2, &
                               1.0e-3_rp*ct%kw(k))
            gn = tsuji_alpha(ct, restitution(bi, bj))*sqrt(mc/(1.5_rp*sn))*sk
            fn = max(kn*overlap**1.5_rp - gn*ul, 0.0_rp)
            call viscous(i, j, bi, bj, gn, n)
            ct%dt_limit = min(ct%dt_limit, 0.2_rp*sqrt(mc/(1.5_rp*kn*ct%kw(k))))
            call apply(i, j, bi, bj, fn*n, .true.)
            call friction(i, j, bi, bj, n, fn, vij, [0.0_rp, 0.0_rp])
         end do
      end subroutine apply_hertz_pairs

      !> Reduced mass of two floating bodies, or the floating one's mass
      !> against a wall, fixed or prescribed body.
      real(rp) function body_mass(bi, bj) result(m)
         integer, intent(in) :: bi, bj
         if (floating(bi) .and. floating(bj)) then
            m = bodies(bi)%mass*bodies(bj)%mass/(bodies(bi)%mass + bodies(bj)%mass)
         else if (floating(bi)) then
            m = bodies(bi)%mass
         else
            m = bodies(bj)%mass
         end if
      end function body_mass

      !> The seed paper's f = n R(psi) P(xi) eps(z, u_L), Eq. 2-6, first pass:
      !> the geometry of the pair, and the contact centre of its two bodies.
      subroutine pair_eq(i, j, bi, bj, d)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: d(2)
         real(rp) :: n(2), psi_c, xi, pw, psi, q, rq
         integer :: k
         ! the normal of the flat side of the pair (a corner or a curve takes
         ! the face's normal); two flats or two curves: their mean
         n = contact_normal(i, j, d)
         psi_c = dot_product(d, n)                 ! normal distance of the particle centres
         if (psi_c <= -prm%dp) return              ! passed through: never pull back across
         xi = norm2(d - psi_c*n)                   ! tangential distance
         if (xi >= prm%dp) return
         pw = 0.5_rp*(1.0_rp + cos(pi*xi/prm%dp))  ! P(xi): a partition of unity along a face
         psi = psi_c - 0.5_rp*prm%dp               ! distance of particle i from the other surface
         q = max(psi, 0.0_rp)/(2.0_rp*prm%h)
         if (q >= 1.0_rp) return
         rq = rhat(ct, q)                          ! R(psi)/A, bounded at contact
         ct%max_penetration = max(ct%max_penetration, prm%dp - psi_c)
         k = key_index(ct, p%body(i), p%body(j))
         ct%kx(:, k) = ct%kx(:, k) + rq*pw*0.5_rp*(p%x(:, i) + p%x(:, j))
         ct%kw(k) = ct%kw(k) + rq*pw
         ct%kt(1:2, k) = ct%kt(1:2, k) + merge(rq*pw, -rq*pw, p%body(i) < p%body(j))*n
         if (bi == 0) ct%kv(:, k) = ct%kv(:, k) + rq*pw*p%v(:, i)
         if (bj == 0) ct%kv(:, k) = ct%kv(:, k) + rq*pw*p%v(:, j)
         call store_pair(i, j, bi, bj, n, rq*pw, q, k)
      end subroutine pair_eq

      !> Second pass: u_L, the coefficient A, the normal force and friction.
      !> u_L and the slip are the two bodies' relative motion at the centre of
      !> their contact, so that a rolling disc or a pivoting corner meets no
      !> resistance from the damping; between two flat faces u_L is that of
      !> the particles themselves, so that rocking is damped.
      subroutine apply_eq_pairs()
         integer :: m, i, j, bi, bj
         real(rp) :: xc(2), vrel(2), n(2), ul, a, fn, m_ij, rp_w, q, kstiff, aimp, xi(2)
         do m = 1, ct%np
            i = ct%pij(1, m); j = ct%pij(2, m); bi = ct%pb(1, m); bj = ct%pb(2, m)
            n = ct%pn(:, m); rp_w = ct%pw(m); q = ct%pq(m)
            xc = ct%kx(:, ct%pkey(m))/ct%kw(ct%pkey(m))
            vrel = velocity_at(bi, xc, i) - velocity_at(bj, xc, j)
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
            m_ij = pair_mass(bi, bj)
            fn = m_ij*(a + aimp)*rp_w
            if (.not. abs(fn) > 0.0_rp) cycle
            if (ct%model /= model_noncohesive .or. ul <= 0.0_rp) then
              call viscous(i, j, bi, bj, m_ij*(ct%k10b2*ct%r_f*ct%c + 2.0_rp*ct%k_imp*abs(min(ul, 0.0_rp)))* &
                           rp_w/prm%h, n)
            end if
            ! stiffness of the static term (and of the approach term, which
            ! multiplies the same R) for the time step: d(R)/d(psi)
            kstiff = m_ij*(ct%k10b2*0.005_rp*ct%c**2/prm%h + aimp)*rp_w/rhat(ct, q)*drhat(ct, q)/(2.0_rp*prm%h)
            ct%dt_limit = min(ct%dt_limit, 0.3_rp*sqrt(m_ij/max(kstiff, tiny(1.0_rp))))
            ! resolve the approach: at most 0.05 dp of closing per step
            if (ul < 0.0_rp) ct%dt_limit = min(ct%dt_limit, 0.05_rp*prm%dp/abs(ul))
            call apply(i, j, bi, bj, fn*n, .true.)
            ! the slip memory of the contact, as the slip of particle i's body
            xi = 0.0_rp
            if (ct%kmem(ct%pkey(m)) > 0) xi = merge(1.0_rp, -1.0_rp, p%body(i) < p%body(j))*ct%mxi(:, ct%kmem(ct%pkey(m)))
            if (fn > 0.0_rp) call friction(i, j, bi, bj, n, fn, vrel, xi)
         end do
      end subroutine apply_eq_pairs

      !> Velocity at point x of the body b that particle own belongs to; for a
      !> wall particle (b = 0) the particle's own velocity.
      function velocity_at(b, x, own) result(v)
         integer, intent(in) :: b, own
         real(rp), intent(in) :: x(2)
         real(rp) :: v(2)
         if (b > 0) then
            v = bodies(b)%v + bodies(b)%omega*[-(x(2) - bodies(b)%c(2)), x(1) - bodies(b)%c(1)]
         else
            v = p%v(:, own)
         end if
      end function velocity_at

      subroutine store_pair(i, j, bi, bj, n, w, q, k)
         integer, intent(in) :: i, j, bi, bj, k
         real(rp), intent(in) :: n(2), w, q
         integer :: cap
         integer :: ist
         character(len=200) :: emsg
         if (.not. allocated(ct%pkey)) then
            ! allow(multiple-allocations-with-stat): any of them refused is the same stop
            allocate (ct%pij(2, 256), ct%pb(2, 256), ct%pkey(256), ct%pn(2, 256), &
                      ct%pw(256), ct%pq(256), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 'ct%pij, ct%pb, ct%pkey, ... in store_pair')
         end if
         cap = size(ct%pkey)
         if (ct%np == cap) then
            ct%pij = reshape([ct%pij, spread(0, 1, 2*cap)], [2, 2*cap])
            ct%pb = reshape([ct%pb, spread(0, 1, 2*cap)], [2, 2*cap])
            ct%pkey = [ct%pkey, spread(0, 1, cap)]
            ct%pn = reshape([ct%pn, spread(0.0_rp, 1, 2*cap)], [2, 2*cap])
            ct%pw = [ct%pw, spread(0.0_rp, 1, cap)]
            ct%pq = [ct%pq, spread(0.0_rp, 1, cap)]
         end if
         ct%np = ct%np + 1
         ct%pij(:, ct%np) = [i, j]
         ct%pb(:, ct%np) = [bi, bj]
         ct%pkey(ct%np) = k
         ct%pn(:, ct%np) = n
         ct%pw(ct%np) = w
         ct%pq(ct%np) = q
      end subroutine store_pair

      !> Coulomb friction: mu |f_n| against the tangential slip when sliding.
      !> Below it, a viscous term proportional to the slip speed (up to
      !> v_stick) plus a spring on the slip memory xi (up to xi_max): the
      !> spring holds a contact that carries a steady tangential load, where
      !> the viscous term alone would let it creep at v_stick load/(mu f_n).
      subroutine friction(i, j, bi, bj, n, fn, vij, xi)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: n(2), fn, vij(2), xi(2)
         real(rp) :: vt(2), u(2), s, mu
         mu = friction_coef(bi, bj)
         if (mu <= 0.0_rp .or. fn <= 0.0_rp) return
         vt = vij - dot_product(vij, n)*n
         u = vt/ct%v_stick
         if (ct%xi_max > 0.0_rp) u = u + (xi - dot_product(xi, n)*n)/ct%xi_max
         s = norm2(u)
         if (s < 1.0_rp) call viscous(i, j, bi, bj, mu*fn/ct%v_stick, [-n(2), n(1)])
         if (s <= 0.0_rp) return
         call apply(i, j, bi, bj, -mu*fn*u/max(s, 1.0_rp), .false.)
      end subroutine friction

      !> Force f on particle i, -f on particle j, summed into their bodies.
      subroutine apply(i, j, bi, bj, f, normal)
         integer, intent(in) :: i, j, bi, bj
         real(rp), intent(in) :: f(2)
         logical, intent(in) :: normal
         real(rp) :: r(2)
         if (bi > 0) then
            r = p%x(:, i) - bodies(bi)%c
            if (normal) then
               bodies(bi)%f_normal = bodies(bi)%f_normal + f
               bodies(bi)%t_normal = bodies(bi)%t_normal + r(1)*f(2) - r(2)*f(1)
            else
               bodies(bi)%f_fric = bodies(bi)%f_fric + f
               bodies(bi)%t_fric = bodies(bi)%t_fric + r(1)*f(2) - r(2)*f(1)
            end if
         end if
         if (bj > 0) then
            r = p%x(:, j) - bodies(bj)%c
            if (normal) then
               bodies(bj)%f_normal = bodies(bj)%f_normal - f
               bodies(bj)%t_normal = bodies(bj)%t_normal - (r(1)*f(2) - r(2)*f(1))
            else
               bodies(bj)%f_fric = bodies(bj)%f_fric - f
               bodies(bj)%t_fric = bodies(bj)%t_fric - (r(1)*f(2) - r(2)*f(1))
            end if
         end if
      end subroutine apply

      function contact_normal(i, j, d) result(n)
         integer, intent(in) :: i, j
         real(rp), intent(in) :: d(2)
         real(rp) :: n(2), s
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
      logical function floating(b)
         integer, intent(in) :: b
         floating = .false.
         if (b > 0) floating = bodies(b)%motion == motion_floating
      end function floating

      !> Mass that scales the pair force: the lighter floating body's mass per
      !> surface particle (walls, fixed and prescribed bodies count as infinite).
      real(rp) function pair_mass(bi, bj) result(m)
         integer, intent(in) :: bi, bj
         m = huge(1.0_rp)
         if (floating(bi)) m = min(m, bodies(bi)%m_surf)
         if (floating(bj)) m = min(m, bodies(bj)%m_surf)
      end function pair_mass

      real(rp) function friction_coef(bi, bj) result(mu)
         integer, intent(in) :: bi, bj
         ! between two floating bodies the mean; a wall, a fixed or a
         ! prescribed body takes the floating body's coefficient
         if (floating(bi) .and. floating(bj)) then
            mu = 0.5_rp*(bodies(bi)%mu + bodies(bj)%mu)
         else if (floating(bi)) then
            mu = bodies(bi)%mu
         else
            mu = bodies(bj)%mu
         end if
      end function friction_coef

      real(rp) function restitution(bi, bj) result(e)
         integer, intent(in) :: bi, bj
         if (bi > 0 .and. bj > 0) then
            e = 0.5_rp*(bodies(bi)%restitution + bodies(bj)%restitution)
         else
            e = bodies(max(bi, bj))%restitution
         end if
      end function restitution

      !> tau_i + tau_j, tau = (1 - nu^2)/E; a wall takes the body's material.
      real(rp) function tau_pair(bi, bj) result(t)
         integer, intent(in) :: bi, bj
         integer :: k1, k2
         k1 = max(bi, bj)
         k2 = k1
         if (bi > 0 .and. bj > 0) k2 = min(bi, bj)
         t = (1.0_rp - bodies(k1)%poisson**2)/bodies(k1)%young + (1.0_rp - bodies(k2)%poisson**2)/bodies(k2)%young
      end function tau_pair
   end subroutine contact_forces

   !> Index of the pair of bodies (ids a, b) in the contact table of the
   !> sweep, added with zero sums (and its slip memory, if it has one) when new.
   integer function key_index(ct, a, b) result(k)
      type(contact_t), intent(inout) :: ct
      integer, intent(in) :: a, b
      integer :: lo, hi
      integer :: ist
      character(len=200) :: emsg
      lo = min(a, b); hi = max(a, b)
      k = slot_of(ct%kid, ct%nk, lo, hi)
      if (k > 0) return
      if (.not. allocated(ct%kid)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (ct%kid(2, 16), ct%kx(2, 16), ct%kw(16), ct%kt(3, 16), ct%kmem(16), ct%kv(2, 16), &
                   stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ct%kid, ct%kx, ct%kw, ... in key_index')
      end if
      if (ct%nk == size(ct%kw)) then
         ct%kid = reshape([ct%kid, spread(0, 1, 2*ct%nk)], [2, 2*ct%nk])
         ct%kx = reshape([ct%kx, spread(0.0_rp, 1, 2*ct%nk)], [2, 2*ct%nk])
         ct%kt = reshape([ct%kt, spread(0.0_rp, 1, 3*ct%nk)], [3, 2*ct%nk])
         ct%kw = [ct%kw, spread(0.0_rp, 1, ct%nk)]
         ct%kmem = [ct%kmem, spread(0, 1, ct%nk)]
         ct%kv = reshape([ct%kv, spread(0.0_rp, 1, 2*ct%nk)], [2, 2*ct%nk])
      end if
      ct%nk = ct%nk + 1
      k = ct%nk
      ct%kid(:, k) = [lo, hi]
      ct%kx(:, k) = 0.0_rp
      ct%kt(:, k) = 0.0_rp
      ct%kw(k) = 0.0_rp
      ct%kv(:, k) = 0.0_rp
      ct%kmem(k) = slot_of(ct%mid, ct%nm, lo, hi)
   end function key_index

   !> Column of the pair (lo, hi) among the first n columns of ids, or 0.
   pure integer function slot_of(ids, n, lo, hi) result(k)
      integer, allocatable, intent(in) :: ids(:, :)
      integer, intent(in) :: n, lo, hi
      do k = 1, n
         if (ids(1, k) == lo .and. ids(2, k) == hi) return
      end do
      k = 0
   end function slot_of

   !> The slip memory after a step of length dt (Eq. 2-6 models with a
   !> friction spring): for every contact of the last evaluation, the
   !> tangential slip of its two bodies at the contact centre added, the part along the present normal dropped (the contact turned),
   !> and the whole held at xi_max, where the spring alone gives mu f_n: a
   !> contact that slides carries its memory at that length. Contacts that
   !> ended are forgotten. Every rank holds every contact (merge_keys), so the
   !> memory is the same on all of them.
   subroutine contact_memory_advance(ct, bodies, dt)
      type(contact_t), intent(inout) :: ct
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(in) :: dt
      integer :: k, n
      integer, allocatable :: ids(:, :)
      real(rp), allocatable :: xis(:, :)
      real(rp) :: xc(2), nn(2), vrel(2), xi(2), s
      integer :: ist
      character(len=200) :: emsg
      if (ct%xi_max <= 0.0_rp .or. ct%model == model_dynamic .or. ct%model == model_hertz) return
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (ids(2, ct%nk), xis(2, ct%nk), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ids, xis in contact_memory_advance')
      n = 0
      do k = 1, ct%nk
         if (ct%kw(k) <= 0.0_rp) cycle
         s = norm2(ct%kt(1:2, k))
         if (s <= 0.0_rp) cycle
         nn = ct%kt(1:2, k)/s
         xc = ct%kx(:, k)/ct%kw(k)
         vrel = velocity(ct%kid(1, k)) - velocity(ct%kid(2, k))
         xi = 0.0_rp
         if (ct%kmem(k) > 0) xi = ct%mxi(:, ct%kmem(k))
         xi = xi - dot_product(xi, nn)*nn + (vrel - dot_product(vrel, nn)*nn)*dt
         s = norm2(xi)
         if (s > ct%xi_max) xi = xi*(ct%xi_max/s)
         n = n + 1
         ids(:, n) = ct%kid(:, k)
         xis(:, n) = xi
      end do
      call contact_memory_set(ct, ids(:, 1:n), xis(:, 1:n))
   contains
      !> Velocity at the contact centre xc of the body with id; for a wall
      !> (no body) the weighted mean velocity of its particles in the contact.
      function velocity(id) result(v)
         integer, intent(in) :: id
         real(rp) :: v(2)
         integer :: b
         b = body_of(bodies, id)
         if (b > 0) then
            v = bodies(b)%v + bodies(b)%omega*[-(xc(2) - bodies(b)%c(2)), xc(1) - bodies(b)%c(1)]
         else
            v = ct%kv(:, k)/ct%kw(k)
         end if
      end function velocity
   end subroutine contact_memory_advance

   !> The slip memory as a table: per contact the two body ids and the slip
   !> (for the checkpoint).
   subroutine contact_memory_get(ct, tab)
      type(contact_t), intent(in) :: ct
      real(rp), allocatable, intent(out) :: tab(:, :)
      integer :: m
      integer :: ist
      character(len=200) :: emsg
      allocate (tab(4, ct%nm), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'tab in contact_memory_get')
      do m = 1, ct%nm
         tab(:, m) = [real(ct%mid(1, m), rp), real(ct%mid(2, m), rp), ct%mxi(:, m)]
      end do
   end subroutine contact_memory_get

   !> Replace the slip memory by the contacts ids(:, m) (lo < hi) with slips xis(:, m).
   subroutine contact_memory_set(ct, ids, xis)
      type(contact_t), intent(inout) :: ct
      integer, intent(in) :: ids(:, :)
      real(rp), intent(in) :: xis(:, :)
      integer :: ist
      character(len=200) :: emsg
      ct%nm = size(ids, 2)
      if (allocated(ct%mid)) deallocate (ct%mid, ct%mxi)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (ct%mid(2, max(ct%nm, 1)), ct%mxi(2, max(ct%nm, 1)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ct%mid, ct%mxi in contact_memory_set')
      ct%mid(:, 1:ct%nm) = ids
      ct%mxi(:, 1:ct%nm) = xis
      ! the sweep's contacts point into the old table: they are rebuilt at the next evaluation
      ct%nk = 0
   end subroutine contact_memory_set

   !> The contact table (weighted centre and weight of each pair of touching
   !> bodies, and the Hertz normal tensor) summed over the ranks, in rank
   !> order, so that every rank that holds a pair of the contact sees the same
   !> centre, normal and stiffness.
   subroutine merge_keys(ct)
      type(contact_t), intent(inout) :: ct
      integer, parameter :: nv = 10          ! per key: two ids, kx(2), kw, kt(3), kv(2)
      real(rp), allocatable :: mine(:), all(:)
      integer :: k, m, o
      integer :: ist
      character(len=200) :: emsg
      allocate (mine(nv*ct%nk), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'mine in merge_keys')
      do k = 1, ct%nk
         mine(nv*(k - 1) + 1:nv*k) = [real(ct%kid(1, k), rp), real(ct%kid(2, k), rp), ct%kx(:, k), ct%kw(k), ct%kt(:, k), &
                                       ct%kv(:, k)]
      end do
      call comm_allgatherv(mine, all)
      ! the sums start over; a contact met only on other ranks is added, so
      ! that every rank holds every contact (and the same slip memory)
      do k = 1, ct%nk
         ct%kx(:, k) = 0.0_rp
         ct%kw(k) = 0.0_rp
         ct%kt(:, k) = 0.0_rp
         ct%kv(:, k) = 0.0_rp
      end do
      do m = 1, size(all)/nv
         o = nv*(m - 1)
         k = key_index(ct, nint(all(o + 1)), nint(all(o + 2)))
         ct%kx(:, k) = ct%kx(:, k) + all(o + 3:o + 4)
         ct%kw(k) = ct%kw(k) + all(o + 5)
         ct%kt(:, k) = ct%kt(:, k) + all(o + 6:o + 8)
         ct%kv(:, k) = ct%kv(:, k) + all(o + 9:o + 10)
      end do
   end subroutine merge_keys

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

   !> Surface particles that can touch: those of floating bodies, and those of
   !> walls and other bodies within reach of a floating body.
   subroutine find_candidates(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(in) :: bodies(:)
      integer :: i, b
      real(rp) :: reach
      integer :: ist
      character(len=200) :: emsg
      if (allocated(ct%cand)) then
         if (size(ct%cand) < p%n) deallocate (ct%cand)
      end if
      if (.not. allocated(ct%cand)) then
         allocate (ct%cand(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ct%cand in find_candidates')
      end if
      slots: do i = 1, p%n
         ct%cand(i) = .false.
         if (p%surf(i) == 0 .or. p%kind(i) == kind_fluid) cycle slots
         if (p%kind(i) == kind_floating) then
            ct%cand(i) = .true.
            cycle slots
         end if
         near: do b = 1, size(bodies)
            if (bodies(b)%motion /= motion_floating) cycle near
            reach = bodies(b)%rbound + 2.0_rp*prm%h + prm%dp
            if (sum((p%x(:, i) - bodies(b)%c)**2) < reach**2) then
               ct%cand(i) = .true.
               exit near
            end if
         end do near
      end do slots
   end subroutine find_candidates
end module contact

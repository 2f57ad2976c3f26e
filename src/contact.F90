!> Contact between bodies, and between a body and a wall: the seed paper's
!> force f = n R(psi) P(xi) eps(z, u_L) (Eq. 2-6) with the repulsive,
!> non-cohesive and non-cohesive-with-spring coefficients (contact_eq), a
!> Hertz DEM contact (contact_hertz), and the dynamic-boundary baseline
!> (contact_dbc); Coulomb friction on top (contact_pair). Every pair force is
!> applied equal and opposite. This module finds the candidate pairs in one
!> traversal and hands them to the chosen model, once per evaluation:
!>   contact_sweep (pairs, first pass) -> the step merges the contact table
!>   over the ranks (contact_keys_pack / _unpack) -> contact_apply (forces).
!> doc/contact.md says how each symbol is computed.
module contact
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use kinds, only: rp
   use constants, only: kind_fluid, kind_floating, ndim, nsym
   use params, only: params_t
   use grid, only: grid_t, grid_ranges, grid_last_cell, grid_nranges
   use particles, only: particles_t
   use body_dynamics, only: body_t, body_of, bodies_damping_reset, body_arm
   use rigid, only: rigid_point_velocity
   use options, only: model_dynamic, model_repulsive, model_noncohesive, &
                      model_spring, model_hertz, motion_floating, motion_fixed
   use contact_state, only: contact_t, contact_settings_t, key_index, store_candidate, contact_memory_set
   use contact_dbc, only: dbc_pairs
   use contact_eq, only: eq_gather, eq_apply
   use contact_hertz, only: tsuji_table, hertz_gather, hertz_apply
   implicit none
   private
   public :: contact_t, contact_settings_t, contact_init, contact_sweep, contact_keys_shared, contact_keys_pack, &
             contact_keys_unpack, &
             contact_apply, contact_memory_advance, contact_memory_get, contact_memory_set

   !> numbers per contact in a packed table: two ids, kx(ndim), kw, kt(nsym), kv(ndim),
   !> starting after the offsets below
   integer, parameter :: o_kx = 2, o_kw = o_kx + ndim, o_kt = o_kw + 1, o_kv = o_kt + nsym, nv = o_kv + ndim

contains

   !> The contact state of a run from the model's settings cs.
   subroutine contact_init(cs, prm, ct)
      type(contact_settings_t), intent(in) :: cs
      type(params_t), intent(in) :: prm
      type(contact_t), intent(out) :: ct
      ct%model = cs%model
      ct%k10b2 = (10.0_rp/cs%b)**2
      ! default c0: the static term (10/B)^2 0.005 c0^2 / h equals g/2, so that
      ! a body resting on a face carries its weight inside the barrier of R,
      ! where the contact is stiffest; with a stiff core, which carries the
      ! load, g/100: the soft term only cushions the approach, and a share of
      ! the load on it would spread a face's support over a spacing of travel
      ! and tip a cube early (doc/contact.md)
      ct%c = cs%c0
      ! without gravity the core (scaled by a weight) is off, and the soft
      ! term keeps its g/2 default
      ct%core = 0.0_rp
      if (prm%g > 0.0_rp) ct%core = cs%core*prm%dp
      if (ct%c <= 0.0_rp) ct%c = sqrt(merge(0.01_rp, 0.5_rp, ct%core > 0.0_rp)*max(prm%g, 1.0e-3_rp)*prm%h/ &
                                       (0.005_rp*ct%k10b2))
      ct%r_f = cs%r_f
      ct%q0 = cs%q0
      ! q_b = barrier dp/(8h): with the default 2, the touching q_t = dp/(4h)
      ct%qb = cs%barrier*0.125_rp*prm%dp/prm%h
      ct%v_stick = cs%stick_velocity
      ct%xi_max = cs%stick_length*prm%dp
      ct%k_imp = cs%impact
      if (ct%model == model_hertz) call tsuji_table(ct)
   end subroutine contact_init

   !> The sweep of one evaluation: the forces and torques of the last one
   !> cleared, the candidate pairs found (one traversal of the grid's half
   !> stencil over the owned particles: every pair is met on one rank only),
   !> and the chosen model's first pass over them. The dynamic boundary
   !> applies its forces here (its density rates into drho); the other models
   !> gather the pairs and the table of touching bodies, which contact_apply
   !> turns into forces once the table is complete over the ranks.
   subroutine contact_sweep(ct, prm, g, p, bodies, drho)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      real(rp), intent(inout) :: drho(:)
      integer :: i, j, c, r, jlo(grid_nranges), jhi(grid_nranges), bi, k
      real(rp) :: d(ndim), r2
      do k = 1, size(bodies)
         bodies(k)%f_normal = 0.0_rp; bodies(k)%t_normal = 0.0_rp
         bodies(k)%f_fric = 0.0_rp; bodies(k)%t_fric = 0.0_rp
      end do
      call bodies_damping_reset(ct%damp, size(bodies))
      ct%max_penetration = 0.0_rp
      ct%dt_limit = huge(1.0_rp)
      ct%dt_bodies = 0
      ct%dt_motion = huge(1.0_rp)
      ct%np = 0
      ct%nk = 0
      ct%nc = 0
      call find_candidates(ct, prm, p, bodies)
      ! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "contact_pairs.inc"
      select case (ct%model)
      case (model_dynamic)
         call dbc_pairs(ct, prm, p, bodies, drho)
      case (model_hertz)
         call hertz_gather(ct, prm, p, bodies)
      case (model_repulsive, model_noncohesive, model_spring)
         call eq_gather(ct, prm, p, bodies)
      case default
         call fatal('contact: no pair force for model '//int_str(ct%model))
      end select
   end subroutine contact_sweep

   !> Whether the model keeps a table of touching bodies that the ranks must
   !> share (contact_keys_pack / contact_keys_unpack) between the sweep and
   !> contact_apply.
   pure logical function contact_keys_shared(ct)
      type(contact_t), intent(in) :: ct
      contact_keys_shared = ct%model /= model_dynamic
   end function contact_keys_shared

   !> This rank's contact table (weighted centre and weight of each pair of
   !> touching bodies, and the Hertz normal tensor) packed for a gather over
   !> the ranks: nv numbers per contact.
   subroutine contact_keys_pack(ct, mine)
      type(contact_t), intent(in) :: ct
      real(rp), allocatable, intent(out) :: mine(:)
      integer :: k
      integer :: ist
      character(len=200) :: emsg
      allocate (mine(nv*ct%nk), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'mine in contact_keys_pack')
      do k = 1, ct%nk
         mine(nv*(k - 1) + 1:nv*k) = [real(ct%kid(1, k), rp), real(ct%kid(2, k), rp), ct%kx(:, k), ct%kw(k), ct%kt(:, k), &
                                       ct%kv(:, k)]
      end do
   end subroutine contact_keys_pack

   !> The contact table from the packed tables of all ranks, in rank order,
   !> so that every rank that holds a pair of the contact sees the same
   !> centre, normal and stiffness; a contact met only on other ranks is
   !> added, so that every rank holds every contact (and the same slip memory).
   subroutine contact_keys_unpack(ct, all)
      type(contact_t), intent(inout) :: ct
      real(rp), intent(in) :: all(:)
      integer :: k, m, o
      do k = 1, ct%nk
         ct%kx(:, k) = 0.0_rp
         ct%kw(k) = 0.0_rp
         ct%kt(:, k) = 0.0_rp
         ct%kv(:, k) = 0.0_rp
      end do
      do m = 1, size(all)/nv
         o = nv*(m - 1)
         k = key_index(ct, nint(all(o + 1)), nint(all(o + 2)))
         ct%kx(:, k) = ct%kx(:, k) + all(o + o_kx + 1:o + o_kx + ndim)
         ct%kw(k) = ct%kw(k) + all(o + o_kw + 1)
         ct%kt(:, k) = ct%kt(:, k) + all(o + o_kt + 1:o + o_kt + nsym)
         ct%kv(:, k) = ct%kv(:, k) + all(o + o_kv + 1:o + o_kv + ndim)
      end do
   end subroutine contact_keys_unpack

   !> Contact forces and torques on every body (f_normal, t_normal, f_fric,
   !> t_fric) from the pairs of the sweep, and the step limit of the bodies' motion.
   subroutine contact_apply(ct, prm, p, bodies)
      type(contact_t), intent(inout) :: ct
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(body_t), intent(inout) :: bodies(:)
      integer :: k
      if (ct%np > 0) then
         if (ct%model == model_hertz) then
            call hertz_apply(ct, prm, p, bodies)
         else
            call eq_apply(ct, prm, p, bodies)
         end if
      end if
      ! no point of a floating or prescribed body moves more than cfl h in a
      ! step, as the fluid's CFL keeps its particles: without water nothing
      ! else limits the step, and two bodies could jump from out of reach into
      ! deep overlap (a prescribed body's velocity is that of its function)
      do k = 1, size(bodies)
         if (bodies(k)%motion == motion_fixed) cycle
         ct%dt_motion = min(ct%dt_motion, prm%cfl*prm%h/max(norm2(bodies(k)%v) + norm2(bodies(k)%omega)* &
                                                             bodies(k)%rbound, tiny(1.0_rp)))
      end do
   end subroutine contact_apply

   !> The slip memory after a step of length dt (Eq. 2-6 models with a
   !> friction spring): for every contact of the last evaluation, the
   !> tangential slip of its two bodies at the contact centre added, the part along the present normal dropped (the contact turned),
   !> and the whole held at xi_max, where the spring alone gives mu f_n: a
   !> contact that slides carries its memory at that length. Contacts that
   !> ended are forgotten. Every rank holds every contact (contact_keys_unpack), so the
   !> memory is the same on all of them.
   subroutine contact_memory_advance(ct, bodies, dt)
      type(contact_t), intent(inout) :: ct
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(in) :: dt
      integer :: k, n
      integer, allocatable :: ids(:, :)
      real(rp), allocatable :: xis(:, :)
      real(rp) :: xc(ndim), nn(ndim), vrel(ndim), xi(ndim), s
      integer :: ist
      character(len=200) :: emsg
      if (ct%xi_max <= 0.0_rp .or. ct%model == model_dynamic .or. ct%model == model_hertz) return
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (ids(2, ct%nk), xis(ndim, ct%nk), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ids, xis in contact_memory_advance')
      n = 0
      do k = 1, ct%nk
         if (ct%kw(k) <= 0.0_rp) cycle
         s = norm2(ct%kt(1:ndim, k))
         if (s <= 0.0_rp) cycle
         nn = ct%kt(1:ndim, k)/s
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
         real(rp) :: v(ndim)
         integer :: b
         b = body_of(bodies, id)
         if (b > 0) then
            v = rigid_point_velocity(bodies(b)%v, bodies(b)%omega, body_arm(bodies(b), xc))
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
      allocate (tab(2 + ndim, ct%nm), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'tab in contact_memory_get')
      do m = 1, ct%nm
         tab(:, m) = [real(ct%mid(1, m), rp), real(ct%mid(2, m), rp), ct%mxi(:, m)]
      end do
   end subroutine contact_memory_get

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
            if (sum(body_arm(bodies(b), p%x(:, i))**2) < reach**2) then
               ct%cand(i) = .true.
               exit near
            end if
         end do near
      end do slots
   end subroutine find_candidates
end module contact

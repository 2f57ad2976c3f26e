!> The state of the contacts (contact_t): the models' constants, the pairs
!> and the table of touching bodies of the last sweep, the slip memory of
!> the static friction kept across steps, the damping matrix of the
!> velocity-proportional forces. The contact modules (contact, contact_dbc,
!> contact_eq, contact_hertz) share it; this module keeps its tables.
module contact_state
   use errors, only: alloc_check
   use kinds, only: rp, lk
   use constants, only: ndim, nsym
   use options, only: model_spring
   implicit none
   private
   public :: contact_t, contact_settings_t, key_index, store_pair, store_candidate, contact_memory_set, contact_note_dt

   !> The contact model a case chooses and its coefficients, as the scene
   !> builder hands them over (doc/contact.md); contact_init derives the
   !> state of contact_t from them.
   type :: contact_settings_t
      integer :: model = model_spring
      real(rp) :: b = 10.0_rp                !< sound coefficient B of Eq. 4-6 [-]
      real(rp) :: c0 = 0.0_rp                !< reference speed of Eq. 4-6 (0: from the static load) [m/s]
      real(rp) :: r_f = 0.5_rp               !< damping coefficient r_f of Eq. 4-6 [-]
      real(rp) :: q0 = 0.001_rp              !< regularisation of 1/sqrt(q) [-]
      real(rp) :: barrier = 2.0_rp           !< barrier of R in units of dp/(8h) [-]; 0: off
      real(rp) :: stick_velocity = 1.0e-3_rp  !< slip speed below which friction is proportional [m/s]
      real(rp) :: stick_length = 0.01_rp     !< slip of the friction spring at mu f_n, in dp [-]; 0: off
      real(rp) :: impact = 20.0_rp           !< K of the approach term of eps (Eq. 2) [-]; 0: off
      real(rp) :: core = 0.0_rp              !< overlap of the stiff core under a body's weight on one pair, in dp [-]; 0: off
   end type contact_settings_t

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
      real(rp) :: core = 0.0_rp       !< overlap of the stiff core at which one pair carries a body's weight [m] (0: no core)
      real(rp) :: max_penetration = 0.0_rp  !< largest overlap of two surfaces in the last evaluation [m]
      real(rp) :: dt_limit = huge(1.0_rp)   !< stable step for the stiffest contact of the last evaluation [s]
      real(rp) :: dt_motion = huge(1.0_rp)  !< step in which no point of a moving body moves more than cfl h [s]
      integer :: dt_bodies(2) = 0           !< the bodies of the contact that set dt_limit (0: a wall)
      ! Hertz: restitution e(alpha) of the damped Hertz spring on a grid of the
      ! damping number alpha (tsuji_table), inverted by interpolation
      real(rp), allocatable :: tab_alpha(:), tab_e(:)
      !> damping of the velocity-proportional contact forces between the floating
      !> bodies, taken implicitly in their step (body_dynamics: implicit_velocities)
      real(rp), allocatable :: damp(:, :)
      logical(lk), allocatable :: cand(:)   !< surface particles that can touch (one byte each)
      ! the candidate pairs of the sweep: particles i, j and their bodies bi, bj
      ! (0: a wall), met in the traversal's order
      integer :: nc = 0
      integer, allocatable :: cij(:, :)
      ! pairs of the last sweep (Eq. 2-6 models), gathered before the forces
      ! are applied: the slip of the friction is taken at the contact centre
      ! of each pair of touching bodies, so that a rolling body does not slip
      integer :: np = 0, nk = 0
      integer, allocatable :: pij(:, :), pb(:, :), pkey(:)
      real(rp), allocatable :: pn(:, :), pw(:), pq(:)
      real(rp), allocatable :: po(:)        !< overlap of the two outlines, dp - (normal distance), times P(xi) [m]
      integer, allocatable :: kid(:, :)
      real(rp), allocatable :: kx(:, :), kw(:)
      real(rp), allocatable :: kt(:, :)     !< Hertz: sum of sqrt(overlap) n n^T per pair of bodies (slots as sym_outer);
                                            !< Eq. 2-6 models: weighted normal (1:ndim), from the higher id to the lower
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
         allocate (ct%kid(2, 16), ct%kx(ndim, 16), ct%kw(16), ct%kt(nsym, 16), ct%kmem(16), ct%kv(ndim, 16), &
                   stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ct%kid, ct%kx, ct%kw, ... in key_index')
      end if
      if (ct%nk == size(ct%kw)) then
         ct%kid = reshape([ct%kid, spread(0, 1, 2*ct%nk)], [2, 2*ct%nk])
         ct%kx = reshape([ct%kx, spread(0.0_rp, 1, ndim*ct%nk)], [ndim, 2*ct%nk])
         ct%kt = reshape([ct%kt, spread(0.0_rp, 1, nsym*ct%nk)], [nsym, 2*ct%nk])
         ct%kw = [ct%kw, spread(0.0_rp, 1, ct%nk)]
         ct%kmem = [ct%kmem, spread(0, 1, ct%nk)]
         ct%kv = reshape([ct%kv, spread(0.0_rp, 1, ndim*ct%nk)], [ndim, 2*ct%nk])
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

   !> One pair of the sweep kept for the second pass: particles i, j of bodies
   !> bi, bj (0: a wall), normal n, weight w, q, weighted overlap o, contact k of the table.
   subroutine store_pair(ct, i, j, bi, bj, n, w, q, o, k)
      type(contact_t), intent(inout) :: ct
      integer, intent(in) :: i, j, bi, bj, k
      real(rp), intent(in) :: n(ndim), w, q, o
      integer :: cap
      integer :: ist
      character(len=200) :: emsg
      if (.not. allocated(ct%pkey)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (ct%pij(2, 256), ct%pb(2, 256), ct%pkey(256), ct%pn(ndim, 256), &
                   ct%pw(256), ct%pq(256), ct%po(256), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ct%pij, ct%pb, ct%pkey, ... in store_pair')
      end if
      cap = size(ct%pkey)
      if (ct%np == cap) then
         ct%pij = reshape([ct%pij, spread(0, 1, 2*cap)], [2, 2*cap])
         ct%pb = reshape([ct%pb, spread(0, 1, 2*cap)], [2, 2*cap])
         ct%pkey = [ct%pkey, spread(0, 1, cap)]
         ct%pn = reshape([ct%pn, spread(0.0_rp, 1, ndim*cap)], [ndim, 2*cap])
         ct%pw = [ct%pw, spread(0.0_rp, 1, cap)]
         ct%pq = [ct%pq, spread(0.0_rp, 1, cap)]
         ct%po = [ct%po, spread(0.0_rp, 1, cap)]
      end if
      ct%np = ct%np + 1
      ct%pij(:, ct%np) = [i, j]
      ct%pb(:, ct%np) = [bi, bj]
      ct%pkey(ct%np) = k
      ct%pn(:, ct%np) = n
      ct%pw(ct%np) = w
      ct%pq(ct%np) = q
      ct%po(ct%np) = o
   end subroutine store_pair


   !> One candidate pair of the sweep (particles i and j within 2h, of two
   !> different bodies, one of them floating), kept in the sweep's order.
   subroutine store_candidate(ct, i, j, bi, bj)
      type(contact_t), intent(inout) :: ct
      integer, intent(in) :: i, j, bi, bj
      integer, allocatable :: t(:, :)
      integer :: ist
      character(len=200) :: emsg
      if (.not. allocated(ct%cij)) then
         allocate (ct%cij(4, 256), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ct%cij in store_candidate')
      end if
      if (ct%nc == size(ct%cij, 2)) then
         allocate (t(4, 2*ct%nc), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 't in store_candidate')
         t(:, 1:ct%nc) = ct%cij(:, 1:ct%nc)
         call move_alloc(t, ct%cij)
      end if
      ct%nc = ct%nc + 1
      ct%cij(:, ct%nc) = [i, j, bi, bj]
   end subroutine store_candidate

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
      allocate (ct%mid(2, max(ct%nm, 1)), ct%mxi(ndim, max(ct%nm, 1)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ct%mid, ct%mxi in contact_memory_set')
      ct%mid(:, 1:ct%nm) = ids
      ct%mxi(:, 1:ct%nm) = xis
      ! the sweep's contacts point into the old table: they are rebuilt at the next evaluation
      ct%nk = 0
   end subroutine contact_memory_set


   !> A contact's stable step dt between bodies bi and bj (0: a wall): the
   !> contact limit is the least of them, and its bodies are kept for the log.
   pure subroutine contact_note_dt(ct, dt, bi, bj)
      type(contact_t), intent(inout) :: ct
      real(rp), intent(in) :: dt
      integer, intent(in) :: bi, bj
      if (dt >= ct%dt_limit) return
      ct%dt_limit = dt
      ct%dt_bodies = [bi, bj]
   end subroutine contact_note_dt
end module contact_state

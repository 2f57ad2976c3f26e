!> The particle store: structure of arrays, vectors shaped (ndim, n).
!>
!> Every per-particle field is one row of the list in src/particle_fields.fypp:
!> its name in the checkpoint, its name in the snapshot (blank: not written
!> there), its components, whether it is an integer field, whether the halo
!> copies of a neighbouring rank carry it, which runs hold it (all, or only
!> those of the Verlet integrator or of the modified dynamic boundary), and
!> the field whose values the checkpoint holds in its place when it is off (so
!> that the file keeps one layout; the mDBC fields are in the checkpoint of an
!> mDBC run only). make writes from that list the components of particles_t,
!> the table `fields` and the cases of field_slot. Allocation, growth, the
!> sort's permutation, the move of a particle to another rank (comm_halo), the
!> halo, the checkpoint and its checksum (io_checkpoint) and the snapshot
!> (io_snapshot) all loop over that table (through particles_field), so that
!> adding a field is adding its row to the list.
module particles
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use kinds, only: rp
   use errors, only: alloc_check, fatal
   use constants, only: ndim, kind_fluid
   implicit none
   private
   public :: grp_all, grp_verlet, grp_mdbc
   public :: particles_t, particles_alloc, particles_grow, particles_fit, particles_permute, particles_count_kind, &
             field_t, fields, nfield, particles_field, field_on, particles_copy, particles_pack, particles_unpack, &
             particles_width, work_array, particles_nan, particles_outside, particles_fill_uncarried

   !> A work array of at least n values, kept between calls (grown, contents not kept).
   interface work_array
      module procedure scratch_int, scratch_real
   end interface work_array

   type :: particles_t
      integer :: n = 0                       !< particles in use: owned, then the halo
      integer :: n_own = 0                   !< particles this rank owns (1 .. n_own); n on one rank
      integer :: n_id = 0                    !< largest id handed out
      logical :: history = .true.            !< the Verlet integrator's fields (vm1, rhom1) are held
      logical :: mdbc = .false.              !< the modified dynamic boundary's fields (gof, gob) are held
      ! the scratch of particles_permute, kept between sorts (sized to the moved slots)
      real(rp), allocatable :: perm_r(:)     !< one row of a real field
      integer, allocatable :: perm_i(:)      !< an integer field
      integer, allocatable :: perm_moved(:)  !< slots whose particle changes, when no work array is lent
      ! the fields of src/particle_fields.fypp
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "particle_decl.inc"
   end type particles_t

   !> One per-particle field of the store.
   type :: field_t
      character(len=8) :: name               !< dataset name in the checkpoint
      character(len=8) :: snap               !< dataset name in the snapshot ('': not written)
      integer :: ncomp                       !< components: ndim for a vector, 1 for a scalar
      logical :: int                         !< an integer field
      logical :: halo                        !< the halo copies carry it
      integer :: group                       !< held in every run (grp_all), with Verlet, with mDBC
      integer :: standin                     !< a field that is off is written as this one (0: none)
   end type field_t

   !> which runs hold a field
   integer, parameter :: grp_all = 0, grp_verlet = 1, grp_mdbc = 2
   !> The fields (src/particle_fields.fypp), reals first; the order is that of the
   !> checkpoint's checksum.
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "particle_table.inc"

   integer, parameter :: act_none = 0, act_alloc = 1, act_grow = 2

contains

   !> Field k of the store: r => its values as (components, particles) for a
   !> real field, iv => its values for an integer field (the other pointer
   !> is nullified).
   subroutine particles_field(p, k, r, iv)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: k
      real(rp), pointer, intent(out) :: r(:, :)
      integer, pointer, intent(out) :: iv(:)
      call field_slot(p, k, act_none, 0, 0, r, iv)
   end subroutine particles_field

   !> particles_field, after the field is allocated for n particles
   !> (act_alloc) or grown to n keeping the first keep (act_grow). The one
   !> place that names the fields' components.
   subroutine field_slot(p, k, a, m, kp, r, iv)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: k, a, m, kp
      real(rp), pointer, intent(out) :: r(:, :)
      integer, pointer, intent(out) :: iv(:)
      r => null()
      iv => null()
      select case (k)
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "particle_slots.inc"
      case default
         call fatal('particles_field: no such field (internal error)')
      end select
   end subroutine field_slot

   !> Whether the store holds field k (a field of the Verlet integrator or of
   !> the modified dynamic boundary only with it).
   pure logical function field_on(p, k)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: k
      select case (fields(k)%group)
      case (grp_verlet); field_on = p%history
      case (grp_mdbc); field_on = p%mdbc
      case default; field_on = .true.
      end select
   end function field_on

   !> Particles i0..i1 (halo copies): each field the halo does not carry takes
   !> its stand-in's values (the Verlet history those of now) or zero: defined,
   !> never read.
   subroutine particles_fill_uncarried(p, i0, i1)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: i0, i1
      real(rp), pointer :: r(:, :), rs(:, :)
      integer, pointer :: iv(:), ivs(:)
      integer :: k
      if (i1 < i0) return
      do k = 1, nfield
         if (fields(k)%halo .or. .not. field_on(p, k)) cycle
         call particles_field(p, k, r, iv)
         if (fields(k)%standin > 0) then
            call particles_field(p, fields(k)%standin, rs, ivs)
            if (associated(r)) r(:, i0:i1) = rs(:, i0:i1)
            if (associated(iv)) iv(i0:i1) = ivs(i0:i1)
         else
            if (associated(r)) r(:, i0:i1) = 0.0_rp
            if (associated(iv)) iv(i0:i1) = 0
         end if
      end do
   end subroutine particles_fill_uncarried

   !> Values per particle of the fields that are on (halo_only: those the halo carries).
   pure integer function particles_width(p, halo_only) result(w)
      type(particles_t), intent(in) :: p
      logical, intent(in) :: halo_only
      integer :: k
      w = 0
      do k = 1, nfield
         if (.not. field_on(p, k)) cycle
         if (halo_only .and. .not. fields(k)%halo) cycle
         w = w + fields(k)%ncomp
      end do
   end function particles_width

   subroutine real2(a, act, n, keep)
      real(rp), allocatable, intent(inout) :: a(:, :)
      integer, intent(in) :: act, n, keep
      real(rp), allocatable :: t(:, :)
      integer :: ist
      character(len=200) :: emsg
      if (act == act_none) return
      allocate (t(ndim, n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the particle store', n)
      if (act == act_grow .and. keep > 0) t(:, 1:keep) = a(:, 1:keep)
      call move_alloc(t, a)
   end subroutine real2

   subroutine real1(a, act, n, keep)
      real(rp), allocatable, intent(inout) :: a(:)
      integer, intent(in) :: act, n, keep
      real(rp), allocatable :: t(:)
      integer :: ist
      character(len=200) :: emsg
      if (act == act_none) return
      allocate (t(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the particle store', n)
      if (act == act_grow .and. keep > 0) t(1:keep) = a(1:keep)
      call move_alloc(t, a)
   end subroutine real1

   subroutine int1(a, act, n, keep)
      integer, allocatable, intent(inout) :: a(:)
      integer, intent(in) :: act, n, keep
      integer, allocatable :: t(:)
      integer :: ist
      character(len=200) :: emsg
      if (act == act_none) return
      allocate (t(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the particle store', n)
      if (act == act_grow .and. keep > 0) t(1:keep) = a(1:keep)
      call move_alloc(t, a)
   end subroutine int1

   !> Room for nmax particles, none in use; every field that is on.
   subroutine particles_alloc(p, nmax)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: nmax
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: k
      do k = 1, nfield
         if (field_on(p, k)) call field_slot(p, k, act_alloc, nmax, 0, r, iv)
      end do
      p%n = 0
      p%n_own = 0
   end subroutine particles_alloc

   !> Make room for at least nmore further particles, keeping the contents.
   subroutine particles_grow(p, nmore)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: nmore
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: cap, k
      cap = 0
      if (allocated(p%x)) cap = size(p%x, 2)
      if (p%n + nmore <= cap) return
      do k = 1, nfield
         if (field_on(p, k)) call field_slot(p, k, act_grow, max(2*cap, p%n + nmore, 1024), p%n, r, iv)
      end do
   end subroutine particles_grow

   !> The store cut to the particles in use: the scene's fills reserve room
   !> by their bounds, and every per-particle work array is as large as the store.
   subroutine particles_fit(p)
      type(particles_t), target, intent(inout) :: p
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: k
      if (.not. allocated(p%x)) return
      if (size(p%x, 2) == max(p%n, 1)) return
      do k = 1, nfield
         if (field_on(p, k)) call field_slot(p, k, act_grow, max(p%n, 1), p%n, r, iv)
      end do
   end subroutine particles_fit

   !> Particle `from` copied into slot `to`, every field.
   subroutine particles_copy(p, from, to)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: from, to
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: k
      do k = 1, nfield
         if (.not. field_on(p, k)) cycle
         call particles_field(p, k, r, iv)
         if (fields(k)%int) then
            iv(to) = iv(from)
         else
            r(:, to) = r(:, from)
         end if
      end do
   end subroutine particles_copy

   !> Particle i's fields that are on (halo_only: those the halo carries)
   !> into buf(at:), integers as reals, in the table's order.
   subroutine particles_pack(p, i, halo_only, buf, at)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: i, at
      logical, intent(in) :: halo_only
      real(rp), intent(inout) :: buf(:)
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: k, o
      o = at
      do k = 1, nfield
         if (.not. field_on(p, k)) cycle
         if (halo_only .and. .not. fields(k)%halo) cycle
         call particles_field(p, k, r, iv)
         if (fields(k)%int) then
            buf(o) = real(iv(i), rp)
         else
            buf(o:o + fields(k)%ncomp - 1) = r(:, i)
         end if
         o = o + fields(k)%ncomp
      end do
   end subroutine particles_pack

   !> The reverse of particles_pack: buf(at:) into particle i.
   subroutine particles_unpack(p, i, halo_only, buf, at)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: i, at
      logical, intent(in) :: halo_only
      real(rp), intent(in) :: buf(:)
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: k, o
      o = at
      do k = 1, nfield
         if (.not. field_on(p, k)) cycle
         if (halo_only .and. .not. fields(k)%halo) cycle
         call particles_field(p, k, r, iv)
         if (fields(k)%int) then
            iv(i) = nint(buf(o))
         else
            r(:, i) = buf(o:o + fields(k)%ncomp - 1)
         end if
         o = o + fields(k)%ncomp
      end do
   end subroutine particles_unpack

   !> Reorder: new particle k is old particle perm(k), for k = 1..nnew
   !> (nnew <= n). work, when given, is an integer array of at least nnew the caller
   !> lends for the list of moved slots (the sort lends its cell array,
   !> free at that point: 4 bytes a particle fewer).
   subroutine particles_permute(p, perm, nnew, work)
      type(particles_t), target, intent(inout) :: p
      integer, intent(in) :: perm(:), nnew
      integer, target, intent(inout), optional :: work(:)
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:), moved(:)
      integer :: d, k, nmoved
      ! Between two sorts few particles change cell: perm is the identity
      ! almost everywhere. Only the moved slots are copied (their sources are
      ! the same set of slots), which keeps the sort's memory traffic
      ! proportional to the particles that moved, not to all of them.
      if (present(work)) then
         moved => work
      else
         call scratch_int(p%perm_moved, nnew)
         moved => p%perm_moved
      end if
      nmoved = 0
      do k = 1, nnew
         if (perm(k) /= k) then
            nmoved = nmoved + 1
            moved(nmoved) = k
         end if
      end do
      if (nmoved > 0) then
         call scratch_real(p%perm_r, max(nmoved, size(p%x, 2)/8))
         call scratch_int(p%perm_i, max(nmoved, size(p%x, 2)/8))
         do k = 1, nfield
            if (.not. field_on(p, k)) cycle
            call particles_field(p, k, r, iv)
            if (fields(k)%int) then
               call permute_int(iv)
            else
               do d = 1, fields(k)%ncomp
                  call permute_row(r, d)
               end do
            end if
         end do
      end if
      p%n = nnew
   contains
      subroutine permute_row(a, row)
         real(rp), intent(inout) :: a(:, :)
         integer, intent(in) :: row
         integer :: m
         do m = 1, nmoved
            p%perm_r(m) = a(row, perm(moved(m)))
         end do
         do m = 1, nmoved
            a(row, moved(m)) = p%perm_r(m)
         end do
      end subroutine permute_row
      subroutine permute_int(a)
         integer, intent(inout) :: a(:)
         integer :: m
         do m = 1, nmoved
            p%perm_i(m) = a(perm(moved(m)))
         end do
         do m = 1, nmoved
            a(moved(m)) = p%perm_i(m)
         end do
      end subroutine permute_int
   end subroutine particles_permute

   !> A work array of at least n values (kept between calls; see work_array).
   subroutine scratch_int(a, n)
      integer, allocatable, intent(inout) :: a(:)
      integer, intent(in) :: n
      integer :: ist
      character(len=200) :: emsg
      if (allocated(a)) then
         if (size(a) >= n) return
         deallocate (a)
      end if
      allocate (a(max(n, 1)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'a work array')
   end subroutine scratch_int

   subroutine scratch_real(a, n)
      real(rp), allocatable, intent(inout) :: a(:)
      integer, intent(in) :: n
      integer :: ist
      character(len=200) :: emsg
      if (allocated(a)) then
         if (size(a) >= n) return
         deallocate (a)
      end if
      allocate (a(max(n, 1)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'a work array')
   end subroutine scratch_real

   !> Owned particles of kind k on this rank.
   integer function particles_count_kind(p, k) result(c)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: k
      c = count(p%kind(1:p%n_own) == k)
   end function particles_count_kind

   !> How many NaNs the positions, velocities and densities of particles
   !> 1..n hold (ieee_is_nan: a quiet test, no floating-point exception).
   pure integer function particles_nan(n, x, v, rho) result(k)
      integer, intent(in) :: n
      real(rp), intent(in) :: x(ndim, n), v(ndim, n), rho(n)
      integer :: i, d
      k = 0
      ! one count per field, so that the loop has no branch and vectorises
      do i = 1, n
         do d = 1, ndim
            k = k + merge(1, 0, ieee_is_nan(x(d, i))) + merge(1, 0, ieee_is_nan(v(d, i)))
         end do
         k = k + merge(1, 0, ieee_is_nan(rho(i)))
      end do
   end function particles_nan

   !> Zero when every fluid particle of 1..n is inside the box (the lower and
   !> upper bound of each dimension in turn: xmin, xmax, ymin, ymax, ...) and the
   !> density limits (else more: an upper bound of the removals, the pores'
   !> limits are looser).
   pure integer function particles_outside(n, kind, x, rho, box, rho_min, rho_max) result(k)
      integer, intent(in) :: n, kind(n)
      real(rp), intent(in) :: x(ndim, n), rho(n), box(2*ndim), rho_min, rho_max
      integer :: i, d, m
      k = 0
      ! one count per limit, so that the loop has no branch (a particle may count twice)
      do i = 1, n
         m = merge(1, 0, rho(i) < rho_min) + merge(1, 0, rho(i) > rho_max)
         do d = 1, ndim
            m = m + merge(1, 0, x(d, i) < box(2*d - 1)) + merge(1, 0, x(d, i) > box(2*d))
         end do
         k = k + merge(1, 0, kind(i) == kind_fluid)*m
      end do
   end function particles_outside
end module particles

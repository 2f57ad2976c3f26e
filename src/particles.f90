!> The particle store: structure of arrays, vectors shaped (ndim, n).
module particles
   use kinds, only: rp
   use errors, only: alloc_check
   use constants, only: ndim
   implicit none
   private
   public :: particles_t, particles_alloc, particles_grow, particles_permute, particles_count_kind

   type :: particles_t
      integer :: n = 0                       !< particles in use: owned, then the halo
      integer :: n_own = 0                   !< particles this rank owns (1 .. n_own); n on one rank
      integer :: n_id = 0                    !< largest id handed out
      real(rp), allocatable :: x(:, :)       !< position [m]
      real(rp), allocatable :: v(:, :)       !< velocity [m/s]
      real(rp), allocatable :: rho(:)        !< density [kg/m3]
      real(rp), allocatable :: p(:)          !< pressure [Pa]
      real(rp), allocatable :: mass(:)       !< mass [kg/m]
      real(rp), allocatable :: nrm(:, :)     !< outward unit normal of boundary particles
      real(rp), allocatable :: xb(:, :)      !< reference position (walls) or body-frame position (bodies) [m]
      real(rp), allocatable :: nb(:, :)      !< body-frame outward normal of a body particle
      real(rp), allocatable :: vm1(:, :)     !< Verlet: velocity one step back
      real(rp), allocatable :: rhom1(:)      !< Verlet: density one step back
      integer, allocatable :: kind(:)        !< kind_fluid, kind_fixed, kind_moving, kind_floating
      integer, allocatable :: body(:)        !< object (body) number, 0 for fluid
      integer, allocatable :: id(:)          !< global id, from 1
      integer, allocatable :: surf(:)        !< 0 inside a solid, 1 on a flat face, 2 at a corner or curve
   end type particles_t

   real(rp), allocatable :: rtmp(:)          ! scratch for permutations
   integer, allocatable :: itmp(:)
   integer, allocatable :: moved(:)          ! slots whose particle changes

contains

   subroutine particles_alloc(p, nmax)
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: nmax
      integer :: ist
      character(len=200) :: emsg
      if (allocated(p%x)) deallocate (p%x, p%v, p%rho, p%p, p%mass, p%nrm, p%xb, p%nb, p%vm1, p%rhom1, &
                                      p%kind, p%body, p%id, p%surf)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (p%x(ndim, nmax), p%v(ndim, nmax), p%rho(nmax), p%p(nmax), p%mass(nmax), &
                p%nrm(ndim, nmax), p%xb(ndim, nmax), p%nb(ndim, nmax), p%vm1(ndim, nmax), p%rhom1(nmax), &
                p%kind(nmax), p%body(nmax), p%id(nmax), p%surf(nmax), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the particle store', nmax)
      p%n = 0
      p%n_own = 0
   end subroutine particles_alloc

   !> Make room for at least nmore further particles, keeping the contents.
   subroutine particles_grow(p, nmore)
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: nmore
      type(particles_t) :: q
      integer :: cap, n
      cap = 0
      if (allocated(p%x)) cap = size(p%rho)
      if (p%n + nmore <= cap) return
      n = p%n
      call particles_alloc(q, max(2*cap, n + nmore, 1024))
      if (n > 0) then
         q%x(:, 1:n) = p%x(:, 1:n); q%v(:, 1:n) = p%v(:, 1:n); q%rho(1:n) = p%rho(1:n)
         q%p(1:n) = p%p(1:n); q%mass(1:n) = p%mass(1:n); q%nrm(:, 1:n) = p%nrm(:, 1:n)
         q%xb(:, 1:n) = p%xb(:, 1:n); q%vm1(:, 1:n) = p%vm1(:, 1:n); q%rhom1(1:n) = p%rhom1(1:n)
         q%kind(1:n) = p%kind(1:n); q%body(1:n) = p%body(1:n); q%id(1:n) = p%id(1:n)
         q%nb(:, 1:n) = p%nb(:, 1:n); q%surf(1:n) = p%surf(1:n)
      end if
      q%n = n
      q%n_own = p%n_own
      q%n_id = p%n_id
      call move_alloc(q%x, p%x); call move_alloc(q%v, p%v); call move_alloc(q%rho, p%rho)
      call move_alloc(q%p, p%p); call move_alloc(q%mass, p%mass); call move_alloc(q%nrm, p%nrm)
      call move_alloc(q%xb, p%xb); call move_alloc(q%vm1, p%vm1); call move_alloc(q%rhom1, p%rhom1)
      call move_alloc(q%kind, p%kind); call move_alloc(q%body, p%body); call move_alloc(q%id, p%id)
      call move_alloc(q%nb, p%nb); call move_alloc(q%surf, p%surf)
   end subroutine particles_grow

   !> Reorder: new particle k is old particle perm(k), for k = 1..nnew (nnew <= n).
   subroutine particles_permute(p, perm, nnew)
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: perm(:), nnew
      integer :: d, k, nmoved
      integer :: ist
      character(len=200) :: emsg
      ! Between two sorts few particles change cell: perm is the identity
      ! almost everywhere. Only the moved slots are copied (their sources are
      ! the same set of slots), which keeps the sort's memory traffic
      ! proportional to the particles that moved, not to all of them.
      if (.not. allocated(moved)) then
         allocate (moved(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'moved in particles_permute')
      end if
      if (size(moved) < size(p%rho)) then
         deallocate (moved)
         allocate (moved(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'moved in particles_permute')
      end if
      nmoved = 0
      do k = 1, nnew
         if (perm(k) /= k) then
            nmoved = nmoved + 1
            moved(nmoved) = k
         end if
      end do
      if (.not. allocated(rtmp)) then
         allocate (rtmp(max(nmoved, 1)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'rtmp in particles_permute')
      end if
      if (size(rtmp) < nmoved) then
         deallocate (rtmp, itmp)
         allocate (rtmp(max(nmoved, size(p%rho)/8)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'rtmp in particles_permute')
      end if
      if (.not. allocated(itmp)) then
         allocate (itmp(size(rtmp)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'itmp in particles_permute')
      end if
      if (size(itmp) < size(rtmp)) then
         deallocate (itmp)
         allocate (itmp(size(rtmp)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'itmp in particles_permute')
      end if
      if (nmoved > 0) then
         do d = 1, ndim
            call permute_row(p%x, d)
            call permute_row(p%v, d)
            call permute_row(p%nrm, d)
            call permute_row(p%xb, d)
            call permute_row(p%nb, d)
            call permute_row(p%vm1, d)
         end do
         call permute_real(p%rho)
         call permute_real(p%p)
         call permute_real(p%mass)
         call permute_real(p%rhom1)
         call permute_int(p%kind)
         call permute_int(p%body)
         call permute_int(p%id)
         call permute_int(p%surf)
      end if
      p%n = nnew
   contains
      subroutine permute_row(a, row)
         real(rp), intent(inout) :: a(:, :)
         integer, intent(in) :: row
         integer :: m
         do m = 1, nmoved
            rtmp(m) = a(row, perm(moved(m)))
         end do
         do m = 1, nmoved
            a(row, moved(m)) = rtmp(m)
         end do
      end subroutine permute_row
      subroutine permute_real(a)
         real(rp), intent(inout) :: a(:)
         integer :: m
         do m = 1, nmoved
            rtmp(m) = a(perm(moved(m)))
         end do
         do m = 1, nmoved
            a(moved(m)) = rtmp(m)
         end do
      end subroutine permute_real
      subroutine permute_int(a)
         integer, intent(inout) :: a(:)
         integer :: m
         do m = 1, nmoved
            itmp(m) = a(perm(moved(m)))
         end do
         do m = 1, nmoved
            a(moved(m)) = itmp(m)
         end do
      end subroutine permute_int
   end subroutine particles_permute

   !> Owned particles of kind k on this rank.
   integer function particles_count_kind(p, k) result(c)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: k
      c = count(p%kind(1:p%n_own) == k)
   end function particles_count_kind
end module particles

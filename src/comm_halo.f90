!> The particle exchange of MBSPH: particles between the slabs of neighbouring ranks.
!>
!> Every pair of particles is computed on one rank only: the pair loops'
!> half stencil looks at the next column to the right, so a rank needs as
!> halo the first cell column of the next rank's slab (particles within one
!> cell, 2h, of its right edge), and nothing from the left. What the pairs
!> add to halo particles (accelerations, density rates, moment sums) is sent
!> back and added on their owner (comm_halo_reverse); values computed on the
!> owner are sent forward again where a later loop needs them
!> (comm_halo_forward). Storage: owned particles 1 .. p%n_own, halo after.
!>
!> Migration (every step, before the sort) sends the particles that crossed
!> a slab edge to the neighbour that now owns them; redistribution (after
!> the slab edges moved) sends every particle to its owner, wherever it is.
!> The images of periodic sides (3D) are a halo of the rank itself: copies
!> of the particles along either side, after the halo (comm_halo_images).
!> The same forward and reverse calls serve them: forward copies the
!> originals' values to the images after the halo's exchange, reverse adds
!> what the images gathered to their originals before it. Without MPI (one
!> rank) only the images remain to do. The messages themselves go through
!> the typed wrappers of comm (the only module that uses MPI).
module comm_halo
   use kinds, only: rp, lk
   use constants, only: ndim
   use particles, only: particles_t, particles_grow, particles_pack, particles_unpack, particles_copy, particles_width, &
                        particles_fill_uncarried, ensure => work_array
   use decomp, only: decomp_t, decomp_owner
   use grid, only: grid_t, grid_add_images
   use comm, only: comm_rank, comm_size, comm_sendrecv, comm_alltoall, comm_alltoallv, comm_no_rank
   use timers, only: timer_start, timer_stop, t_comm
   use errors, only: fatal, alloc_check
   implicit none
   private
   public :: halo_t, comm_halo_migrate, comm_halo_build, comm_halo_refresh, comm_halo_forward, comm_halo_reverse, &
             comm_halo_redistribute, comm_halo_images, comm_halo_refresh_images, comm_halo_fold_images, &
             comm_halo_copy_images

   interface comm_halo_forward
      module procedure forward_1, forward_2
   end interface comm_halo_forward
   !> With two arrays (a 2D and a 1D one): both in one message, the same
   !> additions as two calls (one exchange, so one wait, fewer per step).
   interface comm_halo_reverse
      module procedure reverse_1, reverse_2, reverse_21
   end interface comm_halo_reverse

   !> The halo of this rank: how many particles go to the left neighbour and
   !> come from the right one, and the message buffers (kept between
   !> exchanges so that they are allocated once).
   type :: halo_t
      integer :: n_send = 0                 !< owned particles 1 .. n_send are the left neighbour's halo
      integer :: n_recv = 0                 !< halo particles n_own+1 .. n_own+n_recv
      integer :: n_img = 0                  !< images of periodic sides: n_own+n_recv+1 .. n_own+n_recv+n_img
      integer, allocatable :: img_src(:)    !< the original of each image
      real(rp), allocatable :: img_dz(:)    !< the image's shift across the width [m]
      real(rp), allocatable :: sbuf(:), rbuf(:), sbuf2(:), rbuf2(:)
   end type halo_t

contains

   integer function left()
      left = comm_no_rank
      if (comm_rank() > 0) left = comm_rank() - 1
   end function left

   integer function right()
      right = comm_no_rank
      if (comm_rank() < comm_size() - 1) right = comm_rank() + 1
   end function right

   !> As ensure, keeping the contents.
   subroutine ensure_keep(buf, n)
      real(rp), allocatable, intent(inout) :: buf(:)
      integer, intent(in) :: n
      real(rp), allocatable :: b(:)
      integer :: ist
      character(len=200) :: emsg
      if (.not. allocated(buf)) then
         allocate (buf(max(n, 1024)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'buf in ensure_keep')
      end if
      if (size(buf) >= n) return
      allocate (b(max(n, 2*size(buf))), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'b in ensure_keep')
      b(1:size(buf)) = buf
      call move_alloc(b, buf)
   end subroutine ensure_keep


   !> Particles that crossed a slab edge go to the neighbour that owns them
   !> now: marked in drop here (the sort removes them), appended on the
   !> neighbour, those from the left first. The halo is forgotten first.
   subroutine comm_halo_migrate(h, dc, p, drop)
      type(halo_t), intent(inout) :: h
      type(decomp_t), intent(in) :: dc
      type(particles_t), intent(inout) :: p
      logical(lk), allocatable, intent(inout) :: drop(:)
      integer :: i, d, me, nl, nr, rl, rr, k, nfull
      logical(lk), allocatable :: grown(:)
      integer :: ist
      character(len=200) :: emsg
      if (comm_size() == 1) return
      call timer_start(t_comm)
      nfull = particles_width(p, .false.)     ! every field a particle takes with it
      me = comm_rank()
      p%n = p%n_own
      h%n_send = 0
      h%n_recv = 0
      h%n_img = 0
      nl = 0
      nr = 0
      do i = 1, p%n
         if (drop(i)) cycle
         d = decomp_owner(dc, p%x(1, i))
         if (d == me) cycle
         if (d == me - 1) then
            call ensure_keep(h%sbuf, (nl + 1)*nfull)
            call particles_pack(p, i, .false., h%sbuf, nl*nfull + 1)
            nl = nl + 1
         else if (d == me + 1) then
            call ensure_keep(h%sbuf2, (nr + 1)*nfull)
            call particles_pack(p, i, .false., h%sbuf2, nr*nfull + 1)
            nr = nr + 1
         else
            call fatal('particle id '//istr(p%id(i))//' moved past a whole slab in one step (from rank '// &
                       istr(me)//' to rank '//istr(d)//')')
         end if
         drop(i) = .true.
      end do
      call ensure(h%sbuf, 1)
      call ensure(h%sbuf2, 1)
      ! to the left, from the right
      rr = 0
      call comm_sendrecv(nl, left(), rr, right())
      ! to the right, from the left
      rl = 0
      call comm_sendrecv(nr, right(), rl, left())
      call ensure(h%rbuf, max(rr, 1)*nfull)
      call ensure(h%rbuf2, max(rl, 1)*nfull)
      call comm_sendrecv(h%sbuf, nl*nfull, left(), h%rbuf, rr*nfull, right())
      call comm_sendrecv(h%sbuf2, nr*nfull, right(), h%rbuf2, rl*nfull, left())
      call particles_grow(p, rl + rr)
      if (size(drop) < size(p%rho)) then
         allocate (grown(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'grown in comm_halo_migrate')
         grown(1:p%n) = drop(1:p%n)
         call move_alloc(grown, drop)
      end if
      do k = 1, rl
         p%n = p%n + 1
         call particles_unpack(p, p%n, .false., h%rbuf2, (k - 1)*nfull + 1)
         drop(p%n) = .false.
      end do
      do k = 1, rr
         p%n = p%n + 1
         call particles_unpack(p, p%n, .false., h%rbuf, (k - 1)*nfull + 1)
         drop(p%n) = .false.
      end do
      p%n_own = p%n
      call timer_stop(t_comm)
   end subroutine comm_halo_migrate

   !> After the sort: the first nfirst owned particles (the slab's first
   !> column) go to the left neighbour as its halo; the right neighbour's
   !> arrive after the owned particles.
   subroutine comm_halo_build(h, p, nfirst)
      type(halo_t), intent(inout) :: h
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: nfirst
      integer :: i, k, m, nhalo
      if (comm_size() == 1) return
      call timer_start(t_comm)
      nhalo = particles_width(p, .true.)      ! the fields the pair loops read
      h%n_send = 0
      if (left() /= comm_no_rank) h%n_send = nfirst
      call ensure(h%sbuf, max(h%n_send, 1)*nhalo)
      do i = 1, h%n_send
         k = (i - 1)*nhalo
         call particles_pack(p, i, .true., h%sbuf, k + 1)
      end do
      h%n_recv = 0
      h%n_img = 0
      call comm_sendrecv(h%n_send, left(), h%n_recv, right())
      call ensure(h%rbuf, max(h%n_recv, 1)*nhalo)
      call comm_sendrecv(h%sbuf, h%n_send*nhalo, left(), h%rbuf, h%n_recv*nhalo, right())
      p%n = p%n_own
      call particles_grow(p, h%n_recv)
      do m = 1, h%n_recv
         i = p%n_own + m
         k = (m - 1)*nhalo
         call particles_unpack(p, i, .true., h%rbuf, k + 1)
      end do
      call particles_fill_uncarried(p, p%n_own + 1, p%n_own + h%n_recv)
      p%n = p%n_own + h%n_recv
      call timer_stop(t_comm)
   end subroutine comm_halo_build

   !> New positions, velocities and densities of the halo (between the two
   !> force evaluations of a step).
   subroutine comm_halo_refresh(h, p)
      type(halo_t), intent(inout) :: h
      type(particles_t), intent(inout) :: p
      integer, parameter :: nv = 2*ndim + 1     ! position, velocity, density
      integer :: i, k
      if (comm_size() > 1) then
         call timer_start(t_comm)
         call ensure(h%sbuf, max(h%n_send, 1)*nv)
         call ensure(h%rbuf, max(h%n_recv, 1)*nv)
         do i = 1, h%n_send
            k = (i - 1)*nv
            h%sbuf(k + 1:k + nv) = [p%x(:, i), p%v(:, i), p%rho(i)]
         end do
         call comm_sendrecv(h%sbuf, h%n_send*nv, left(), h%rbuf, h%n_recv*nv, right())
         do i = 1, h%n_recv
            k = (i - 1)*nv
            p%x(:, p%n_own + i) = h%rbuf(k + 1:k + ndim)
            p%v(:, p%n_own + i) = h%rbuf(k + ndim + 1:k + 2*ndim)
            p%rho(p%n_own + i) = h%rbuf(k + nv)
         end do
         call timer_stop(t_comm)
      end if
      ! the images after the halo: theirs may be copies of halo particles
      call comm_halo_refresh_images(h, p)
   end subroutine comm_halo_refresh

   !> After the sort and the halo: the images of the periodic sides (none
   !> without them), appended after the halo.
   subroutine comm_halo_images(h, g, p)
      type(halo_t), intent(inout) :: h
      type(grid_t), intent(inout) :: g
      type(particles_t), intent(inout) :: p
      integer :: k, n0, ist
      character(len=200) :: emsg
      n0 = p%n
      call grid_add_images(g, p, h%img_src, h%n_img)
      if (h%n_img == 0) return
      if (allocated(h%img_dz)) then
         if (size(h%img_dz) < h%n_img) deallocate (h%img_dz)
      end if
      if (.not. allocated(h%img_dz)) then
         allocate (h%img_dz(size(h%img_src)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the shifts of the images', size(h%img_src))
      end if
      do k = 1, h%n_img
         h%img_dz(k) = p%x(ndim, n0 + k) - p%x(ndim, h%img_src(k))
      end do
   end subroutine comm_halo_images

   !> The images' positions, velocities and densities from their originals
   !> (the halo's refreshed first).
   subroutine comm_halo_refresh_images(h, p)
      type(halo_t), intent(in) :: h
      type(particles_t), intent(inout) :: p
      integer :: k, i, n0
      n0 = p%n_own + h%n_recv
      do k = 1, h%n_img
         i = h%img_src(k)
         p%x(:, n0 + k) = p%x(:, i)
         p%x(ndim, n0 + k) = p%x(ndim, i) + h%img_dz(k)
         p%v(:, n0 + k) = p%v(:, i)
         p%rho(n0 + k) = p%rho(i)
      end do
   end subroutine comm_halo_refresh_images

   !> The sums of the images with particle numbers i0 .. i1 added to their
   !> originals and set to zero (a later reverse adds nothing more): a sweep
   !> that finishes its sums column by column (fluid_forces).
   subroutine comm_halo_fold_images(h, a, n_own, i0, i1)
      type(halo_t), intent(in) :: h
      real(rp), intent(inout) :: a(:, :)
      integer, intent(in) :: n_own, i0, i1
      integer :: i, n0
      n0 = n_own + h%n_recv
      do i = i0, i1
         a(:, h%img_src(i - n0)) = a(:, h%img_src(i - n0)) + a(:, i)
         a(:, i) = 0.0_rp
      end do
   end subroutine comm_halo_fold_images

   !> The originals' values to the images i0 .. i1.
   subroutine comm_halo_copy_images(h, a, n_own, i0, i1)
      type(halo_t), intent(in) :: h
      real(rp), intent(inout) :: a(:, :)
      integer, intent(in) :: n_own, i0, i1
      integer :: i, n0
      n0 = n_own + h%n_recv
      do i = i0, i1
         a(:, i) = a(:, h%img_src(i - n0))
      end do
   end subroutine comm_halo_copy_images

   !> Owner's values of a per-particle array to the halo copies.
   subroutine forward_2(h, a, n_own)
      type(halo_t), intent(inout) :: h
      real(rp), intent(inout) :: a(:, :)
      integer, intent(in) :: n_own
      integer :: m, k
      if (comm_size() > 1) then
         call timer_start(t_comm)
         m = size(a, 1)
         call ensure(h%sbuf, max(h%n_send, 1)*m)
         call ensure(h%rbuf, max(h%n_recv, 1)*m)
         h%sbuf(1:h%n_send*m) = reshape(a(:, 1:h%n_send), [h%n_send*m])
         call comm_sendrecv(h%sbuf, h%n_send*m, left(), h%rbuf, h%n_recv*m, right())
         a(:, n_own + 1:n_own + h%n_recv) = reshape(h%rbuf(1:h%n_recv*m), [m, h%n_recv])
         call timer_stop(t_comm)
      end if
      do k = 1, h%n_img
         a(:, n_own + h%n_recv + k) = a(:, h%img_src(k))
      end do
   end subroutine forward_2

   subroutine forward_1(h, a, n_own)
      type(halo_t), intent(inout) :: h
      real(rp), intent(inout) :: a(:)
      integer, intent(in) :: n_own
      integer :: k
      if (comm_size() > 1) then
         call timer_start(t_comm)
         call ensure(h%rbuf, max(h%n_recv, 1))
         call comm_sendrecv(a, h%n_send, left(), h%rbuf, h%n_recv, right())
         a(n_own + 1:n_own + h%n_recv) = h%rbuf(1:h%n_recv)
         call timer_stop(t_comm)
      end if
      do k = 1, h%n_img
         a(n_own + h%n_recv + k) = a(h%img_src(k))
      end do
   end subroutine forward_1

   !> What the pair loops added to the halo copies, added on the owner.
   subroutine reverse_2(h, a, n_own, images)
      type(halo_t), intent(inout) :: h
      real(rp), intent(inout) :: a(:, :)
      integer, intent(in) :: n_own
      logical, intent(in), optional :: images   !< .false.: the images were folded already (comm_halo_fold_images)
      integer :: m, k
      logical :: fold
      fold = .true.
      if (present(images)) fold = images
      if (fold) then
         do k = 1, h%n_img
            a(:, h%img_src(k)) = a(:, h%img_src(k)) + a(:, n_own + h%n_recv + k)
         end do
      end if
      if (comm_size() == 1) return
      call timer_start(t_comm)
      m = size(a, 1)
      call ensure(h%sbuf, max(h%n_recv, 1)*m)
      call ensure(h%rbuf, max(h%n_send, 1)*m)
      h%sbuf(1:h%n_recv*m) = reshape(a(:, n_own + 1:n_own + h%n_recv), [h%n_recv*m])
      call comm_sendrecv(h%sbuf, h%n_recv*m, right(), h%rbuf, h%n_send*m, left())
      a(:, 1:h%n_send) = a(:, 1:h%n_send) + reshape(h%rbuf(1:h%n_send*m), [m, h%n_send])
      call timer_stop(t_comm)
   end subroutine reverse_2

   subroutine reverse_1(h, a, n_own)
      type(halo_t), intent(inout) :: h
      real(rp), intent(inout) :: a(:)
      integer, intent(in) :: n_own
      integer :: k
      do k = 1, h%n_img
         a(h%img_src(k)) = a(h%img_src(k)) + a(n_own + h%n_recv + k)
      end do
      if (comm_size() == 1) return
      call timer_start(t_comm)
      call ensure(h%sbuf, max(h%n_recv, 1))
      call ensure(h%rbuf, max(h%n_send, 1))
      h%sbuf(1:h%n_recv) = a(n_own + 1:n_own + h%n_recv)
      call comm_sendrecv(h%sbuf, h%n_recv, right(), h%rbuf, h%n_send, left())
      a(1:h%n_send) = a(1:h%n_send) + h%rbuf(1:h%n_send)
      call timer_stop(t_comm)
   end subroutine reverse_1

   subroutine reverse_21(h, a, b, n_own)
      type(halo_t), intent(inout) :: h
      real(rp), intent(inout) :: a(:, :), b(:)
      integer, intent(in) :: n_own
      integer :: m, i, k
      do k = 1, h%n_img
         i = h%img_src(k)
         a(:, i) = a(:, i) + a(:, n_own + h%n_recv + k)
         b(i) = b(i) + b(n_own + h%n_recv + k)
      end do
      if (comm_size() == 1) return
      call timer_start(t_comm)
      m = size(a, 1)
      call ensure(h%sbuf, max(h%n_recv, 1)*(m + 1))
      call ensure(h%rbuf, max(h%n_send, 1)*(m + 1))
      do i = 1, h%n_recv
         k = (i - 1)*(m + 1)
         h%sbuf(k + 1:k + m) = a(:, n_own + i)
         h%sbuf(k + m + 1) = b(n_own + i)
      end do
      call comm_sendrecv(h%sbuf, h%n_recv*(m + 1), right(), h%rbuf, h%n_send*(m + 1), left())
      do i = 1, h%n_send
         k = (i - 1)*(m + 1)
         a(:, i) = a(:, i) + h%rbuf(k + 1:k + m)
         b(i) = b(i) + h%rbuf(k + m + 1)
      end do
      call timer_stop(t_comm)
   end subroutine reverse_21

   !> After the slab edges moved: every owned particle to the rank that owns
   !> it now. Those that stay keep their order; the arrivals follow in the
   !> order of their senders' ranks. The halo is forgotten.
   subroutine comm_halo_redistribute(h, dc, p)
      type(halo_t), intent(inout) :: h
      type(decomp_t), intent(in) :: dc
      type(particles_t), intent(inout) :: p
      integer :: i, d, me, nr, k, m, nkeep
      integer, allocatable :: scount(:), rcount(:), sdispl(:), rdispl(:), dest(:), fill(:)
      integer :: ist, nfull
      character(len=200) :: emsg
      if (comm_size() == 1) return
      call timer_start(t_comm)
      nfull = particles_width(p, .false.)
      me = comm_rank()
      nr = comm_size()
      p%n = p%n_own
      h%n_send = 0
      h%n_recv = 0
      h%n_img = 0
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (scount(0:nr - 1), rcount(0:nr - 1), sdispl(0:nr - 1), rdispl(0:nr - 1), dest(p%n), fill(0:nr - 1), &
                stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
         call alloc_check(ist, emsg, 'scount, rcount, sdispl, ... in comm_halo_redistribute')
         error stop
      end if
      scount = 0
      do i = 1, p%n
         dest(i) = decomp_owner(dc, p%x(1, i))
         if (dest(i) /= me) scount(dest(i)) = scount(dest(i)) + 1
      end do
      call comm_alltoall(scount, rcount)
      sdispl(0) = 0
      rdispl(0) = 0
      do d = 1, nr - 1
         sdispl(d) = sdispl(d - 1) + scount(d - 1)
         rdispl(d) = rdispl(d - 1) + rcount(d - 1)
      end do
      call ensure(h%sbuf, max(sum(scount), 1)*nfull)
      call ensure(h%rbuf, max(sum(rcount), 1)*nfull)
      fill = sdispl
      nkeep = 0
      do i = 1, p%n
         d = dest(i)
         if (d == me) then
            nkeep = nkeep + 1
            if (nkeep /= i) call particles_copy(p, i, nkeep)
         else
            call particles_pack(p, i, .false., h%sbuf, fill(d)*nfull + 1)
            fill(d) = fill(d) + 1
         end if
      end do
      call comm_alltoallv(h%sbuf, scount*nfull, sdispl*nfull, h%rbuf, rcount*nfull, rdispl*nfull)
      p%n = nkeep
      m = sum(rcount)
      call particles_grow(p, m)
      do k = 1, m
         p%n = p%n + 1
         call particles_unpack(p, p%n, .false., h%rbuf, (k - 1)*nfull + 1)
      end do
      p%n_own = p%n
      call timer_stop(t_comm)
   end subroutine comm_halo_redistribute

   function istr(i) result(s)
      integer, intent(in) :: i
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i0)') i
      s = trim(b)
   end function istr
end module comm_halo

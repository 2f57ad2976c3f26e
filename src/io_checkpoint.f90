!> Checkpoint: the whole state, in memory order, so that a restart repeats
!> the uninterrupted run bit for bit. Written to a temporary file, then
!> renamed over the old checkpoint. On several ranks each rank writes its
!> particles at its offset, rank after rank, with the count of every rank
!> (/rank_counts) and the slab edges (/slab_edges): a restart on the same
!> number of ranks takes up the same slabs, in the same memory order; any
!> other number of ranks can restart it too (each rank keeps its slab).
module io_checkpoint
   use kinds, only: rp
   use constants, only: ndim
   use rigid, only: npose, nrot, rigid_pose_pack, rigid_pose_unpack
   use particles, only: particles_t, particles_alloc, particles_field, field_on, fields, nfield, grp_mdbc
   use run_state, only: state_t
   use body_dynamics, only: body_t
   use, intrinsic :: iso_fortran_env, only: int64
   use io_hdf5, only: hid_t, h5_create, h5_open_read, h5_close, h5_write, h5_write_part, h5_read, &
                      h5_attr_write, h5_attr_read, h5_attr_exists, h5_length, h5_exists, file_rename
   use comm, only: comm_rank, comm_size, comm_exscan, comm_allgather, comm_sum
   use errors, only: input_error, alloc_check
   use input_check, only: int_str, real_str
   implicit none
   private
   public :: checkpoint_write, checkpoint_read, checkpoint_check

   !> The checksum is a sum over the particles, modulo this prime, of a hash of
   !> each one's record: the same whatever the order of the particles or the
   !> number of ranks that wrote them.
   integer(int64), parameter :: prime = 2147483629_int64

   !> One field of the particles as the checksum reads it: the store's
   !> values, or for a field that is off the values written in its place.
   type :: column_t
      real(rp), pointer :: r(:, :) => null()
      integer, pointer :: iv(:) => null()
      real(rp), allocatable :: own(:, :)
   end type column_t

   !> numbers per body in the checkpoint: the pose, the velocity and the angular velocity
   integer, parameter :: nbody_row = npose + ndim + nrot

contains

   !> mem: the contacts' slip memory (contact_memory_get), the same on every rank.
   subroutine checkpoint_write(out_dir, dp, p, st, bodies, mem, edges)
      character(len=*), intent(in) :: out_dir
      real(rp), intent(in) :: dp              !< the case's particle spacing, checked on restart
      type(particles_t), target, intent(inout) :: p
      type(state_t), intent(in) :: st
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(in) :: mem(:, :)
      integer, intent(in) :: edges(0:)        !< the slab edges (decomp_t), for a restart on as many ranks
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      type(column_t) :: col(nfield)
      integer :: k, kk
      integer :: b
      real(rp), allocatable :: bs(:, :)
      integer(hid_t) :: f
      character(len=:), allocatable :: path
      integer :: n, off, tot, counts(comm_size())
      real(rp) :: sums(1)
      integer :: ist
      character(len=200) :: emsg
      n = p%n_own
      call comm_allgather(n, counts)
      off = comm_exscan(n)
      tot = sum(counts)
      path = trim(out_dir)//'/checkpoint.h5'
      f = h5_create(path//'.tmp')
      do k = 1, nfield
         if (.not. in_file(p, k)) cycle
         ! a field that is off is written as its stand-in: one file layout
         kk = k
         if (.not. field_on(p, k)) kk = fields(k)%standin
         call particles_field(p, kk, r, iv)
         if (fields(k)%int) then
            call h5_write_part(f, trim(fields(k)%name), iv(1:n), off, tot)
         else if (fields(k)%ncomp == 1) then
            call h5_write_part(f, trim(fields(k)%name), r(1, 1:n), off, tot)
         else
            call h5_write_part(f, trim(fields(k)%name), r(:, 1:n), off, tot)
         end if
      end do
      call h5_write(f, 'rank_counts', counts)
      call h5_write(f, 'slab_edges', edges)
      call h5_attr_write(f, 'n_id', p%n_id)
      call h5_attr_write(f, 't', st%t)
      call h5_attr_write(f, 'dt', st%dt)
      call h5_attr_write(f, 'istep', st%istep)
      call h5_attr_write(f, 'isnap', st%isnap)
      call h5_attr_write(f, 'ienergy', st%ienergy)
      call h5_attr_write(f, 't_next_snap', st%t_next_snap)
      call h5_attr_write(f, 't_next_energy', st%t_next_energy)
      call h5_attr_write(f, 'lost_domain', st%lost_domain)
      call h5_attr_write(f, 'lost_density', st%lost_density)
      call h5_attr_write(f, 'n_fluid0', st%n_fluid0)
      call h5_attr_write(f, 'h_swl', st%h_swl)
      call h5_attr_write(f, 'y_surface', st%y_surface)
      call h5_attr_write(f, 'pad_xc', st%pad_xc)
      call h5_attr_write(f, 'pad_eta_mean', st%pad_eta_mean)
      if (size(bodies) > 0) then
         allocate (bs(nbody_row, size(bodies)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'bs in checkpoint_write')
         do b = 1, size(bodies)
            bs(:, b) = [rigid_pose_pack(bodies(b)%pose), bodies(b)%v, bodies(b)%omega]
         end do
         call h5_write(f, 'bodies', bs)
      end if
      if (size(mem, 2) > 0) call h5_write(f, 'contact_memory', mem)
      if (allocated(st%pad_hist)) then
         if (size(st%pad_hist, 2) > 0) call h5_write(f, 'pad_history', st%pad_hist)
      end if
      call h5_attr_write(f, 'dp', dp)
      call h5_attr_write(f, 'ndim', ndim)
      call h5_attr_write(f, 'n_bodies', size(bodies))
      ! each rank's particles, summed over the ranks (exact: every part is below 2^31)
      do k = 1, nfield
         if (.not. in_file(p, k)) cycle
         kk = k
         if (.not. field_on(p, k)) kk = fields(k)%standin
         call particles_field(p, kk, col(k)%r, col(k)%iv)
      end do
      sums(1) = real(fields_checksum(col, n, [(in_file(p, k), k=1, nfield)]), rp)
      call comm_sum(sums)
      call h5_attr_write(f, 'checksum', real(mod(nint(sums(1), int64), prime), rp))
      call h5_close(f)
      if (comm_rank() == 0) call file_rename(path//'.tmp', path)
   end subroutine checkpoint_write

   !> The whole checkpoint, on every rank; counts and edges are the writer's
   !> particles per rank and slab edges (one rank, no edges, for a
   !> checkpoint of a serial build); mem the contacts' slip memory (none: 0 columns).
   subroutine checkpoint_read(case_file, out_dir, p, st, bodies, counts, edges, mem)
      character(len=*), intent(in) :: case_file, out_dir
      type(particles_t), target, intent(inout) :: p
      type(state_t), intent(inout) :: st
      type(body_t), intent(inout) :: bodies(:)
      integer, allocatable, intent(out) :: counts(:), edges(:)
      real(rp), allocatable, intent(out) :: mem(:, :)
      integer(hid_t) :: f
      integer :: n, b, nr
      logical :: parts
      real(rp), allocatable :: bs(:, :)
      real(rp) :: sum_file
      type(column_t), target :: col(nfield)
      integer :: k
      integer :: ist
      character(len=200) :: emsg
      f = h5_open_read(trim(out_dir)//'/checkpoint.h5')
      n = h5_length(f, 'rho')
      call particles_alloc(p, n)
      p%n = n
      p%n_own = n
      parts = h5_exists(f, 'rank_counts')
      if (parts) parts = h5_exists(f, 'slab_edges')
      if (parts) then
         nr = h5_length(f, 'rank_counts')
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (counts(nr), edges(nr + 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'counts, edges in checkpoint_read')
         call h5_read(f, 'rank_counts', counts)
         call h5_read(f, 'slab_edges', edges)
      else
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (counts(1), edges(0), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'counts, edges in checkpoint_read')
         counts(1) = n
      end if
      ! a field that is off is read aside, for the checksum only
      do k = 1, nfield
         if (.not. in_file(p, k)) cycle
         if (.not. h5_exists(f, trim(fields(k)%name))) call input_error(case_file, 'run', 'restart', &
            trim(out_dir)//'/checkpoint.h5 holds no '//trim(fields(k)%name)//': it was written by a run '// &
            "without boundary = 'mdbc'; restart with the case's first boundary or run anew")
         if (field_on(p, k)) then
            call particles_field(p, k, col(k)%r, col(k)%iv)
         else
            allocate (col(k)%own(fields(k)%ncomp, n), stat=ist, errmsg=emsg)
            call alloc_check(ist, emsg, 'a field that is off, in checkpoint_read')
            col(k)%r => col(k)%own
         end if
         if (fields(k)%int) then
            call h5_read(f, trim(fields(k)%name), col(k)%iv)
         else if (fields(k)%ncomp == 1) then
            call h5_read(f, trim(fields(k)%name), col(k)%r(1, :))
         else
            call h5_read(f, trim(fields(k)%name), col(k)%r)
         end if
      end do
      ! a checkpoint changed after it was written (a byte overwritten, a copy cut
      ! short that HDF5 still reads) is refused here, not run from
      if (h5_attr_exists(f, 'checksum')) then
         call h5_attr_read(f, 'checksum', sum_file)
         if (fields_checksum(col, n, [(in_file(p, k), k=1, nfield)]) /= nint(sum_file, int64)) then
            call input_error(case_file, 'run', 'restart', &
                             trim(out_dir)//'/checkpoint.h5: the particle data do not match the checksum written '// &
                             'with them: the file was changed or damaged after it was written; restart from an '// &
                             'earlier copy or run anew')
         end if
      end if
      call h5_attr_read(f, 'n_id', p%n_id)
      call h5_attr_read(f, 't', st%t)
      call h5_attr_read(f, 'dt', st%dt)
      call h5_attr_read(f, 'istep', st%istep)
      call h5_attr_read(f, 'isnap', st%isnap)
      call h5_attr_read(f, 'ienergy', st%ienergy)
      call h5_attr_read(f, 't_next_snap', st%t_next_snap)
      call h5_attr_read(f, 't_next_energy', st%t_next_energy)
      call h5_attr_read(f, 'lost_domain', st%lost_domain)
      call h5_attr_read(f, 'lost_density', st%lost_density)
      call h5_attr_read(f, 'n_fluid0', st%n_fluid0)
      call h5_attr_read(f, 'h_swl', st%h_swl)
      call h5_attr_read(f, 'y_surface', st%y_surface)
      ! checkpoints from before the absorbing paddle: no correction
      st%pad_xc = 0.0_rp
      st%pad_eta_mean = 0.0_rp
      if (h5_attr_exists(f, 'pad_xc')) call h5_attr_read(f, 'pad_xc', st%pad_xc)
      if (h5_attr_exists(f, 'pad_eta_mean')) call h5_attr_read(f, 'pad_eta_mean', st%pad_eta_mean)
      if (size(bodies) > 0) then
         allocate (bs(nbody_row, size(bodies)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'bs in checkpoint_read')
         call h5_read(f, 'bodies', bs)
         do b = 1, size(bodies)
            bodies(b)%pose = rigid_pose_unpack(bs(1:npose, b))
            bodies(b)%v = bs(npose + 1:npose + ndim, b)
            bodies(b)%omega = bs(npose + ndim + 1:nbody_row, b)
         end do
      end if
      if (h5_exists(f, 'pad_history')) then
         allocate (st%pad_hist(2, h5_length(f, 'pad_history')), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'pad_hist in checkpoint_read')
         call h5_read(f, 'pad_history', st%pad_hist)
      end if
      if (h5_exists(f, 'contact_memory')) then
         allocate (mem(2 + ndim, h5_length(f, 'contact_memory')), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'mem in checkpoint_read')
         call h5_read(f, 'contact_memory', mem)
      else
         allocate (mem(2 + ndim, 0), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'mem in checkpoint_read')
      end if
      call h5_close(f)
   end subroutine checkpoint_read
   !> Before a restart reads anything: the checkpoint must come from this
   !> case's scene, the same spacing dp, the same number of bodies and of
   !> particles made (n_made: the case's scene; particles lost since may be fewer).
   subroutine checkpoint_check(case_file, out_dir, dp, n_bodies, n_made)
      character(len=*), intent(in) :: case_file, out_dir
      real(rp), intent(in) :: dp
      integer, intent(in) :: n_bodies, n_made
      integer(hid_t) :: f
      integer :: nb, n_id, nd
      real(rp) :: dp_file
      character(len=:), allocatable :: what
      what = trim(out_dir)//'/checkpoint.h5 '
      f = h5_open_read(trim(out_dir)//'/checkpoint.h5')
      ! a checkpoint without the attribute is from a 2D build (before there was a 3D one)
      nd = 2
      if (h5_attr_exists(f, 'ndim')) call h5_attr_read(f, 'ndim', nd)
      if (nd /= ndim) call input_error(case_file, 'run', 'restart', what//'was written by the '//int_str(nd)// &
         'D build; this is the '//int_str(ndim)//'D one ('//trim(merge('build/mbsph  ', 'build/mbsph3d', ndim == 2))//')')
      nb = 0
      if (h5_exists(f, 'bodies')) nb = h5_length(f, 'bodies')
      if (nb /= n_bodies) call input_error(case_file, 'run', 'restart', what//'holds '//int_str(nb)// &
         ' bodies, the case '//int_str(n_bodies)//': it was written by another case')
      if (h5_attr_exists(f, 'dp')) then
         call h5_attr_read(f, 'dp', dp_file)
         if (abs(dp_file - dp) > 1.0e-12_rp*dp) call input_error(case_file, 'numerics', 'dp', what// &
            'was written at dp = '//real_str(dp_file)//' m, the case has dp = '//real_str(dp)// &
            ' m: a restart continues the same particles')
      end if
      call h5_attr_read(f, 'n_id', n_id)
      if (n_id /= n_made) call input_error(case_file, 'run', 'restart', what//'was written by a case of '// &
         int_str(n_id)//' particles, this case makes '//int_str(n_made)//': it was written by another case '// &
         '(or the geometry changed)')
      call h5_close(f)
   end subroutine checkpoint_check

   !> Whether the checkpoint holds field k: every field, the Verlet history as
   !> its stand-in when it is off (one layout), the mDBC ghost offsets only
   !> in mDBC runs (so a checkpoint of any other run is as it was before them).
   pure logical function in_file(p, k)
      type(particles_t), intent(in) :: p
      integer, intent(in) :: k
      in_file = field_on(p, k) .or. fields(k)%group /= grp_mdbc
   end function in_file

   !> Sum over particles 1..n, modulo prime, of a hash of each one's record
   !> (every word of every field, as its bits, in the order of the fields'
   !> table: the reals, then the integers).
   integer(int64) function fields_checksum(col, n, use) result(cs)
      type(column_t), intent(in) :: col(nfield)
      integer, intent(in) :: n
      logical, intent(in) :: use(nfield)
      integer :: i, k
      integer(int64) :: h
      cs = 0
      do i = 1, n
         h = 0
         columns: do k = 1, nfield
            if (.not. use(k)) cycle columns
            if (fields(k)%int) then
               call mix_i(h, col(k)%iv(i:i))
            else
               call mix_r(h, col(k)%r(:, i))
            end if
         end do columns
         cs = mod(cs + h, prime)
      end do
   end function fields_checksum

   !> h from the bits of the reals a, 32 at a time (a polynomial hash modulo prime).
   pure subroutine mix_r(h, a)
      integer(int64), intent(inout) :: h
      real(rp), intent(in) :: a(:)
      integer :: k
      integer(int64) :: b
      integer(int64), parameter :: low = 4294967295_int64
      do k = 1, size(a)
         b = transfer(a(k), b)
         h = mod(h*131_int64 + iand(b, low), prime)
         h = mod(h*131_int64 + iand(ishft(b, -32), low), prime)
      end do
   end subroutine mix_r

   pure subroutine mix_i(h, a)
      integer(int64), intent(inout) :: h
      integer, intent(in) :: a(:)
      integer :: k
      do k = 1, size(a)
         h = mod(h*131_int64 + iand(int(a(k), int64), 4294967295_int64), prime)
      end do
   end subroutine mix_i
end module io_checkpoint

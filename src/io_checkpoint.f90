!> Checkpoint: the whole state, in memory order, so that a restart repeats
!> the uninterrupted run bit for bit. Written to a temporary file, then
!> renamed over the old checkpoint. On several ranks each rank writes its
!> particles at its offset, rank after rank, with the count of every rank
!> (/rank_counts) and the slab edges (/slab_edges): a restart on the same
!> number of ranks takes up the same slabs, in the same memory order; any
!> other number of ranks can restart it too (each rank keeps its slab).
module io_checkpoint
   use kinds, only: rp
   use particles, only: particles_t, particles_alloc
   use run_state, only: state_t
   use body_dynamics, only: body_t
   use io_hdf5, only: hid_t, h5_create, h5_open_read, h5_close, h5_write, h5_write_part, h5_read, &
                      h5_attr_write, h5_attr_read, h5_length, h5_exists, file_rename
   use comm, only: comm_rank, comm_size, comm_exscan, comm_allgather
   use decomp, only: decomp_edges
   implicit none
   private
   public :: checkpoint_write, checkpoint_read

contains

   !> mem: the contacts' slip memory (contact_memory_get), the same on every rank.
   subroutine checkpoint_write(out_dir, p, st, bodies, mem)
      character(len=*), intent(in) :: out_dir
      type(particles_t), intent(in) :: p
      type(state_t), intent(in) :: st
      type(body_t), intent(in) :: bodies(:)
      real(rp), intent(in) :: mem(:, :)
      integer :: b
      real(rp), allocatable :: bs(:, :)
      integer(hid_t) :: f
      character(len=:), allocatable :: path
      integer :: n, off, tot, counts(comm_size())
      n = p%n_own
      call comm_allgather(n, counts)
      off = comm_exscan(n)
      tot = sum(counts)
      path = trim(out_dir)//'/checkpoint.h5'
      f = h5_create(path//'.tmp')
      call h5_write_part(f, 'x', p%x(:, 1:n), off, tot)
      call h5_write_part(f, 'v', p%v(:, 1:n), off, tot)
      call h5_write_part(f, 'rho', p%rho(1:n), off, tot)
      call h5_write_part(f, 'p', p%p(1:n), off, tot)
      call h5_write_part(f, 'mass', p%mass(1:n), off, tot)
      call h5_write_part(f, 'nrm', p%nrm(:, 1:n), off, tot)
      call h5_write_part(f, 'xb', p%xb(:, 1:n), off, tot)
      call h5_write_part(f, 'nb', p%nb(:, 1:n), off, tot)
      call h5_write_part(f, 'surf', p%surf(1:n), off, tot)
      call h5_write_part(f, 'vm1', p%vm1(:, 1:n), off, tot)
      call h5_write_part(f, 'rhom1', p%rhom1(1:n), off, tot)
      call h5_write_part(f, 'kind', p%kind(1:n), off, tot)
      call h5_write_part(f, 'body', p%body(1:n), off, tot)
      call h5_write_part(f, 'id', p%id(1:n), off, tot)
      call h5_write(f, 'rank_counts', counts)
      call h5_write(f, 'slab_edges', decomp_edges())
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
      if (size(bodies) > 0) then
         allocate (bs(6, size(bodies)))
         do b = 1, size(bodies)
            bs(:, b) = [bodies(b)%c, bodies(b)%theta, bodies(b)%v, bodies(b)%omega]
         end do
         call h5_write(f, 'bodies', bs)
      end if
      if (size(mem, 2) > 0) call h5_write(f, 'contact_memory', mem)
      call h5_close(f)
      if (comm_rank() == 0) call file_rename(path//'.tmp', path)
   end subroutine checkpoint_write

   !> The whole checkpoint, on every rank; counts and edges are the writer's
   !> particles per rank and slab edges (one rank, no edges, for a
   !> checkpoint of a serial build); mem the contacts' slip memory (none: 0 columns).
   subroutine checkpoint_read(out_dir, p, st, bodies, counts, edges, mem)
      character(len=*), intent(in) :: out_dir
      type(particles_t), intent(inout) :: p
      type(state_t), intent(inout) :: st
      type(body_t), intent(inout) :: bodies(:)
      integer, allocatable, intent(out) :: counts(:), edges(:)
      real(rp), allocatable, intent(out) :: mem(:, :)
      integer(hid_t) :: f
      integer :: n, b, nr
      logical :: parts
      real(rp), allocatable :: bs(:, :)
      f = h5_open_read(trim(out_dir)//'/checkpoint.h5')
      n = h5_length(f, 'rho')
      call particles_alloc(p, n)
      p%n = n
      p%n_own = n
      parts = h5_exists(f, 'rank_counts')
      if (parts) parts = h5_exists(f, 'slab_edges')
      if (parts) then
         nr = h5_length(f, 'rank_counts')
         allocate (counts(nr), edges(nr + 1))
         call h5_read(f, 'rank_counts', counts)
         call h5_read(f, 'slab_edges', edges)
      else
         allocate (counts(1), edges(0))
         counts(1) = n
      end if
      call h5_read(f, 'x', p%x)
      call h5_read(f, 'v', p%v)
      call h5_read(f, 'rho', p%rho)
      call h5_read(f, 'p', p%p)
      call h5_read(f, 'mass', p%mass)
      call h5_read(f, 'nrm', p%nrm)
      call h5_read(f, 'xb', p%xb)
      call h5_read(f, 'nb', p%nb)
      call h5_read(f, 'surf', p%surf)
      call h5_read(f, 'vm1', p%vm1)
      call h5_read(f, 'rhom1', p%rhom1)
      call h5_read(f, 'kind', p%kind)
      call h5_read(f, 'body', p%body)
      call h5_read(f, 'id', p%id)
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
      if (size(bodies) > 0) then
         allocate (bs(6, size(bodies)))
         call h5_read(f, 'bodies', bs)
         do b = 1, size(bodies)
            bodies(b)%c = bs(1:2, b)
            bodies(b)%theta = bs(3, b)
            bodies(b)%v = bs(4:5, b)
            bodies(b)%omega = bs(6, b)
         end do
      end if
      if (h5_exists(f, 'contact_memory')) then
         allocate (mem(4, h5_length(f, 'contact_memory')))
         call h5_read(f, 'contact_memory', mem)
      else
         allocate (mem(4, 0))
      end if
      call h5_close(f)
   end subroutine checkpoint_read
end module io_checkpoint

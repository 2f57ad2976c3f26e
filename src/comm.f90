!> All MPI of MBSPH: start and stop, ranks, the abort path, the collective
!> reductions the solver needs, and the thin typed exchanges that comm_halo
!> builds the particle exchange from. This is the only module that uses
!> mpi_f08; every other module (comm_halo included) calls the routines here.
!> On one rank every routine returns at once, before any MPI call, so a
!> serial run pays nothing (and the unit tests need no MPI_Init).
module comm
   use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Abort, MPI_Comm_rank, MPI_Comm_size, &
                      MPI_COMM_WORLD, MPI_Wtime, MPI_Initialized, MPI_Finalized, MPI_Allreduce, &
                      MPI_Allgather, MPI_Allgatherv, MPI_Exscan, MPI_Barrier, MPI_IN_PLACE, MPI_SUM, &
                      MPI_MAX, MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_INFO_NULL, MPI_Sendrecv, MPI_Alltoall, &
                      MPI_Alltoallv, MPI_PROC_NULL, MPI_STATUS_IGNORE, MPI_Comm, MPI_Comm_split_type, &
                      MPI_COMM_TYPE_SHARED, MPI_Comm_free
   use, intrinsic :: iso_c_binding, only: c_int
   use, intrinsic :: iso_fortran_env, only: error_unit
   use kinds, only: rp
   use timers, only: timer_start, timer_stop, t_comm
   implicit none
   private
   public :: comm_init, comm_finalize, comm_abort, comm_rank, comm_size, comm_wtime, &
             comm_handle, comm_info_handle, comm_barrier, comm_sum, comm_max, comm_exscan, comm_allgather, comm_allgatherv, &
             comm_grace, comm_sendrecv, comm_alltoall, comm_alltoallv, comm_no_rank, comm_node_size

   !> Neighbour rank meaning "none" (the edge of the domain): an exchange
   !> with it sends and receives nothing (MPI_PROC_NULL inside this module).
   integer, parameter :: comm_no_rank = -1

   interface
      subroutine c_exit(status) bind(C, name='exit')
         import :: c_int
         implicit none
         integer(c_int), value :: status
      end subroutine c_exit
      subroutine c_exit_now(status) bind(C, name='_exit')
         import :: c_int
         implicit none
         integer(c_int), value :: status
      end subroutine c_exit_now
      function c_usleep(usec) bind(C, name='usleep') result(r)
         import :: c_int
         implicit none
         integer(c_int), value :: usec
         integer(c_int) :: r
      end function c_usleep
   end interface

   !> Sum over ranks, in place.
   interface comm_sum
      module procedure sum_r, sum_i
   end interface comm_sum

   !> One exchange with two ranks: send to one, receive from another (the
   !> caller times it; comm_halo wraps whole exchanges in t_comm).
   interface comm_sendrecv
      module procedure sendrecv_r, sendrecv_i, sendrecv_count
   end interface comm_sendrecv

   integer, parameter :: tag = 7

   integer :: my_rank = 0
   integer :: n_ranks = 1

contains

   subroutine comm_init()
      logical :: done
      call MPI_Initialized(done)
      if (.not. done) call MPI_Init()
      call MPI_Comm_rank(MPI_COMM_WORLD, my_rank)
      call MPI_Comm_size(MPI_COMM_WORLD, n_ranks)
   end subroutine comm_init

   !> The ranks that share this rank's machine (its memory), this one included.
   integer function comm_node_size() result(n)
      type(MPI_Comm) :: node
      n = 1
      if (n_ranks == 1) return
      call MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, my_rank, MPI_INFO_NULL, node)
      call MPI_Comm_size(node, n)
      call MPI_Comm_free(node)
   end function comm_node_size

   subroutine comm_finalize()
      logical :: init, fin
      call MPI_Initialized(init)
      if (.not. init) return
      call MPI_Finalized(fin)
      if (.not. fin) call MPI_Finalize()
   end subroutine comm_finalize

   !> Stop every rank with a non-zero exit code. On one rank MPI is closed
   !> cleanly so that the user sees only our message, not MPI's abort banner.
   !> hard: exit at once (_exit), without the exit handlers of the libraries,
   !> when one of them is left in a state its handler cannot clean up.
   subroutine comm_abort(code, hard)
      integer, intent(in) :: code
      logical, intent(in), optional :: hard
      logical :: init, now
      now = .false.
      if (present(hard)) now = hard
      call MPI_Initialized(init)
      if (init .and. n_ranks > 1) then
         call MPI_Abort(MPI_COMM_WORLD, code)
      end if
      if (now) call c_exit_now(int(code, c_int))
      call comm_finalize()
      ! exit through the C library: our message stays the only output
      ! (error stop would add the runtime's own lines and a backtrace)
      call c_exit(int(code, c_int))
   end subroutine comm_abort

   !> A rank other than 0 that meets an error waits this long before it
   !> speaks and aborts: an error every rank meets (bad input, a file that
   !> cannot be written) is then reported once, by rank 0, whose abort ends
   !> the waiting ranks; an error of one rank alone is reported after the wait.
   subroutine comm_grace()
      integer :: k
      if (n_ranks == 1 .or. my_rank == 0) return
      do k = 1, 20
         if (c_usleep(100000_c_int) /= 0) exit
      end do
   end subroutine comm_grace

   pure integer function comm_rank()
      comm_rank = my_rank
   end function comm_rank

   pure integer function comm_size()
      comm_size = n_ranks
   end function comm_size

   !> The world communicator as the integer handle of the Fortran 77 MPI
   !> interface (what the HDF5 Fortran API takes).
   integer function comm_handle()
      comm_handle = MPI_COMM_WORLD%MPI_VAL
   end function comm_handle

   !> MPI_INFO_NULL as an integer handle (for the parallel HDF5 file driver).
   integer function comm_info_handle()
      comm_info_handle = MPI_INFO_NULL%MPI_VAL
   end function comm_info_handle

   !> Wall-clock time in seconds.
   real(rp) function comm_wtime()
      comm_wtime = real(MPI_Wtime(), rp)
   end function comm_wtime

   subroutine comm_barrier()
      if (n_ranks == 1) return
      call timer_start(t_comm)
      call MPI_Barrier(MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine comm_barrier

   subroutine sum_r(a)
      real(rp), intent(inout) :: a(:)
      if (n_ranks == 1) return
      call timer_start(t_comm)
      call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine sum_r

   subroutine sum_i(a)
      integer, intent(inout) :: a(:)
      if (n_ranks == 1) return
      call timer_start(t_comm)
      call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine sum_i

   !> Maximum over ranks, in place (a minimum is the maximum of the negatives).
   subroutine comm_max(a)
      real(rp), intent(inout) :: a(:)
      if (n_ranks == 1) return
      call timer_start(t_comm)
      call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine comm_max

   !> Sum of n over the ranks before this one (0 on rank 0).
   integer function comm_exscan(n) result(s)
      integer, intent(in) :: n
      s = 0
      if (n_ranks == 1) return
      call timer_start(t_comm)
      call MPI_Exscan(n, s, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
      call timer_stop(t_comm)
      if (my_rank == 0) s = 0
   end function comm_exscan

   !> n of every rank, in rank order.
   subroutine comm_allgather(n, all)
      integer, intent(in) :: n
      integer, intent(out) :: all(:)
      if (n_ranks == 1) then
         all(1) = n
         return
      end if
      call timer_start(t_comm)
      call MPI_Allgather(n, 1, MPI_INTEGER, all, 1, MPI_INTEGER, MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine comm_allgather

   !> The arrays a of every rank, one after the other in rank order.
   subroutine comm_allgatherv(a, all)
      real(rp), intent(in) :: a(:)
      real(rp), allocatable, intent(out) :: all(:)
      integer :: counts(n_ranks), displ(n_ranks), r, ist
      character(len=200) :: emsg
      call comm_allgather(size(a), counts)
      displ(1) = 0
      do r = 2, n_ranks
         displ(r) = displ(r - 1) + counts(r - 1)
      end do
      allocate (all(sum(counts)), stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! errors (alloc_check) sits above this module
         write (error_unit, '(a)') 'mbsph: error: out of memory: cannot allocate all in comm_allgatherv ('// &
            trim(emsg)//')'
         call comm_abort(1)
      end if
      if (n_ranks == 1) then
         all = a
         return
      end if
      call timer_start(t_comm)
      call MPI_Allgatherv(a, size(a), MPI_DOUBLE_PRECISION, all, counts, displ, MPI_DOUBLE_PRECISION, &
                          MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine comm_allgatherv

   !> comm_no_rank as MPI_PROC_NULL, any other rank unchanged.
   integer function mpi_peer(r)
      integer, intent(in) :: r
      mpi_peer = r
      if (r == comm_no_rank) mpi_peer = MPI_PROC_NULL
   end function mpi_peer

   !> Send sbuf(1:ns) to rank dest and receive rbuf(1:nr) from rank src at
   !> once (either may be comm_no_rank). On one rank both are comm_no_rank.
   subroutine sendrecv_r(sbuf, ns, dest, rbuf, nr, src)
      real(rp), intent(in) :: sbuf(:)
      integer, intent(in) :: ns, dest, nr, src
      real(rp), intent(inout) :: rbuf(:)
      if (n_ranks == 1) return
      call MPI_Sendrecv(sbuf, ns, MPI_DOUBLE_PRECISION, mpi_peer(dest), tag, rbuf, nr, MPI_DOUBLE_PRECISION, &
                        mpi_peer(src), tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE)
   end subroutine sendrecv_r

   subroutine sendrecv_i(sbuf, ns, dest, rbuf, nr, src)
      integer, intent(in) :: sbuf(:)
      integer, intent(in) :: ns, dest, nr, src
      integer, intent(inout) :: rbuf(:)
      if (n_ranks == 1) return
      call MPI_Sendrecv(sbuf, ns, MPI_INTEGER, mpi_peer(dest), tag, rbuf, nr, MPI_INTEGER, mpi_peer(src), tag, &
                        MPI_COMM_WORLD, MPI_STATUS_IGNORE)
   end subroutine sendrecv_i

   !> One count to rank dest and one from rank src (either may be
   !> comm_no_rank); n_recv is left as it is when nothing arrives.
   subroutine sendrecv_count(n_send, dest, n_recv, src)
      integer, intent(in) :: n_send, dest, src
      integer, intent(inout) :: n_recv
      integer :: r(1)
      r(1) = n_recv
      call sendrecv_i([n_send], 1, dest, r, 1, src)
      n_recv = r(1)
   end subroutine sendrecv_count

   !> One integer to and from every rank: scount(r+1) goes to rank r, and
   !> rcount(r+1) is what rank r sent here (the caller times it).
   subroutine comm_alltoall(scount, rcount)
      integer, intent(in) :: scount(:)
      integer, intent(out) :: rcount(:)
      if (n_ranks == 1) then
         rcount(1) = scount(1)
         return
      end if
      call MPI_Alltoall(scount, 1, MPI_INTEGER, rcount, 1, MPI_INTEGER, MPI_COMM_WORLD)
   end subroutine comm_alltoall

   !> Blocks of reals to and from every rank: sbuf(sdispl(r+1)+1 ..) with
   !> scount(r+1) values goes to rank r, and rank r's block lands at
   !> rbuf(rdispl(r+1)+1 ..) with rcount(r+1) values (the caller times it).
   subroutine comm_alltoallv(sbuf, scount, sdispl, rbuf, rcount, rdispl)
      real(rp), intent(in) :: sbuf(:)
      integer, intent(in) :: scount(:), sdispl(:), rcount(:), rdispl(:)
      real(rp), intent(inout) :: rbuf(:)
      if (n_ranks == 1) then
         rbuf(rdispl(1) + 1:rdispl(1) + rcount(1)) = sbuf(sdispl(1) + 1:sdispl(1) + scount(1))
         return
      end if
      call MPI_Alltoallv(sbuf, scount, sdispl, MPI_DOUBLE_PRECISION, rbuf, rcount, rdispl, MPI_DOUBLE_PRECISION, &
                         MPI_COMM_WORLD)
   end subroutine comm_alltoallv
end module comm

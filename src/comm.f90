!> MPI of MBSPH, part one: start and stop, ranks, the abort path, and the
!> collective reductions the solver needs. Every MPI call of MBSPH lives in
!> this module or in comm_halo (the particle exchange); no other module
!> calls MPI. On one rank every routine returns at once, before any MPI
!> call, so a serial run pays nothing (and the unit tests need no MPI_Init).
module comm
   use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Abort, MPI_Comm_rank, MPI_Comm_size, &
                      MPI_COMM_WORLD, MPI_Wtime, MPI_Initialized, MPI_Finalized, MPI_Allreduce, &
                      MPI_Allgather, MPI_Allgatherv, MPI_Exscan, MPI_Barrier, MPI_IN_PLACE, MPI_SUM, &
                      MPI_MAX, MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_INFO_NULL
   use, intrinsic :: iso_c_binding, only: c_int
   use kinds, only: rp
   use timers, only: timer_start, timer_stop, t_comm
   implicit none
   private
   public :: comm_init, comm_finalize, comm_abort, comm_rank, comm_size, comm_wtime, &
             comm_handle, comm_info_handle, comm_barrier, comm_sum, comm_max, comm_exscan, comm_allgather, comm_allgatherv, &
             comm_grace

   interface
      subroutine c_exit(status) bind(C, name='exit')
         import :: c_int
         implicit none
         integer(c_int), value :: status
      end subroutine c_exit
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

   subroutine comm_finalize()
      logical :: init, fin
      call MPI_Initialized(init)
      if (.not. init) return
      call MPI_Finalized(fin)
      if (.not. fin) call MPI_Finalize()
   end subroutine comm_finalize

   !> Stop every rank with a non-zero exit code. On one rank MPI is closed
   !> cleanly so that the user sees only our message, not MPI's abort banner.
   subroutine comm_abort(code)
      integer, intent(in) :: code
      logical :: init
      call MPI_Initialized(init)
      if (init .and. n_ranks > 1) then
         call MPI_Abort(MPI_COMM_WORLD, code)
      end if
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
      integer :: counts(n_ranks), displ(n_ranks), r
      call comm_allgather(size(a), counts)
      displ(1) = 0
      do r = 2, n_ranks
         displ(r) = displ(r - 1) + counts(r - 1)
      end do
      allocate (all(sum(counts)))
      if (n_ranks == 1) then
         all = a
         return
      end if
      call timer_start(t_comm)
      call MPI_Allgatherv(a, size(a), MPI_DOUBLE_PRECISION, all, counts, displ, MPI_DOUBLE_PRECISION, &
                          MPI_COMM_WORLD)
      call timer_stop(t_comm)
   end subroutine comm_allgatherv
end module comm

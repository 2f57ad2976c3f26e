!> All MPI calls of MBSPH live here; no other module calls MPI.
module comm
   use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Abort, MPI_Comm_rank, MPI_Comm_size, &
                      MPI_COMM_WORLD, MPI_Wtime, MPI_Initialized, MPI_Finalized
   use, intrinsic :: iso_c_binding, only: c_int
   use kinds, only: rp
   implicit none
   private
   public :: comm_init, comm_finalize, comm_abort, comm_rank, comm_size, comm_wtime

   interface
      subroutine c_exit(status) bind(C, name='exit')
         import :: c_int
         implicit none
         integer(c_int), value :: status
      end subroutine c_exit
   end interface

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
      call MPI_Finalized(fin)
      if (init .and. .not. fin) call MPI_Finalize()
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

   integer function comm_rank()
      comm_rank = my_rank
   end function comm_rank

   integer function comm_size()
      comm_size = n_ranks
   end function comm_size

   !> Wall-clock time in seconds.
   real(rp) function comm_wtime()
      comm_wtime = real(MPI_Wtime(), rp)
   end function comm_wtime
end module comm

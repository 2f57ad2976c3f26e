!> Fatal errors: one clear message naming the cause, then every rank stops
!> with a non-zero exit code. An error every rank meets (bad input) is
!> reported once, by rank 0; an error of one rank alone by that rank, with
!> its number, a moment later (comm_grace).
module errors
   use comm, only: comm_abort, comm_rank, comm_size, comm_grace
   use logger, only: log_error
   implicit none
   private
   public :: fatal, input_error, alloc_check

contains

   !> Stop the run with a message. Exit code 1 (2 for input errors).
   subroutine fatal(msg, code, hard)
      character(len=*), intent(in) :: msg
      integer, intent(in), optional :: code
      logical, intent(in), optional :: hard   !< exit without the libraries' exit handlers
      character(len=16) :: r
      integer :: c
      c = 1
      if (present(code)) c = code
      if (comm_size() > 1) then
         call comm_grace()
         write (r, '(i0)') comm_rank()
         call log_error('mbsph: error (rank '//trim(r)//'): '//msg)
      else
         call log_error('mbsph: error: '//msg)
      end if
      call comm_abort(c, hard)
   end subroutine fatal

   !> Stop on bad input, naming the file, the namelist group and the variable.
   subroutine input_error(file, group, var, msg)
      character(len=*), intent(in) :: file, group, var, msg
      if (len_trim(var) > 0) then
         call fatal(trim(file)//': &'//trim(group)//': '//trim(var)//': '//msg, 2)
      else
         call fatal(trim(file)//': &'//trim(group)//': '//msg, 2)
      end if
   end subroutine input_error

   !> After allocate(..., stat=stat, errmsg=msg): stop with one line when the
   !> memory was refused (the size check before the run estimates it; a run
   !> that grows beyond it still ends with a message, not a crash).
   subroutine alloc_check(stat, msg, what, n)
      integer, intent(in) :: stat
      character(len=*), intent(in) :: msg, what
      integer, intent(in), optional :: n  !< elements asked for (particles, pairs, cells)
      character(len=32) :: b, code
      character(len=:), allocatable :: why
      if (stat == 0) return
      write (code, '(i0)') stat
      ! gfortran 12 gives a refused allocation the errmsg of a double one
      ! ('Attempt to allocate an allocated object'); the solver allocates only
      ! what is not allocated, so that text is left out
      if (index(msg, 'allocated object') > 0 .or. len_trim(msg) == 0) then
         why = 'allocate stat '//trim(code)
      else
         why = trim(msg)//', allocate stat '//trim(code)
      end if
      b = ''
      if (present(n)) write (b, '(a, i0)') ' for ', n
      call fatal('out of memory: cannot allocate '//what//trim(b)//' ('//why// &
                 '): raise dp, or run on more ranks or where more memory is available')
   end subroutine alloc_check

end module errors

!> Screen and run.log output. Only rank 0 writes. The progress line is
!> redrawn in place on a terminal and written as plain lines elsewhere.
module logger
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_size_t, c_null_char
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use constants, only: msg_len
   use comm, only: comm_rank
   implicit none
   private
   public :: log_open, log_close, log_line, log_error, log_progress

   integer :: log_unit = 0
   logical :: log_opened = .false.   !< newunit= numbers are negative: keep a flag
   logical :: tty = .false.
   integer, parameter :: proc_len = 256   !< room for a /proc path and a link target
   logical :: progress_pending = .false.   !< an in-place line is on the screen

   interface
      function c_isatty(fd) bind(C, name='isatty') result(r)
         import :: c_int
         implicit none
         integer(c_int), value :: fd
         integer(c_int) :: r
      end function c_isatty
      function c_getppid() bind(C, name='getppid') result(r)
         import :: c_int
         implicit none
         integer(c_int) :: r
      end function c_getppid
      function c_readlink(path, buf, bufsiz) bind(C, name='readlink') result(r)
         import :: c_char, c_size_t, proc_len
         implicit none
         character(kind=c_char), intent(in) :: path(proc_len)
         character(kind=c_char), intent(out) :: buf(proc_len)
         integer(c_size_t), value :: bufsiz
         integer(c_size_t) :: r   ! ssize_t: same width as size_t on the supported platforms
      end function c_readlink
   end interface

contains

   !> Open (append) the run log; decide whether stdout is a terminal.
   subroutine log_open(path, append)
      character(len=*), intent(in) :: path
      logical, intent(in) :: append
      integer :: ios
      character(len=msg_len) :: msg
      if (comm_rank() /= 0) return
      tty = stdout_is_terminal()
      if (append) then
         open (newunit=log_unit, file=path, status='unknown', position='append', action='write', iostat=ios, iomsg=msg)
      else
         open (newunit=log_unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      end if
      log_opened = ios == 0
   end subroutine log_open

   !> Whether the user sees stdout on a terminal. MBSPH_PROGRESS = plain or inplace decides
   !> when set. Open MPI hands every rank a pseudo-terminal even when mpirun's own output
   !> goes to a file, so under it the answer is read from the launcher's stdout instead
   !> (Linux /proc; where that cannot be read, the rank's own isatty stands).
   logical function stdout_is_terminal() result(yes)
      character(len=32) :: mode
      character(len=proc_len) :: path, target
      character(kind=c_char) :: cpath(proc_len), buf(proc_len)
      integer(c_size_t) :: n
      integer :: st, i
      call get_environment_variable('MBSPH_PROGRESS', mode, status=st)
      if (st == 0 .and. trim(mode) == 'plain') then
         yes = .false.
         return
      end if
      if (st == 0 .and. trim(mode) == 'inplace') then
         yes = .true.
         return
      end if
      yes = c_isatty(1_c_int) == 1
      if (.not. yes) return
      call get_environment_variable('OMPI_COMM_WORLD_SIZE', status=st)
      if (st /= 0) return
      write (path, '(a,i0,a)') '/proc/', c_getppid(), '/fd/1'
      cpath = c_null_char
      do i = 1, len_trim(path)
         cpath(i) = path(i:i)
      end do
      n = c_readlink(cpath, buf, int(proc_len - 1, c_size_t))
      if (n <= 0) return
      target = ''
      do i = 1, int(n)
         target(i:i) = buf(i)
      end do
      yes = index(target, '/dev/pts/') == 1 .or. index(target, '/dev/tty') == 1
   end function stdout_is_terminal


   subroutine log_close()
      if (log_opened) close (log_unit)
      log_opened = .false.
   end subroutine log_close

   subroutine end_progress()
      if (progress_pending) then
         write (output_unit, '(a)') ''
         progress_pending = .false.
      end if
   end subroutine end_progress

   !> A plain line on the screen and in run.log.
   subroutine log_line(text)
      character(len=*), intent(in) :: text
      if (comm_rank() /= 0) return
      call end_progress()
      write (output_unit, '(a)') text
      flush (output_unit)
      if (log_opened) then
         write (log_unit, '(a)') text
         flush (log_unit)
      end if
   end subroutine log_line

   !> An error: standard error and run.log, from any rank.
   subroutine log_error(text)
      character(len=*), intent(in) :: text
      call end_progress()
      write (error_unit, '(a)') text
      flush (error_unit)
      if (log_opened) then
         write (log_unit, '(a)') text
         flush (log_unit)
      end if
   end subroutine log_error

   !> The progress line: redrawn in place on a terminal, a plain line otherwise.
   subroutine log_progress(text)
      character(len=*), intent(in) :: text
      if (comm_rank() /= 0) return
      if (tty) then
         write (output_unit, '(a,a,a)', advance='no') achar(13), text, achar(27)//'[K'
         flush (output_unit)
         progress_pending = .true.
      else
         write (output_unit, '(a)') text
         flush (output_unit)
      end if
      if (log_opened) then
         write (log_unit, '(a)') text
         flush (log_unit)
      end if
   end subroutine log_progress
end module logger

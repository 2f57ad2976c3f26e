!> The output folder: refuse to overwrite a run unless asked, create it,
!> and keep energy.csv consistent with a restart.
module io_files
   use, intrinsic :: iso_fortran_env, only: int64
   use kinds, only: rp
   use constants, only: path_len, msg_len
   use errors, only: input_error, fatal
   use input_check, only: int_str
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_size_t
   implicit none
   private

   interface
      !> POSIX mkdir(2); mode_t is an unsigned 32-bit integer on Linux
      integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
         import :: c_int, c_char
         implicit none
         ! allow(assumed-size): a C string, null-terminated
         character(kind=c_char), dimension(*), intent(in) :: path
         integer(c_int), value, intent(in) :: mode
      end function c_mkdir
      integer(c_int) function c_getpid() bind(C, name='getpid')
         import :: c_int
         implicit none
      end function c_getpid
      !> kill(pid, 0): 0 while the process exists
      integer(c_int) function c_kill(pid, sig) bind(C, name='kill')
         import :: c_int
         implicit none
         integer(c_int), value, intent(in) :: pid, sig
      end function c_kill
      integer(c_int) function c_gethostname(name, n) bind(C, name='gethostname')
         import :: c_int, c_char, c_size_t
         implicit none
         ! allow(assumed-size, assumed-size-character-intent): a C string buffer that gethostname fills
         character(kind=c_char), dimension(*), intent(out) :: name
         integer(c_size_t), value, intent(in) :: n
      end function c_gethostname
   end interface
   public :: csv_flush, dir_writable, text_hash, outdir_unlock, outdir_prepare, file_exists, file_text, snap_name, &
             energy_open, energy_row, energy_close, csv_rows_until

   !> energy.csv of a run (open on rank 0 only).
   type, public :: energy_file_t
      integer :: unit = 0
      logical :: opened = .false.   !< newunit= numbers are negative: keep a flag
   end type energy_file_t

contains

   logical function file_exists(path)
      character(len=*), intent(in) :: path
      inquire (file=trim(path), exist=file_exists)
   end function file_exists

   !> OUT/snap_NNNNN.h5
   function snap_name(out_dir, k) result(s)
      character(len=*), intent(in) :: out_dir
      integer, intent(in) :: k
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i5.5)') k
      s = trim(out_dir)//'/snap_'//trim(b)//'.h5'
   end function snap_name

   subroutine delete_file(path)
      character(len=*), intent(in) :: path
      integer :: u, ios
      character(len=msg_len) :: msg
      if (.not. file_exists(path)) return
      open (newunit=u, file=trim(path), status='old', action='read', iostat=ios, iomsg=msg)
      if (ios == 0) close (u, status='delete')
   end subroutine delete_file

   !> Check and create the output folder. A folder that holds a run is only
   !> reused with overwrite = .true. (its old output is deleted first) or
   !> restart = .true. (it must hold a checkpoint).
   subroutine outdir_prepare(case_file, out_dir, overwrite, restart)
      ! the files of a run besides its snapshots (doc/output.md)
      character(len=*), parameter :: run_files(*) = [character(len=20) :: 'checkpoint.h5', 'checkpoint.h5.tmp', &
         'energy.csv', 'bodies.csv', 'gauges.csv', 'armour.csv', 'particles.xmf', 'case.nml', 'run.log']
      character(len=*), intent(in) :: case_file, out_dir
      logical, intent(in) :: overwrite, restart
      character(len=path_len) :: d
      integer :: k
      logical :: held(4), ok
      d = out_dir
      if (restart) then
         if (.not. file_exists(trim(d)//'/checkpoint.h5')) call input_error(case_file, 'run', 'restart', &
            'restart = .true. needs '//trim(d)//'/checkpoint.h5, which does not exist')
         call outdir_lock(case_file, d)
         return
      end if
      held = [file_exists(trim(d)//'/case.nml'), file_exists(trim(d)//'/checkpoint.h5'), &
              file_exists(snap_name(d, 0)), file_exists(trim(d)//'/energy.csv')]
      if (any(held) .and. .not. overwrite) call input_error(case_file, 'run', 'out_dir', "the folder '"//trim(d)// &
         "' already holds a run; set overwrite = .true. to replace it, restart = .true. to continue it,"// &
         ' or choose another out_dir')
      call make_dirs(trim(d))
      ok = dir_writable(d)
      if (.not. ok) call input_error(case_file, 'run', 'out_dir', &
         "cannot create or write the folder '"//trim(d)//"'")
      ! a run still writing here keeps its files: the lock before any is deleted
      call outdir_lock(case_file, d)
      if (any(held)) then
         k = 0
         do while (file_exists(snap_name(d, k)))
            call delete_file(snap_name(d, k))
            k = k + 1
         end do
         ! every file a run writes: a run without gauges or armour must not leave
         ! an earlier run's gauges.csv or armour.csv beside its own output
         do k = 1, size(run_files)
            call delete_file(trim(d)//'/'//trim(run_files(k)))
         end do
      end if
   end subroutine outdir_prepare

   !> Claim the folder for this run: out_dir/.mbsph.lock holds 'host pid' of
   !> the run writing into it. A lock of a process that no longer exists on
   !> this machine (a run killed) is taken over; a live one stops this run.
   subroutine outdir_lock(case_file, d)
      character(len=*), intent(in) :: case_file, d
      character(len=:), allocatable :: path
      character(len=256) :: host, other
      character(len=msg_len) :: msg
      integer :: u, ios, pid, attempt
      path = trim(d)//'/.mbsph.lock'
      host = host_name()
      do attempt = 1, 2
         ! status='new' creates the file only if it does not exist (O_EXCL): one run wins
         open (newunit=u, file=path, status='new', action='write', iostat=ios, iomsg=msg)
         if (ios == 0) then
            write (u, '(a,1x,i0)') trim(host), c_getpid()
            close (u)
            return
         end if
         other = ''
         pid = -1
         open (newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
         if (ios == 0) then
            read (u, *, iostat=ios, iomsg=msg) other, pid
            if (ios /= 0) other = ''
            close (u)
         end if
         if (other == host .and. pid > 0) then
            if (process_alive(pid)) call input_error(case_file, 'run', 'out_dir', "the folder '"// &
               trim(d)//"' is in use by another run (process "//int_str(pid)//' on this machine, '//path// &
               '): wait for it to end, or choose another out_dir')
         else if (len_trim(other) > 0) then
            call input_error(case_file, 'run', 'out_dir', "the folder '"//trim(d)//"' is in use by a run on "// &
               trim(other)//' (process '//int_str(pid)//', '//path//'); if that run has ended, delete '//path)
         end if
         ! the run that held it is gone (or the lock is unreadable): take it over
         call delete_file(path)
      end do
      call input_error(case_file, 'run', 'out_dir', 'cannot create the lock '//path)
   end subroutine outdir_lock

   !> The process pid runs on this machine: it exists (kill(pid, 0)) and is not
   !> a zombie, a process killed but not yet reaped by its parent.
   logical function process_alive(pid)
      integer, intent(in) :: pid
      character(len=512) :: line
      character(len=msg_len) :: msg
      integer :: u, ios, k
      process_alive = c_kill(int(pid, c_int), 0_c_int) == 0
      if (.not. process_alive) return
      open (newunit=u, file='/proc/'//int_str(pid)//'/stat', status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) return
      read (u, '(a)', iostat=ios, iomsg=msg) line
      close (u)
      if (ios /= 0) return
      ! 'pid (name) S ...': the state follows the name's closing parenthesis
      k = index(line, ')', back=.true.)
      if (k > 0 .and. k + 2 <= len(line)) process_alive = line(k + 2:k + 2) /= 'Z'
   end function process_alive

   !> Release the folder at the end of a run.
   subroutine outdir_unlock(d)
      character(len=*), intent(in) :: d
      call delete_file(trim(d)//'/.mbsph.lock')
   end subroutine outdir_unlock

   function host_name() result(h)
      integer, parameter :: host_len = 256
      character(len=host_len) :: h
      character(kind=c_char) :: b(host_len)
      integer :: k
      h = 'localhost'
      b = c_null_char
      if (c_gethostname(b, int(size(b) - 1, c_size_t)) /= 0) return
      h = ''
      chars: do k = 1, size(b) - 1
         if (b(k) == c_null_char) exit chars
         h(k:k) = b(k)
      end do chars
   end function host_name

   !> mkdir -p without a shell: mkdir(2) on every prefix of the path that ends at a
   !> '/', then on the whole path. Failures (the folder exists, no permission) are
   !> judged afterwards by dir_writable, which names the folder.
   subroutine make_dirs(d)
      character(len=*), intent(in) :: d
      integer :: k, rc
      do k = 2, len(d)
         if (d(k:k) == '/') rc = c_mkdir(d(1:k - 1)//c_null_char, int(o'755', c_int))
      end do
      rc = c_mkdir(d//c_null_char, int(o'755', c_int))
   end subroutine make_dirs

   !> A file can be made in folder d (a test file of this process's own name:
   !> several ranks may test the same folder at once).
   logical function dir_writable(d)
      character(len=*), intent(in) :: d
      integer :: u, ios
      character(len=msg_len) :: msg
      open (newunit=u, file=trim(d)//'/.mbsph_write_test_'//int_str(c_getpid()), status='replace', action='write', &
            iostat=ios, iomsg=msg)
      dir_writable = ios == 0
      if (ios /= 0) return
      close (u, status='delete', iostat=ios, iomsg=msg)
      dir_writable = ios == 0
   end function dir_writable

   !> Whole text of a file, lines joined with newlines.
   function file_text(path) result(s)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: s
      character(len=4096) :: line
      integer :: u, ios
      character(len=msg_len) :: msg
      s = ''
      open (newunit=u, file=trim(path), status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) return
      do
         read (u, '(a)', iostat=ios, iomsg=msg) line
         if (ios /= 0) exit
         s = s//trim(line)//new_line('a')
      end do
      close (u)
   end function file_text

   !> A number that differs, but for a chance of 1 in 2e9, between two
   !> different texts (a polynomial hash modulo a prime).
   integer function text_hash(s) result(h)
      character(len=*), intent(in) :: s
      integer(int64) :: a
      integer :: k
      integer(int64), parameter :: prime = 2147483629_int64
      a = 0
      do k = 1, len(s)
         a = mod(a*257_int64 + iachar(s(k:k)), prime)
      end do
      h = int(a)
   end function text_hash

   !> Open energy.csv: a new file, or on restart the old one cut back to the
   !> rows written before the checkpoint (steps <= last_step).
   subroutine energy_open(ef, out_dir, restart, last_step)
      type(energy_file_t), intent(inout) :: ef
      character(len=*), intent(in) :: out_dir
      logical, intent(in) :: restart
      integer, intent(in) :: last_step
      character(len=:), allocatable :: path, keep
      character(len=4096) :: line
      character(len=64) :: tok
      integer :: u, ios, k, step
      character(len=msg_len) :: msg
      logical :: have
      path = trim(out_dir)//'/energy.csv'
      keep = ''
      have = file_exists(path)
      if (restart .and. have) then
         open (newunit=u, file=path, status='old', action='read')
         read (u, '(a)', iostat=ios, iomsg=msg) line          ! header
         ! no header: an empty file, nothing to keep
         if (ios == 0) then
            do
               read (u, '(a)', iostat=ios, iomsg=msg) line
               if (ios /= 0) exit
               k = index(line, ',')
               tok = line(k + 1:)
               k = index(tok, ',')
               read (tok(1:k - 1), *, iostat=ios, iomsg=msg) step
               if (ios == 0 .and. step <= last_step) keep = keep//trim(line)//new_line('a')
            end do
         end if
         close (u)
      end if
      open (newunit=ef%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//': '//trim(msg))
      ef%opened = .true.
      write (ef%unit, '(a)') 'time,step,kinetic,potential,total_mass,n_fluid,lost,body_kinetic,body_potential,max_penetration'
      if (len(keep) > 0) write (ef%unit, '(a)', advance='no') keep
      call csv_flush(ef%unit, 'energy.csv')
   end subroutine energy_open

   subroutine energy_row(ef, t, istep, ekin, epot, mass, n_fluid, lost, bkin, bpot, pen)
      type(energy_file_t), intent(in) :: ef
      real(rp), intent(in) :: t, ekin, epot, mass, bkin, bpot, pen
      integer, intent(in) :: istep, n_fluid, lost
      if (.not. ef%opened) return
      write (ef%unit, '(es23.15e3,",",i0,3(",",es23.15e3),",",i0,",",i0,3(",",es23.15e3))') t, istep, &
         ekin, epot, mass, n_fluid, lost, bkin, bpot, pen
      call csv_flush(ef%unit, 'energy.csv')
   end subroutine energy_row

   !> Flush a series' unit to the file; a write the system refuses (a full
   !> disk) stops the run with one line naming the file.
   subroutine csv_flush(u, name)
      integer, intent(in) :: u
      character(len=*), intent(in) :: name
      integer :: ios
      character(len=msg_len) :: msg
      flush (u, iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//name//' in the output folder: '//trim(msg)// &
                               ' (the rows before it are whole)')
   end subroutine csv_flush

   subroutine energy_close(ef)
      type(energy_file_t), intent(inout) :: ef
      if (ef%opened) close (ef%unit)
      ef%opened = .false.
   end subroutine energy_close
   !> The data rows of a CSV time series whose first field, a time, is at most
   !> t_keep: what a restart at t_keep keeps of the file. Comment lines ('#'),
   !> the header and unreadable rows are left out; '' when there is no file.
   function csv_rows_until(path, t_keep) result(keep)
      character(len=*), intent(in) :: path
      real(rp), intent(in) :: t_keep
      character(len=:), allocatable :: keep
      character(len=4096) :: line
      character(len=msg_len) :: msg
      integer :: u, ios, k
      real(rp) :: t
      keep = ''
      open (newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) return
      rows: do
         read (u, '(a)', iostat=ios, iomsg=msg) line
         if (ios /= 0) exit rows
         if (line(1:1) == '#') cycle rows
         k = index(line, ',')
         if (k < 2) cycle rows
         read (line(1:k - 1), *, iostat=ios, iomsg=msg) t
         if (ios == 0 .and. t <= t_keep*(1.0_rp + 1.0e-12_rp)) keep = keep//trim(line)//new_line('a')
      end do rows
      close (u)
   end function csv_rows_until
end module io_files

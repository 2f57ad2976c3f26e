!> The output folder: refuse to overwrite a run unless asked, create it,
!> and keep energy.csv consistent with a restart.
module io_files
   use kinds, only: rp
   use constants, only: path_len, msg_len
   use errors, only: input_error, fatal
   use input_check, only: int_str
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
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
   end interface
   public :: outdir_prepare, file_exists, file_text, snap_name, energy_open, energy_row, energy_close, csv_rows_until

   integer :: energy_unit = 0
   logical :: energy_opened = .false.   !< newunit= numbers are negative: keep a flag

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
         return
      end if
      held = [file_exists(trim(d)//'/case.nml'), file_exists(trim(d)//'/checkpoint.h5'), &
              file_exists(snap_name(d, 0)), file_exists(trim(d)//'/energy.csv')]
      if (any(held)) then
         if (.not. overwrite) call input_error(case_file, 'run', 'out_dir', "the folder '"//trim(d)// &
            "' already holds a run; set overwrite = .true. to replace it, restart = .true. to continue it,"// &
            ' or choose another out_dir')
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
      call make_dirs(trim(d))
      ok = dir_writable(d)
      if (.not. ok) call input_error(case_file, 'run', 'out_dir', &
         "cannot create or write the folder '"//trim(d)//"'")
   end subroutine outdir_prepare

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

   logical function dir_writable(d)
      character(len=*), intent(in) :: d
      integer :: u, ios
      character(len=msg_len) :: msg
      open (newunit=u, file=trim(d)//'/.mbsph_write_test', status='replace', action='write', iostat=ios, iomsg=msg)
      dir_writable = ios == 0
      if (ios == 0) close (u, status='delete')
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

   !> Open energy.csv: a new file, or on restart the old one cut back to the
   !> rows written before the checkpoint (steps <= last_step).
   subroutine energy_open(out_dir, restart, last_step)
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
      open (newunit=energy_unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//': '//trim(msg))
      energy_opened = .true.
      write (energy_unit, '(a)') 'time,step,kinetic,potential,total_mass,n_fluid,lost,body_kinetic,body_potential,max_penetration'
      if (len(keep) > 0) write (energy_unit, '(a)', advance='no') keep
      flush (energy_unit)
   end subroutine energy_open

   subroutine energy_row(t, istep, ekin, epot, mass, n_fluid, lost, bkin, bpot, pen)
      real(rp), intent(in) :: t, ekin, epot, mass, bkin, bpot, pen
      integer, intent(in) :: istep, n_fluid, lost
      if (.not. energy_opened) return
      write (energy_unit, '(es23.15e3,",",i0,3(",",es23.15e3),",",i0,",",i0,3(",",es23.15e3))') t, istep, &
         ekin, epot, mass, n_fluid, lost, bkin, bpot, pen
      flush (energy_unit)
   end subroutine energy_row

   subroutine energy_close()
      if (energy_opened) close (energy_unit)
      energy_opened = .false.
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

!> &run: run control (end time, output, restart, checkpoints).
module input_run
   use kinds, only: rp
   use constants, only: name_len, path_len, msg_len
   use input_check, only: open_case, read_failed, check_real, check_int, group_count, int_str
   use errors, only: input_error
   implicit none
   private
   public :: run_cfg, read_run, write_run

   type :: run_cfg
      character(len=name_len) :: case_name = 'case'
      real(rp) :: t_end = 1.0_rp            !< simulated end time [s]
      real(rp) :: dt_out = 0.1_rp           !< interval between snapshots [s]
      character(len=path_len) :: out_dir = 'OUT'
      logical :: overwrite = .false.        !< allow writing into a folder that holds a run
      logical :: restart = .false.          !< continue from out_dir/checkpoint.h5
      integer :: checkpoint_every = 0       !< steps between checkpoints (0: only at the end)
      integer :: max_steps = 0              !< stop after this many steps (0: no limit)
      real(rp) :: max_lost_fraction = 0.02_rp  !< stop when more fluid than this is lost
      real(rp) :: progress_interval = 2.0_rp  !< wall seconds between progress lines
      real(rp) :: energy_interval = 0.0_rp    !< interval of energy.csv rows [s] (0: dt_out)
      integer :: balance_every = 100        !< steps between moves of the slab edges (0: never)
      real(rp) :: gauge_interval = 0.01_rp    !< interval of gauges.csv rows [s]
   end type run_cfg

   character(len=name_len) :: case_name
   real(rp) :: t_end, dt_out, max_lost_fraction, progress_interval, energy_interval, gauge_interval
   character(len=path_len) :: out_dir
   logical :: overwrite, restart
   integer :: checkpoint_every, max_steps, balance_every
   namelist /run/ case_name, t_end, dt_out, out_dir, overwrite, restart, checkpoint_every, &
      max_steps, max_lost_fraction, progress_interval, energy_interval, balance_every, gauge_interval

contains

   subroutine to_vars(c)
      type(run_cfg), intent(in) :: c
      case_name = c%case_name; t_end = c%t_end; dt_out = c%dt_out; out_dir = c%out_dir
      overwrite = c%overwrite; restart = c%restart; checkpoint_every = c%checkpoint_every
      max_steps = c%max_steps; max_lost_fraction = c%max_lost_fraction
      progress_interval = c%progress_interval; energy_interval = c%energy_interval
      balance_every = c%balance_every
      gauge_interval = c%gauge_interval
   end subroutine to_vars

   subroutine from_vars(c)
      type(run_cfg), intent(out) :: c
      c%case_name = case_name; c%t_end = t_end; c%dt_out = dt_out; c%out_dir = out_dir
      c%overwrite = overwrite; c%restart = restart; c%checkpoint_every = checkpoint_every
      c%max_steps = max_steps; c%max_lost_fraction = max_lost_fraction
      c%progress_interval = progress_interval; c%energy_interval = energy_interval
      c%balance_every = balance_every
      c%gauge_interval = gauge_interval
   end subroutine from_vars

   subroutine read_run(file, c)
      character(len=*), intent(in) :: file
      type(run_cfg), intent(out) :: c
      integer :: u, ios
      character(len=msg_len) :: msg
      type(run_cfg) :: defaults
      if (group_count(file, 'run') == 0) call input_error(file, 'run', '', 'required group is missing')
      if (group_count(file, 'run') > 1) call input_error(file, 'run', '', 'group appears more than once')
      call to_vars(defaults)
      u = open_case(file)
      read (u, nml=run, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, 'run', ios, msg)) return
      call from_vars(c)
      if (len_trim(c%case_name) == 0) call input_error(file, 'run', 'case_name', 'must not be empty')
      if (len_trim(c%out_dir) == 0) call input_error(file, 'run', 'out_dir', 'must not be empty')
      call check_path(file, c%out_dir)
      call check_real(file, 'run', 't_end', c%t_end, 0.0_rp, 1.0e6_rp, lo_open=.true.)
      call check_real(file, 'run', 'dt_out', c%dt_out, 0.0_rp, huge(1.0_rp), lo_open=.true.)
      call check_int(file, 'run', 'checkpoint_every', c%checkpoint_every, 0, huge(1))
      call check_int(file, 'run', 'max_steps', c%max_steps, 0, huge(1))
      call check_real(file, 'run', 'max_lost_fraction', c%max_lost_fraction, 0.0_rp, 1.0_rp)
      call check_real(file, 'run', 'progress_interval', c%progress_interval, 0.0_rp, huge(1.0_rp))
      call check_real(file, 'run', 'energy_interval', c%energy_interval, 0.0_rp, huge(1.0_rp))
      call check_int(file, 'run', 'balance_every', c%balance_every, 0, huge(1))
      call check_real(file, 'run', 'gauge_interval', c%gauge_interval, 0.0_rp, huge(1.0_rp), lo_open=.true.)
   end subroutine read_run

   !> out_dir names a folder and nothing else: a case file received from someone else
   !> must not be able to smuggle quotes, shell metacharacters or control characters
   !> into a path (the folder is made with mkdir(2), never through a shell).
   subroutine check_path(file, d)
      character(len=*), intent(in) :: file, d
      character(len=*), parameter :: allowed = 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789' &
                                              //'._-/+,=@~'
      integer :: k
      k = verify(trim(d), allowed)
      if (k > 0) call input_error(file, 'run', 'out_dir', "character '"//d(k:k)//"' at position "// &
         int_str(k)//' is not allowed; use letters, digits and . _ - / + , = @ ~')
      if (len_trim(d) > path_len - 64) call input_error(file, 'run', 'out_dir', 'longer than '// &
         int_str(path_len - 64)//' characters')
   end subroutine check_path

   subroutine write_run(u, c)
      integer, intent(in) :: u
      type(run_cfg), intent(in) :: c
      call to_vars(c)
      write (u, nml=run)
   end subroutine write_run
end module input_run

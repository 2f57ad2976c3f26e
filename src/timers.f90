!> Phase timers: wall time summed per phase of the step.
module timers
   use kinds, only: rp
   use comm, only: comm_wtime
   implicit none
   private
   public :: timer_start, timer_stop, timer_get, timer_reset, n_timers, timer_label, &
             t_grid, t_pairs, t_bodies, t_integrate, t_output, t_comm, t_setup

   integer, parameter :: t_setup = 1, t_grid = 2, t_pairs = 3, t_bodies = 4, &
                         t_integrate = 5, t_output = 6, t_comm = 7, n_timers = 7
   character(len=12), parameter :: labels(n_timers) = [character(len=12) :: &
      'setup', 'grid', 'pair loop', 'bodies', 'integrate', 'output', 'comm']

   real(rp) :: acc(n_timers) = 0.0_rp
   real(rp) :: started(n_timers) = 0.0_rp

contains

   subroutine timer_start(id)
      integer, intent(in) :: id
      started(id) = comm_wtime()
   end subroutine timer_start

   subroutine timer_stop(id)
      integer, intent(in) :: id
      acc(id) = acc(id) + (comm_wtime() - started(id))
   end subroutine timer_stop

   real(rp) function timer_get(id)
      integer, intent(in) :: id
      timer_get = acc(id)
   end function timer_get

   function timer_label(id) result(s)
      integer, intent(in) :: id
      character(len=12) :: s
      s = labels(id)
   end function timer_label

   subroutine timer_reset()
      acc = 0.0_rp
   end subroutine timer_reset
end module timers

!> Phase timers: wall time summed per phase of the step. A phase started
!> inside another pauses it (a stack of running phases), so the phases are
!> exclusive and add up to the wall time: the communication inside the pair
!> loop's phase counts as 'comm' only. The clock is the Fortran system clock,
!> so that the communication module can time itself.
module timers
   use kinds, only: rp, i8
   implicit none
   private
   public :: timer_start, timer_stop, timer_get, n_timers, timer_label, &
             t_grid, t_pairs, t_bodies, t_integrate, t_output, t_comm, t_setup

   integer, parameter :: t_setup = 1, t_grid = 2, t_pairs = 3, t_bodies = 4, &
                         t_integrate = 5, t_output = 6, t_comm = 7, n_timers = 7
   character(len=12), parameter :: labels(n_timers) = [character(len=12) :: &
      'setup', 'grid', 'pair loop', 'bodies', 'integrate', 'output', 'comm']
   integer, parameter :: max_depth = 16

   real(rp) :: acc(n_timers) = 0.0_rp
   integer :: stack(max_depth) = 0
   integer :: depth = 0
   integer(i8) :: since = 0_i8          !< clock count when the running phase was (re)started

contains

   integer(i8) function now()
      call system_clock(now)
   end function now

   real(rp) function seconds(counts)
      integer(i8), intent(in) :: counts
      integer(i8) :: rate
      call system_clock(count_rate=rate)
      seconds = real(counts, rp)/real(rate, rp)
   end function seconds

   !> Start phase id; the running phase (if any) pauses until id stops.
   subroutine timer_start(id)
      integer, intent(in) :: id
      integer(i8) :: t
      t = now()
      if (depth > 0) acc(stack(depth)) = acc(stack(depth)) + seconds(t - since)
      if (depth < max_depth) depth = depth + 1
      stack(depth) = id
      since = t
   end subroutine timer_start

   !> Stop the running phase (id) and resume the one it interrupted.
   subroutine timer_stop(id)
      integer, intent(in) :: id
      integer(i8) :: t
      t = now()
      if (depth == 0) return
      acc(stack(depth)) = acc(stack(depth)) + seconds(t - since)
      if (stack(depth) == id) depth = depth - 1
      since = t
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

end module timers

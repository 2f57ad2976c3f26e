!> The target free surface and paddle displacement of an irregular `&wavemaker`
!> (wave = 'irregular'), synthesised by the solver's own jonswap_paddle_signal with
!> the sampling the solver uses (dt = min(tp/200, 0.01 s)); for comparing a run's
!> gauges with the wave it was asked for (tools/jonswap_target.py, doc/waves.md).
!> Build: make build/jonswap_signal (make unit builds it too).
!> Usage: build/jonswap_signal HS TP GAMMA DEPTH SEED DURATION [PADDLE [G]] > signal.csv
!> (DURATION: the wavemaker's duration, or t_end - t_start, at least 20 TP, as the solver takes it).
program jonswap_signal
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use kinds, only: rp
   use wave_spectrum, only: jonswap_paddle_signal
   use options, only: option_index, paddle_names
   implicit none
   real(rp), allocatable :: t(:), x(:), eta(:)
   real(rp) :: hs, tp, gamma, depth, duration, g, nwaves
   integer :: seed, j
   character(len=64) :: paddle

   if (command_argument_count() < 6) then
      write (error_unit, '(a)') 'usage: jonswap_signal HS TP GAMMA DEPTH SEED DURATION [PADDLE [G]]'
      stop 2
   end if
   hs = real_arg(1)
   tp = real_arg(2)
   gamma = real_arg(3)
   depth = real_arg(4)
   seed = nint(real_arg(5))
   duration = max(real_arg(6), 20.0_rp*tp)
   paddle = 'piston'
   if (command_argument_count() >= 7) call get_command_argument(7, paddle)
   g = 9.81_rp
   if (command_argument_count() >= 8) g = real_arg(8)
   ! the paddle's name to its value as the solver's input does (an unknown name: an error naming the allowed ones)
   call jonswap_paddle_signal(hs, tp, gamma, depth, g, option_index('command line', 'argument 7', 'PADDLE', paddle, &
                                                                    paddle_names), seed, duration, min(tp/200.0_rp, 0.01_rp), &
                              t, x, eta, nwaves)
   write (output_unit, '(a)') 'time,x,eta'
   do j = 1, size(t)
      write (output_unit, '(es24.16e3, 2(",", es24.16e3))') t(j), x(j), eta(j)
   end do

contains

   !> The i-th command argument as a real; stops with exit code 2 when it is not a number.
   function real_arg(i) result(v)
      integer, intent(in) :: i
      real(rp) :: v
      character(len=64) :: s
      character(len=256) :: msg
      integer :: ios
      call get_command_argument(i, s)
      read (s, *, iostat=ios, iomsg=msg) v
      if (ios /= 0) then
         write (error_unit, '(a)') 'jonswap_signal: argument '//trim(s)//' is not a number ('//trim(msg)//')'
         stop 2
      end if
   end function real_arg
end program jonswap_signal

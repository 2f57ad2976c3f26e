!> The wavemaker's motion: the paddle displacement X(t) at the still-water
!> level and its velocity, for regular waves (Biesel transfer function,
!> optionally Madsen's second-order correction), irregular waves (JONSWAP
!> synthesised by FFT) or a signal read from a file. A piston moves all its
!> particles by X; a flap turns about its hinge on the bed so that the face
!> at the still-water level moves by X. bc_motion places the particles.
module wave_paddle
   use kinds, only: rp
   use constants, only: pi
   use input_wave, only: wavemaker_cfg
   use input_check, only: real_str, int_str
   use wave_theory, only: wave_number, piston_transfer, flap_transfer, piston_second_order, ramp, ramp_rate
   use wave_spectrum, only: jonswap_paddle_signal, signal_hm0
   use wave_signal, only: signal_t, signal_eval, signal_read
   use errors, only: fatal
   use options, only: wave_regular, wave_irregular, wave_file, paddle_piston, paddle_flap
   implicit none
   private
   public :: paddle_t, paddle_init, paddle_motion, paddle_place

   !> The paddle's law of motion, prepared once by paddle_init.
   type :: paddle_t
      logical :: on = .false.          !< a &wavemaker group: the paddle moves
      logical :: flap = .false.        !< a flap (turns about its hinge), else a piston
      integer :: wave = wave_regular   !< wave_regular: the Biesel law below; else the signal sig
      real(rp) :: t_start = 0.0_rp     !< the paddle starts at this time [s]
      real(rp) :: omega = 0.0_rp       !< regular: angular frequency [rad/s]
      real(rp) :: amp1 = 0.0_rp        !< regular: first-harmonic stroke amplitude [m]
      real(rp) :: amp2 = 0.0_rp        !< regular: second-order stroke amplitude [m]
      real(rp) :: t_ramp = 0.0_rp      !< duration of the start-up ramp [s]
      type(signal_t) :: sig            !< irregular and file: the stroke signal
   end type paddle_t

contains

   !> Prepare the motion from the input (nothing without a &wavemaker group);
   !> report what it makes in lines.
   !> A signal that exceeds the stroke stops here, before any particle is made.
   subroutine paddle_init(file, c, g, t_end, pad, lines)
      character(len=*), intent(in) :: file
      type(wavemaker_cfg), intent(in) :: c
      real(rp), intent(in) :: g, t_end
      type(paddle_t), intent(out) :: pad
      character(len=:), allocatable, intent(out) :: lines
      real(rp) :: k, kd, dur, dt, nwaves, xmax, hm0
      real(rp), allocatable :: ts(:), xs(:), eta(:)
      integer :: i
      lines = ''
      if (.not. c%on) return
      pad%on = .true.
      pad%flap = c%paddle_id == paddle_flap
      pad%wave = c%wave_id
      pad%t_start = c%t_start
      associate (wm => c, omega => pad%omega, amp1 => pad%amp1, amp2 => pad%amp2, t_ramp => pad%t_ramp, &
                 sig => pad%sig)
         select case (wm%wave_id)
         case (wave_regular)
            omega = 2.0_rp*pi/wm%period
            k = wave_number(omega, wm%depth, g)
            kd = k*wm%depth
            if (wm%paddle_id == paddle_piston) then
               amp1 = 0.5_rp*wm%height/piston_transfer(kd)
            else
               amp1 = 0.5_rp*wm%height/flap_transfer(kd)
            end if
            if (wm%second_order) amp2 = piston_second_order(wm%height, kd, wm%depth)
            t_ramp = wm%ramp_periods*wm%period
            lines = '  wavemaker: '//trim(wm%paddle)//', regular H = '//real_str(wm%height)//' m, T = '// &
                    real_str(wm%period)//' s, depth '//real_str(wm%depth)//' m: L = '//real_str(2.0_rp*pi/k)// &
                    ' m, kd = '//real_str(kd)//', stroke '//real_str(2.0_rp*amp1)//' m'
            if (wm%second_order) lines = lines//' + second order '//real_str(amp2)//' m'
         case (wave_irregular)
            dur = wm%duration
            if (dur <= 0.0_rp) dur = max(t_end - wm%t_start, 20.0_rp*wm%tp)
            dt = min(wm%tp/200.0_rp, 0.01_rp)
            call jonswap_paddle_signal(wm%hs, wm%tp, wm%gamma, wm%depth, g, wm%paddle, wm%seed, dur, dt, ts, xs, eta, &
                                       nwaves, wm%f_lo, wm%f_hi)
            sig%t = ts
            sig%x = xs
            t_ramp = wm%ramp_periods*wm%tp
            hm0 = signal_hm0(eta, ts(2) - ts(1))
            lines = '  wavemaker: '//trim(wm%paddle)//', irregular JONSWAP Hs = '//real_str(wm%hs)//' m, Tp = '// &
                    real_str(wm%tp)//' s, gamma = '//real_str(wm%gamma)//', seed '//int_str(wm%seed)// &
                    ': signal of '//real_str(ts(size(ts)) - ts(1))//' s, about '//real_str(nwaves)// &
                    ' waves, Hm0 of the target elevation '//real_str(hm0)//' m'
         case (wave_file)
            call signal_read(trim(wm%signal_file), 'wavemaker', sig, file, 'signal_file')
            t_ramp = 0.0_rp
            lines = '  wavemaker: '//trim(wm%paddle)//', signal from '//trim(wm%signal_file)//' ('// &
                    int_str(size(sig%t))//' samples, '//real_str(sig%t(1))//' to '//real_str(sig%t(size(sig%t)))//' s)'
         case default
            call fatal('paddle_init: unknown wave '//int_str(wm%wave_id))
         end select
         if (wm%ramp_time > 0.0_rp) t_ramp = wm%ramp_time
         if (wm%wave_id /= wave_regular) then
            xmax = 0.0_rp
            do i = 1, size(sig%x)
               xmax = max(xmax, abs(sig%x(i)))
            end do
            if (2.0_rp*xmax > wm%max_stroke) then
               call fatal(trim(file)//': &wavemaker: the paddle signal moves +-'//real_str(xmax)// &
                          ' m, beyond max_stroke/2 = '//real_str(0.5_rp*wm%max_stroke)// &
                          ' m: lower hs (or the signal), or raise max_stroke', 2)
            end if
         end if
         if (t_ramp > 0.0_rp) lines = lines//', ramp '//real_str(t_ramp)//' s'
         if (wm%t_start > 0.0_rp) lines = lines//', starting at t = '//real_str(wm%t_start)//' s'
      end associate
   end subroutine paddle_init

   !> Displacement X and velocity U of the paddle face at the still-water
   !> level at time t_run; the signal's clock starts at t_start.
   subroutine paddle_motion(pad, t_run, x, u)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t_run
      real(rp), intent(out) :: x, u
      real(rp) :: r, dr, x0, u0, t
      x = 0.0_rp
      u = 0.0_rp
      if (.not. pad%on) return
      t = t_run - pad%t_start
      if (t <= 0.0_rp) return
      associate (omega => pad%omega, amp1 => pad%amp1, amp2 => pad%amp2, t_ramp => pad%t_ramp)
         if (pad%wave == wave_regular) then
            ! starts at rest: sin(w t) and the second harmonic both vanish at t = 0
            x0 = amp1*sin(omega*t) + amp2*sin(2.0_rp*omega*t)
            u0 = omega*(amp1*cos(omega*t) + 2.0_rp*amp2*cos(2.0_rp*omega*t))
         else
            call signal_eval(pad%sig, t, x0, u0)
         end if
         r = 1.0_rp
         dr = 0.0_rp
         if (t_ramp > 0.0_rp) then
            r = ramp(t, t_ramp)
            dr = ramp_rate(t, t_ramp)
         end if
         x = r*x0
         u = r*u0 + dr*x0
      end associate
   end subroutine paddle_motion

   !> Position and velocity of a paddle particle whose rest position is xb.
   pure subroutine paddle_place(flap, xb, x_face, u_face, hinge, depth, x, v)
      logical, intent(in) :: flap
      real(rp), intent(in) :: xb(2), x_face, u_face, hinge(2), depth
      real(rp), intent(out) :: x(2), v(2)
      real(rp) :: th, dth, d(2), c, s
      if (.not. flap) then
         x = [xb(1) + x_face, xb(2)]
         v = [u_face, 0.0_rp]
         return
      end if
      ! clockwise turn by th about the hinge: the face at the still-water
      ! level (depth above the hinge) moves by x_face
      th = atan2(x_face, depth)
      dth = u_face*depth/(depth*depth + x_face*x_face)
      d = xb - hinge
      c = cos(th)
      s = sin(th)
      x = hinge + [c*d(1) + s*d(2), -s*d(1) + c*d(2)]
      v = dth*[-s*d(1) + c*d(2), -c*d(1) - s*d(2)]
   end subroutine paddle_place
end module wave_paddle

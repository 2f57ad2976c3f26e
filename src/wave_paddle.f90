!> The wavemaker's motion: the paddle displacement X(t) at the still-water
!> level and its velocity, for regular waves (Biesel transfer function,
!> optionally Madsen's second-order correction), irregular waves (JONSWAP
!> synthesised by FFT) or a signal read from a file. A piston moves all its
!> particles by X; a flap turns about its hinge on the bed so that the face
!> at the still-water level moves by X. bc_motion places the particles.
module wave_paddle
   use kinds, only: rp
   use wave_theory, only: ramp, ramp_rate
   use wave_signal, only: signal_t, signal_eval
   use options, only: wave_regular
   implicit none
   private
   public :: paddle_t, paddle_motion, paddle_place

   !> The paddle's law of motion, prepared once by the scene builder (scene_paddle).
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

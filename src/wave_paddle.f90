!> The wavemaker's motion: the paddle displacement X(t) at the still-water
!> level and its velocity, for regular waves (Biesel transfer function,
!> optionally Madsen's second-order correction), irregular waves (JONSWAP
!> synthesised by FFT) or a signal read from a file. A piston moves all its
!> particles by X; a flap turns about its hinge on the bed so that the face
!> at the still-water level moves by X. bc_motion places the particles.
!>
!> Active absorption (doc/waves.md, "Active absorption at the paddle"): the
!> paddle adds to its target motion the velocity that cancels the wave
!> coming back to it, u_c = -G (eta_m - eta_t), from the elevation eta_m
!> measured in front of its face and the elevation eta_t of the wave it is
!> making; G = omega / (H/S) at the (peak) period, the linear gain that
!> makes no wave of that period (sqrt(g/d) in shallow water). The gauge
!> stands a distance D in front of the face (the kernel's support must hold
!> only water): the wave coming in passes it D/c before it reaches the
!> paddle, so eta_m is used D/c late, and the paddle's own wave reaches it
!> D/c after it left, so eta_t is taken 2 D/c late.
module wave_paddle
   use kinds, only: rp
   use wave_theory, only: ramp, ramp_rate
   use wave_signal, only: signal_t, signal_eval
   use options, only: wave_regular
   implicit none
   private
   public :: paddle_t, paddle_motion, paddle_place, paddle_target_eta, paddle_absorb_set, paddle_absorb_advance

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
      real(rp) :: t_stop = 0.0_rp      !< > 0: the wave ends this long after t_start, ramped down over t_ramp [s]
      type(signal_t) :: sig            !< irregular and file: the stroke signal
      ! active absorption
      logical :: absorb = .false.      !< the paddle absorbs the waves that come back to it
      real(rp) :: gain = 0.0_rp        !< G: paddle velocity per metre of elevation [1/s]
      real(rp) :: tau = 0.0_rp         !< time scale of the drift control and of the mean level ignored [s]
      real(rp) :: eta1 = 0.0_rp        !< regular: amplitude of the target elevation at the paddle [m]
      type(signal_t) :: sig_eta        !< irregular: the target elevation at the paddle
      real(rp) :: x_face = 0.0_rp      !< rest position of the face at the still-water level [m]
      real(rp) :: x_max = 0.0_rp       !< the paddle's excursion allowed, max_stroke / 2 [m]
      real(rp) :: gauge_offset = 0.0_rp   !< the elevation is measured this far in front of the face [m]
      real(rp) :: celerity = 0.0_rp    !< phase speed at the (peak) period [m/s]
      real(rp) :: delay = 0.0_rp       !< gauge_offset / celerity [s]
      ! the correction over the present step (paddle_absorb_set): X_c + (t - t_c) u_c
      real(rp) :: xc = 0.0_rp, uc = 0.0_rp, tc = 0.0_rp
   end type paddle_t

contains


   !> Displacement X and velocity U of the paddle face at the still-water
   !> level at time t_run; the signal's clock starts at t_start. With
   !> absorption, the correction of the present step is added.
   pure subroutine paddle_motion(pad, t_run, x, u)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t_run
      real(rp), intent(out) :: x, u
      real(rp) :: r, dr, x0, u0, t
      logical :: on
      x = 0.0_rp
      u = 0.0_rp
      if (.not. pad%on) return
      if (pad%absorb) then
         x = pad%xc + (t_run - pad%tc)*pad%uc
         u = pad%uc
      end if
      t = t_run - pad%t_start
      call envelope(pad, t, r, dr, on)
      if (.not. on) return
      if (pad%wave == wave_regular) then
         ! starts at rest: sin(w t) and the second harmonic both vanish at t = 0
         x0 = pad%amp1*sin(pad%omega*t) + pad%amp2*sin(2.0_rp*pad%omega*t)
         u0 = pad%omega*(pad%amp1*cos(pad%omega*t) + 2.0_rp*pad%amp2*cos(2.0_rp*pad%omega*t))
      else
         call signal_eval(pad%sig, t, x0, u0)
      end if
      x = x + r*x0
      u = u + r*u0 + dr*x0
   end subroutine paddle_motion

   !> The target elevation at the paddle [m] at time t_run: the first-order
   !> progressive wave the paddle makes (no evanescent modes), ramped as the
   !> motion is; 0 for a signal file, whose wave is not known.
   pure function paddle_target_eta(pad, t_run) result(eta)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t_run
      real(rp) :: eta
      real(rp) :: r, dr, t, e0, de0
      logical :: on
      eta = 0.0_rp
      if (.not. pad%on) return
      t = t_run - pad%t_start
      call envelope(pad, t, r, dr, on)
      if (.not. on) return
      if (pad%wave == wave_regular) then
         ! in phase with the paddle velocity
         e0 = pad%eta1*cos(pad%omega*t)
      else if (allocated(pad%sig_eta%t)) then
         call signal_eval(pad%sig_eta, t, e0, de0)
      else
         e0 = 0.0_rp
      end if
      eta = r*e0
   end function paddle_target_eta

   !> The ramps of the signal at time t after t_start: up over t_ramp, and
   !> down over t_ramp before t_stop when the wave has an end; r = 0 before
   !> the start and after the end; .false. there (the paddle makes no wave).
   pure subroutine envelope(pad, t, r, dr, on)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t
      real(rp), intent(out) :: r, dr
      logical, intent(out) :: on
      real(rp) :: rd, drd
      r = 0.0_rp
      dr = 0.0_rp
      on = t > 0.0_rp
      if (pad%t_stop > 0.0_rp) on = on .and. t < pad%t_stop
      if (.not. on) return
      r = 1.0_rp
      if (pad%t_ramp > 0.0_rp) then
         r = ramp(t, pad%t_ramp)
         dr = ramp_rate(t, pad%t_ramp)
         if (pad%t_stop > 0.0_rp) then
            rd = ramp(pad%t_stop - t, pad%t_ramp)
            drd = -ramp_rate(pad%t_stop - t, pad%t_ramp)
            dr = dr*rd + r*drd
            r = r*rd
         end if
      end if
   end subroutine envelope

   !> The absorber's correction for the step from time t: with the elevation
   !> eta_m measured in front of the face, the correction's displacement xc,
   !> the slow mean level eta_mean and the history of eta_m - eta_mean (all
   !> kept in the run's state; the sample of time t is added here),
   !> u_c = -G (e(t - D/c) - eta_t(t - 2 D/c)) - xc / tau, e = eta_m - eta_mean.
   !> The mean level is left out so that a slow change of the level
   !> (set-down, water taken up by a porous core) does not walk the paddle
   !> away; the last term brings the paddle back to its signal over tau.
   pure subroutine paddle_absorb_set(pad, t, eta_m, xc, eta_mean, hist)
      type(paddle_t), intent(inout) :: pad
      real(rp), intent(in) :: t, eta_m, xc, eta_mean
      real(rp), allocatable, intent(inout) :: hist(:, :)   !< (time, e) of past steps, oldest first
      real(rp) :: e
      call history_add(hist, t, eta_m - eta_mean, pad%delay)
      e = history_at(hist, t - pad%delay)
      pad%xc = xc
      pad%tc = t
      pad%uc = -pad%gain*(e - paddle_target_eta(pad, t - 2.0_rp*pad%delay)) - xc/pad%tau
   end subroutine paddle_absorb_set

   !> Append (t, e) to the history and drop what is no longer needed: every
   !> sample but the last one older than t - delay.
   pure subroutine history_add(hist, t, e, delay)
      real(rp), allocatable, intent(inout) :: hist(:, :)
      real(rp), intent(in) :: t, e, delay
      integer :: n, first
      if (.not. allocated(hist)) allocate (hist(2, 0))
      n = size(hist, 2)
      first = 1
      do while (first < n)
         if (hist(1, first + 1) > t - delay) exit
         first = first + 1
      end do
      hist = reshape([hist(:, first:n), t, e], [2, n - first + 2])
   end subroutine history_add

   !> The history's value at time t, linear between samples; its first value
   !> before its first sample.
   pure function history_at(hist, t) result(e)
      real(rp), intent(in) :: hist(:, :)
      real(rp), intent(in) :: t
      real(rp) :: e
      integer :: k, n
      real(rp) :: s
      n = size(hist, 2)
      e = hist(2, 1)
      if (t <= hist(1, 1)) return
      e = hist(2, n)
      do k = 1, n - 1
         if (hist(1, k + 1) >= t) then
            s = (t - hist(1, k))/max(hist(1, k + 1) - hist(1, k), tiny(1.0_rp))
            e = hist(2, k) + s*(hist(2, k + 1) - hist(2, k))
            return
         end if
      end do
   end function history_at

   !> The absorber's state after a step of dt from the time of paddle_absorb_set.
   pure subroutine paddle_absorb_advance(pad, dt, eta_m, xc, eta_mean)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: dt, eta_m
      real(rp), intent(inout) :: xc, eta_mean
      xc = pad%xc + dt*pad%uc
      eta_mean = eta_mean + (dt/pad%tau)*(eta_m - eta_mean)
   end subroutine paddle_absorb_advance

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

!> The wavemaker's motion: the paddle displacement X(t) at the still-water
!> level and its velocity, for regular waves (Biesel transfer function,
!> optionally Madsen's second-order correction), irregular waves (JONSWAP
!> synthesised by FFT) or a signal read from a file. A piston moves all its
!> particles by X; a flap turns about its hinge on the bed so that the face
!> at the still-water level moves by X. bc_motion places the particles.
!>
!> Active absorption (doc/waves.md, "Active absorption at the paddle"): the
!> paddle adds to its target motion the velocity that cancels the wave
!> coming back to it, u_c = -G e, from the wave coming in e: the elevation
!> measured in front of its face less the paddle's own wave there. The
!> gauge stands a distance D in front of the wave's source (the kernel's
!> support must hold only water), so e is read some D/c late. The gain and
!> that delay come from linear theory at the (peak) period
!> (paddle_absorb_tune): with the paddle's evanescent modes at the gauge and
!> the lead of the absorber's slow filters, they make no reflection of that
!> period; without either, G = omega / (H/S) (sqrt(g/d) in shallow water)
!> and the delay D/c.
module wave_paddle
   use kinds, only: rp
   use constants, only: pi
   use wave_theory, only: ramp, ramp_rate, paddle_mode, piston_transfer, flap_transfer, wave_number
   use wave_signal, only: signal_t, signal_eval
   use options, only: wave_regular
   implicit none
   private
   public :: paddle_t, paddle_motion, paddle_place, paddle_target_eta, paddle_absorb_set, paddle_absorb_advance, &
             paddle_absorb_tune, paddle_own_wave

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
      real(rp) :: depth = 0.0_rp       !< still-water depth at the paddle [m]
      real(rp) :: delay = 0.0_rp       !< the paddle's wave from its source to the gauge [s]
      real(rp) :: near = 0.0_rp        !< the paddle's evanescent modes at the gauge per unit of its wave, a quarter period late
      real(rp) :: lag = 0.0_rp         !< the wave coming in is read this late [s]
      real(rp) :: omega_abs = 1.0_rp   !< the (peak) angular frequency the absorber is tuned to [rad/s]
      ! the correction over the present step (paddle_absorb_set): X_c + (t - t_c) u_c,
      ! and the wave coming in at t_c, which the step's mean level takes up
      real(rp) :: xc = 0.0_rp, uc = 0.0_rp, tc = 0.0_rp, ein = 0.0_rp
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
   !> the slow mean level eta_mean and the history of the wave coming in
   !> e = eta_m - eta_own(t) - eta_mean (all kept in the run's state; the
   !> sample of time t is added here), u_c = -G e(t - lag) - xc / tau.
   !> The mean level is left out so that a slow change of the level
   !> (set-down, water taken up by a porous core) does not walk the paddle
   !> away; the last term brings the paddle back to its signal over tau.
   !> Both lead the correction by atan(1/(omega tau)) at the wave's
   !> frequency, which gain and lag take back (paddle_absorb_tune).
   pure subroutine paddle_absorb_set(pad, t, eta_m, xc, eta_mean, hist)
      type(paddle_t), intent(inout) :: pad
      real(rp), intent(in) :: t, eta_m, xc, eta_mean
      real(rp), allocatable, intent(inout) :: hist(:, :)   !< (time, e) of past steps, oldest first
      real(rp) :: e
      pad%ein = paddle_incoming(pad, t, eta_m, eta_mean)
      call history_add(hist, t, pad%ein, pad%lag)
      e = history_at(hist, t - pad%lag)
      pad%xc = xc
      pad%tc = t
      pad%uc = -pad%gain*e - xc/pad%tau
   end subroutine paddle_absorb_set

   !> The wave coming in at the gauge at time t: what the gauge measures less
   !> the paddle's own wave there and the slow mean level.
   pure function paddle_incoming(pad, t, eta_m, eta_mean) result(e)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t, eta_m, eta_mean
      real(rp) :: e
      e = eta_m - paddle_own_wave(pad, t) - eta_mean
   end function paddle_incoming

   !> The elevation of the paddle's target wave at the gauge at time t: the
   !> progressive wave that left its source delay earlier, and the evanescent
   !> modes of its motion now (in quadrature with the motion: a quarter of the
   !> (peak) period late).
   pure function paddle_own_wave(pad, t) result(eta)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: t
      real(rp) :: eta
      eta = paddle_target_eta(pad, t - pad%delay)
      eta = eta + pad%near*paddle_target_eta(pad, t - 0.5_rp*pi/pad%omega_abs)
   end function paddle_own_wave

   !> The absorber's gain, delays and near field from linear theory at the
   !> (peak) angular frequency omega_abs, for a gauge x_g in front of the wave's
   !> source in water of the paddle's depth, the slow time tau already set. With the
   !> correction velocity U (time factor exp(-i omega t)), the gauge reads
   !> the wave coming in, I exp(-i k x_g) at the source I, its reflection by
   !> the paddle at rest, I exp(i k x_g), and U (P exp(i k x_g) + i q), P the
   !> progressive and i q the evanescent elevation per unit face velocity
   !> (paddle_mode). The absorber U = -K e, with the two filters' lead
   !> (1 + i/(omega tau))^-2 and e the reading less the paddle's own wave,
   !> returns nothing (I + U P = 0) for K = (1 + i/(omega tau))^2 / (P exp(-i k x_g) - i q):
   !> its modulus is the gain, its phase over omega the lag. Without q and
   !> tau: G = 1/P = omega / (H/S) and the lag x_g / c.
   pure subroutine paddle_absorb_tune(pad, g, x_g)
      type(paddle_t), intent(inout) :: pad
      real(rp), intent(in) :: g, x_g
      complex(rp), parameter :: iu = (0.0_rp, 1.0_rp)
      complex(rp) :: kk
      real(rp) :: k, kn, cn, q, pp, term
      integer :: n
      associate (flap => pad%flap, omega => pad%omega_abs, depth => pad%depth)
         k = wave_number(omega, depth, g)
         if (flap) then
            pp = flap_transfer(k*depth)/omega
         else
            pp = piston_transfer(k*depth)/omega
         end if
         q = 0.0_rp
         do n = 1, 100000
            call paddle_mode(flap, n, omega, depth, g, kn, cn)
            term = -omega/(g*kn)*cn*cos(kn*depth)*exp(-kn*max(x_g, 0.0_rp))
            q = q + term
            if (abs(term) < 1.0e-12_rp*pp .and. n > 10) exit
         end do
         kk = (1.0_rp + iu/(omega*pad%tau))**2/(pp*exp(-iu*k*x_g) - iu*q)
         pad%gain = abs(kk)
         pad%lag = modulo(atan2(aimag(kk), real(kk)), 2.0_rp*pi)/omega
         pad%delay = x_g*k/omega
         pad%near = q/pp
      end associate
   end subroutine paddle_absorb_tune

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
   pure subroutine paddle_absorb_advance(pad, dt, xc, eta_mean)
      type(paddle_t), intent(in) :: pad
      real(rp), intent(in) :: dt
      real(rp), intent(inout) :: xc, eta_mean
      xc = pad%xc + dt*pad%uc
      ! the mean of what is not the paddle's own wave: a level that wave leaves alone
      eta_mean = eta_mean + (dt/pad%tau)*pad%ein
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

!> Wave theory and wave signals: dispersion and its limits, the Biesel
!> transfer functions and their limits, Madsen's second-order stroke, the
!> Miche limit, the ramp, the JONSWAP integral, the random stream, FFT
!> synthesis of a JONSWAP paddle signal, and sampled signals (interpolation,
!> file reading).
program test_waves
   use kinds, only: rp
   use constants, only: pi
   use wave_theory, only: wave_number, piston_transfer, flap_transfer, piston_second_order, miche_limit, ramp, ramp_rate, &
                          paddle_mode
   use wave_fftw, only: fft_c2r, fft_r2c
   use wave_spectrum, only: jonswap, jonswap_paddle_signal, signal_hm0, signal_peak_frequency, signal_periodogram, &
                            rng_t, rng_seed, rng_uniform
   use wave_signal, only: signal_t, signal_eval, signal_read
   use wave_paddle, only: paddle_t, paddle_motion, paddle_target_eta, paddle_absorb_set, paddle_absorb_advance, &
                          paddle_absorb_tune
   use options, only: wave_regular, paddle_piston, paddle_flap, paddle_names
   use testing, only: check, check_close, test_summary
   implicit none
   real(rp), parameter :: g = 9.81_rp

   call test_dispersion()
   call test_transfer()
   call test_second_order_and_limits()
   call test_jonswap()
   call test_rng()
   call test_fft()
   call test_synthesis(paddle_piston)
   call test_synthesis(paddle_flap)
   call test_signal_eval()
   call test_signal_read()
   call test_paddle_end()
   call test_absorber()
   call test_paddle_modes(.false.)
   call test_paddle_modes(.true.)
   call test_absorber_tune()
   call test_summary('test_waves')

contains

   !> w^2 = g k tanh(kd) solved to 1e-12 for kd in [0.05, 10]; the shallow
   !> (k = w / sqrt(g d)) and deep (k = w^2 / g) limits where they apply.
   subroutine test_dispersion()
      integer :: i
      real(rp) :: kd, d, k0, w, k, worst_res, worst_k
      d = 0.7_rp
      worst_res = 0.0_rp
      worst_k = 0.0_rp
      do i = 0, 80
         kd = 0.05_rp*(10.0_rp/0.05_rp)**(i/80.0_rp)
         k0 = kd/d
         w = sqrt(g*k0*tanh(kd))
         k = wave_number(w, d, g)
         worst_res = max(worst_res, abs(w*w - g*k*tanh(k*d))/(w*w))
         worst_k = max(worst_k, abs(k - k0)/k0)
      end do
      call check(worst_res < 1.0e-12_rp, 'dispersion residual below 1e-12 for kd in [0.05, 10]')
      call check(worst_k < 1.0e-12_rp, 'dispersion recovers k to 1e-12 for kd in [0.05, 10]')
      ! shallow: k d = 0.05, relative departure (kd)^2/6 = 4e-4
      w = sqrt(g*(0.05_rp/d)*tanh(0.05_rp))
      call check_close(wave_number(w, d, g), w/sqrt(g*d), 1.0e-3_rp, 'dispersion shallow limit k = w/sqrt(g d)')
      ! deep: k d = 10, tanh = 1 - 4e-9
      w = sqrt(g*(10.0_rp/d)*tanh(10.0_rp))
      call check_close(wave_number(w, d, g), w*w/g, 1.0e-3_rp, 'dispersion deep limit k = w^2/g')
      ! far outside the tested range: no overflow, no loss of the root
      w = 50.0_rp
      call check_close(wave_number(w, 100.0_rp, g), w*w/g, 1.0e-14_rp, 'dispersion kd = 25000 (deep)')
      w = 1.0e-4_rp
      call check_close(wave_number(w, 1.0_rp, g), w/sqrt(g), 1.0e-9_rp, 'dispersion kd = 3e-5 (shallow)')
      call check(same(wave_number(0.0_rp, 1.0_rp, g), 0.0_rp), 'dispersion omega = 0 gives k = 0')
   end subroutine test_dispersion

   !> Biesel H/S: piston -> 2 deep, kd shallow; flap -> 2 (1 - 1/kd) deep
   !> (so 2), kd/2 shallow; kd = 1 against the textbook formulas as written.
   subroutine test_transfer()
      real(rp) :: x, ref
      call check_close(piston_transfer(10.0_rp), 2.0_rp, 0.01_rp, 'piston H/S -> 2 in deep water (kd = 10)')
      call check_close(piston_transfer(0.05_rp), 0.05_rp, 0.01_rp, 'piston H/S -> kd in shallow water (kd = 0.05)')
      call check_close(piston_transfer(1000.0_rp), 2.0_rp, 1.0e-15_rp, 'piston H/S at kd = 1000 (no overflow)')
      call check_close(piston_transfer(1.0e-6_rp), 1.0e-6_rp, 1.0e-9_rp, 'piston H/S at kd = 1e-6')
      call check_close(flap_transfer(0.05_rp), 0.025_rp, 0.01_rp, 'flap H/S -> kd/2 in shallow water (kd = 0.05)')
      call check_close(flap_transfer(300.0_rp), 2.0_rp, 0.01_rp, 'flap H/S -> 2 in deep water (kd = 300)')
      ! the deep-water approach is slow, 2 (1 - 1/kd) up to exp(-kd) terms
      call check_close(flap_transfer(30.0_rp), 2.0_rp*(1.0_rp - 1.0_rp/30.0_rp), 1.0e-12_rp, 'flap H/S = 2 (1 - 1/kd) at kd = 30')
      call check_close(flap_transfer(1.0e-6_rp), 0.5e-6_rp, 1.0e-9_rp, 'flap H/S at kd = 1e-6')
      call check_close(flap_transfer(1000.0_rp), 2.0_rp*(1.0_rp - 1.0e-3_rp), 1.0e-14_rp, 'flap H/S at kd = 1000 (no overflow)')
      x = 1.0_rp
      ref = 2.0_rp*(cosh(2.0_rp*x) - 1.0_rp)/(sinh(2.0_rp*x) + 2.0_rp*x)
      call check_close(piston_transfer(x), ref, 1.0e-13_rp, 'piston H/S at kd = 1 against Biesel as written')
      ref = 4.0_rp*(sinh(x)/x)*(x*sinh(x) - cosh(x) + 1.0_rp)/(sinh(2.0_rp*x) + 2.0_rp*x)
      call check_close(flap_transfer(x), ref, 1.0e-13_rp, 'flap H/S at kd = 1 against Biesel as written')
      x = 0.3_rp
      ref = 4.0_rp*(sinh(x)/x)*(x*sinh(x) - cosh(x) + 1.0_rp)/(sinh(2.0_rp*x) + 2.0_rp*x)
      call check_close(flap_transfer(x), ref, 1.0e-12_rp, 'flap H/S at kd = 0.3 against Biesel as written')
   end subroutine test_transfer

   !> Madsen's X2 against the formula as written; Miche limit in both
   !> limits (H/L = 0.142 deep, H/d = 0.142 * 2 pi shallow); ramp and its rate.
   subroutine test_second_order_and_limits()
      real(rp) :: kd, d, h, n1, ref, k, t, e, tr
      integer :: i
      d = 0.6_rp
      h = 0.08_rp
      kd = 0.8_rp
      n1 = 0.5_rp*(1.0_rp + 2.0_rp*kd/sinh(2.0_rp*kd))
      ref = h*h/(32.0_rp*d)*(3.0_rp*cosh(kd)/sinh(kd)**3 - 2.0_rp/n1)
      call check_close(piston_second_order(h, kd, d), ref, 1.0e-13_rp, 'Madsen X2 at kd = 0.8 against the formula')
      ! deep water: 3 cosh/sinh^3 -> 0, n1 -> 1/2: X2 -> -h^2 / (8 d)
      call check_close(piston_second_order(h, 500.0_rp, d), -h*h/(8.0_rp*d), 1.0e-14_rp, 'Madsen X2 deep limit')
      k = 20.0_rp/d
      call check_close(miche_limit(k, d)*k/(2.0_rp*pi), 0.142_rp, 1.0e-12_rp, 'Miche H/L = 0.142 in deep water')
      k = 1.0e-3_rp/d
      call check_close(miche_limit(k, d)/d, 0.142_rp*2.0_rp*pi, 1.0e-6_rp, 'Miche H/d = 0.892 in shallow water')
      tr = 2.0_rp
      call check(same(ramp(-1.0_rp, tr), 0.0_rp) .and. same(ramp(0.0_rp, tr), 0.0_rp), 'ramp is 0 up to t = 0')
      call check_close(ramp(1.0_rp, tr), 0.5_rp, 1.0e-15_rp, 'ramp is 1/2 at half the ramp time')
      call check(same(ramp(tr, tr), 1.0_rp) .and. same(ramp(5.0_rp, tr), 1.0_rp), 'ramp is 1 from t_ramp on')
      call check(same(ramp(0.3_rp, 0.0_rp), 1.0_rp) .and. same(ramp_rate(0.3_rp, 0.0_rp), 0.0_rp), 'no ramp when t_ramp = 0')
      e = 0.0_rp
      do i = 1, 19
         t = 0.1_rp*i
         e = max(e, abs(ramp_rate(t, tr) - (ramp(t + 1.0e-6_rp, tr) - ramp(t - 1.0e-6_rp, tr))/2.0e-6_rp))
      end do
      ! centred difference: truncation (pi/2)^3 / 12 * 1e-12, rounding 1e-16 / 1e-6
      call check(e < 1.0e-8_rp, 'ramp_rate is the derivative of ramp (centred difference, 1e-8)')
      call check(same(ramp_rate(-0.1_rp, tr), 0.0_rp) .and. same(ramp_rate(2.5_rp, tr), 0.0_rp), 'ramp_rate is 0 outside the ramp')
   end subroutine test_second_order_and_limits

   !> Integral of Goda's JONSWAP: at gamma = 1, m0 = bJ(1) hs^2 / 5 exactly
   !> (int f^-5 exp(-1.25 fp^4 f^-4) df = fp^-4 / 5); at gamma = 3.3,
   !> 4 sqrt(m0) = 1.034 hs (the reference's note) within 1 %. Composite
   !> Simpson rule over [0.25, 40] fp; the tail beyond is 5e-7 of m0.
   subroutine test_jonswap()
      real(rp) :: hs, tp, m0, bj1
      hs = 0.12_rp
      tp = 1.6_rp
      m0 = simpson(hs, tp, 1.0_rp)
      bj1 = 0.0624_rp/(0.230_rp + 0.0336_rp - 0.185_rp/2.9_rp)*1.094_rp
      call check_close(m0, bj1*hs*hs/5.0_rp, 1.0e-5_rp, 'JONSWAP gamma = 1: m0 = bJ hs^2 / 5')
      m0 = simpson(hs, tp, 3.3_rp)
      call check_close(4.0_rp*sqrt(m0), 1.034_rp*hs, 0.01_rp, 'JONSWAP gamma = 3.3: Hm0 = 1.034 hs before normalisation')
      call check(jonswap(1.0_rp/tp, hs, tp, 3.3_rp) > jonswap(1.01_rp/tp, hs, tp, 3.3_rp) .and. &
                 jonswap(1.0_rp/tp, hs, tp, 3.3_rp) > jonswap(0.99_rp/tp, hs, tp, 3.3_rp), 'JONSWAP peaks at 1/tp')
      call check(same(jonswap(0.0_rp, hs, tp, 3.3_rp), 0.0_rp), 'JONSWAP is 0 at f = 0')
   end subroutine test_jonswap

   !> m0 of JONSWAP by the composite Simpson rule (1e5 intervals) on [0.25, 40] / tp.
   function simpson(hs, tp, gamma) result(m)
      real(rp), intent(in) :: hs, tp, gamma
      real(rp) :: m, a, b, hstep
      integer :: i, nint2
      nint2 = 100000
      a = 0.25_rp/tp
      b = 40.0_rp/tp
      hstep = (b - a)/nint2
      m = jonswap(a, hs, tp, gamma) + jonswap(b, hs, tp, gamma)
      do i = 1, nint2 - 1
         m = m + merge(4.0_rp, 2.0_rp, mod(i, 2) == 1)*jonswap(a + i*hstep, hs, tp, gamma)
      end do
      m = m*hstep/3.0_rp
   end function simpson

   !> The stream against the reference xoshiro128** C code (Blackman and
   !> Vigna, xoshiro128starstar.c) compiled with the same fmix32 seeding and
   !> 53-bit conversion: the first three uniforms must agree bit for bit.
   !> Then the mean and variance of 1e5 uniforms (1/2 and 1/12, within five
   !> standard errors) and the range [0, 1).
   subroutine test_rng()
      type(rng_t) :: r
      real(rp) :: u(3), s1, s2, v
      integer :: i, n
      real(rp), parameter :: ref42(3) = [0.66061572080016207_rp, 0.11170196395322241_rp, 0.079105645614491404_rp]
      real(rp), parameter :: refm7(3) = [0.95592686802641069_rp, 0.34061017891707845_rp, 0.96095202492291165_rp]
      call rng_seed(r, 42)
      do i = 1, 3
         u(i) = rng_uniform(r)
      end do
      call check(all(same(u, ref42)), 'xoshiro128** seed 42 matches the C reference bit for bit')
      call rng_seed(r, -7)
      do i = 1, 3
         u(i) = rng_uniform(r)
      end do
      call check(all(same(u, refm7)), 'xoshiro128** seed -7 matches the C reference bit for bit')
      n = 100000
      s1 = 0.0_rp
      s2 = 0.0_rp
      call rng_seed(r, 2024)
      do i = 1, n
         v = rng_uniform(r)
         if (v < 0.0_rp .or. v >= 1.0_rp) s1 = huge(1.0_rp)
         s1 = s1 + v
         s2 = s2 + v*v
      end do
      s1 = s1/n
      s2 = s2/n - s1*s1
      ! standard errors: sqrt(1/12 / n) = 9.1e-4 for the mean, sqrt(1/180 / n) = 2.4e-4 for the variance
      call check(abs(s1 - 0.5_rp) < 5.0_rp*9.1e-4_rp, 'uniforms in [0,1) with mean 1/2')
      call check(abs(s2 - 1.0_rp/12.0_rp) < 5.0_rp*2.4e-4_rp, 'uniforms with variance 1/12')
   end subroutine test_rng

   !> r2c then c2r returns n times the input, inputs untouched; a cosine
   !> lands in its own bin with amplitude n a / 2.
   subroutine test_fft()
      integer, parameter :: n = 64
      real(rp) :: x(n), x0(n), y(n)
      complex(rp) :: c(0:n/2), c0(0:n/2)
      integer :: j
      do j = 1, n
         x(j) = 0.3_rp + 0.7_rp*cos(2.0_rp*pi*5*(j - 1)/n + 0.4_rp) + 0.1_rp*(-1)**j
      end do
      x0 = x
      call fft_r2c(x, c)
      call check(all(same(x, x0)), 'fft_r2c leaves its input alone')
      call check_close(abs(c(5)), 0.35_rp*n, 1.0e-13_rp, 'fft_r2c: cosine of amplitude a gives n a / 2')
      call check_close(atan2(aimag(c(5)), real(c(5))), 0.4_rp, 1.0e-13_rp, 'fft_r2c: phase of the cosine')
      call check_close(real(c(0)), 0.3_rp*n, 1.0e-13_rp, 'fft_r2c: mean')
      c0 = c
      call fft_c2r(c, y)
      call check(all(same(real(c), real(c0)) .and. same(aimag(c), aimag(c0))), 'fft_c2r leaves its input alone')
      call check(maxval(abs(y/n - x)) < 1.0e-14_rp, 'fft_c2r(fft_r2c(x)) = n x')
   end subroutine test_fft

   !> JONSWAP paddle signal: Hm0 of eta equals hs (exact by construction:
   !> deterministic amplitudes scaled to 4 sqrt(m0) = hs, and Parseval; so
   !> 1e-9 rather than a statistical tolerance), peak within one bin of 1/tp
   !> (no smoothing needed: the periodogram is the discrete target spectrum),
   !> bitwise reproducible, seed-dependent, zero-mean stroke, and per bin the
   !> stroke spectrum is -i eta / (H/S) of the paddle's transfer function.
   subroutine test_synthesis(paddle)
      integer, intent(in) :: paddle
      real(rp), parameter :: hs = 0.1_rp, tp = 1.5_rp, gam = 3.3_rp, d = 0.5_rp, dur = 300.0_rp, dt = 0.02_rp
      real(rp), allocatable :: t(:), x(:), eta(:), t2(:), x2(:), eta2(:), f(:), s(:)
      complex(rp), allocatable :: ce(:), cx(:)
      real(rp) :: nw, nw2, var, df, tr, kd, err, m0, m2
      integer :: n, i, nup
      character(len=:), allocatable :: lbl
      lbl = ' ('//trim(paddle_names(paddle))//')'
      call jonswap_paddle_signal(hs, tp, gam, d, g, paddle, 12345, dur, dt, t, x, eta, nw)
      n = size(t)
      call check(mod(n, 2) == 0 .and. size(x) == n .and. size(eta) == n, 'signal length even, arrays agree'//lbl)
      call check_close(n*dt, dur, 1.0e-12_rp, 'record length n dt = duration'//lbl)
      call check(same(t(1), 0.0_rp) .and. abs(t(n) - (n - 1)*dt) < 1.0e-9_rp, 't(j) = (j-1) dt'//lbl)
      var = sum((eta - sum(eta)/n)**2)/n
      call check_close(4.0_rp*sqrt(var), hs, 1.0e-9_rp, '4 sqrt(variance of eta) = hs'//lbl)
      call check_close(signal_hm0(eta, dt), hs, 1.0e-9_rp, 'signal_hm0(eta) = hs'//lbl)
      df = 1.0_rp/(n*dt)
      call check(abs(signal_peak_frequency(eta, dt) - 1.0_rp/tp) <= df, 'spectral peak within one bin of 1/tp'//lbl)
      call check(abs(signal_peak_frequency(eta, dt, nsmooth=5) - 1.0_rp/tp) <= df, &
                 'smoothed spectral peak within one bin of 1/tp'//lbl)
      call check(abs(sum(x)/n) < 1.0e-12_rp*maxval(abs(x)), 'paddle stroke has zero mean'//lbl)
      ! nwaves = duration / Tm02, against m2/m0 of the periodogram and the zero up-crossings
      call signal_periodogram(eta, dt, f, s)
      m0 = sum(s)*df
      m2 = sum(f*f*s)*df
      call check_close(nw, dur*sqrt(m2/m0), 1.0e-9_rp, 'nwaves = duration / Tm02 of the record'//lbl)
      nup = count(eta(1:n - 1) < 0.0_rp .and. eta(2:n) >= 0.0_rp)
      call check_close(real(nup, rp), nw, 0.1_rp, 'zero up-crossings = nwaves within 10 %'//lbl)
      call check(nw > dur/tp .and. nw < 1.5_rp*dur/tp, 'Tm02 between tp/1.5 and tp'//lbl)
      ! paddle stroke per component: x_k = -i eta_k / T(k d)
      allocate (ce(0:n/2), cx(0:n/2))
      call fft_r2c(eta, ce)
      call fft_r2c(x, cx)
      err = 0.0_rp
      do i = 1, n/2 - 1
         kd = wave_number(2.0_rp*pi*i*df, d, g)*d
         if (paddle == paddle_piston) then
            tr = piston_transfer(kd)
         else
            tr = flap_transfer(kd)
         end if
         err = max(err, abs(cx(i)*tr - cmplx(0.0_rp, -1.0_rp, rp)*ce(i)))
      end do
      call check(err < 1.0e-9_rp*maxval(abs(ce)), 'stroke spectrum = -i eta spectrum / (H/S) per bin'//lbl)
      call check(abs(ce(nint(0.4_rp/(tp*df)))) < 1.0e-12_rp*maxval(abs(ce)) .and. &
                 abs(ce(nint(3.1_rp/(tp*df)))) < 1.0e-12_rp*maxval(abs(ce)), &
                 'no energy outside [0.5, 3] fp'//lbl)
      ! reproducible with the same seed, different with another
      call jonswap_paddle_signal(hs, tp, gam, d, g, paddle, 12345, dur, dt, t2, x2, eta2, nw2)
      call check(all(same(eta2, eta)) .and. all(same(x2, x)) .and. same(nw2, nw), &
                 'same seed gives the same signal bit for bit'//lbl)
      call jonswap_paddle_signal(hs, tp, gam, d, g, paddle, 12346, dur, dt, t2, x2, eta2, nw2)
      call check(maxval(abs(eta2 - eta)) > 0.5_rp*hs, 'another seed gives another signal'//lbl)
      call check_close(signal_hm0(eta2, dt), hs, 1.0e-9_rp, 'another seed: same Hm0'//lbl)
   end subroutine test_synthesis

   !> Hermite interpolation: exact at the samples, exact for a linear signal
   !> on uneven samples, velocity of a sine sampled 50 times a period within
   !> 1 % of its amplitude a w; zero before the start, held after the end.
   subroutine test_signal_eval()
      type(signal_t) :: sig
      integer :: i, n
      real(rp) :: x, u, t, err_x, err_u, w, a
      n = 11
      allocate (sig%t(n), sig%x(n))
      do i = 1, n
         sig%t(i) = 0.5_rp + 0.1_rp*(i - 1) + 0.03_rp*sin(1.7_rp*i)   ! uneven spacing
         sig%x(i) = 0.2_rp - 0.35_rp*sig%t(i)
      end do
      err_x = 0.0_rp
      err_u = 0.0_rp
      do i = 0, 200
         t = sig%t(1) + (sig%t(n) - sig%t(1))*i/200.0_rp
         if (i == 200) t = t - 1.0e-12_rp
         call signal_eval(sig, t, x, u)
         err_x = max(err_x, abs(x - (0.2_rp - 0.35_rp*t)))
         err_u = max(err_u, abs(u + 0.35_rp))
      end do
      call check(err_x < 1.0e-14_rp .and. err_u < 1.0e-12_rp, 'linear signal reproduced exactly (x and u)')
      call signal_eval(sig, sig%t(1) - 0.1_rp, x, u)
      call check(same(x, 0.0_rp) .and. same(u, 0.0_rp), 'zero before the start')
      call signal_eval(sig, sig%t(n) + 3.0_rp, x, u)
      call check(same(x, sig%x(n)) .and. same(u, 0.0_rp), 'last value held after the end, zero velocity')
      deallocate (sig%t, sig%x)
      ! a sine, 50 samples a period, two periods
      n = 101
      a = 0.05_rp
      w = 2.0_rp*pi/1.3_rp
      allocate (sig%t(n), sig%x(n))
      do i = 1, n
         sig%t(i) = (i - 1)*1.3_rp/50.0_rp
         sig%x(i) = a*sin(w*sig%t(i))
      end do
      err_x = 0.0_rp
      do i = 1, n
         call signal_eval(sig, sig%t(i), x, u)
         err_x = max(err_x, abs(x - sig%x(i)))
      end do
      call check(same(err_x, 0.0_rp), 'exact at the samples')
      err_u = 0.0_rp
      do i = 0, 1999
         t = sig%t(n)*i/2000.0_rp
         call signal_eval(sig, t, x, u)
         err_u = max(err_u, abs(u - a*w*cos(w*t)))
      end do
      call check(err_u < 0.01_rp*a*w, 'velocity of a sampled sine within 1 % of a w (50 samples a period)')
   end subroutine test_signal_eval

   !> A small file with comments, a blank line, commas and an inline comment.
   subroutine test_signal_read()
      type(signal_t) :: sig
      integer :: u
      character(len=*), parameter :: file = 'test_waves_signal.txt'
      real(rp) :: x, v
      open (newunit=u, file=file, status='replace', action='write')
      write (u, '(a)') '# paddle signal: time [s], displacement [m]'
      write (u, '(a)') '0.0   0.0'
      write (u, '(a)') ''
      write (u, '(a)') '  # a comment line'
      write (u, '(a)') '0.5, 0.01'
      write (u, '(a)') '1.0   0.03   # inline comment'
      write (u, '(a)') '1.5   -2.5e-2'
      close (u)
      call signal_read(file, 'wavemaker', sig)
      call check(size(sig%t) == 4 .and. size(sig%x) == 4, 'signal_read: 4 samples')
      call check(all(same(sig%t, [0.0_rp, 0.5_rp, 1.0_rp, 1.5_rp])), 'signal_read: times')
      call check(all(same(sig%x, [0.0_rp, 0.01_rp, 0.03_rp, -2.5e-2_rp])), 'signal_read: displacements')
      call signal_eval(sig, 1.0_rp, x, v)
      call check(same(x, 0.03_rp), 'signal_read then signal_eval at a sample')
      open (newunit=u, file=file, status='old', action='read')
      close (u, status='delete')
   end subroutine test_signal_read

   !> a and b hold the same number (an exact comparison without -Wcompare-reals).
   elemental function same(a, b) result(r)
      real(rp), intent(in) :: a, b
      logical :: r
      r = .not. (a < b .or. a > b)
   end function same

   !> A regular wave with a duration: the paddle starts and ends at rest, its
   !> velocity is the derivative of its displacement (centred differences)
   !> through both ramps, and it rests at X = 0 after the end.
   subroutine test_paddle_end()
      type(paddle_t) :: pad
      real(rp) :: t, x, u, xa, ua, xb, ub, worst, e
      integer :: i
      pad%on = .true.
      pad%wave = wave_regular
      pad%t_start = 0.5_rp
      pad%omega = 2.0_rp*pi
      pad%amp1 = 0.02_rp
      pad%eta1 = 0.01_rp
      pad%t_ramp = 1.0_rp
      pad%t_stop = 4.3_rp
      worst = 0.0_rp
      e = 1.0e-6_rp
      do i = 1, 599
         t = 0.5_rp + 4.3_rp*i/600.0_rp
         call paddle_motion(pad, t - e, xa, ua)
         call paddle_motion(pad, t + e, xb, ub)
         call paddle_motion(pad, t, x, u)
         worst = max(worst, abs((xb - xa)/(2.0_rp*e) - u))
      end do
      call check(worst < 1.0e-6_rp, 'paddle velocity = dX/dt through the ramps up and down')
      call paddle_motion(pad, 0.5_rp + 4.3_rp - 1.0e-4_rp, x, u)
      call check(abs(x) < 1.0e-8_rp .and. abs(u) < 1.0e-4_rp, 'paddle comes to rest at the end of its wave')
      call paddle_motion(pad, 6.0_rp, x, u)
      call check(same(x, 0.0_rp) .and. same(u, 0.0_rp), 'paddle rests at X = 0 after its wave')
      call check(same(paddle_target_eta(pad, 6.0_rp), 0.0_rp), 'no target elevation after the wave')
      ! the target elevation is in phase with the paddle velocity, of amplitude H/2
      call paddle_motion(pad, 0.5_rp + 2.0_rp, x, u)
      call check_close(paddle_target_eta(pad, 0.5_rp + 2.0_rp), 0.01_rp, 1.0e-12_rp, &
                       'target elevation H/2 where the velocity peaks')
      call check_close(u, 0.02_rp*2.0_rp*pi, 1.0e-12_rp, 'paddle velocity peaks at omega X')
   end subroutine test_paddle_end

   !> The absorber: a paddle that makes no wave (before its start) and meets
   !> an elevation e held constant moves at -G e (the delayed value of a
   !> constant is the constant); its displacement grows by u dt a step; the
   !> mean level follows e over tau, and the drift term pulls back by xc/tau.
   subroutine test_absorber()
      type(paddle_t) :: pad
      real(rp), allocatable :: hist(:, :)
      real(rp) :: xc, mean, t, x, u
      integer :: k
      pad%on = .true.
      pad%wave = wave_regular
      pad%t_start = 100.0_rp
      pad%absorb = .true.
      pad%gain = 5.0_rp
      pad%tau = 2.0_rp
      pad%lag = 0.05_rp
      xc = 0.0_rp
      mean = 0.0_rp
      t = 0.0_rp
      call paddle_absorb_set(pad, t, 0.01_rp, xc, mean, hist)
      call check_close(pad%uc, -0.05_rp, 1.0e-14_rp, 'absorber: u_c = -G eta')
      call paddle_motion(pad, t + 0.001_rp, x, u)
      call check_close(x, -0.05_rp*0.001_rp, 1.0e-12_rp, 'absorber: X = X_c + (t - t_c) u_c')
      call check_close(u, -0.05_rp, 1.0e-14_rp, 'absorber: U = u_c')
      do k = 1, 100
         call paddle_absorb_advance(pad, 0.001_rp, xc, mean)
         t = t + 0.001_rp
         call paddle_absorb_set(pad, t, 0.01_rp, xc, mean, hist)
      end do
      call check_close(mean, 0.01_rp*(1.0_rp - (1.0_rp - 0.001_rp/2.0_rp)**100), 1.0e-12_rp, &
                       'absorber: the mean level relaxes over tau')
      call check(size(hist, 2) <= 52 .and. size(hist, 2) >= 50, 'absorber: history holds the last delay only')
      ! the last step: e = 0.01 - mean of the step D/c before (linear between samples), and the drift term
      call check_close(pad%uc, -5.0_rp*(0.01_rp - 0.01_rp*(1.0_rp - (1.0_rp - 0.0005_rp)**50)) - xc/2.0_rp, &
                       1.0e-12_rp, 'absorber: u_c = -G e(t - lag) - X_c / tau')
      ! a measured level rising as 0.2 t: the paddle reads it D/c late
      deallocate (hist)
      pad%tau = 1.0e12_rp
      xc = 0.0_rp
      mean = 0.0_rp
      do k = 0, 200
         t = 0.0007_rp*k
         call paddle_absorb_set(pad, t, 0.2_rp*t, xc, mean, hist)
      end do
      call check_close(pad%uc, -5.0_rp*0.2_rp*(t - 0.05_rp), 1.0e-10_rp, 'absorber: the elevation is read lag late')
      ! an active paddle in still water: its own wave at the gauge, the target
      ! delay late and its near field a quarter period late, is taken for a
      ! wave coming in, and pushes
      deallocate (hist)
      pad%t_start = 0.0_rp
      pad%omega = 2.0_rp*pi
      pad%omega_abs = 2.0_rp*pi
      pad%eta1 = 0.01_rp
      pad%t_ramp = 0.0_rp
      pad%lag = 0.0_rp
      pad%delay = 0.1_rp
      pad%near = 0.2_rp
      t = 1.3_rp
      call paddle_absorb_set(pad, t, 0.0_rp, 0.0_rp, 0.0_rp, hist)
      call check_close(pad%uc, 5.0_rp*0.01_rp*(cos(2.0_rp*pi*(t - 0.1_rp)) + 0.2_rp*cos(2.0_rp*pi*(t - 0.25_rp))), &
                       1.0e-12_rp, 'absorber: the own wave is the target delay late and its near field T/4 late')
   end subroutine test_absorber

   !> The modes of a paddle's flow (Havelock): the evanescent wave numbers
   !> solve omega^2 = -g kappa tan(kappa d) (the first 100 to 1e-9); the modes together give back the
   !> face's velocity profile (piston 1, flap (z + d)/d) inside the water to
   !> 2e-3 with 4000 modes; the progressive mode's elevation is Biesel's.
   subroutine test_paddle_modes(flap)
      logical, intent(in) :: flap
      real(rp), parameter :: d = 0.25_rp
      real(rp) :: w, k, c0, kn, cn, z, u, worst_root, worst_u, p0
      integer :: n, iz
      logical :: bracketed
      character(len=:), allocatable :: what
      what = 'paddle modes ('//trim(merge('flap  ', 'piston', flap))//'): '
      w = sqrt(g*(1.2_rp/d)*tanh(1.2_rp))
      call paddle_mode(flap, 0, w, d, g, k, c0)
      p0 = w/(g*k)*c0*cosh(k*d)
      if (flap) then
         call check_close(p0, flap_transfer(k*d)/w, 1.0e-12_rp, what//'progressive elevation = (H/S) / omega')
      else
         call check_close(p0, piston_transfer(k*d)/w, 1.0e-12_rp, what//'progressive elevation = (H/S) / omega')
      end if
      worst_root = 0.0_rp
      worst_u = 0.0_rp
      bracketed = .true.
      do iz = 1, 3
         z = -0.25_rp*iz*d
         u = c0*cosh(k*(z + d))
         do n = 1, 4000
            call paddle_mode(flap, n, w, d, g, kn, cn)
            if (iz == 1 .and. n <= 100) then
               worst_root = max(worst_root, abs(w*w + g*kn*tan(kn*d))/(w*w))
               bracketed = bracketed .and. kn*d > (n - 0.5_rp)*pi .and. kn*d < n*pi
            end if
            u = u + cn*cos(kn*(z + d))
         end do
         worst_u = max(worst_u, abs(u - merge((z + d)/d, 1.0_rp, flap)))
      end do
      call check(worst_root < 1.0e-9_rp, what//'evanescent roots to 1e-9')
      call check(bracketed, what//'kappa_n d in ((n - 1/2) pi, n pi)')
      call check(worst_u < 2.0e-3_rp, what//'the modes give back the face velocity to 2e-3')
   end subroutine test_paddle_modes

   !> The tuned absorber's limits: far from the face (no evanescent modes
   !> left) and with slow filters (tau -> infinity) the gain is Biesel's
   !> omega / (H/S) and the wave coming in is read x_g / c late; near the
   !> face the evanescent modes, a quarter period out of phase, are seen.
   subroutine test_absorber_tune()
      type(paddle_t) :: pad
      real(rp), parameter :: d = 0.25_rp
      real(rp) :: w, k
      w = sqrt(g*(1.2_rp/d)*tanh(1.2_rp))
      k = 1.2_rp/d
      pad%depth = d
      pad%omega_abs = w
      pad%tau = 1.0e12_rp
      call paddle_absorb_tune(pad, g, 5.0_rp*d)
      call check_close(pad%gain, w/piston_transfer(1.2_rp), 1.0e-6_rp, 'absorber tune: far, slow: G = omega / (H/S)')
      call check_close(pad%lag, 5.0_rp*d*k/w, 1.0e-6_rp, 'absorber tune: far, slow: lag = x_g / c')
      call check_close(pad%delay, 5.0_rp*d*k/w, 1.0e-12_rp, 'absorber tune: own wave delay = x_g / c')
      call check(abs(pad%near) < 1.0e-6_rp, 'absorber tune: far: no near field')
      ! slow filters of 5 T lead by 2 atan(1 / (10 pi)): read that much later
      pad%tau = 5.0_rp*2.0_rp*pi/w
      call paddle_absorb_tune(pad, g, 5.0_rp*d)
      call check_close(pad%lag, (5.0_rp*d*k + 2.0_rp*atan(0.1_rp/pi))/w, 1.0e-6_rp, &
                       'absorber tune: filters of 5 T: lag = x_g / c + 2 atan(1 / (10 pi)) / omega')
      ! at 0.34 d the piston's evanescent modes are about 3 % of its wave, in quadrature
      call paddle_absorb_tune(pad, g, 0.084_rp)
      call check(pad%near > 0.02_rp .and. pad%near < 0.05_rp, 'absorber tune: near the face: 2 to 5 % near field')
   end subroutine test_absorber_tune
end program test_waves

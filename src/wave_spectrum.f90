!> Irregular waves: the JONSWAP spectrum (Goda's form), a reproducible random
!> number stream for the phases, synthesis of the target free surface and of
!> the paddle displacement by inverse FFT, and the spectral height and peak
!> of a sampled record.
module wave_spectrum
   use, intrinsic :: iso_fortran_env, only: int64
   use kinds, only: rp
   use constants, only: pi
   use errors, only: fatal, alloc_check
   use input_check, only: real_str, int_str
   use options, only: paddle_piston, paddle_flap
   use wave_theory, only: wave_number, piston_transfer, flap_transfer
   use wave_fftw, only: fft_c2r, fft_r2c
   implicit none
   private
   public :: jonswap, jonswap_paddle_signal, signal_hm0, signal_peak_frequency, signal_periodogram
   public :: rng_t, rng_seed, rng_uniform

   !> State of a xoshiro128** stream (Blackman and Vigna 2018): four 32-bit
   !> words, each held in the low half of a 64-bit integer so that no
   !> operation overflows a signed integer (products stay below 2**49).
   type :: rng_t
      integer(int64) :: s(4) = 0_int64
   end type rng_t

   integer(int64), parameter :: mask32 = 4294967295_int64   !< 2**32 - 1
   integer(int64), parameter :: mask16 = 65535_int64

contains

   ! ------------------------------------------------------------------ spectrum

   !> JONSWAP spectral density S(f) [m^2 s] in Goda's form, for significant
   !> height hs [m], peak period tp [s] and peak enhancement gamma:
   !>   S = bJ hs^2 tp^-4 f^-5 exp(-1.25 (tp f)^-4) gamma^exp(-(tp f - 1)^2 / (2 s^2)),
   !>   bJ = 0.0624 / (0.230 + 0.0336 gamma - 0.185 / (1.9 + gamma)) (1.094 - 0.01915 ln gamma),
   !> s = 0.07 for f <= 1/tp and 0.09 above. Its 4 sqrt(m0) is not exactly hs
   !> (about 1.034 hs at gamma = 3.3): jonswap_paddle_signal renormalises.
   !> S = 0 for tp f < 0.25, where the exponential is below 1e-139.
   elemental function jonswap(f, hs, tp, gamma) result(s)
      real(rp), intent(in) :: f, hs, tp, gamma
      real(rp) :: s
      real(rp) :: bj, x, sig, e
      x = tp*f
      if (x < 0.25_rp) then
         s = 0.0_rp
         return
      end if
      bj = 0.0624_rp/(0.230_rp + 0.0336_rp*gamma - 0.185_rp/(1.9_rp + gamma))*(1.094_rp - 0.01915_rp*log(gamma))
      sig = merge(0.07_rp, 0.09_rp, x <= 1.0_rp)
      e = (x - 1.0_rp)**2/(2.0_rp*sig*sig)
      s = bj*hs*hs*tp*x**(-5)*exp(-1.25_rp/x**4)
      ! far from the peak gamma^exp(-e) = 1 to 1e-300; skipping it avoids an exp underflow
      if (e < 690.0_rp) s = s*gamma**exp(-e)
   end function jonswap

   !> Target free surface eta(t) at the paddle and paddle displacement x(t)
   !> for a JONSWAP sea, by random-phase synthesis on the FFT grid:
   !> - n = 2 nint(duration / (2 dt)) samples (even), t(j) = (j - 1) dt for
   !>   j = 1..n (arrays are 1-based); the record has period n dt, which is
   !>   the duration actually used (duration rounded to an even number of dt);
   !> - components f_i = i / (n dt) with f_lo fp <= f_i <= f_hi fp (defaults
   !>   0.5 and 3.0), fp = 1/tp; amplitude a_i = sqrt(2 S(f_i) df) with
   !>   df = 1/(n dt), all scaled so that 4 sqrt(sum a_i^2 / 2) = hs exactly;
   !> - phases phi_i uniform in [0, 2 pi) from rng_seed(seed), drawn in order
   !>   of increasing frequency: the same seed gives the same signal bit for
   !>   bit on any machine with IEEE doubles and the same FFTW;
   !> - eta(t) = sum a_i cos(w_i t + phi_i), the linear wave leaving the
   !>   paddle; x(t) = sum (a_i / T_i) sin(w_i t + phi_i) with T_i the piston
   !>   or flap transfer function H/S at k_i d (paddle = 'piston' or 'flap';
   !>   for a flap, x is the displacement at the still-water level), which is
   !>   the regular-wave convention of wave_theory applied per component;
   !>   both series have zero mean;
   !> - nwaves = (n dt) / Tm02, Tm02 = sqrt(m0 / m2) of the discrete spectrum:
   !>   the expected number of zero up-crossings in the record.
   !> First-order only: no second-order correction of the irregular signal.
   ! allow(too-many-arguments): the argument list is the API agreed with the solver integration
   subroutine jonswap_paddle_signal(hs, tp, gamma, depth, g, paddle, seed, duration, dt, t, x, eta, nwaves, f_lo, f_hi)
      real(rp), intent(in) :: hs, tp, gamma, depth, g
      integer, intent(in) :: paddle           !< paddle_piston or paddle_flap (options)
      integer, intent(in) :: seed
      real(rp), intent(in) :: duration, dt
      real(rp), allocatable, intent(out) :: t(:), x(:), eta(:)
      real(rp), intent(out) :: nwaves
      real(rp), intent(in), optional :: f_lo, f_hi
      real(rp) :: flo, fhi, df, m0, m2, phi
      complex(rp), allocatable :: spec_eta(:), spec_x(:)
      real(rp), allocatable :: amp(:), tra(:)
      type(rng_t) :: rng
      integer :: n, i, j
      logical :: piston
      integer :: ist
      character(len=200) :: emsg

      flo = 0.5_rp
      fhi = 3.0_rp
      if (present(f_lo)) flo = f_lo
      if (present(f_hi)) fhi = f_hi
      call check_signal_args(hs, tp, gamma, depth, g, paddle, dt, flo, fhi, piston)
      n = 2*max(1, nint(duration/(2.0_rp*dt)))
      df = 1.0_rp/(n*dt)
      call component_amplitudes(n, df, hs, tp, gamma, depth, g, piston, flo, fhi, amp, tra)
      m0 = 0.5_rp*sum(amp**2)
      m2 = 0.0_rp
      do i = 1, n/2 - 1
         m2 = m2 + 0.5_rp*amp(i)**2*(i*df)**2
      end do
      nwaves = n*dt*sqrt(m2/m0)

      ! x(j) = sum_k c_k exp(2 pi i jk/n) + c.c. with c_k = a/2 e^{i phi} gives a cos(w t + phi);
      ! sin(w t + phi) = cos(w t + phi - pi/2) multiplies c_k by -i
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (spec_eta(0:n/2), spec_x(0:n/2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'spec_eta, spec_x in jonswap_paddle_signal')
      spec_eta = (0.0_rp, 0.0_rp)
      spec_x = (0.0_rp, 0.0_rp)
      call rng_seed(rng, seed)
      do i = 1, n/2 - 1
         if (amp(i) <= 0.0_rp) cycle
         phi = 2.0_rp*pi*rng_uniform(rng)
         spec_eta(i) = 0.5_rp*amp(i)*cmplx(cos(phi), sin(phi), rp)
         spec_x(i) = 0.5_rp*amp(i)/tra(i)*cmplx(sin(phi), -cos(phi), rp)
      end do
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (t(n), x(n), eta(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 't, x, eta in jonswap_paddle_signal')
      call fft_c2r(spec_eta, eta)
      call fft_c2r(spec_x, x)
      t = [((j - 1)*dt, j=1, n)]
   end subroutine jonswap_paddle_signal

   !> Stop on arguments jonswap_paddle_signal cannot use (the solver checks its
   !> input first; this guards other callers); piston = .true. for a piston.
   subroutine check_signal_args(hs, tp, gamma, depth, g, paddle, dt, flo, fhi, piston)
      real(rp), intent(in) :: hs, tp, gamma, depth, g, dt, flo, fhi
      integer, intent(in) :: paddle
      logical, intent(out) :: piston
      select case (paddle)
      case (paddle_piston)
         piston = .true.
      case (paddle_flap)
         piston = .false.
      case default
         piston = .true.
         call fatal('jonswap_paddle_signal: paddle must be paddle_piston or paddle_flap, not '//int_str(paddle))
      end select
      if (.not. (hs > 0.0_rp .and. tp > 0.0_rp .and. gamma >= 1.0_rp .and. depth > 0.0_rp .and. g > 0.0_rp &
                 .and. dt > 0.0_rp .and. flo >= 0.0_rp .and. fhi > flo)) then
         call fatal('jonswap_paddle_signal: need hs, tp, depth, g, dt > 0, gamma >= 1 and 0 <= f_lo < f_hi')
      end if
      if (fhi/tp >= 0.5_rp/dt) then
         call fatal('jonswap_paddle_signal: f_hi/tp = '//real_str(fhi/tp)//' Hz is not below the Nyquist frequency '// &
                    real_str(0.5_rp/dt)//' Hz of dt')
      end if
   end subroutine check_signal_args

   !> Amplitudes amp(i) of the components i = 1..n/2-1 (frequency i df) in the
   !> band [flo, fhi]/tp, scaled to 4 sqrt(sum amp^2 / 2) = hs, and the
   !> paddle transfer function tra(i) = H/S at each (1 outside the band).
   subroutine component_amplitudes(n, df, hs, tp, gamma, depth, g, piston, flo, fhi, amp, tra)
      integer, intent(in) :: n
      real(rp), intent(in) :: df, hs, tp, gamma, depth, g, flo, fhi
      logical, intent(in) :: piston
      real(rp), allocatable, intent(out) :: amp(:), tra(:)
      real(rp) :: f, kd
      integer :: i
      integer :: ist
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (amp(n/2 - 1), tra(n/2 - 1), stat=ist, errmsg=emsg)
      if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
         call alloc_check(ist, emsg, 'amp, tra in component_amplitudes')
         error stop
      end if
      amp = 0.0_rp
      tra = 1.0_rp
      do i = 1, n/2 - 1
         f = i*df
         if (f*tp < flo .or. f*tp > fhi) cycle
         amp(i) = sqrt(2.0_rp*jonswap(f, hs, tp, gamma)*df)
         kd = wave_number(2.0_rp*pi*f, depth, g)*depth
         if (piston) then
            tra(i) = piston_transfer(kd)
         else
            tra(i) = flap_transfer(kd)
         end if
      end do
      if (.not. any(amp > 0.0_rp)) then
         call fatal('jonswap_paddle_signal: no frequency of the record (df = '//real_str(df)// &
                    ' Hz) lies in the band; make the duration longer')
      end if
      amp = hs/(4.0_rp*sqrt(0.5_rp*sum(amp**2)))*amp
   end subroutine component_amplitudes

   ! ------------------------------------------------------------------ analysis

   !> One-sided periodogram of a record eta(1:n) sampled at dt [s]: f(k) = k df
   !> and s(k) [m^2 s] for k = 1..n/2 (the mean, k = 0, is left out), with
   !> df = 1/(n dt) and sum(s) df = variance of eta.
   subroutine signal_periodogram(eta, dt, f, s)
      real(rp), intent(in) :: eta(:), dt
      real(rp), allocatable, intent(out) :: f(:), s(:)
      complex(rp), allocatable :: c(:)
      real(rp) :: df
      integer :: n, k
      integer :: ist
      character(len=200) :: emsg
      n = size(eta)
      if (n < 2) call fatal('signal_periodogram: need at least 2 samples')
      ! f and s each by itself: their bounds are then set whatever becomes of
      ! another allocation (the optimiser cannot tell that alloc_check does not
      ! return from a refusal)
      allocate (f(n/2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'f in signal_periodogram')
      allocate (s(n/2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 's in signal_periodogram')
      allocate (c(0:n/2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'c in signal_periodogram')
      call fft_r2c(eta, c)
      df = 1.0_rp/(n*dt)
      do k = 1, n/2
         f(k) = k*df
         ! |c_k|^2 / n^2 is the power of bin k; bins k and n-k are folded, except the Nyquist bin
         s(k) = 2.0_rp*abs(c(k))**2/(real(n, rp)**2*df)
      end do
      if (mod(n, 2) == 0 .and. n >= 2) s(n/2) = 0.5_rp*s(n/2)
   end subroutine signal_periodogram

   !> Spectral significant wave height Hm0 = 4 sqrt(m0) [m] of a record
   !> sampled at dt [s], m0 from the periodogram (the mean is removed).
   function signal_hm0(eta, dt) result(hm0)
      real(rp), intent(in) :: eta(:), dt
      real(rp) :: hm0
      real(rp), allocatable :: f(:), s(:)
      call signal_periodogram(eta, dt, f, s)
      hm0 = 4.0_rp*sqrt(sum(s)*f(1))
   end function signal_hm0

   !> Frequency [Hz] of the largest periodogram value of a record sampled at
   !> dt [s]. nsmooth (odd, default 1 = none) smooths the periodogram with a
   !> running mean over that many bins first, as a noisy measured record needs.
   function signal_peak_frequency(eta, dt, nsmooth) result(fpk)
      real(rp), intent(in) :: eta(:), dt
      integer, intent(in), optional :: nsmooth
      real(rp) :: fpk
      real(rp), allocatable :: f(:), s(:), sm(:)
      integer :: h, k, m
      integer :: ist
      character(len=200) :: emsg
      call signal_periodogram(eta, dt, f, s)
      h = 0
      if (present(nsmooth)) h = max(0, nsmooth/2)
      m = size(s)
      allocate (sm(m), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'sm in signal_peak_frequency')
      do k = 1, m
         sm(k) = sum(s(max(1, k - h):min(m, k + h)))/(min(m, k + h) - max(1, k - h) + 1)
      end do
      fpk = f(maxloc(sm, 1))
   end function signal_peak_frequency

   ! ------------------------------------------------------------------ random numbers

   !> a*b mod 2**32 for 0 <= a, b < 2**32, without signed overflow: b is split
   !> into 16-bit halves so every product is below 2**48.
   elemental function mul32(a, b) result(c)
      integer(int64), intent(in) :: a, b
      integer(int64) :: c
      c = iand(a*iand(b, mask16) + ishft(iand(a*ishft(b, -16), mask16), 16), mask32)
   end function mul32

   !> 32-bit left rotation of 0 <= x < 2**32 by k bits.
   elemental function rotl32(x, k) result(r)
      integer(int64), intent(in) :: x
      integer, intent(in) :: k
      integer(int64) :: r
      r = ior(iand(ishft(x, k), mask32), ishft(x, k - 32))
   end function rotl32

   !> The 32-bit finaliser of MurmurHash3 (a bijection of [0, 2**32) that
   !> mixes every input bit into every output bit).
   elemental function fmix32(x0) result(x)
      integer(int64), intent(in) :: x0
      integer(int64) :: x
      x = ieor(x0, ishft(x0, -16))
      x = mul32(x, int(z'85EBCA6B', int64))
      x = ieor(x, ishft(x, -13))
      x = mul32(x, int(z'C2B2AE35', int64))
      x = ieor(x, ishft(x, -16))
   end function fmix32

   !> Start a stream from an integer seed: the four state words are fmix32 of
   !> the low 32 bits of seed plus 1..4 times 0x9E3779B9 (mod 2**32). These
   !> are distinct, so at most one word is zero and the state never is.
   subroutine rng_seed(rng, seed)
      type(rng_t), intent(out) :: rng
      integer, intent(in) :: seed
      integer(int64) :: z
      integer :: i
      z = iand(int(seed, int64), mask32)
      do i = 1, 4
         z = iand(z + int(z'9E3779B9', int64), mask32)
         rng%s(i) = fmix32(z)
      end do
   end subroutine rng_seed

   !> Next 32-bit output of xoshiro128**, as an integer in [0, 2**32).
   function rng_next32(rng) result(r)
      type(rng_t), intent(inout) :: rng
      integer(int64) :: r, tt
      r = mul32(rotl32(mul32(rng%s(2), 5_int64), 7), 9_int64)
      tt = iand(ishft(rng%s(2), 9), mask32)
      rng%s(3) = ieor(rng%s(3), rng%s(1))
      rng%s(4) = ieor(rng%s(4), rng%s(2))
      rng%s(2) = ieor(rng%s(2), rng%s(3))
      rng%s(1) = ieor(rng%s(1), rng%s(4))
      rng%s(3) = ieor(rng%s(3), tt)
      rng%s(4) = rotl32(rng%s(4), 11)
   end function rng_next32

   !> Uniform double in [0, 1) with 53 random bits, from two 32-bit outputs
   !> (27 and 26 high bits), exactly as genrand_res53 of the Mersenne Twister.
   function rng_uniform(rng) result(u)
      type(rng_t), intent(inout) :: rng
      real(rp) :: u
      integer(int64) :: a, b
      a = ishft(rng_next32(rng), -5)
      b = ishft(rng_next32(rng), -6)
      u = real(a*67108864_int64 + b, rp)/9007199254740992.0_rp
   end function rng_uniform
end module wave_spectrum

!> Linear and second-order wavemaker theory: dispersion, the Biesel transfer
!> functions of piston and flap paddles, Madsen's second-order piston
!> correction, the Miche breaking limit and the start-up ramp.
!>
!> Every hyperbolic function is written in a form that neither overflows in
!> deep water (kd of several hundred) nor loses precision in shallow water
!> (kd -> 0), so that the debug build's overflow and invalid traps never fire.
module wave_theory
   use kinds, only: rp
   use constants, only: pi
   implicit none
   private
   public :: wave_number, piston_transfer, flap_transfer, piston_second_order, miche_limit, ramp, ramp_rate, paddle_mode

   !> above this kd, exp(-2 kd) terms are below 1e-34 relative: dropped
   real(rp), parameter :: kd_deep = 40.0_rp

contains

   !> Wave number k [1/m] of a linear wave of angular frequency omega [rad/s]
   !> in water of depth depth [m] under gravity g [m/s^2]: the root of
   !> omega^2 = g k tanh(k d). Newton iteration on x = k d, started from
   !> Eckart's approximation x0 = y / sqrt(tanh y), y = omega^2 d / g (within
   !> 5 % everywhere, exact in both limits), to 1e-14 relative.
   !> omega <= 0 gives k = 0. Requires depth > 0 and g > 0.
   pure function wave_number(omega, depth, g) result(k)
      real(rp), intent(in) :: omega, depth, g
      real(rp) :: k
      real(rp) :: y, x, t, dx
      integer :: it
      k = 0.0_rp
      if (omega <= 0.0_rp) return
      y = omega*omega*depth/g
      x = y/sqrt(tanh(y))
      do it = 1, 50
         t = tanh(x)
         ! d/dx (x tanh x) = tanh x + x sech^2 x, with sech^2 = 1 - tanh^2 (no cosh to overflow)
         dx = (x*t - y)/(t + x*(1.0_rp - t*t))
         x = x - dx
         if (abs(dx) <= 1.0e-14_rp*x) exit
      end do
      k = x/depth
   end function wave_number

   !> 2x / sinh(2x), for x >= 0: 1 at x = 0, exponentially small in deep water.
   pure function q_ratio(x) result(q)
      real(rp), intent(in) :: x
      real(rp) :: q
      if (x < 1.0e-8_rp) then
         q = 1.0_rp
      else if (x > kd_deep) then
         q = 0.0_rp
      else
         q = 2.0_rp*x/sinh(2.0_rp*x)
      end if
   end function q_ratio

   !> Biesel's piston transfer function H/S (wave height over full paddle
   !> stroke), H/S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd), evaluated as
   !> 2 tanh(kd) / (1 + 2kd/sinh 2kd). Limits: kd in shallow water, 2 in deep.
   pure function piston_transfer(kd) result(hs)
      real(rp), intent(in) :: kd
      real(rp) :: hs
      hs = 2.0_rp*tanh(kd)/(1.0_rp + q_ratio(kd))
   end function piston_transfer

   !> Biesel's transfer function H/S of a flap hinged at the bed, S being the
   !> full stroke at the still-water level:
   !> H/S = 4 (sinh kd / kd) (kd sinh kd - cosh kd + 1) / (sinh 2kd + 2kd),
   !> evaluated as 2 (kd tanh kd - (1 - sech kd)) / (kd (1 + 2kd/sinh 2kd)).
   !> Limits: kd/2 in shallow water, 2 in deep water (there only the top of
   !> the flap moves water, and it moves like a piston).
   pure function flap_transfer(kd) result(hs)
      real(rp), intent(in) :: kd
      real(rp) :: hs
      real(rp) :: c
      if (kd < 1.0e-8_rp) then
         hs = 0.5_rp*kd
         return
      end if
      ! c = 1 - sech(kd); for small kd as 2 sinh^2(kd/2) / cosh kd, free of cancellation
      if (kd <= 1.0_rp) then
         c = 2.0_rp*sinh(0.5_rp*kd)**2/cosh(kd)
      else if (kd > 700.0_rp) then
         c = 1.0_rp
      else
         c = 1.0_rp - 1.0_rp/cosh(kd)
      end if
      hs = 2.0_rp*(kd*tanh(kd) - c)/(kd*(1.0_rp + q_ratio(kd)))
   end function flap_transfer

   !> Mode n of the flow a paddle makes in water of depth d (Havelock 1929):
   !> n = 0 the progressive wave, kn = k of wave_number; n >= 1 the evanescent
   !> modes, which decay as exp(-kn x), omega^2 = -g kn tan(kn d) with kn d in
   !> ((n - 1/2) pi, n pi). The face's horizontal velocity per unit velocity at
   !> the still-water level (piston 1, flap hinged at the bed (z + d)/d) is
   !> u(z) = c_0 cosh(k (z + d)) + sum_n c_n cos(kn (z + d)); the elevation of a
   !> mode per unit face velocity (time factor exp(-i omega t)) is
   !> (omega/(g k)) c_0 cosh(kd) exp(i k x), in phase with the velocity, and
   !> -i (omega/(g kn)) c_n cos(kn d) exp(-kn x), a quarter period ahead or behind.
   !> For kd below a few hundred.
   pure subroutine paddle_mode(flap, n, omega, depth, g, kn, cn)
      logical, intent(in) :: flap
      integer, intent(in) :: n
      real(rp), intent(in) :: omega, depth, g
      real(rp), intent(out) :: kn, cn
      real(rp) :: y, c, lo, hi, dl, proj, norm
      integer :: it
      if (n == 0) then
         kn = wave_number(omega, depth, g)
         y = kn*depth
         if (flap) then
            proj = (y*sinh(y) - cosh(y) + 1.0_rp)/(kn*kn*depth)
         else
            proj = sinh(y)/kn
         end if
         norm = 0.5_rp*depth + sinh(2.0_rp*y)/(4.0_rp*kn)
         cn = proj/norm
         return
      end if
      ! y = n pi - dl: (n pi - dl) tan(dl) = omega^2 d / g rises with dl on (0, pi/2)
      c = omega*omega*depth/g
      lo = 0.0_rp
      hi = 0.5_rp*pi
      do it = 1, 200
         dl = 0.5_rp*(lo + hi)
         if ((n*pi - dl)*tan(dl) > c) then
            hi = dl
         else
            lo = dl
         end if
         if (hi - lo <= 4.0_rp*epsilon(1.0_rp)*hi) exit
      end do
      y = n*pi - 0.5_rp*(lo + hi)
      kn = y/depth
      if (flap) then
         proj = (y*sin(y) + cos(y) - 1.0_rp)/(kn*kn*depth)
      else
         proj = sin(y)/kn
      end if
      norm = 0.5_rp*depth + sin(2.0_rp*y)/(4.0_rp*kn)
      cn = proj/norm
   end subroutine paddle_mode

   !> Amplitude X2 [m] of the second-harmonic paddle motion that a piston
   !> needs to make a regular wave of height h [m] without the spurious free
   !> second harmonic (Madsen 1971):
   !>   X(t) = S/2 sin(w t) + X2 sin(2 w t),
   !>   X2 = h^2 / (32 d) (3 cosh kd / sinh^3 kd - 2 / n1),  n1 = (1 + 2kd / sinh 2kd) / 2,
   !> with S = h / piston_transfer(kd). Phase convention: the paddle at x = 0
   !> moves towards +x (into the tank) with displacement X(t) as above; the
   !> wave it makes is eta(0, t) = h/2 cos(w t) + a2 cos(2 w t), the crest
   !> leaving the paddle when its velocity is largest, with a2 the bound
   !> second-order Stokes amplitude. X2 can be negative (deep water).
   !> This correction applies to the piston only; for a flap no second-order
   !> correction is provided.
   pure function piston_second_order(h, kd, depth) result(x2)
      real(rp), intent(in) :: h, kd, depth
      real(rp) :: x2
      real(rp) :: n1, b, sh
      n1 = 0.5_rp*(1.0_rp + q_ratio(kd))
      if (kd > 300.0_rp) then
         b = 0.0_rp                            ! 3 cosh/sinh^3 ~ 12 exp(-2 kd)
      else
         sh = sinh(kd)
         b = 3.0_rp/(tanh(kd)*sh*sh)           ! = 3 cosh kd / sinh^3 kd
      end if
      x2 = h*h/(32.0_rp*depth)*(b - 2.0_rp/n1)
   end function piston_second_order

   !> Miche's breaking limit: largest wave height [m] for wave number k [1/m]
   !> in depth [m], H_max = 0.142 (2 pi / k) tanh(k d).
   pure function miche_limit(k, depth) result(hmax)
      real(rp), intent(in) :: k, depth
      real(rp) :: hmax
      hmax = 0.142_rp*(2.0_rp*pi/k)*tanh(k*depth)
   end function miche_limit

   !> Smooth start of the paddle motion: 0 before t = 0,
   !> 0.5 (1 - cos(pi t / t_ramp)) during the ramp, 1 after it (and always 1
   !> when t_ramp <= 0).
   pure function ramp(t, t_ramp) result(r)
      real(rp), intent(in) :: t, t_ramp
      real(rp) :: r
      if (t >= t_ramp) then
         r = 1.0_rp
      else if (t <= 0.0_rp) then
         r = 0.0_rp
      else
         r = 0.5_rp*(1.0_rp - cos(pi*t/t_ramp))
      end if
   end function ramp

   !> Time derivative [1/s] of ramp(t, t_ramp): the paddle velocity of a
   !> ramped signal r(t) X(t) is r u + dr/dt X.
   pure function ramp_rate(t, t_ramp) result(dr)
      real(rp), intent(in) :: t, t_ramp
      real(rp) :: dr
      if (t >= t_ramp .or. t <= 0.0_rp) then
         dr = 0.0_rp
      else
         dr = 0.5_rp*pi/t_ramp*sin(pi*t/t_ramp)
      end if
   end function ramp_rate
end module wave_theory

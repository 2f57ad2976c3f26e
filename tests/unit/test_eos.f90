!> Equation of state: the Newton seventh root agrees with pow to the last place on
!> its range, the Tait pressure of the hydrostatic density is rho0 g d, and the
!> dynamic density of water at rest is zero to rounding whichever path computes it.
program test_eos
   use kinds, only: rp
   use params, only: params_t
   use eos, only: eos_update, eos_density_at_depth, eos_dynamic_density, root7, root7_max
   use testing, only: check, check_close, test_summary
   implicit none
   integer, parameter :: n = 200001, m = 101
   type(params_t) :: prm
   real(rp) :: s, worst, x(2, m), rho(m), rhod(m), p(m), cs(m), d
   integer :: i

   ! one unit in the last place of pow, over the range the solver uses it on
   worst = 0.0_rp
   do i = 0, n - 1
      s = 0.5_rp + (root7_max - 0.5_rp)*real(i, rp)/real(n - 1, rp)
      worst = max(worst, abs(root7(s) - s**(1.0_rp/7.0_rp))/s**(1.0_rp/7.0_rp))
   end do
   call check(worst <= epsilon(1.0_rp), 'root7 within one unit of the last place of pow on [0.5, 2]')

   prm%rho0 = 1000.0_rp
   prm%g = 9.81_rp
   prm%gamma = 7.0_rp
   prm%igamma = 7
   prm%c0 = 10.0_rp*sqrt(9.81_rp*0.3_rp)
   prm%b = prm%c0**2*prm%rho0/prm%gamma
   prm%y_surface = 0.3_rp
   ! a column from 0.1 m above the surface to 0.4 m below the bed's level, and one
   ! particle 3 m above it (a splash: the density of the law is held at 0.5 there)
   do i = 1, m
      x(:, i) = [0.0_rp, 0.4_rp - 0.7_rp*real(i - 1, rp)/real(m - 1, rp)]
   end do
   x(2, 1) = prm%y_surface + 3.0_rp
   do i = 1, m
      rho(i) = eos_density_at_depth(prm, prm%y_surface - x(2, i))
   end do
   call eos_update(prm, m, rho, p, cs)
   do i = 1, m
      d = prm%y_surface - x(2, i)
      if (d > 0.0_rp) call check_close(p(i), prm%rho0*prm%g*d, 1.0e-12_rp, 'Tait pressure of the hydrostatic density', 1.0e-9_rp)
   end do
   ! against the law written with pow here, the clamp at 0.5 included (the top particle)
   call check(1.0_rp + prm%rho0*prm%g*(prm%y_surface - x(2, 1))/prm%b < 0.5_rp, 'the top particle is in the clamp')
   worst = 0.0_rp
   do i = 1, m
      d = prm%y_surface - x(2, i)
      worst = max(worst, abs(rho(i) - prm%rho0*max(1.0_rp + prm%rho0*prm%g*d/prm%b, 0.5_rp)**(1.0_rp/7.0_rp))/rho(i))
   end do
   call check(worst <= 2.0_rp*epsilon(1.0_rp), 'hydrostatic density within two units of the last place of the law with pow')
   call eos_dynamic_density(prm, m, rho, x, rhod)
   ! zero to rounding: the vectorised loop may contract its products differently
   call check(maxval(abs(rhod)) <= 4.0_rp*epsilon(1.0_rp)*maxval(rho), 'dynamic density of water at rest is zero (Newton root)')

   ! a sound speed so low that the deepest particle is beyond the root's range: pow
   prm%c0 = 1.5_rp
   prm%b = prm%c0**2*prm%rho0/prm%gamma
   do i = 1, m
      rho(i) = eos_density_at_depth(prm, prm%y_surface - x(2, i))
   end do
   call check(1.0_rp + prm%rho0*prm%g*(prm%y_surface - x(2, m))/prm%b > root7_max, 'the low sound speed leaves the range')
   call eos_dynamic_density(prm, m, rho, x, rhod)
   call check(maxval(abs(rhod)) <= 4.0_rp*epsilon(1.0_rp)*maxval(rho), 'dynamic density of water at rest is zero (pow)')
   call eos_update(prm, m, rho, p, cs)
   do i = 1, m
      d = prm%y_surface - x(2, i)
      if (d > 0.0_rp) call check_close(p(i), prm%rho0*prm%g*d, 1.0e-12_rp, 'Tait pressure, low sound speed', 1.0e-9_rp)
   end do
   call test_summary('test_eos')
end program test_eos

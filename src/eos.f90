!> Tait equation of state: p = B ((rho/rho0)^gamma - 1), c = c0 (rho/rho0)^((gamma-1)/2).
module eos
   use kinds, only: rp
   use params, only: params_t
   use constants, only: ndim, iup
   implicit none
   private
   public :: eos_update, eos_density_at_depth, eos_dynamic_density, root7

   !> the top of the range where root7 is exact to the last place
   real(rp), parameter, public :: root7_max = 2.0_rp

contains

   !> Pressure and sound speed of particles 1..n.
   subroutine eos_update(prm, n, rho, p, cs)
      type(params_t), intent(in) :: prm
      integer, intent(in) :: n
      real(rp), intent(in) :: rho(:)
      real(rp), intent(out) :: p(:), cs(:)
      integer :: i
      real(rp) :: r, r3, rg, inv_rho0
      inv_rho0 = 1.0_rp/prm%rho0
      if (prm%igamma == 7) then
         ! water's gamma: (rho/rho0)^7 by four products, and c = c0 (rho/rho0)^3
         ! without the square root
         do i = 1, n
            r = rho(i)*inv_rho0
            r3 = r*r*r
            p(i) = prm%b*(r3*r3*r - 1.0_rp)
            cs(i) = prm%c0*r3
         end do
         return
      end if
      do i = 1, n
         r = rho(i)*inv_rho0
         ! another whole gamma: the power by multiplication, several times cheaper
         ! than pow (the test is the same for every particle: the compiler takes it out)
         if (prm%igamma > 0) then
            rg = r**prm%igamma
         else
            rg = r**prm%gamma
         end if
         p(i) = prm%b*(rg - 1.0_rp)
         cs(i) = prm%c0*sqrt(rg/r)
      end do
   end subroutine eos_update

   !> The dynamic part of the density of particles 1..n (Fourtakas et al. 2019):
   !> rho minus the density of water at rest at their depth below y_surface. One
   !> loop here, where the compiler sees the root and vectorises it.
   subroutine eos_dynamic_density(prm, n, rho, x, rhod)
      type(params_t), intent(in) :: prm
      integer, intent(in) :: n
      ! explicit shapes, so that the loop runs four particles at a time
      real(rp), intent(in) :: rho(n), x(ndim, n)
      real(rp), intent(out) :: rhod(n)
      integer :: i
      real(rp) :: ymin
      ymin = prm%y_surface
      do i = 1, n
         ymin = min(ymin, x(iup, i))
      end do
      if (prm%igamma == 7 .and. depth_ratio(prm, prm%y_surface - ymin) <= root7_max) then
         ! every particle in the range of the Newton root: the same numbers as
         ! eos_density_at_depth gives, without its test per particle
         do i = 1, n
            rhod(i) = rho(i) - prm%rho0*root7(depth_ratio(prm, prm%y_surface - x(iup, i)))
         end do
      else
         do i = 1, n
            rhod(i) = rho(i) - eos_density_at_depth(prm, prm%y_surface - x(iup, i))
         end do
      end if
   end subroutine eos_dynamic_density

   !> Density of water at rest at depth d below the surface (d < 0: above it).
   elemental real(rp) function eos_density_at_depth(prm, d) result(rho)
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: d
      real(rp) :: s
      s = depth_ratio(prm, d)
      if (prm%igamma == 7 .and. s <= root7_max) then
         rho = prm%rho0*root7(s)
      else
         rho = prm%rho0*s**(1.0_rp/prm%gamma)
      end if
   end function eos_density_at_depth

   !> (rho/rho0)**gamma of water at rest at depth d, kept from below at 0.5 above
   !> the surface.
   elemental real(rp) function depth_ratio(prm, d) result(s)
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: d
      s = max(1.0_rp + prm%rho0*prm%g*d/prm%b, 0.5_rp)
   end function depth_ratio

   !> s**(1/7) for s in [0.5, root7_max] by Newton's steps from a second-order
   !> start: products and divisions that vectorise, where pow does not (3 % of the
   !> dam break's step). The start is within 2e-2 on that range (8e-3 on [0.5, 1])
   !> and the error squares at each step, so four steps reach the rounding floor
   !> (within one unit of the last place of pow, checked on the range in tests/unit).
   elemental real(rp) function root7(s) result(y)
      real(rp), intent(in) :: s
      real(rp), parameter :: seventh = 1.0_rp/7.0_rp
      real(rp) :: e, y3
      integer :: k
      e = s - 1.0_rp
      y = 1.0_rp + e*seventh*(1.0_rp - 3.0_rp*seventh*e)
      do k = 1, 4
         y3 = y*y*y
         y = y - (y*y3*y3 - s)/(7.0_rp*y3*y3)
      end do
   end function root7
end module eos

!> Tait equation of state: p = B ((rho/rho0)^gamma - 1), c = c0 (rho/rho0)^((gamma-1)/2).
module eos
   use kinds, only: rp
   use params, only: params_t
   implicit none
   private
   public :: eos_update, eos_density_at_depth, eos_dynamic_density

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
   !> loop here, where the compiler sees the power and vectorises it.
   subroutine eos_dynamic_density(prm, n, rho, x, rhod)
      type(params_t), intent(in) :: prm
      integer, intent(in) :: n
      ! explicit shapes, so that the loop runs four particles at a time
      real(rp), intent(in) :: rho(n), x(2, n)
      real(rp), intent(out) :: rhod(n)
      integer :: i
      do i = 1, n
         rhod(i) = rho(i) - eos_density_at_depth(prm, prm%y_surface - x(2, i))
      end do
   end subroutine eos_dynamic_density

   !> Density of water at rest at depth d below the surface (d < 0: above it).
   elemental real(rp) function eos_density_at_depth(prm, d) result(rho)
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: d
      rho = prm%rho0*max(1.0_rp + prm%rho0*prm%g*d/prm%b, 0.5_rp)**(1.0_rp/prm%gamma)
   end function eos_density_at_depth
end module eos

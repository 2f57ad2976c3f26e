!> The modified dynamic boundary (mDBC, English et al. 2022). Every solid
!> particle with a ghost point (its mirror across the solid's face towards
!> the water, at x + gof; scene_ghosts) takes its density from the water
!> around that point, by the first-order corrected interpolation of Liu and
!> Liu (2006), extrapolated back to the particle along the density gradient:
!>
!>     rho_b = rho_g + (x_b - x_g) . grad rho_g
!>
!> Where the water around the ghost point is too thin for the gradient (the
!> system's determinant below det_min) the ghost takes the Shepard mean
!> instead; with no water there the particle takes rho0. A solid particle
!> never goes below rho0 (it would pull the water). The velocity the water
!> sees at a solid particle (mdbc_slip): the wall's own ('wall', as the
!> dynamic boundary), its mirror 2 v_wall - v_g ('noslip'), or the ghost's
!> tangential velocity with the normal one mirrored ('freeslip').
!> The neighbours of a ghost point are found on the grid around it, beyond
!> the half stencil: so far on one rank only (run_setup refuses more).
module bc_mdbc
   use kinds, only: rp
   use constants, only: kind_fluid, ndim
   use params, only: params_t, slip_wall, slip_noslip, slip_freeslip
   use grid, only: grid_t, grid_column
   use particles, only: particles_t
   use options, only: kernel_cubic
   implicit none
   private
   public :: mdbc_update, mdbc_rates, mdbc_solve

   !> unknowns of the corrected interpolation: the value and its gradient
   integer, parameter :: nu = ndim + 1
   !> smallest determinant of the (dimensionless) first-order system; below
   !> it the water around the ghost point is too one-sided for a gradient
   !> (the value DualSPHysics uses)
   real(rp), parameter :: det_min = 1.0e-3_rp

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> The density of every solid particle with a ghost point, from the water
   !> at that point; with slip /= 'wall' also vb, the velocities the pair
   !> loop reads (the water's own, the solids' as the slip condition makes
   !> them). The kernel and whether velocities are summed are chosen once
   !> here, not per pair.
   subroutine mdbc_update(prm, g, p, vol, vb)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      real(rp), intent(inout) :: vol(:)
      real(rp), intent(inout) :: vb(:, :)
      integer :: i
      ! the water's volumes once, not a division per pair (vol is the
      ! evaluation's scratch here: forces_prepare fills it again)
      do i = 1, p%n
         vol(i) = p%mass(i)/p%rho(i)
      end do
      if (prm%slip /= slip_wall) then
         vb(:, 1:p%n) = p%v(:, 1:p%n)
         if (prm%kernel == kernel_cubic) then
            call ghosts_cubic_v(prm, g, p, vol, vb)
         else
            call ghosts_wendland_v(prm, g, p, vol, vb)
         end if
      else if (prm%kernel == kernel_cubic) then
         call ghosts_cubic(prm, g, p, vol, vb)
      else
         call ghosts_wendland(prm, g, p, vol, vb)
      end if
   end subroutine mdbc_update

! the four routines of the ghost points' sums, generated from src/mdbc_ghosts.fypp
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "mdbc_ghosts.inc"

   !> The solids' densities come from the water, not from their own
   !> continuity equation: their rates are zero.
   subroutine mdbc_rates(n, kind, drho)
      integer, intent(in) :: n, kind(:)
      real(rp), intent(inout) :: drho(:)
      integer :: i
      do i = 1, n
         if (kind(i) /= kind_fluid) drho(i) = 0.0_rp
      end do
   end subroutine mdbc_rates

   !> From the sums a, b of the water around the ghost point of solid
   !> particle i: its density and, by the slip condition, the velocity the
   !> water sees at it.
   subroutine ghost_finish(prm, p, i, a, b, vb)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: i
      real(rp), intent(in) :: a(nu, nu), b(nu, 1 + ndim)
      real(rp), intent(inout) :: vb(:, :)
      real(rp) :: s(nu, 1 + ndim), det, rho_b, vg(ndim), vw(ndim), nrm(ndim)
      if (a(1, 1) <= 0.0_rp) then
         ! no water near: no pressure, the wall's own velocity
         p%rho(i) = prm%rho0
         return
      end if
      call mdbc_solve(a, b, s, det)
      if (abs(det) >= det_min) then
         rho_b = s(1, 1) - dot_product(p%gof(:, i), s(2:nu, 1))
         vg = s(1, 2:1 + ndim)
      else
         ! too little water for a gradient: the Shepard mean at the ghost point
         rho_b = b(1, 1)/a(1, 1)
         vg = b(1, 2:1 + ndim)/a(1, 1)
      end if
      p%rho(i) = max(rho_b, prm%rho0)
      vw = p%v(:, i)
      select case (prm%slip)
      case (slip_noslip)
         vb(:, i) = 2.0_rp*vw - vg
      case (slip_freeslip)
         nrm = p%gof(:, i)/norm2(p%gof(:, i))
         vb(:, i) = vg - 2.0_rp*dot_product(vg - vw, nrm)*nrm
      case default
         ! slip_wall: the pair loop reads the wall's own velocity
      end select
   end subroutine ghost_finish

   !> Solve a s = b for the columns of b by Gaussian elimination with partial
   !> pivoting; det: the determinant of a (0: singular, s undefined). Loops
   !> over scalars: called once per solid particle and step, no temporaries.
   pure subroutine mdbc_solve(a, b, s, det)
      real(rp), intent(in) :: a(:, :), b(:, :)
      real(rp), intent(out) :: s(:, :), det
      real(rp) :: m(size(a, 1), size(a, 1)), t, piv, fk
      integer :: n, nc, k, q, l, c
      n = size(a, 1)
      nc = size(b, 2)
      m = a
      s = b
      det = 1.0_rp
      do k = 1, n
         q = k
         do l = k + 1, n
            if (abs(m(l, k)) > abs(m(q, k))) q = l
         end do
         if (q /= k) then
            do c = 1, n
               t = m(k, c); m(k, c) = m(q, c); m(q, c) = t
            end do
            do c = 1, nc
               t = s(k, c); s(k, c) = s(q, c); s(q, c) = t
            end do
            det = -det
         end if
         piv = m(k, k)
         det = det*piv
         if (abs(piv) <= tiny(1.0_rp)) return
         do l = k + 1, n
            fk = m(l, k)/piv
            do c = k, n
               m(l, c) = m(l, c) - fk*m(k, c)
            end do
            do c = 1, nc
               s(l, c) = s(l, c) - fk*s(k, c)
            end do
         end do
      end do
      do k = n, 1, -1
         do c = 1, nc
            t = s(k, c)
            do l = k + 1, n
               t = t - m(k, l)*s(l, c)
            end do
            s(k, c) = t/m(k, k)
         end do
      end do
   end subroutine mdbc_solve
end module bc_mdbc

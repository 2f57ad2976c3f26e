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
!> the half stencil, among the particles this rank owns. On several ranks a
!> ghost point whose support reaches into a neighbour's slab is summed on
!> every rank over its own particles, and the sums added over the ranks
!> (the step does the exchange: mdbc_update leaves those points to it).
module bc_mdbc
   use kinds, only: rp
   use constants, only: kind_fluid, ndim
   use params, only: params_t, slip_wall, slip_noslip, slip_freeslip
   use grid, only: grid_t, grid_column, grid_neighbours, grid_point_ranges, grid_npoint
   use particles, only: particles_t
   use options, only: kernel_cubic, kernel_wendland
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   implicit none
   private
   public :: mdbc_work_t, mdbc_update, mdbc_sums, mdbc_finish, mdbc_rates, mdbc_solve, mdbc_nsum

   !> unknowns of the corrected interpolation: the value and its gradient
   integer, parameter :: nu = ndim + 1
   !> the sums of one ghost point: the system a (nu x nu) and the right-hand
   !> sides b (nu x (1 + ndim): density, velocity), as mdbc_sums packs them
   integer, parameter :: mdbc_nsum = nu*nu + nu*(1 + ndim)
   !> smallest determinant of the (dimensionless) first-order system; below
   !> it the water around the ghost point is too one-sided for a gradient
   !> (the value DualSPHysics uses)
   real(rp), parameter :: det_min = 1.0e-3_rp

   !> The ghost points of one evaluation: those whose water is all on this
   !> rank's slab (summed and finished by mdbc_update), and those whose kernel
   !> support crosses into a neighbour's slab (left to the step, which sums
   !> them over every rank: ie the particles, xe their ghost points).
   type :: mdbc_work_t
      integer :: ni = 0, ne = 0
      integer, allocatable :: ii(:), ie(:)
      real(rp), allocatable :: xi(:, :), xe(:, :), s(:, :)
      !> the mass each water particle lends the interpolated density: its own, or in
      !> the pores m / n, so that the solids take the pore water's density rho_s / n
      real(rp), allocatable :: mw(:)
   end type mdbc_work_t

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> The density of every owned solid particle with a ghost point, from the
   !> water at that point; with slip /= 'wall' also vb, the velocities the
   !> pair loop reads (the water's own, the solids' as the slip condition
   !> makes them). On several ranks the ghost points whose support reaches
   !> into a neighbour's slab are left in md%ie, md%xe for the step to sum
   !> over every rank (mdbc_sums, mdbc_finish); on one rank there are none.
   !> With porous regions nf(1, :) is each particle's porosity (porous_field):
   !> a solid among the stones takes the density of the pore water, rho_s / n,
   !> which is what the pair loops take a solid's density for there.
   subroutine mdbc_update(prm, g, p, vol, vb, md, nf)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      real(rp), intent(inout) :: vol(:)
      real(rp), intent(inout) :: vb(:, :)
      type(mdbc_work_t), intent(inout) :: md
      real(rp), intent(in), optional :: nf(:, :)
      integer :: i, kx
      logical :: left, right
      ! the water's volumes once, not a division per pair (vol is the
      ! evaluation's scratch here: forces_prepare fills it again)
      do i = 1, p%n
         vol(i) = p%mass(i)/p%rho(i)
      end do
      call ensure_mass(md, size(p%rho))
      if (present(nf)) then
         do i = 1, p%n
            md%mw(i) = p%mass(i)/nf(1, i)
         end do
      else
         md%mw(1:p%n) = p%mass(1:p%n)
      end if
      if (prm%slip /= slip_wall) vb(:, 1:p%n) = p%v(:, 1:p%n)
      call ensure_lists(md, p%n_own)
      call grid_neighbours(g, left, right)
      md%ni = 0
      md%ne = 0
      do i = 1, p%n_own
         if (p%kind(i) == kind_fluid) cycle
         if (dot_product(p%gof(:, i), p%gof(:, i)) <= 0.0_rp) cycle   ! no ghost point
         kx = grid_column(g%x0, g%cs, g%ncx_all, p%x(1, i) + p%gof(1, i)) - g%col0 + 1
         if ((left .and. kx - 1 < 1) .or. (right .and. kx + 1 > g%ncol)) then
            md%ne = md%ne + 1
            md%ie(md%ne) = i
            md%xe(:, md%ne) = p%x(:, i) + p%gof(:, i)
         else
            md%ni = md%ni + 1
            md%ii(md%ni) = i
            md%xi(:, md%ni) = p%x(:, i) + p%gof(:, i)
         end if
      end do
      call mdbc_sums(prm, g, p, vol, md%mw, md%xi(:, 1:md%ni), md%s(:, 1:md%ni))
      call mdbc_finish(prm, p, md%ii(1:md%ni), md%s(:, 1:md%ni), vb)
   end subroutine mdbc_update

   !> The work lists for up to n ghost points.
   subroutine ensure_lists(md, n)
      type(mdbc_work_t), intent(inout) :: md
      integer, intent(in) :: n
      integer :: ist
      character(len=200) :: emsg
      if (allocated(md%ii)) then
         if (size(md%ii) >= n) return
         deallocate (md%ii, md%ie, md%xi, md%xe, md%s)
      end if
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (md%ii(n), md%ie(n), md%xi(ndim, n), md%xe(ndim, n), md%s(mdbc_nsum, n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the ghost point lists of mdbc_update', n)
   end subroutine ensure_lists

   !> The mass weights md%mw for a store of n slots.
   subroutine ensure_mass(md, n)
      type(mdbc_work_t), intent(inout) :: md
      integer, intent(in) :: n
      integer :: ist
      character(len=200) :: emsg
      if (allocated(md%mw)) then
         if (size(md%mw) >= n) return
         deallocate (md%mw)
      end if
      allocate (md%mw(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the mass weights of mdbc_update', n)
   end subroutine ensure_mass

   !> s(:, k): the sums of the water this rank owns around ghost point xg(:, k)
   !> (packed as mdbc_nsum numbers), with the volumes vol and the mass weights
   !> mw (mdbc_update) of the water; the kernel and whether velocities are
   !> summed are chosen here, once for the list.
   subroutine mdbc_sums(prm, g, p, vol, mw, xg, s)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: vol(:), mw(:)
      real(rp), intent(in) :: xg(:, :)
      real(rp), intent(out) :: s(:, :)
      if (prm%kernel /= kernel_cubic .and. prm%kernel /= kernel_wendland) then
         call fatal('mdbc_sums: unknown kernel '//int_str(prm%kernel)//' (internal error)')
      end if
      if (prm%slip /= slip_wall) then
         if (prm%kernel == kernel_cubic) then
            call ghosts_cubic_v(prm, g, p, vol, mw, xg, s)
         else
            call ghosts_wendland_v(prm, g, p, vol, mw, xg, s)
         end if
      else if (prm%kernel == kernel_cubic) then
         call ghosts_cubic(prm, g, p, vol, mw, xg, s)
      else
         call ghosts_wendland(prm, g, p, vol, mw, xg, s)
      end if
   end subroutine mdbc_sums

   !> The densities (and slip velocities) of particles ie from the complete
   !> sums s(:, k) of their ghost points.
   subroutine mdbc_finish(prm, p, ie, s, vb)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(inout) :: p
      integer, intent(in) :: ie(:)
      real(rp), intent(in) :: s(mdbc_nsum, size(ie))
      real(rp), intent(inout) :: vb(:, :)
      integer :: k
      do k = 1, size(ie)
         ! a and b, column after column: the explicit-shape dummies of ghost_finish take them in place
         call ghost_finish(prm, p, ie(k), s(1, k), s(nu*nu + 1, k), vb)
      end do
   end subroutine mdbc_finish

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
      case (slip_wall)
         ! the pair loop reads the wall's own velocity
      case default
         call fatal('ghost_finish: unknown slip treatment '//int_str(prm%slip)//' (internal error)')
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

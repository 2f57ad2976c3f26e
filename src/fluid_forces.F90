!> Fluid forces: continuity and momentum of weakly compressible SPH over all
!> particle pairs. Dynamic boundary: wall particles take part in continuity
!> and lend their pressure to the fluid; repulsive boundary: the outer row of
!> every solid pushes fluid particles off with the Monaghan-Kos force. The
!> pair loop is chosen once per run among specialised variants
!> (fluid_pairs.inc), one per combination of boundary, kernel, viscosity
!> model, density diffusion and gradient correction.
module fluid_forces
   use kinds, only: rp
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use constants, only: kind_fluid
   use params, only: params_t, visc_laminar_sps, diff_none, diff_fourtakas, kgc_gradient, bnd_repulsive
   use grid, only: grid_t, grid_ranges, grid_last_cell
   use particles, only: particles_t
   use eos, only: eos_update, eos_dynamic_density
   use nbr_list, only: nbr_t, nbr_build
   use kernel, only: kernel_cubic
   use kernel_correction, only: kgc_matrices, kgc_finish
   use comm_halo, only: comm_halo_forward, comm_halo_reverse
   implicit none
   private
   public :: forces_work_t, forces_init, forces_compute

   !> constants of the repulsive boundary handed to the pair loops: A's two
   !> factors, q0, 40/c0, the still-water level, 1/h_swl, dp
   integer, parameter :: n_rep = 7

   !> Per-particle work arrays of a force evaluation (not kept across steps).
   type :: forces_work_t
      real(rp), allocatable :: acc(:, :)   !< acceleration [m/s2]
      real(rp), allocatable :: drho(:)     !< density rate [kg/m3/s]
      real(rp), allocatable :: cs(:)       !< sound speed [m/s]
      real(rp), allocatable :: irho(:)     !< 1/density [m3/kg]
      real(rp), allocatable :: vol(:)      !< volume mass/density [m3]
      real(rp), allocatable :: rhod(:)     !< density used by the diffusion term
      real(rp), allocatable :: lm(:, :)    !< gradient correction matrices
      real(rp), allocatable :: tau(:, :)   !< SPS stress / rho^2
      real(rp) :: mumax = 0.0_rp           !< max |h v.r / (r^2 + eta^2)| over pairs [m/s]
      type(nbr_t) :: nb                    !< the pairs of the evaluation
   end type forces_work_t

   abstract interface
      subroutine pairs_iface(n, g, nb, x, v, rho, irho, p, mass, kind, cs, rhod, lm, tau, nrm, surf, &
                             h, support2, eta2, fw, alpha, nu4, dcoef, ckgc, rep, acc, drho, mumax)
         import :: rp, n_rep, grid_t, nbr_t
         implicit none
         integer, intent(in) :: n
         type(grid_t), intent(in) :: g
         type(nbr_t), intent(in) :: nb
         real(rp), intent(in) :: x(2, n), v(2, n), rho(n), irho(n), p(n), mass(n), cs(n), rhod(:), lm(:, :), tau(:, :)
         real(rp), intent(in) :: nrm(2, n)
         integer, intent(in) :: kind(n), surf(n)
         real(rp), intent(in) :: h, support2, eta2, fw, alpha, nu4, dcoef, ckgc, rep(n_rep)
         real(rp), intent(inout) :: acc(2, n), drho(n)
         real(rp), intent(inout) :: mumax
      end subroutine pairs_iface
   end interface

   procedure(pairs_iface), pointer :: pairs => null()

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> Choose the pair loop for this run's models. A model that needs a pass
   !> over the pairs before the forces (gradient correction, SPS) gets the
   !> loops over the evaluation's pair list, which both passes share; the
   !> others a loop over the grid's stencil, which needs no list in memory.
   subroutine forces_init(prm)
      type(params_t), intent(in) :: prm
      integer :: code
      ! the repulsive boundary runs without density diffusion and gradient
      ! correction (the input refuses them; doc/theory.md says why)
      if (needs_list(prm)) then
         code = merge(1, 0, prm%visc == visc_laminar_sps) + 2*merge(1, 0, prm%diffusion /= diff_none) + &
                4*merge(1, 0, prm%kgc == kgc_gradient)
         if (prm%boundary == bnd_repulsive) code = 8
         select case (code)
         case (1); pairs => pairs_l_b1_v2_d0_g0
         case (3); pairs => pairs_l_b1_v2_d1_g0
         case (4); pairs => pairs_l_b1_v1_d0_g1
         case (5); pairs => pairs_l_b1_v2_d0_g1
         case (6); pairs => pairs_l_b1_v1_d1_g1
         case (7); pairs => pairs_l_b1_v2_d1_g1
         case (8); pairs => pairs_l_b2_v2_d0_g0
         case default  ! 0 and 2 need no list: needs_list and this table disagree
            call fatal('forces_init: no listed pair loop for the models of code '//int_str(code))
         end select
      else
         code = merge(1, 0, prm%kernel == kernel_cubic) + 2*merge(1, 0, prm%diffusion /= diff_none)
         if (prm%boundary == bnd_repulsive) code = 4 + merge(1, 0, prm%kernel == kernel_cubic)
         select case (code)
         case (0); pairs => pairs_s_b1_k1_d0
         case (1); pairs => pairs_s_b1_k2_d0
         case (2); pairs => pairs_s_b1_k1_d1
         case (3); pairs => pairs_s_b1_k2_d1
         case (4); pairs => pairs_s_b2_k1
         case (5); pairs => pairs_s_b2_k2
         case default
            call fatal('forces_init: no stencil pair loop for the models of code '//int_str(code))
         end select
      end if
   end subroutine forces_init

   !> The models that sum over the pairs before the forces, and so share a pair list.
   pure logical function needs_list(prm)
      type(params_t), intent(in) :: prm
      needs_list = prm%kgc == kgc_gradient .or. prm%visc == visc_laminar_sps
   end function needs_list

   subroutine ensure(w, nmax, prm)
      type(forces_work_t), intent(inout) :: w
      integer, intent(in) :: nmax
      type(params_t), intent(in) :: prm
      integer :: ist
      character(len=200) :: emsg
      if (allocated(w%acc)) then
         if (size(w%drho) >= nmax) return
         deallocate (w%acc, w%drho, w%cs, w%irho, w%vol, w%rhod, w%lm, w%tau)
      end if
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (w%acc(2, nmax), w%drho(nmax), w%cs(nmax), w%irho(nmax), w%vol(nmax), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the force arrays', nmax)
      ! arrays of models that are off stay minimal
      if (prm%diffusion /= diff_none) then
         allocate (w%rhod(nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%rhod in ensure')
      else
         allocate (w%rhod(1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%rhod in ensure')
      end if
      if (prm%kgc == kgc_gradient) then
         allocate (w%lm(3, nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%lm in ensure')
      else
         allocate (w%lm(3, 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%lm in ensure')
      end if
      if (prm%visc == visc_laminar_sps) then
         allocate (w%tau(3, nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%tau in ensure')
      else
         allocate (w%tau(3, 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%tau in ensure')
      end if
   end subroutine ensure

   !> Pressure from density, then every pair: w%acc (gravity included, fluid
   !> only meaningful) and w%drho for all particles; on several ranks the
   !> halo's share still has to be sent to its owners.
   subroutine forces_compute(prm, g, p, w)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(forces_work_t), intent(inout) :: w
      integer :: i, n
      real(rp) :: rep(n_rep)
      n = p%n
      call ensure(w, size(p%rho), prm)
      call eos_update(prm, n, p%rho, p%p, w%cs)
      if (prm%diffusion == diff_fourtakas) then
         call eos_dynamic_density(prm, n, p%rho, p%x, w%rhod)
      else if (prm%diffusion /= diff_none) then
         w%rhod(1:n) = p%rho(1:n)
      end if
      do i = 1, n
         w%irho(i) = 1.0_rp/p%rho(i)
         w%vol(i) = p%mass(i)*w%irho(i)
      end do
      ! the pairs of this evaluation, for the passes below, when there are two
      if (needs_list(prm)) call nbr_build(w%nb, g, p%x, n, prm%kernel, prm%h, prm%support2, prm%fw)
      if (prm%kgc == kgc_gradient .and. prm%visc == visc_laminar_sps) then
         ! both need a pass over the pairs before the forces: one shared pass
         call sps_stress(prm, w%nb, p, w%vol, w%tau, w%lm)
      else if (prm%kgc == kgc_gradient) then
         call kgc_matrices(w%nb, p, w%vol, w%lm)
      else if (prm%visc == visc_laminar_sps) then
         call sps_stress(prm, w%nb, p, w%vol, w%tau)
      end if
      w%acc(:, 1:n) = 0.0_rp
      w%drho(1:n) = 0.0_rp
      w%mumax = 0.0_rp
      ! constants of the repulsive boundary, unused by the dynamic one
      rep = [prm%rep_a, prm%rep_b, prm%rep_q0, prm%rep_u, prm%y_surface, prm%rep_rhswl, prm%dp]
      call pairs(n, g, w%nb, p%x, p%v, p%rho, w%irho, p%p, p%mass, p%kind, w%cs, w%rhod, w%lm, w%tau, &
                 p%nrm, p%surf, prm%h, prm%support2, prm%eta2, prm%fw, prm%alpha, 4.0_rp*prm%nu, prm%delta_coef, &
                 prm%kgc_cont, rep, w%acc, w%drho, w%mumax)
      ! gravity on the owned particles only: the pair sums of the halo
      ! copies are added to their owners afterwards (comm_halo_reverse)
      do i = 1, p%n_own
         if (p%kind(i) == kind_fluid) w%acc(2, i) = w%acc(2, i) - prm%g
      end do
   end subroutine forces_compute

   !> Sub-particle-scale stress (Smagorinsky eddy viscosity with the Blin
   !> term, Dalrymple and Rogers 2006), stored as (tau/rho)/rho per fluid particle.
   !> With lm present, the gradient correction matrices (kgc_matrices) from the
   !> same sweep over the pairs, at about the cost of one of the two sweeps.
   subroutine sps_stress(prm, nb, p, vol, tau, lm)
      type(params_t), intent(in) :: prm
      type(nbr_t), intent(in) :: nb
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: vol(:)
      real(rp), intent(out) :: tau(:, :)
      real(rp), intent(out), optional :: lm(:, :)
      real(rp), allocatable :: gv(:, :)
      integer :: i, j, k
      real(rp) :: dx, dy, fac, vi, vj, dvx, dvy, sxx, sxy, syy, s2, nut, sk, xi, yi, vxi, vyi
      real(rp) :: b1, b2, b3, g1, g2, g3, g4
      integer :: ist
      character(len=200) :: emsg
      allocate (gv(4, p%n), stat=ist, errmsg=emsg)  ! du/dx, du/dy, dv/dx, dv/dy
      call alloc_check(ist, emsg, 'gv in sps_stress')
      gv = 0.0_rp
      ! one copy of the pass per choice: no test inside the pair loop
#define PRE_SPS 1
      if (present(lm)) then
         lm(:, 1:p%n) = 0.0_rp
#define PRE_KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
         call kgc_finish(p, lm)
      else
#define PRE_KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
      end if
#undef PRE_SPS
      call comm_halo_reverse(gv, p%n_own)
      do i = 1, p%n
         sxx = gv(1, i)
         syy = gv(4, i)
         sxy = 0.5_rp*(gv(2, i) + gv(3, i))
         s2 = 2.0_rp*(sxx*sxx + syy*syy) + 4.0_rp*sxy*sxy        ! 2 S:S
         nut = prm%sps_smag*sqrt(s2)
         sk = -(2.0_rp/3.0_rp)*nut*(sxx + syy) - prm%sps_blin*s2
         tau(1, i) = (2.0_rp*nut*sxx + sk)/p%rho(i)
         tau(2, i) = 2.0_rp*nut*sxy/p%rho(i)
         tau(3, i) = (2.0_rp*nut*syy + sk)/p%rho(i)
         if (p%kind(i) /= kind_fluid) tau(:, i) = 0.0_rp
      end do
      call comm_halo_forward(tau, p%n_own)
   end subroutine sps_stress

! the variants: over the grid's stencil (s) without a pass before the forces, over the pair list (l) with one
#define PAIRS_NAME pairs_s_b1_k1_d0
#define LIST 0
#define BC 1
#define KERN 1
#define VISC 1
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_s_b1_k1_d1
#define LIST 0
#define BC 1
#define KERN 1
#define VISC 1
#define DIFF 1
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_s_b2_k1
#define LIST 0
#define BC 2
#define KERN 1
#define VISC 1
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_s_b1_k2_d0
#define LIST 0
#define BC 1
#define KERN 2
#define VISC 1
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_s_b1_k2_d1
#define LIST 0
#define BC 1
#define KERN 2
#define VISC 1
#define DIFF 1
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_s_b2_k2
#define LIST 0
#define BC 2
#define KERN 2
#define VISC 1
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v2_d0_g0
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 2
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v2_d1_g0
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 2
#define DIFF 1
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v1_d0_g1
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 1
#define DIFF 0
#define KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v2_d0_g1
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 2
#define DIFF 0
#define KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v1_d1_g1
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 1
#define DIFF 1
#define KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b1_v2_d1_g1
#define LIST 1
#define BC 1
#define KERN 0
#define VISC 2
#define DIFF 1
#define KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"

#define PAIRS_NAME pairs_l_b2_v2_d0_g0
#define LIST 1
#define BC 2
#define KERN 0
#define VISC 2
#define DIFF 0
#define KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_pairs.inc"
end module fluid_forces

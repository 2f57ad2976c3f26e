!> Kernel correction: the gradient correction matrices L_i (so that the
!> corrected gradient L_i grad W_ij is exact for linear fields) and the
!> Shepard density filter.
module kernel_correction
   use kinds, only: rp
   use constants, only: kind_fluid, ndim
   use params, only: params_t
   use kernel, only: kernel_cubic, kernel_wendland
   use errors, only: fatal
   use input_check, only: int_str
   use grid, only: grid_t, grid_ranges, grid_last_cell, grid_nranges
   use particles, only: particles_t
   use nbr_list, only: nbr_t
   use tensor, only: sym_det, sym_adjugate, sym_identity
   implicit none
   private
   public :: kgc_sums, kgc_finish, shepard_sums, shepard_apply

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> The moment matrices B_i = sum_j V_j grad W_ij (x_j - x_i)^T, stored as
   !> their nsym components (Bxx, Bxy, Byy in 2D: the slots of tensor) in lm(:, i): the pairs of the rows of nb added to lm
   !> (zero before the first rows); kgc_finish turns them into the
   !> correction matrices once every pair of a particle is in (on several
   !> ranks, once the halo's share has reached its owner).
   subroutine kgc_sums(nb, p, vol, lm)
      type(nbr_t), intent(in) :: nb
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: vol(:)       !< mass/density of every particle
      real(rp), intent(inout) :: lm(:, :)
      integer :: i, j, k
      real(rp) :: fac, vi, vj
#define PRE_KGC 1
#define PRE_SPS 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_decl.inc"
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
#undef PRE_SPS
   end subroutine kgc_sums

   !> From the moment matrices B summed over the pairs (kgc_sums, or the
   !> sweep shared with the SPS velocity gradients) to L_i = B^-1, stored in
   !> the same slots, blended to the identity where B is near-singular
   !> (free-surface spray).
   subroutine kgc_finish(lm, i_lo, i_hi)
      real(rp), intent(inout) :: lm(:, :)
      integer, intent(in) :: i_lo, i_hi     !< the particles whose sums are complete
      integer :: i
      real(rp) :: det, wgt
      real(rp), parameter :: det_full = 0.75_rp, det_none = 0.5_rp
      do i = i_lo, i_hi
         det = sym_det(lm(:, i))
         ! a full support gives det(B) = 1. Near a free surface the support is
         ! cut and the inverse would amplify forces there (an instability):
         ! blend from the full correction at det >= det_full to none at
         ! det <= det_none, continuously.
         wgt = min(max((det - det_none)/(det_full - det_none), 0.0_rp), 1.0_rp)
         if (wgt > 0.0_rp) then
            lm(:, i) = wgt*sym_adjugate(lm(:, i))/det + (1.0_rp - wgt)*sym_identity()
         else
            lm(:, i) = sym_identity()
         end if
      end do
   end subroutine kgc_finish

   !> Shepard filter, first part: msum_i = sum_j m_j W_ij and wsum_i =
   !> sum_j V_j W_ij over fluid neighbours and itself (shepard_apply divides
   !> them once the halo's share has reached its owners).
   subroutine shepard_sums(prm, g, p, wsum, msum)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      real(rp), intent(inout) :: wsum(:), msum(:)
      integer :: i
      do i = 1, p%n_own
         msum(i) = p%mass(i)*prm%w0
         wsum(i) = p%mass(i)/p%rho(i)*prm%w0
      end do
      ! the halo copies collect pair sums only: their owner adds its own term
      msum(p%n_own + 1:p%n) = 0.0_rp
      wsum(p%n_own + 1:p%n) = 0.0_rp
      ! one copy of the sweep per kernel: no kernel test inside the pair loop
      select case (prm%kernel)
      case (kernel_cubic)
         call shepard_pairs_cubic(prm, g, p, wsum, msum)
      case (kernel_wendland)
         call shepard_pairs_wendland(prm, g, p, wsum, msum)
      case default
         call fatal('shepard_sums: unknown kernel '//int_str(prm%kernel)//' (internal error)')
      end select
   end subroutine shepard_sums

! the sweeps over the pairs, one per kernel (src/shepard_pairs.fypp)
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "shepard_pairs.inc"

   !> Shepard filter, second part: rho_i = msum_i / wsum_i for the owned fluid particles.
   subroutine shepard_apply(p, wsum, msum)
      type(particles_t), intent(inout) :: p
      real(rp), intent(in) :: wsum(:), msum(:)
      integer :: i
      do i = 1, p%n_own
         if (p%kind(i) == kind_fluid) p%rho(i) = msum(i)/wsum(i)
      end do
   end subroutine shepard_apply
end module kernel_correction

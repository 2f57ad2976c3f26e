!> Kernel correction: the gradient correction matrices L_i (so that the
!> corrected gradient L_i grad W_ij is exact for linear fields) and the
!> Shepard density filter.
module kernel_correction
   use kinds, only: rp
   use constants, only: kind_fluid
   use params, only: params_t
   use kernel, only: kernel_cubic
   use grid, only: grid_t, grid_ranges, grid_last_cell
   use particles, only: particles_t
   use nbr_list, only: nbr_t
   use comm_halo, only: comm_halo_forward, comm_halo_reverse
   implicit none
   private
   public :: kgc_matrices, kgc_finish, shepard_filter

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> L_i stored as (Lxx, Lxy, Lyy) in lm(:, i), for every particle; the
   !> identity where the moment matrix is near-singular (free surface spray).
   subroutine kgc_matrices(nb, p, vol, lm)
      type(nbr_t), intent(in) :: nb
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: vol(:)       !< mass/density of every particle
      real(rp), intent(out) :: lm(:, :)
      integer :: i, j, k
      real(rp) :: dx, dy, fac, vi, vj, xi, yi, b1, b2, b3
      lm(:, 1:p%n) = 0.0_rp
#define PRE_KGC 1
#define PRE_SPS 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
#undef PRE_SPS
      call kgc_finish(p, lm)
   end subroutine kgc_matrices

   !> From the moment matrices B summed over the pairs (kgc_matrices, or the
   !> sweep shared with the SPS velocity gradients) to L_i = B^-1, blended to
   !> the identity where B is near-singular.
   subroutine kgc_finish(p, lm)
      type(particles_t), intent(in) :: p
      real(rp), intent(inout) :: lm(:, :)
      integer :: i
      real(rp) :: a11, a12, a22, det, wgt
      real(rp), parameter :: det_full = 0.75_rp, det_none = 0.5_rp
      ! the moments of the halo copies belong to the next rank's particles
      call comm_halo_reverse(lm, p%n_own)
      do i = 1, p%n
         a11 = lm(1, i); a12 = lm(2, i); a22 = lm(3, i)
         det = a11*a22 - a12*a12
         ! a full support gives det(B) = 1. Near a free surface the support is
         ! cut and the inverse would amplify forces there (an instability):
         ! blend from the full correction at det >= det_full to none at
         ! det <= det_none, continuously.
         wgt = min(max((det - det_none)/(det_full - det_none), 0.0_rp), 1.0_rp)
         if (wgt > 0.0_rp) then
            lm(:, i) = wgt*[a22, -a12, a11]/det + (1.0_rp - wgt)*[1.0_rp, 0.0_rp, 1.0_rp]
         else
            lm(:, i) = [1.0_rp, 0.0_rp, 1.0_rp]
         end if
      end do
      call comm_halo_forward(lm, p%n_own)
   end subroutine kgc_finish

   !> Shepard filter: rho_i = sum_j m_j W_ij / sum_j V_j W_ij over fluid
   !> neighbours and itself, for fluid particles.
   subroutine shepard_filter(prm, g, p, wsum, msum)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      real(rp), intent(inout) :: wsum(:), msum(:)
      integer :: c, i, j, r, jlo(2), jhi(2)
      real(rp) :: dx, dy, r2, q, w, hinv
      hinv = 1.0_rp/prm%h
      do i = 1, p%n_own
         msum(i) = p%mass(i)*prm%w0
         wsum(i) = p%mass(i)/p%rho(i)*prm%w0
      end do
      ! the halo copies collect pair sums only: their owner adds its own term
      msum(p%n_own + 1:p%n) = 0.0_rp
      wsum(p%n_own + 1:p%n) = 0.0_rp
      ! one copy of the sweep per kernel: no kernel test inside the pair loop
      if (prm%kernel == kernel_cubic) then
#define KFAC(q) KW_CUBIC(q)
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "shepard_pairs.inc"
#undef KFAC
      else
#define KFAC(q) KW_WENDLAND(q)
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "shepard_pairs.inc"
#undef KFAC
      end if
      call comm_halo_reverse(msum, p%n_own)
      call comm_halo_reverse(wsum, p%n_own)
      do i = 1, p%n_own
         if (p%kind(i) == kind_fluid) p%rho(i) = msum(i)/wsum(i)
      end do
      call comm_halo_forward(p%rho, p%n_own)
   end subroutine shepard_filter
end module kernel_correction

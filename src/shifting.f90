!> Particle shifting (Lind et al. 2012, in the Fickian form of Skillen et al.
!> 2013 that DualSPHysics uses). At the end of each step every fluid particle
!> moves against the gradient of the particle concentration,
!>
!>     dr_i = -A h |v_i| dt grad C_i,     grad C_i = sum_j V_j grad W_ij,
!>
!> which spreads clumps and fills gaps as the flow shears the particle
!> arrangement (the walls' particles are in the sum, so the water is not
!> pushed into them). A particle whose divergence of position,
!> div r_i = sum_j V_j (x_j - x_i) . grad W_ij (ndim inside the water, about
!> half of it on the surface), is below shift_tfs is a free-surface particle
!> and is not shifted at all: its grad C is the kernel's truncation, normal
!> to the surface, and would pull it out of the water. The sums come from the
!> pair loop (fluid_pair_body.inc, SHIFT = 1); nothing here runs without
!> shifting = 'fickian'.
module shifting
   use kinds, only: rp
   use constants, only: kind_fluid, ndim
   use params, only: params_t
   use particles, only: particles_t
   implicit none
   private
   public :: shifting_apply

contains

   !> The shift of each owned fluid particle after a step of length dt, from
   !> the sums sh (rows 1 .. ndim: grad C; row ndim + 1: div r) of the
   !> step's last force evaluation.
   subroutine shifting_apply(prm, p, sh, dt)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(inout) :: p
      real(rp), intent(in) :: sh(:, :)
      real(rp), intent(in) :: dt
      integer :: i
      real(rp) :: d
      do i = 1, p%n_own
         if (p%kind(i) /= kind_fluid) cycle
         if (sh(ndim + 1, i) < prm%shift_tfs) cycle
         d = prm%shift_coef*prm%h*norm2(p%v(:, i))*dt
         p%x(:, i) = p%x(:, i) - d*sh(1:ndim, i)
      end do
   end subroutine shifting_apply
end module shifting

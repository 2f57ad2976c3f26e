!> Absorbing zone at the end of a flume: the velocity of the fluid is
!> relaxed towards rest, v <- v exp(-sigma(x) dt), with a rate that grows
!> from zero at x0 to `strength` at x1 as ((x - x0)/(x1 - x0))^2, so that
!> the wave meets no sudden change and is damped over the zone's length.
module wave_damping
   use kinds, only: rp
   use constants, only: kind_fluid
   use particles, only: particles_t
   implicit none
   private
   public :: damping_t, damping_apply

   !> An absorbing zone: where it starts and ends, and its rate at the end.
   type :: damping_t
      logical :: on = .false.
      real(rp) :: x0 = 0.0_rp             !< start of the zone [m]: no damping there
      real(rp) :: x1 = 0.0_rp             !< end of the zone [m]: full damping (x1 < x0 damps to the left)
      real(rp) :: strength = 0.0_rp       !< relaxation rate at x1 [1/s]
   end type damping_t

contains

   subroutine damping_apply(d, p, dt)
      type(damping_t), intent(in) :: d
      type(particles_t), intent(inout) :: p
      real(rp), intent(in) :: dt
      integer :: i
      real(rp) :: s, inv_len, f
      inv_len = 1.0_rp/(d%x1 - d%x0)
      do i = 1, p%n
         if (p%kind(i) /= kind_fluid) cycle
         s = (p%x(1, i) - d%x0)*inv_len
         if (s <= 0.0_rp) cycle
         s = min(s, 1.0_rp)
         f = exp(-d%strength*s*s*dt)
         p%v(:, i) = f*p%v(:, i)
         if (p%history) p%vm1(:, i) = f*p%vm1(:, i)
      end do
   end subroutine damping_apply
end module wave_damping

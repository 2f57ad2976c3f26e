!> Prescribed motion of moving boundaries (dynamic boundary particles whose
!> positions and velocities are a function of time).
module bc_motion
   use kinds, only: rp
   use constants, only: pi, kind_moving
   use input_geometry, only: geom_object
   use particles, only: particles_t
   implicit none
   private
   public :: motion_apply

contains

   !> Set position and velocity of every moving particle at time t.
   subroutine motion_apply(objs, p, t)
      type(geom_object), intent(in) :: objs(:)
      type(particles_t), intent(inout) :: p
      real(rp), intent(in) :: t
      integer :: i, b
      real(rp) :: w
      do i = 1, p%n
         if (p%kind(i) /= kind_moving) cycle
         b = p%body(i)
         if (b > size(objs)) cycle            ! a prescribed body: moved by body_dynamics
         select case (objs(b)%motion)
         case ('oscillate')
            w = 2.0_rp*pi/objs(b)%period
            p%x(:, i) = p%xb(:, i) + objs(b)%amplitude*sin(w*t)
            p%v(:, i) = objs(b)%amplitude*w*cos(w*t)
         case default  ! 'fixed': nothing to move
         end select
      end do
   end subroutine motion_apply
end module bc_motion

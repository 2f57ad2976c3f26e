!> Prescribed motion of moving boundaries (dynamic boundary particles whose
!> positions and velocities are a function of time): oscillating walls and
!> the wavemaker paddle.
module bc_motion
   use kinds, only: rp
   use constants, only: pi, kind_moving
   use input_geometry, only: geom_object
   use particles, only: particles_t
   use wave_paddle, only: paddle_motion, paddle_place, paddle_is_flap
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
      real(rp) :: w, xf, uf, hinge(2), depth
      logical :: flap
      call paddle_motion(t, xf, uf)
      flap = paddle_is_flap()
      do i = 1, p%n
         if (p%kind(i) /= kind_moving) cycle
         b = p%body(i)
         if (b > size(objs)) cycle            ! a prescribed body: moved by body_dynamics
         select case (objs(b)%motion)
         case ('oscillate')
            w = 2.0_rp*pi/objs(b)%period
            p%x(:, i) = p%xb(:, i) + objs(b)%amplitude*sin(w*t)
            p%v(:, i) = objs(b)%amplitude*w*cos(w*t)
         case ('wavemaker')
            ! the hinge is the bottom of the paddle face; depth: hinge to still water
            hinge = [objs(b)%box(2), objs(b)%box(3)]
            depth = objs(b)%hinge_depth
            call paddle_place(flap, p%xb(:, i), xf, uf, hinge, depth, p%x(:, i), p%v(:, i))
         case default  ! 'fixed': nothing to move
         end select
      end do
   end subroutine motion_apply
end module bc_motion

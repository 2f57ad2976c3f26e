!> Prescribed motion of moving boundaries (dynamic boundary particles whose
!> positions and velocities are a function of time): oscillating walls and
!> the wavemaker paddle. The scene builder turns the geometry objects of the
!> input into the motions (scene_walls), walls_init gathers them with the
!> paddle's law, so that this module and the step never see the input.
module bc_motion
   use kinds, only: rp
   use constants, only: pi, kind_moving, nsec
   use particles, only: particles_t
   use wave_paddle, only: paddle_t, paddle_motion, paddle_place
   use options, only: wall_fixed, wall_oscillate, wall_wavemaker
   use errors, only: fatal
   use input_check, only: int_str
   implicit none
   private
   public :: wall_motion_t, walls_t, walls_init, motion_apply, motion_offset

   !> The motion of one geometry object (a wall, or the paddle).
   type :: wall_motion_t
      integer :: motion = wall_fixed        !< wall_fixed, wall_oscillate or wall_wavemaker (options)
      real(rp) :: amplitude(2) = 0.0_rp     !< oscillate: amplitude of the displacement [m]
      real(rp) :: period = 1.0_rp           !< oscillate: period [s]
      real(rp) :: hinge(2) = 0.0_rp         !< wavemaker: bottom of the paddle face [m]
      real(rp) :: hinge_depth = 0.0_rp      !< wavemaker: still-water depth above the hinge [m]
   end type wall_motion_t

   !> Everything that moves boundary particles on a law of time: one motion
   !> per geometry object (particle%body of a wall particle indexes it) and
   !> the paddle's law.
   type :: walls_t
      logical :: moving = .false.           !< some particle moves on a law of time
      type(wall_motion_t), allocatable :: obj(:)
      type(paddle_t) :: paddle
   end type walls_t

contains

   !> The walls' motions (one per geometry object, from scene_walls) and the
   !> paddle's law (scene_paddle); moving: whether any particle moves.
   subroutine walls_init(motions, paddle, moving, walls)
      type(wall_motion_t), intent(in) :: motions(:)
      type(paddle_t), intent(in) :: paddle
      logical, intent(in) :: moving
      type(walls_t), intent(out) :: walls
      walls%obj = motions
      walls%paddle = paddle
      walls%moving = moving
   end subroutine walls_init

   !> Set position and velocity of every moving particle at time t.
   subroutine motion_apply(walls, p, t)
      type(walls_t), intent(in) :: walls
      type(particles_t), intent(inout) :: p
      real(rp), intent(in) :: t
      integer :: i, b
      real(rp) :: w, xf, uf, xg(2), vg(2)
      call paddle_motion(walls%paddle, t, xf, uf)
      do i = 1, p%n
         if (p%kind(i) /= kind_moving) cycle
         b = p%body(i)
         if (b > size(walls%obj)) cycle            ! a prescribed body: moved by body_dynamics
         associate (m => walls%obj(b))
            select case (m%motion)
            ! in the section (x, y): the walls move alike over the width (3D)
            case (wall_oscillate)
               w = 2.0_rp*pi/m%period
               p%x(1:nsec, i) = p%xb(1:nsec, i) + m%amplitude*sin(w*t)
               p%v(1:nsec, i) = m%amplitude*w*cos(w*t)
            case (wall_wavemaker)
               call paddle_place(walls%paddle%flap, p%xb(1:nsec, i), xf, uf, m%hinge, m%hinge_depth, p%x(1:nsec, i), &
                                 p%v(1:nsec, i))
               if (p%mdbc) then
                  ! the ghost point moves with the paddle (a flap turns it)
                  call paddle_place(walls%paddle%flap, p%xb(1:nsec, i) + p%gob(1:nsec, i), xf, uf, m%hinge, &
                                    m%hinge_depth, xg, vg)
                  p%gof(1:nsec, i) = xg - p%x(1:nsec, i)
               end if
            case (wall_fixed)    ! nothing to move
            case default
               call fatal('motion_apply: unknown motion '//int_str(m%motion))
            end select
         end associate
      end do
   end subroutine motion_apply

   !> The largest distance [m] between a moving wall particle and where the
   !> walls' laws put it at time t (a restart's check).
   function motion_offset(walls, p, t) result(d)
      type(walls_t), intent(in) :: walls
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: t
      real(rp) :: d
      type(particles_t) :: q
      integer :: i
      q%n = p%n
      q%kind = p%kind(1:p%n)
      q%body = p%body(1:p%n)
      q%xb = p%xb(:, 1:p%n)
      q%x = p%x(:, 1:p%n)
      q%v = p%v(:, 1:p%n)
      q%mdbc = .false.
      call motion_apply(walls, q, t)
      d = 0.0_rp
      do i = 1, p%n
         if (p%kind(i) /= kind_moving) cycle
         if (p%body(i) > size(walls%obj)) cycle
         d = max(d, norm2(q%x(:, i) - p%x(:, i)))
      end do
   end function motion_offset
end module bc_motion

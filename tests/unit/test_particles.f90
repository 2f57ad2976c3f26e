!> The particle checks of every step: particles_nan counts the NaNs in the
!> positions, velocities and densities (an infinity is not one), and particles_outside
!> finds a fluid particle beyond any side of the box or density limit (a wall
!> particle never); both are zero on a sound set.
program test_particles
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
   use kinds, only: rp
   use constants, only: kind_fluid, kind_fixed
   use particles, only: particles_nan, particles_outside
   use testing, only: check, test_summary
   implicit none
   integer, parameter :: n = 37
   real(rp) :: x(2, n), v(2, n), rho(n), r(2, n), bad(2)
   real(rp), parameter :: box(4) = [0.0_rp, 1.0_rp, 0.0_rp, 2.0_rp], rho_min = 700.0_rp, rho_max = 1300.0_rp
   integer :: kind(n), i, d, k
   character(len=40) :: name

   call random_number(r)
   x(1, :) = 0.01_rp + 0.98_rp*r(1, :)
   x(2, :) = 0.01_rp + 1.98_rp*r(2, :)
   v = 2.0_rp*r - 1.0_rp
   rho = 1000.0_rp + 50.0_rp*(r(1, :) - 0.5_rp)
   kind = kind_fluid
   kind(1:5) = kind_fixed
   call check(particles_nan(n, x, v, rho) == 0, 'a sound set has no NaN')
   call check(particles_outside(n, kind, x, rho, box, rho_min, rho_max) == 0, 'a sound set is inside')

   bad = [ieee_value(1.0_rp, ieee_quiet_nan), ieee_value(1.0_rp, ieee_positive_inf)]
   do k = 1, 2
      do i = 1, n, 12
         do d = 1, 2
            write (name, '("position ",i0,",",i0,",",i0)') k, d, i
            call check((particles_nan(n, put(x, d, i, bad(k)), v, rho) == 1) .eqv. (k == 1), trim(name))
            write (name, '("velocity ",i0,",",i0,",",i0)') k, d, i
            call check((particles_nan(n, x, put(v, d, i, bad(k)), rho) == 1) .eqv. (k == 1), trim(name))
         end do
         write (name, '("density ",i0,",",i0)') k, i
         call check((particles_nan(n, x, v, put1(rho, i, bad(k))) == 1) .eqv. (k == 1), trim(name))
      end do
   end do
   call check(particles_nan(n, put(x, 1, 7, bad(1)), put(v, 2, 30, bad(1)), rho) == 2, 'two NaNs counted')

   ! each side of the box and each density limit, on a fluid particle (i = 20) and on a wall one (i = 3)
   call outside_cases(20, .true.)
   call outside_cases(3, .false.)
   call test_summary('test_particles')

contains

   function put(a, d, i, val) result(b)
      real(rp), intent(in) :: a(:, :), val
      integer, intent(in) :: d, i
      real(rp) :: b(size(a, 1), size(a, 2))
      b = a
      b(d, i) = val
   end function put

   function put1(a, i, val) result(b)
      real(rp), intent(in) :: a(:), val
      integer, intent(in) :: i
      real(rp) :: b(size(a))
      b = a
      b(i) = val
   end function put1

   subroutine outside_cases(i, counts)
      integer, intent(in) :: i
      logical, intent(in) :: counts
      character(len=60) :: what
      write (what, '(" (particle ",i0,", fluid ",l1,")")') i, counts
      call check((particles_outside(n, kind, put(x, 1, i, -1.0e-9_rp), rho, box, rho_min, rho_max) > 0) .eqv. counts, &
                 'left of the box'//trim(what))
      call check((particles_outside(n, kind, put(x, 1, i, 1.0_rp + 1.0e-9_rp), rho, box, rho_min, rho_max) > 0) .eqv. &
                 counts, 'right of the box'//trim(what))
      call check((particles_outside(n, kind, put(x, 2, i, -1.0e-9_rp), rho, box, rho_min, rho_max) > 0) .eqv. counts, &
                 'below the box'//trim(what))
      call check((particles_outside(n, kind, put(x, 2, i, 2.0_rp + 1.0e-9_rp), rho, box, rho_min, rho_max) > 0) .eqv. &
                 counts, 'above the box'//trim(what))
      call check((particles_outside(n, kind, x, put1(rho, i, 699.9_rp), box, rho_min, rho_max) > 0) .eqv. counts, &
                 'below rho_min'//trim(what))
      call check((particles_outside(n, kind, x, put1(rho, i, 1300.1_rp), box, rho_min, rho_max) > 0) .eqv. counts, &
                 'above rho_max'//trim(what))
      ! on the limits themselves: inside
      call check(particles_outside(n, kind, put(x, 1, i, 1.0_rp), put1(rho, i, 1300.0_rp), box, rho_min, rho_max) == 0, &
                 'on the limits'//trim(what))
   end subroutine outside_cases
end program test_particles

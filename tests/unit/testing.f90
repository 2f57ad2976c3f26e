!> Minimal assertion helpers for the Fortran unit tests. Each test program
!> ends with test_summary, which prints 'N passed, M failed' and exits
!> non-zero when anything failed.
module testing
   use, intrinsic :: iso_fortran_env, only: real64
   implicit none
   private
   public :: check, check_close, test_summary, random_seed_fixed

   integer :: n_pass = 0, n_fail = 0

contains

   subroutine check(ok, name)
      logical, intent(in) :: ok
      character(len=*), intent(in) :: name
      if (ok) then
         n_pass = n_pass + 1
      else
         n_fail = n_fail + 1
         write (*, '(a)') 'FAIL: '//name
      end if
   end subroutine check

   !> |a - b| <= tol * max(|b|, floor): relative, with an absolute floor.
   subroutine check_close(a, b, tol, name, floor)
      real(real64), intent(in) :: a, b, tol
      character(len=*), intent(in) :: name
      real(real64), intent(in), optional :: floor
      real(real64) :: f
      f = 1.0e-300_real64
      if (present(floor)) f = floor
      if (abs(a - b) <= tol*max(abs(b), f)) then
         n_pass = n_pass + 1
      else
         n_fail = n_fail + 1
         write (*, '(a,3(a,es12.5))') 'FAIL: '//name, '  got ', a, '  expected ', b, '  tolerance ', tol
      end if
   end subroutine check_close

   subroutine test_summary(suite)
      character(len=*), intent(in) :: suite
      write (*, '(a,": ",i0," passed, ",i0," failed")') suite, n_pass, n_fail
      if (n_fail > 0) error stop 1
   end subroutine test_summary

   !> The same random numbers in every run of a test.
   subroutine random_seed_fixed()
      integer :: m
      integer, allocatable :: seed(:)
      call random_seed(size=m)
      allocate (seed(m))
      seed = 12345
      call random_seed(put=seed)
   end subroutine random_seed_fixed
end module testing

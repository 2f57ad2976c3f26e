!> Thin wrappers over FFTW 3's one-dimensional real transforms. This is the
!> only file that includes FFTW's Fortran interface (fftw3.f03), so the rest
!> of the code sees plain real(rp)/complex(rp) arrays.
!>
!> Each call plans with FFTW_ESTIMATE (no timing runs, arrays untouched while
!> planning) on local copies, executes and destroys the plan: the caller's
!> input is never overwritten (a c2r execution destroys its input), and
!> nothing is kept between calls. Transforms are unnormalised, as in FFTW:
!> fft_c2r(fft_r2c(x)) = n x.
module wave_fftw
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_double_complex, c_float, c_float_complex, &
                                          c_int32_t, c_ptr, c_funptr, c_intptr_t, c_size_t, c_char
   use kinds, only: rp
   use errors, only: fatal, alloc_check
   implicit none
   private
   public :: fft_c2r, fft_r2c

   ! allow(include-statement): FFTW 3 ships its Fortran 2003 interface only as this include file
   include 'fftw3.f03'

contains

   !> Backward real transform: the half spectrum spec(0:n/2) (n/2+1 values)
   !> of a real series becomes x(1:n), n = size(x):
   !>   x(j+1) = sum_{k=0}^{n-1} spec(k) exp(+2 pi i j k / n),  spec(n-k) = conj(spec(k)).
   !> The imaginary parts of spec(0) (and of spec(n/2) for even n) are ignored.
   subroutine fft_c2r(spec, x)
      complex(rp), intent(in) :: spec(0:)
      real(rp), intent(out) :: x(:)
      complex(c_double_complex), allocatable :: cin(:)
      real(c_double), allocatable :: rout(:)
      type(c_ptr) :: plan
      integer :: n
      integer :: ist
      character(len=200) :: emsg
      n = size(x)
      if (size(spec) /= n/2 + 1) call fatal('fft_c2r: half spectrum must have n/2+1 values')
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (cin(0:n/2), rout(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'cin, rout in fft_c2r')
      cin = spec
      plan = fftw_plan_dft_c2r_1d(int(n, c_int), cin, rout, fftw_estimate)
      call fftw_execute_dft_c2r(plan, cin, rout)
      call fftw_destroy_plan(plan)
      x = real(rout, rp)
   end subroutine fft_c2r

   !> Forward real transform: x(1:n) becomes its half spectrum spec(0:n/2),
   !>   spec(k) = sum_{j=0}^{n-1} x(j+1) exp(-2 pi i j k / n).
   subroutine fft_r2c(x, spec)
      real(rp), intent(in) :: x(:)
      complex(rp), intent(out) :: spec(0:)
      complex(c_double_complex), allocatable :: cout(:)
      real(c_double), allocatable :: rin(:)
      type(c_ptr) :: plan
      integer :: n
      integer :: ist
      character(len=200) :: emsg
      n = size(x)
      if (size(spec) /= n/2 + 1) call fatal('fft_r2c: half spectrum must have n/2+1 values')
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (rin(n), cout(0:n/2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'rin, cout in fft_r2c')
      rin = x
      plan = fftw_plan_dft_r2c_1d(int(n, c_int), rin, cout, fftw_estimate)
      call fftw_execute_dft_r2c(plan, rin, cout)
      call fftw_destroy_plan(plan)
      spec = cmplx(cout, kind=rp)
   end subroutine fft_r2c
end module wave_fftw

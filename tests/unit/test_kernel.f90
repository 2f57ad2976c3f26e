!> Kernels: W(0), zero outside the support, normalisation on a lattice,
!> gradient against central finite differences, cubic spline continuity.
program test_kernel
   use kinds, only: rp
   use constants, only: pi
   use kernel, only: kernel_wendland, kernel_cubic, kernel_w, kernel_f, kernel_gradw, kernel_norm
   use testing, only: check, check_close, test_summary
   implicit none
   integer :: k, kk, i, j, m
   real(rp) :: h, dp, s, d(2), g(2), e, fd(2), hh
   ! lattices fine enough that the sum is the integral (at h/dp = 1.4 the
   ! discrete sum itself is off by 0.6 %, which Shepard correction addresses)
   real(rp), parameter :: ratios(2) = [3.0_rp, 4.0_rp]
   integer, parameter :: kernels(2) = [kernel_wendland, kernel_cubic]
   character(len=8), parameter :: names(2) = ['wendland', 'cubic   ']

   h = 0.013_rp
   ! W(0) is the 2D normalisation: 7/(4 pi h^2) and 10/(7 pi h^2)
   call check_close(kernel_w(kernel_wendland, 0.0_rp, h), 7.0_rp/(4.0_rp*pi*h*h), 1.0e-14_rp, 'wendland W(0)')
   call check_close(kernel_w(kernel_cubic, 0.0_rp, h), 10.0_rp/(7.0_rp*pi*h*h), 1.0e-14_rp, 'cubic W(0)')
   do kk = 1, 2
      k = kernels(kk)
      ! compact support 2h, and W, F vanish at its edge
      call check(abs(kernel_w(k, 2.0_rp*h, h)) <= 0.0_rp .and. abs(kernel_w(k, 3.0_rp*h, h)) <= 0.0_rp, &
                 trim(names(kk))//' zero outside 2h')
      call check(abs(kernel_w(k, 1.999999_rp*h, h)) < 1.0e-12_rp*kernel_norm(k, h), trim(names(kk))//' W -> 0 at 2h')
      ! normalisation: sum_j W(x_i - x_j) dp^2 over a square lattice is 1 (error below 1e-3)
      do m = 1, size(ratios)
         dp = h/ratios(m)
         s = 0.0_rp
         do j = -10, 10
            do i = -10, 10
               s = s + kernel_w(k, dp*hypot(real(i, rp), real(j, rp)), h)*dp*dp
            end do
         end do
         call check_close(s, 1.0_rp, 1.0e-3_rp, trim(names(kk))//' lattice normalisation')
      end do
      ! gradient against central differences of W, at many points of the support
      e = 1.0e-6_rp*h
      do i = 1, 40
         d = 1.9_rp*h*[cos(0.37_rp*i), sin(0.37_rp*i)]*(0.02_rp + 0.98_rp*i/40.0_rp)
         g = kernel_gradw(k, d, h)
         fd(1) = (kernel_w(k, norm2(d + [e, 0.0_rp]), h) - kernel_w(k, norm2(d - [e, 0.0_rp]), h))/(2*e)
         fd(2) = (kernel_w(k, norm2(d + [0.0_rp, e]), h) - kernel_w(k, norm2(d - [0.0_rp, e]), h))/(2*e)
         call check_close(norm2(g - fd), 0.0_rp, 1.0_rp, trim(names(kk))//' gradient vs finite differences', &
                          floor=1.0e-6_rp*maxval(abs(fd)) + 1.0e-9_rp*kernel_norm(k, h)/h)
      end do
      ! the gradient points from j to i times a negative F: W decreases with r
      call check(kernel_f(k, 0.5_rp*h, h) < 0.0_rp, trim(names(kk))//' F < 0')
   end do
   ! the cubic spline pieces meet at q = 1 (value and slope)
   hh = 1.0e-9_rp*h
   call check_close(kernel_w(kernel_cubic, h - hh, h), kernel_w(kernel_cubic, h + hh, h), 1.0e-8_rp, 'cubic W continuous at q=1')
   call check_close(kernel_f(kernel_cubic, h - hh, h), kernel_f(kernel_cubic, h + hh, h), 1.0e-7_rp, 'cubic F continuous at q=1')
   call test_summary('test_kernel')
end program test_kernel

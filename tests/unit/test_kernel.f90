!> Kernels: W(0), zero outside the support, normalisation on a lattice,
!> gradient against central finite differences, cubic spline continuity; in the
!> dimensions of the build (ndim: the 3D build runs it too, make unit-3d).
program test_kernel
   use kinds, only: rp
   use constants, only: pi, ndim
   use kernel, only: kernel_wendland, kernel_cubic, kernel_w, kernel_f, kernel_gradw, kernel_norm
   use testing, only: check, check_close, test_summary
   implicit none
   integer :: k, kk, i, j, l, m, a, lz
   real(rp) :: h, dp, s, d(ndim), g(ndim), e, fd(ndim), hh, u(ndim), u3(3), w0(2)
   ! lattices fine enough that the sum is the integral (at h/dp = 1.4 the
   ! discrete sum itself is off by 0.6 %, which Shepard correction addresses)
   real(rp), parameter :: ratios(2) = [3.0_rp, 4.0_rp]
   integer, parameter :: kernels(2) = [kernel_wendland, kernel_cubic]
   character(len=8), parameter :: names(2) = ['wendland', 'cubic   ']

   h = 0.013_rp
   ! W(0) is the normalisation: 7/(4 pi h^2) and 10/(7 pi h^2) in 2D, 21/(16 pi h^3) and 1/(pi h^3) in 3D
   if (ndim == 2) then
      w0 = [7.0_rp/(4.0_rp*pi*h*h), 10.0_rp/(7.0_rp*pi*h*h)]
   else
      w0 = [21.0_rp/(16.0_rp*pi*h**3), 1.0_rp/(pi*h**3)]
   end if
   call check_close(kernel_w(kernel_wendland, 0.0_rp, h), w0(1), 1.0e-14_rp, 'wendland W(0)')
   call check_close(kernel_w(kernel_cubic, 0.0_rp, h), w0(2), 1.0e-14_rp, 'cubic W(0)')
   lz = merge(0, 10, ndim == 2)
   do kk = 1, 2
      k = kernels(kk)
      ! compact support 2h, and W, F vanish at its edge
      call check(abs(kernel_w(k, 2.0_rp*h, h)) <= 0.0_rp .and. abs(kernel_w(k, 3.0_rp*h, h)) <= 0.0_rp, &
                 trim(names(kk))//' zero outside 2h')
      call check(abs(kernel_w(k, 1.999999_rp*h, h)) < 1.0e-12_rp*kernel_norm(k, h), trim(names(kk))//' W -> 0 at 2h')
      ! normalisation: sum_j W(x_i - x_j) dp^ndim over a square (cubic) lattice is 1 (error below 1e-3)
      do m = 1, size(ratios)
         dp = h/ratios(m)
         s = 0.0_rp
         do l = -lz, lz
            do j = -10, 10
               do i = -10, 10
                  s = s + kernel_w(k, dp*norm2(real([i, j, l], rp)), h)*dp**ndim
               end do
            end do
         end do
         call check_close(s, 1.0_rp, 1.0e-3_rp, trim(names(kk))//' lattice normalisation')
      end do
      ! gradient against central differences of W, at many points of the support
      e = 1.0e-6_rp*h
      do i = 1, 40
         ! directions on a spiral (in 3D tilted out of the plane by a turning angle)
         u3 = [cos(0.37_rp*i), sin(0.37_rp*i), 0.6_rp*sin(0.91_rp*i)]
         u = u3(1:ndim)
         d = 1.9_rp*h*u/norm2(u)*(0.02_rp + 0.98_rp*i/40.0_rp)
         g = kernel_gradw(k, d, h)
         do a = 1, ndim
            u = 0.0_rp; u(a) = e
            fd(a) = (kernel_w(k, norm2(d + u), h) - kernel_w(k, norm2(d - u), h))/(2*e)
         end do
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

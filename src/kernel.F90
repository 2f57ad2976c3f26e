!> SPH kernels in 2D and 3D (ndim): Wendland C2 and cubic spline, with support 2h.
!> The formulas themselves are in kernel_formulas.inc, shared with the pair loops.
module kernel
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use kinds, only: rp
   use constants, only: pi, ndim
   use options, only: kernel_wendland, kernel_cubic
   implicit none
   private
   public :: kernel_wendland, kernel_cubic, kernel_norm, kernel_w, kernel_f, kernel_gradw

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> Normalisation aw (W = aw w(q)) in ndim dimensions, so that W integrates to 1 over
   !> the plane (2D) or space (3D); Monaghan (1992) for the spline, Wendland (1995) for C2.
   pure real(rp) function kernel_norm(k, h) result(aw)
      integer, intent(in) :: k
      real(rp), intent(in) :: h
      ! (an unknown kernel, which no input can give, makes NaN: pure procedures cannot stop)
      select case (k)
      case (kernel_cubic)
         aw = merge(10.0_rp/(7.0_rp*pi*h*h), 1.0_rp/(pi*h*h*h), ndim == 2)
      case (kernel_wendland)
         aw = merge(7.0_rp/(4.0_rp*pi*h*h), 21.0_rp/(16.0_rp*pi*h*h*h), ndim == 2)
      case default
         aw = ieee_value(aw, ieee_quiet_nan)
      end select
   end function kernel_norm

   !> W(r) for r >= 0.
   elemental real(rp) function kernel_w(k, r, h) result(w)
      integer, intent(in) :: k
      real(rp), intent(in) :: r, h
      real(rp) :: q
      q = r/h
      w = 0.0_rp
      if (q >= 2.0_rp) return
      select case (k)
      case (kernel_cubic)
         w = kernel_norm(k, h)*KW_CUBIC(q)
      case (kernel_wendland)
         w = kernel_norm(k, h)*KW_WENDLAND(q)
      case default
         w = ieee_value(w, ieee_quiet_nan)
      end select
   end function kernel_w

   !> F(r) with grad_i W = F (x_i - x_j); r > 0.
   elemental real(rp) function kernel_f(k, r, h) result(f)
      integer, intent(in) :: k
      real(rp), intent(in) :: r, h
      real(rp) :: q
      q = r/h
      f = 0.0_rp
      if (q >= 2.0_rp) return
      select case (k)
      case (kernel_cubic)
         f = kernel_norm(k, h)/(h*h)*KF_CUBIC(q)
      case (kernel_wendland)
         f = kernel_norm(k, h)/(h*h)*KF_WENDLAND(q)
      case default
         f = ieee_value(f, ieee_quiet_nan)
      end select
   end function kernel_f

   !> Gradient with respect to x_i of W(|x_i - x_j|), given d = x_i - x_j.
   pure function kernel_gradw(k, d, h) result(g)
      integer, intent(in) :: k
      real(rp), intent(in) :: d(ndim), h
      real(rp) :: g(ndim), r
      r = norm2(d)
      g = 0.0_rp
      if (r > 0.0_rp) g = kernel_f(k, r, h)*d
   end function kernel_gradw
end module kernel

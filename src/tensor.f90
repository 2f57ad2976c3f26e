!> Small vector and tensor algebra in ndim dimensions, for the pair code of
!> the contacts and the gradient correction: symmetric tensors stored as their
!> nsym components in the slot order of the pair loops (xx, xy, yy in 2D; xx,
!> xy, xz, yy, yz, zz in 3D), its determinant and adjugate, and an orthonormal
!> basis of the plane tangent to a unit normal. The 2D forms keep the order of
!> the products of the formulas they replaced, so results did not change by a bit.
module tensor
   use kinds, only: rp
   use constants, only: ndim, nsym
   implicit none
   private
   public :: sym_slot, sym_outer, sym_quad, sym_det, sym_adjugate, sym_identity, tangent_basis, tangent_basis_along

contains

   !> The slot of component (a, b) of a symmetric tensor (1-based a, b).
   pure integer function sym_slot(a, b) result(s)
      integer, intent(in) :: a, b
      integer :: r
      s = abs(a - b) + 1
      do r = 0, min(a, b) - 2
         s = s + ndim - r
      end do
   end function sym_slot

   !> n n^T.
   pure function sym_outer(n) result(t)
      real(rp), intent(in) :: n(ndim)
      real(rp) :: t(nsym)
      integer :: a, b
      do a = 1, ndim
         do b = a, ndim
            t(sym_slot(a, b)) = n(a)*n(b)
         end do
      end do
   end function sym_outer

   !> n^T T n.
   pure real(rp) function sym_quad(t, n) result(q)
      real(rp), intent(in) :: t(nsym), n(ndim)
      integer :: a, b
      if (ndim == 2) then   ! the sum in the order of the 2D formula it replaced
         q = t(1)*n(1)**2 + 2.0_rp*t(2)*n(1)*n(ndim) + t(nsym)*n(ndim)**2
         return
      end if
      q = 0.0_rp
      do a = 1, ndim
         q = q + t(sym_slot(a, a))*n(a)**2
         do b = a + 1, ndim
            q = q + 2.0_rp*t(sym_slot(a, b))*n(a)*n(b)
         end do
      end do
   end function sym_quad

   !> The identity.
   pure function sym_identity() result(t)
      real(rp) :: t(nsym)
      integer :: a, b
      do a = 1, ndim
         do b = a, ndim
            t(sym_slot(a, b)) = merge(1.0_rp, 0.0_rp, a == b)
         end do
      end do
   end function sym_identity

   !> The determinant.
   pure real(rp) function sym_det(t) result(d)
      real(rp), intent(in) :: t(nsym)
      real(rp) :: m(ndim, ndim)
      integer :: b
      if (ndim == 2) then
         d = t(1)*t(nsym) - t(2)*t(2)
      else
         m = sym_full(t)
         d = 0.0_rp
         do b = 1, ndim
            d = d + m(1, b)*cofactor(m, 1, b)
         end do
      end if
   end function sym_det

   !> The adjugate: the inverse times the determinant (sym_det).
   pure function sym_adjugate(t) result(u)
      real(rp), intent(in) :: t(nsym)
      real(rp) :: u(nsym), m(ndim, ndim)
      integer :: a, b
      if (ndim == 2) then
         u(1) = t(nsym)
         u(2) = -t(2)
         u(nsym) = t(1)
      else
         m = sym_full(t)
         do a = 1, ndim
            do b = a, ndim
               u(sym_slot(a, b)) = cofactor(m, b, a)
            end do
         end do
      end if
   end function sym_adjugate

   !> An orthonormal basis of the plane tangent to the unit normal n: one
   !> vector in 2D (n turned by +90 degrees), two in 3D.
   pure function tangent_basis(n) result(e)
      real(rp), intent(in) :: n(ndim)
      real(rp) :: e(ndim, ndim - 1), a(ndim)
      if (ndim == 2) then
         e(1, 1) = -n(ndim)
         e(ndim, 1) = n(1)
      else
         ! along the axis least aligned with n
         a = 0.0_rp
         a(minloc(abs(n), 1)) = 1.0_rp
         e = tangent_basis_along(n, a)
      end if
   end function tangent_basis

   !> An orthonormal basis of the plane tangent to the unit normal n whose
   !> first vector is the direction a (not along n) made orthogonal to n; in
   !> 3D the second is n x e1. A face's lattice axes from one of them.
   pure function tangent_basis_along(n, a) result(e)
      real(rp), intent(in) :: n(ndim), a(ndim)
      real(rp) :: e(ndim, ndim - 1)
      integer :: k, k1, k2
      e(:, 1) = a - dot_product(a, n)*n
      e(:, 1) = e(:, 1)/norm2(e(:, 1))
      if (ndim == 3) then
         do k = 1, ndim
            k1 = mod(k, ndim) + 1
            k2 = mod(k + 1, ndim) + 1
            e(k, ndim - 1) = n(k1)*e(k2, 1) - n(k2)*e(k1, 1)
         end do
      end if
   end function tangent_basis_along

   !> The full matrix of a symmetric tensor.
   pure function sym_full(t) result(m)
      real(rp), intent(in) :: t(nsym)
      real(rp) :: m(ndim, ndim)
      integer :: a, b
      do a = 1, ndim
         do b = 1, ndim
            m(a, b) = t(sym_slot(a, b))
         end do
      end do
   end function sym_full

   !> The cofactor (a, b) of a 3 x 3 matrix: cyclic indices give the sign.
   pure real(rp) function cofactor(m, a, b) result(c)
      real(rp), intent(in) :: m(ndim, ndim)
      integer, intent(in) :: a, b
      integer :: a1, a2, b1, b2
      a1 = mod(a, ndim) + 1
      a2 = mod(a + 1, ndim) + 1
      b1 = mod(b, ndim) + 1
      b2 = mod(b + 1, ndim) + 1
      c = m(a1, b1)*m(a2, b2) - m(a1, b2)*m(a2, b1)
   end function cofactor
end module tensor

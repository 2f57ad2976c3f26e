!> The small tensor algebra of the pair code (tensor.f90), in the build's
!> dimension: the slots of a symmetric tensor cover each component once; n n^T,
!> n^T T n, the determinant and the adjugate against the full matrices
!> (T adj(T) = det(T) I); the tangent basis orthonormal and orthogonal to n.
program test_tensor
   use kinds, only: rp
   use constants, only: ndim, nsym
   use tensor, only: sym_slot, sym_outer, sym_quad, sym_det, sym_adjugate, sym_identity, tangent_basis
   use testing, only: check, check_close, test_summary, random_seed_fixed
   implicit none
   real(rp) :: t(nsym), m(ndim, ndim), a(ndim, ndim), n(ndim), e(ndim, ndim - 1), u(nsym), d
   real(rp) :: err_q, err_o, err_i, err_e
   integer :: k, i, j, seen(nsym)

   seen = 0
   do i = 1, ndim
      do j = 1, ndim
         if (sym_slot(i, j) /= sym_slot(j, i)) seen = -99
         if (j >= i) seen(sym_slot(i, j)) = seen(sym_slot(i, j)) + 1
      end do
   end do
   call check(all(seen == 1), 'symmetric slots: each of the nsym components once, (a, b) = (b, a)')
   call check(maxval(abs(full(sym_identity()) - eye())) <= 0.0_rp, 'the identity')

   call random_seed_fixed()
   err_q = 0.0_rp; err_o = 0.0_rp; err_i = 0.0_rp; err_e = 0.0_rp
   do k = 1, 200
      call random_number(a)
      a = a - 0.5_rp
      m = matmul(a, transpose(a)) + 0.1_rp*eye()      ! symmetric, positive definite
      do i = 1, ndim
         do j = i, ndim
            t(sym_slot(i, j)) = m(i, j)
         end do
      end do
      call random_number(n)
      n = (n - 0.5_rp)
      n = n/norm2(n)
      err_q = max(err_q, abs(sym_quad(t, n) - dot_product(n, matmul(m, n)))/maxval(abs(m)))
      err_o = max(err_o, maxval(abs(full(sym_outer(n)) - spread(n, 2, ndim)*spread(n, 1, ndim))))
      d = sym_det(t)
      u = sym_adjugate(t)
      err_i = max(err_i, maxval(abs(matmul(m, full(u)) - d*eye()))/(abs(d) + maxval(abs(m))**ndim))
      e = tangent_basis(n)
      err_e = max(err_e, maxval(abs(matmul(transpose(e), e) - eye_t())), maxval(abs(matmul(n, e))))
   end do
   call check_close(err_q, 0.0_rp, 1.0_rp, 'n^T T n against the full matrix, to 1e-14', floor=1.0e-14_rp)
   call check_close(err_o, 0.0_rp, 1.0_rp, 'n n^T against the full matrix, to 1e-15', floor=1.0e-15_rp)
   call check_close(err_i, 0.0_rp, 1.0_rp, 'T adj(T) = det(T) I, to 1e-14', floor=1.0e-14_rp)
   call check_close(err_e, 0.0_rp, 1.0_rp, 'tangent basis orthonormal and normal to n, to 1e-15', floor=1.0e-15_rp)
   call test_summary('test_tensor')
contains
   pure function full(s) result(f)
      real(rp), intent(in) :: s(nsym)
      real(rp) :: f(ndim, ndim)
      integer :: p, q
      do p = 1, ndim
         do q = 1, ndim
            f(p, q) = s(sym_slot(p, q))
         end do
      end do
   end function full
   pure function eye() result(f)
      real(rp) :: f(ndim, ndim)
      integer :: p
      f = 0.0_rp
      do p = 1, ndim
         f(p, p) = 1.0_rp
      end do
   end function eye
   pure function eye_t() result(f)
      real(rp) :: f(ndim - 1, ndim - 1)
      integer :: p
      f = 0.0_rp
      do p = 1, ndim - 1
         f(p, p) = 1.0_rp
      end do
   end function eye_t
end program test_tensor

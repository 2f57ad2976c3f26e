!> The weight P of the seed paper's contact in 3D (contact_pair, make unit-3d):
!> over the particles of a face, a plane lattice of spacing dp, the shares of a
!> particle facing it add up to one wherever it sits, for a lattice along the
!> world axes and for one turned about its normal and tilted; a weight of the
!> distance alone would not (its sum ranges from 0.79 to 1). The tangent basis
!> of a direction is orthonormal, its first vector that direction in the plane.
program test_partition3d
   use kinds, only: rp
   use constants, only: ndim, pi
   use tensor, only: tangent_basis_along
   use contact_pair, only: lattice_share
   use testing, only: check, check_close, test_summary
   implicit none
   real(rp), parameter :: dp = 0.01_rp
   real(rp) :: n(ndim), a(ndim), e(ndim, ndim - 1), off(2), sum_w, worst, radial_lo, u(ndim), w
   integer :: trial, i, j

   call check(ndim == 3, 'a 3D build (ndim = 3)')
   ! a tilted normal and a direction not along it
   n = [0.3_rp, 0.9_rp, -0.2_rp]
   n = n/norm2(n)
   a = [1.0_rp, 0.2_rp, 0.4_rp]
   e = tangent_basis_along(n, a)
   call check_close(norm2(e(:, 1)), 1.0_rp, 1.0e-14_rp, 'e1 is a unit vector')
   call check_close(norm2(e(:, 2)), 1.0_rp, 1.0e-14_rp, 'e2 is a unit vector')
   call check(abs(dot_product(e(:, 1), n)) < 1.0e-14_rp .and. abs(dot_product(e(:, 2), n)) < 1.0e-14_rp .and. &
              abs(dot_product(e(:, 1), e(:, 2))) < 1.0e-14_rp, 'e1, e2 and n orthogonal')
   u = a - dot_product(a, n)*n
   call check_close(dot_product(e(:, 1), u/norm2(u)), 1.0_rp, 1.0e-14_rp, 'e1 along a in the plane')

   ! the face's lattice on those axes; the facing particle at pseudo-random offsets
   worst = 0.0_rp
   radial_lo = 1.0_rp
   do trial = 1, 200
      off = [modulo(0.618034_rp*trial, 1.0_rp), modulo(0.414214_rp*trial*trial, 1.0_rp)]*dp
      sum_w = 0.0_rp
      w = 0.0_rp
      do j = -3, 3
         do i = -3, 3
            ! t: the offset of the facing particle from lattice point (i, j), in the plane
            u = (off(1) - i*dp)*e(:, 1) + (off(2) - j*dp)*e(:, 2)
            sum_w = sum_w + lattice_share(u, e, dp)
            if (norm2(u) < dp) w = w + 0.5_rp*(1.0_rp + cos(pi*norm2(u)/dp))
         end do
      end do
      worst = max(worst, abs(sum_w - 1.0_rp))
      radial_lo = min(radial_lo, w)
   end do
   call check(worst < 1.0e-12_rp, 'the shares over a face add up to one at 200 positions')
   call check(radial_lo < 0.85_rp, 'a weight of the distance alone does not (its sum falls below 0.85)')
   ! the weight is zero from dp on along either axis, and one over a lattice point
   call check_close(lattice_share(0.0_rp*n, e, dp), 1.0_rp, 1.0e-15_rp, 'one over a lattice point')
   call check(.not. lattice_share(dp*e(:, 2), e, dp) > 0.0_rp, 'zero at dp along e2')
   call check(lattice_share(0.7_rp*dp*(e(:, 1) + e(:, 2)), e, dp) > 0.0_rp, 'nonzero inside the square')
   call test_summary('test_partition3d')
end program test_partition3d

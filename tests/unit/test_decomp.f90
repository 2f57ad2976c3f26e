!> Slab decomposition: balanced edges split the particle count evenly to within
!> half a column's count, every slab keeps at least one column (also when the
!> particles crowd into one column), and a particle's owner is the rank whose
!> columns hold it.
program test_decomp
   use kinds, only: rp
   use decomp, only: decomp_t, decomp_init, decomp_balance, decomp_owner, decomp_set_edges
   use testing, only: check, test_summary
   implicit none
   integer, parameter :: ncol = 40
   integer :: hist(0:ncol - 1), e(0:4), r, k, worst
   real(rp) :: share
   logical :: moved
   type(decomp_t) :: d

   ! 4 ranks; water in the left quarter (heavy columns), walls elsewhere (light ones)
   call decomp_init(d, 0.0_rp, 1.0_rp, ncol, 4, 0)
   hist = 10
   hist(0:9) = 500
   call decomp_balance(d, hist, moved)
   call check(moved, 'edges move away from equal widths')
   e = d%edge
   call check(e(0) == 0 .and. e(4) == ncol, 'the slabs cover every column')
   call check(all(e(1:4) - e(0:3) >= 1), 'every slab at least one column wide')
   ! each rank's count within half of its edge columns' counts of the ideal share
   worst = 0
   do r = 0, 3
      share = real(sum(hist), rp)/4.0_rp
      k = sum(hist(e(r):e(r + 1) - 1))
      worst = max(worst, nint(abs(k - share)))
   end do
   call check(worst <= maxval(hist), 'counts within one column of an even split')
   call decomp_balance(d, hist, moved)
   call check(.not. moved, 'balancing again moves nothing')

   ! everything in one column: the other slabs stay one column wide
   hist = 0
   hist(20) = 1000
   call decomp_balance(d, hist, moved)
   e = d%edge
   call check(all(e(1:4) - e(0:3) >= 1), 'one crowded column: slabs still one column wide')
   call check(e(4) == ncol, 'one crowded column: the last slab ends at the domain edge')

   ! owners follow the columns
   call decomp_set_edges(d, [0, 5, 10, 30, 40])
   call check(decomp_owner(d, 0.5_rp) == 0 .and. decomp_owner(d, 9.99_rp) == 1 .and. decomp_owner(d, 10.0_rp) == 2, &
              'owner by column')
   call check(decomp_owner(d, -3.0_rp) == 0 .and. decomp_owner(d, 99.0_rp) == 3, 'points outside: nearest slab')
   call test_summary('test_decomp')
end program test_decomp

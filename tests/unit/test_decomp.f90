!> Slab decomposition: balanced edges split the particle count evenly to within
!> half a column's count, every slab keeps at least one column (also when the
!> particles crowd into one column), and a particle's owner is the rank whose
!> columns hold it. decomp_count weighs a fluid particle twice a wall one, and
!> two ranks over water beside a wall split the work, not the particle count.
program test_decomp
   use kinds, only: rp
   use constants, only: kind_fluid, kind_fixed
   use decomp, only: decomp_t, decomp_init, decomp_balance, decomp_owner, decomp_set_edges, decomp_count
   use testing, only: check, test_summary
   implicit none
   integer, parameter :: ncol = 40
   integer :: hist(0:ncol - 1), e(0:4), r, k, worst, i
   integer, allocatable :: kind(:)
   real(rp), allocatable :: x(:, :)
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

   ! water in columns 0..19 (30 particles each), a thick wall in 20..39 (30 each):
   ! the work is 2 x 600 + 600, and two ranks split it at 1/2, in column 15
   allocate (x(2, 40*30), kind(40*30))
   do i = 1, 40*30
      x(:, i) = [real((i - 1)/30, rp) + 0.5_rp, 0.0_rp]
      kind(i) = merge(kind_fluid, kind_fixed, (i - 1)/30 < 20)
   end do
   call decomp_init(d, 0.0_rp, 1.0_rp, ncol, 2, 0)
   call decomp_count(d, x, kind, size(kind), hist)
   call check(all(hist(0:19) == 60) .and. all(hist(20:39) == 30), 'fluid counted twice, walls once')
   call decomp_balance(d, hist, moved)
   call check(d%edge(1) == 15, 'two ranks split the work: water 0..14 | water 15..19 and the wall')
   call test_summary('test_decomp')
end program test_decomp

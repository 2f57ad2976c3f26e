!> The pair list of one force evaluation: every pair of particles closer than
!> the kernel support, each once, found by the grid's half stencil, with the
!> kernel factor F of the pair (grad_i W_ij = F (x_i - x_j)). Every pass over
!> the pairs (gradient correction, SPS velocity gradients, continuity and
!> momentum) reads this list instead of searching the grid again: the search,
!> the square root and the kernel are paid once per evaluation, not once per
!> pass, and a pass has no rejected candidates and no cut-off test.
!>
!> Order: the pairs of particle i are pairs first(i-i0+1) .. first(i-i0+2)-1,
!> with i in increasing order and its partners in the grid's stencil order, so
!> a pass over the list sums in the same order as a pass over the grid did.
!> Rows of the halo particles (on several ranks) are empty: they appear only
!> as partners j. A list holds the rows of every particle (i0 = 1) or those of
!> one cell column (fluid_forces keeps a window of a few columns' lists).
module nbr_list
   use kinds, only: rp
   use constants, only: ndim
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use grid, only: grid_t, grid_ranges, grid_last_cell, grid_nranges
   use kernel, only: kernel_cubic, kernel_wendland
   implicit none
   private
   public :: nbr_t, nbr_build

   type :: nbr_t
      integer :: n = 0                     !< particles the list was built for
      integer :: i0 = 1, i1 = 0            !< its rows: particles i0 .. i1
      integer :: np = 0                    !< pairs
      integer, allocatable :: first(:)     !< pairs of particle i: first(i-i0+1) .. first(i-i0+2)-1
      integer, allocatable :: j(:)         !< partner of each pair (the later particle of the stencil)
      real(rp), allocatable :: f(:)        !< kernel factor F of each pair [1/m4 in 2D]
   end type nbr_t

contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> The pairs of the n particles at x, sorted by the grid g, within the
   !> support (squared distance below support2), and their kernel factors
   !> for the kernel k with smoothing length h and factor fw = aw/h^2: the
   !> rows of every particle, or with col those of the particles of cell
   !> column col of the grid (1 .. g%ncol) only.
   subroutine nbr_build(nb, g, x, n, k, h, support2, fw, col)
      type(nbr_t), intent(inout) :: nb
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:, :)
      integer, intent(in) :: n, k
      real(rp), intent(in) :: h, support2, fw
      integer, intent(in), optional :: col
      integer :: c, i, j, r, m, jlo(grid_nranges), jhi(grid_nranges), need, c_lo, c_hi, nrows
      real(rp) :: xi(ndim), dr(ndim), r2, q, hinv
      integer :: ist
      character(len=200) :: emsg
      if (present(col)) then
         c_lo = col*g%stride + 1
         c_hi = min(col*g%stride + g%stride, grid_last_cell(g))
         nb%i0 = g%cstart(c_lo)
         nb%i1 = g%cstart(c_hi + 1) - 1
      else
         c_lo = 1
         c_hi = grid_last_cell(g)
         nb%i0 = 1
         nb%i1 = n
      end if
      nrows = nb%i1 - nb%i0 + 1
      if (allocated(nb%first)) then
         if (size(nb%first) < nrows + 1) deallocate (nb%first)
      end if
      if (.not. allocated(nb%first)) then
         allocate (nb%first(max(nrows + 1, 64)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'nb%first in nbr_build')
      end if
      ! a first guess of the size (13 pairs a particle at h = sqrt(2) dp, 16 at
      ! 1.6 dp): grown by a quarter when short, so that it stays close to the need
      if (.not. allocated(nb%j)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (nb%j(max(8*nrows, 1024)), nb%f(max(8*nrows, 1024)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the pair list', max(8*nrows, 1024))
      end if
      nb%n = n
      m = 0
      ! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "nbr_pairs.inc"
      ! particles of the last column (the halo or an empty ghost column) start no pairs
      nb%first(g%cstart(c_hi + 1) - nb%i0 + 1:nrows + 1) = m + 1
      nb%np = m
      ! the kernel factor of every pair, from its squared distance: one loop
      ! per kernel, without branches, that the compiler vectorises
      hinv = 1.0_rp/h
      select case (k)
      case (kernel_cubic)
         do m = 1, nb%np
            q = sqrt(nb%f(m))*hinv
            nb%f(m) = fw*KF_CUBIC(q)
         end do
      case (kernel_wendland)
         do m = 1, nb%np
            q = sqrt(nb%f(m))*hinv
            nb%f(m) = fw*KF_WENDLAND(q)
         end do
      case default
         call fatal('nbr_build: unknown kernel '//int_str(k)//' (internal error)')
      end select
   end subroutine nbr_build

   !> Room for at least need pairs, keeping the first ones.
   subroutine grow(nb, need)
      type(nbr_t), intent(inout) :: nb
      integer, intent(in) :: need
      integer, allocatable :: jn(:)
      real(rp), allocatable :: fn(:)
      integer :: cap
      integer :: ist
      character(len=200) :: emsg
      cap = max(need, size(nb%j) + size(nb%j)/4)
      ! allow(multiple-allocations-with-stat): either refused is the same stop
      allocate (jn(cap), fn(cap), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the pair list', cap)
      jn(1:size(nb%j)) = nb%j
      fn(1:size(nb%f)) = nb%f
      call move_alloc(jn, nb%j)
      call move_alloc(fn, nb%f)
   end subroutine grow
end module nbr_list

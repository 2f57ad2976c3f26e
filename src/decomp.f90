!> Domain decomposition into slabs along x: rank r owns the cell columns
!> edge(r) .. edge(r+1)-1 of the neighbour grid (cells of side 2h), so a
!> slab is never narrower than the kernel support. A particle belongs to
!> the rank whose slab holds its column (grid_column). The edges are chosen
!> so that every rank has about the same work (decomp_count's weights).
module decomp
   use errors, only: alloc_check
   use kinds, only: rp
   use constants, only: kind_fluid, ndim
   use grid, only: grid_column
   implicit none
   private
   public :: decomp_t, decomp_init, decomp_owner, decomp_count, decomp_balance, decomp_set_edges, decomp_lo, &
             decomp_hi

   !> The slabs of a run: the columns, the ranks and each rank's first column.
   type :: decomp_t
      real(rp) :: x0 = 0.0_rp, cs = 1.0_rp   !< left edge and width of the cell columns [m]
      integer :: ncol = 1                     !< cell columns of the domain
      integer :: nr = 1, me = 0               !< ranks, and this rank
      integer, allocatable :: edge(:)         !< edge(0:nr): first column of each rank, edge(nr) = ncol
      integer, allocatable :: owner(:)        !< owner(0:ncol-1): rank of each column
   end type decomp_t

   !> a fluid particle's work in units of a wall or body particle's (decomp_count):
   !> 2 in 2D (the breakwater, doc/parallel.md); 3 in 3D, where a fluid particle
   !> has some 95 neighbours against 12 (the 3D dam break's two ranks: 2.7, doc/3d.md)
   integer, parameter :: weight_fluid = merge(2, 3, ndim == 2)

contains

   !> Columns of side cs from x0, ncol of them, over nranks ranks; the
   !> slabs start equal in width.
   subroutine decomp_init(d, xmin, cell, ncolumns, nranks, rank)
      type(decomp_t), intent(out) :: d
      real(rp), intent(in) :: xmin, cell
      integer, intent(in) :: ncolumns, nranks, rank
      integer :: r
      integer :: ist
      character(len=200) :: emsg
      d%x0 = xmin
      d%cs = cell
      d%ncol = ncolumns
      d%nr = nranks
      d%me = rank
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (d%edge(0:d%nr), d%owner(0:d%ncol - 1), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'edge, owner in decomp_init')
      do r = 0, d%nr
         d%edge(r) = (r*d%ncol)/d%nr
      end do
      call set_owner(d)
   end subroutine decomp_init

   subroutine set_owner(d)
      type(decomp_t), intent(inout) :: d
      integer :: r
      do r = 0, d%nr - 1
         d%owner(d%edge(r):d%edge(r + 1) - 1) = r
      end do
   end subroutine set_owner

   !> First column of this rank's slab (0-based).
   pure integer function decomp_lo(d)
      type(decomp_t), intent(in) :: d
      decomp_lo = d%edge(d%me)
   end function decomp_lo

   !> One past the last column of this rank's slab.
   pure integer function decomp_hi(d)
      type(decomp_t), intent(in) :: d
      decomp_hi = d%edge(d%me + 1)
   end function decomp_hi

   !> Adopt given edges (a restart on the same number of ranks).
   subroutine decomp_set_edges(d, e)
      type(decomp_t), intent(inout) :: d
      integer, intent(in) :: e(0:)
      d%edge = e(0:d%nr)
      call set_owner(d)
   end subroutine decomp_set_edges

   pure integer function decomp_column(d, x) result(k)
      type(decomp_t), intent(in) :: d
      real(rp), intent(in) :: x
      k = grid_column(d%x0, d%cs, d%ncol, x)
   end function decomp_column

   !> Rank that owns a particle at abscissa x.
   pure integer function decomp_owner(d, x) result(r)
      type(decomp_t), intent(in) :: d
      real(rp), intent(in) :: x
      r = d%owner(grid_column(d%x0, d%cs, d%ncol, x))
   end function decomp_owner

   !> The work of particles 1..n (abscissae x(1, :), kinds kind) by cell column
   !> (0-based): weight_fluid for a fluid particle, 1 for any other. A fluid
   !> particle takes part in every pair of its neighbourhood, a wall or body
   !> particle only in those with water; on the breakwater (doc/parallel.md)
   !> the two ranks wait least for each other with fluid counted twice (2D).
   subroutine decomp_count(d, x, kind, n, count)
      type(decomp_t), intent(in) :: d
      real(rp), intent(in) :: x(:, :)
      integer, intent(in) :: kind(:)
      integer, intent(in) :: n
      integer, intent(out) :: count(0:)
      integer :: i, k
      count(0:d%ncol - 1) = 0
      do i = 1, n
         k = decomp_column(d, x(1, i))
         count(k) = count(k) + merge(weight_fluid, 1, kind(i) == kind_fluid)
      end do
   end subroutine decomp_count

   !> New edges from the work count of every column (decomp_count, summed over
   !> the ranks): rank r starts at the first column where the running count
   !> reaches r/nranks of the total, each slab at least one column wide.
   !> moved: whether any edge moved.
   subroutine decomp_balance(d, count, moved)
      type(decomp_t), intent(inout) :: d
      integer, intent(in) :: count(0:)
      logical, intent(out) :: moved
      integer :: r, k, e(0:d%nr)
      real(rp) :: total, cum, target
      total = real(sum(count(0:d%ncol - 1)), rp)
      e(0) = 0
      e(d%nr) = d%ncol
      k = 0
      cum = 0.0_rp
      do r = 1, d%nr - 1
         target = total*real(r, rp)/real(d%nr, rp)
         ! advance while the column still fits under the target (nearest split)
         advance: do while (k < d%ncol - 1)
            if (cum + 0.5_rp*count(k) >= target) exit advance
            cum = cum + count(k)
            k = k + 1
         end do advance
         ! each slab at least one column, and room left for the ranks after
         e(r) = min(max(k, e(r - 1) + 1), d%ncol - (d%nr - r))
         if (e(r) /= k) then
            k = e(r)
            cum = real(sum(count(0:k - 1)), rp)
         end if
      end do
      moved = any(e /= d%edge)
      d%edge = e
      call set_owner(d)
   end subroutine decomp_balance
end module decomp

!> Domain decomposition into slabs along x: rank r owns the cell columns
!> edge(r) .. edge(r+1)-1 of the neighbour grid (cells of side 2h), so a
!> slab is never narrower than the kernel support. A particle belongs to
!> the rank whose slab holds its column (grid_column). The edges are chosen
!> so that every rank owns about the same number of particles.
module decomp
   use errors, only: alloc_check
   use kinds, only: rp
   use grid, only: grid_column
   implicit none
   private
   public :: decomp_init, decomp_owner, decomp_column, decomp_balance, decomp_set_edges, decomp_edges, &
             decomp_lo, decomp_hi

   real(rp) :: x0 = 0.0_rp, cs = 1.0_rp
   integer :: ncol = 1                     !< cell columns of the domain
   integer :: nr = 1, me = 0
   integer, allocatable :: edge(:)         !< edge(0:nr): first column of each rank, edge(nr) = ncol
   integer, allocatable :: owner(:)        !< owner(0:ncol-1): rank of each column

contains

   !> Columns of side cs from x0, ncol of them, over nranks ranks; the
   !> slabs start equal in width.
   subroutine decomp_init(xmin, cell, ncolumns, nranks, rank)
      real(rp), intent(in) :: xmin, cell
      integer, intent(in) :: ncolumns, nranks, rank
      integer :: r
      integer :: ist
      character(len=200) :: emsg
      x0 = xmin
      cs = cell
      ncol = ncolumns
      nr = nranks
      me = rank
      if (allocated(edge)) deallocate (edge, owner)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (edge(0:nr), owner(0:ncol - 1), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'edge, owner in decomp_init')
      do r = 0, nr
         edge(r) = (r*ncol)/nr
      end do
      call set_owner()
   end subroutine decomp_init

   subroutine set_owner()
      integer :: r
      do r = 0, nr - 1
         owner(edge(r):edge(r + 1) - 1) = r
      end do
   end subroutine set_owner


   !> First column of this rank's slab (0-based).
   integer function decomp_lo()
      decomp_lo = edge(me)
   end function decomp_lo

   !> One past the last column of this rank's slab.
   integer function decomp_hi()
      decomp_hi = edge(me + 1)
   end function decomp_hi

   function decomp_edges() result(e)
      integer :: e(0:nr)
      e = edge
   end function decomp_edges

   !> Adopt given edges (a restart on the same number of ranks).
   subroutine decomp_set_edges(e)
      integer, intent(in) :: e(0:)
      edge = e(0:nr)
      call set_owner()
   end subroutine decomp_set_edges

   pure integer function decomp_column(x) result(k)
      real(rp), intent(in) :: x
      k = grid_column(x0, cs, ncol, x)
   end function decomp_column

   !> Rank that owns a particle at abscissa x.
   pure integer function decomp_owner(x) result(r)
      real(rp), intent(in) :: x
      r = owner(grid_column(x0, cs, ncol, x))
   end function decomp_owner

   !> New edges from the particle count of every column (summed over the
   !> ranks): rank r starts at the first column where the running count
   !> reaches r/nranks of the total, each slab at least one column wide.
   !> Returns whether any edge moved.
   logical function decomp_balance(count) result(moved)
      integer, intent(in) :: count(0:)
      integer :: r, k, e(0:nr)
      real(rp) :: total, cum, target
      total = real(sum(count(0:ncol - 1)), rp)
      e(0) = 0
      e(nr) = ncol
      k = 0
      cum = 0.0_rp
      do r = 1, nr - 1
         target = total*real(r, rp)/real(nr, rp)
         ! advance while the column still fits under the target (nearest split)
         advance: do while (k < ncol - 1)
            if (cum + 0.5_rp*count(k) >= target) exit advance
            cum = cum + count(k)
            k = k + 1
         end do advance
         ! each slab at least one column, and room left for the ranks after
         e(r) = min(max(k, e(r - 1) + 1), ncol - (nr - r))
         if (e(r) /= k) then
            k = e(r)
            cum = real(sum(count(0:k - 1)), rp)
         end if
      end do
      moved = any(e /= edge)
      edge = e
      call set_owner()
   end function decomp_balance
end module decomp

!> Neighbour grid: square cells of side 2h over the domain, one empty ghost
!> column on each side and an empty ghost row above and below. Particles are
!> sorted by cell (counting sort), so that a cell and its right neighbour,
!> and the three cells above, are each one contiguous index range: the
!> half stencil of a pair loop is two ranges per particle.
module grid
   use kinds, only: rp
   use particles, only: particles_t, particles_permute
   implicit none
   private
   public :: grid_t, grid_init, grid_sort, grid_cell_of, grid_visit_pairs

   type :: grid_t
      real(rp) :: x0, y0          !< lower-left corner of the domain [m]
      real(rp) :: cs              !< cell side = 2h [m]
      integer :: ncx, ncy         !< cells over the domain
      integer :: nx, ny           !< with ghost columns and rows: ncx+2, ncy+2
      integer :: ncell            !< nx*ny
      integer, allocatable :: cstart(:)   !< particles of cell c: cstart(c) .. cstart(c+1)-1
      integer, allocatable :: cell(:)     !< cell of each particle (scratch)
      integer, allocatable :: perm(:)     !< sort permutation (scratch)
      integer, allocatable :: icell(:)    !< cell of each particle slot after the sort
   end type grid_t

contains

   subroutine grid_init(g, xmin, xmax, ymin, ymax, h)
      type(grid_t), intent(out) :: g
      real(rp), intent(in) :: xmin, xmax, ymin, ymax, h
      g%cs = 2.0_rp*h
      g%x0 = xmin
      g%y0 = ymin
      g%ncx = max(1, ceiling((xmax - xmin)/g%cs))
      g%ncy = max(1, ceiling((ymax - ymin)/g%cs))
      g%nx = g%ncx + 2
      g%ny = g%ncy + 2
      g%ncell = g%nx*g%ny
      allocate (g%cstart(g%ncell + 2))
   end subroutine grid_init

   !> Cell number (1-based, ghosts included) of a point inside the domain.
   pure integer function grid_cell_of(g, x, y) result(c)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x, y
      integer :: ix, iy
      ix = min(max(int((x - g%x0)/g%cs) + 1, 1), g%ncx)
      iy = min(max(int((y - g%y0)/g%cs) + 1, 1), g%ncy)
      c = ix + iy*g%nx + 1
   end function grid_cell_of

   !> Sort particles by cell. Particles with drop(i) set are moved past the
   !> end and forgotten; p%n shrinks accordingly. The sort is stable, so the
   !> order is a function of the previous order and the positions only.
   subroutine grid_sort(g, p, drop, cells)
      type(grid_t), intent(inout) :: g
      type(particles_t), intent(inout) :: p
      logical, intent(in) :: drop(:)
      logical, intent(in), optional :: cells   !< also fill g%icell (the contact loop needs it)
      integer :: i, c, n, nkeep
      n = p%n
      if (allocated(g%cell)) then
         if (size(g%cell) < n) deallocate (g%cell, g%perm, g%icell)
      end if
      if (.not. allocated(g%cell)) allocate (g%cell(size(p%rho)), g%perm(size(p%rho)), g%icell(size(p%rho)))
      g%cstart = 0
      do i = 1, n
         if (drop(i)) then
            c = g%ncell + 1
         else
            c = grid_cell_of(g, p%x(1, i), p%x(2, i))
         end if
         g%cell(i) = c
         g%cstart(c + 1) = g%cstart(c + 1) + 1
      end do
      g%cstart(1) = 1
      do c = 1, g%ncell + 1
         g%cstart(c + 1) = g%cstart(c + 1) + g%cstart(c)
      end do
      ! cstart(c) is now the first slot of cell c; fill using it as a cursor
      do i = 1, n
         c = g%cell(i)
         g%perm(g%cstart(c)) = i
         g%cstart(c) = g%cstart(c) + 1
      end do
      ! restore the starts: the cursor of cell c ended at the start of c+1
      do c = g%ncell + 1, 2, -1
         g%cstart(c) = g%cstart(c - 1)
      end do
      g%cstart(1) = 1
      nkeep = g%cstart(g%ncell + 1) - 1
      call particles_permute(p, g%perm(1:n), nkeep)
      g%cstart(g%ncell + 2) = n + 1
      if (present(cells)) then
         if (cells) then
            do c = 1, g%ncell
               g%icell(g%cstart(c):g%cstart(c + 1) - 1) = c
            end do
         end if
      end if
   end subroutine grid_sort

   !> Call visit(i, j, r2) once for every pair i /= j closer than sqrt(r2max),
   !> by the half stencil every pair loop uses: for particle i of cell c, the
   !> later particles of c and those of c+1 (one index range), then the cells
   !> c+nx-1 .. c+nx+1 above (another range). Ghost cells are empty, so no
   !> range needs a bounds test. The hot loops inline this traversal.
   subroutine grid_visit_pairs(g, x, r2max, visit)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:, :), r2max
      interface
         subroutine visit(i, j, r2)
            import :: rp
            implicit none
            integer, intent(in) :: i, j
            real(rp), intent(in) :: r2
         end subroutine visit
      end interface
      integer :: c, i, j, r, jlo(2), jhi(2)
      real(rp) :: r2
      do c = 1, g%ncell - g%nx - 1
         do i = g%cstart(c), g%cstart(c + 1) - 1
            jlo = [i + 1, g%cstart(c + g%nx - 1)]
            jhi = [g%cstart(c + 2) - 1, g%cstart(c + g%nx + 2) - 1]
            do r = 1, 2
               do j = jlo(r), jhi(r)
                  r2 = (x(1, i) - x(1, j))**2 + (x(2, i) - x(2, j))**2
                  if (r2 < r2max) call visit(i, j, r2)
               end do
            end do
         end do
      end do
   end subroutine grid_visit_pairs
end module grid

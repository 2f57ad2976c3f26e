!> Neighbour grid: cells 2h wide and 2h/reach tall (reach = 4: the stencil
!> reaches four cells up and down), numbered column by column (y fastest),
!> with reach empty ghost rows below and above every column. Shorter cells
!> leave fewer candidates beyond 2h in the stencil: its area is
!> 12 h^2 + 6 h^2/reach against 2 pi h^2 for the half support (18 h^2 with
!> square cells, 13.5 h^2 with reach 4; doc/performance.md). A rank
!> holds the columns of its slab of the domain (all of them on one rank),
!> an empty ghost column on the left, and on the right either an empty
!> ghost column or the halo: the first column of the next rank's slab.
!> Particles are sorted by cell (counting sort), so that a cell and the reach
!> cells above it, and the 2 reach + 1 neighbouring cells of the next column,
!> are each one contiguous index range: the half stencil of a pair loop is two
!> ranges per particle (grid_ranges). Columns being contiguous, the owned particles come
!> first and the halo (the last column) after them.
!> In 3D (ndim = 3) a column is (x, z): each x column of the slab is ncz
!> columns across the width, and the half stencil is the cells above in the
!> same column, the next column across (z + 1) and the three of the next x
!> column (z - 1, z, z + 1): grid_nranges = 5 index ranges against 2 in 2D.
!> The slabs of the ranks stay slabs along x. The ghost columns across the
!> width (z = 0 and z = ncz + 1 of every x column) are numbered after all
!> the others, so that their particles sit after the halo: they are empty
!> beside side walls, and with periodic sides they hold the images of the
!> last and the first column, shifted by the width (grid_add_images). A
!> table (later) gives each column the first cells of its stencil's later
!> columns.
module grid
   use kinds, only: rp, lk
   use constants, only: ndim
   use errors, only: alloc_check
   use particles, only: particles_t, particles_permute, particles_grow, particles_copy
   implicit none
   private
   public :: grid_t, grid_neighbours, grid_init, grid_columns, grid_sort, grid_column, &
             grid_first_column_end, &
             grid_add_halo, grid_ranges, grid_last_cell, grid_point_ranges, grid_line_ranges, &
             grid_nranges, grid_npoint, grid_add_images, grid_wrap, grid_image_range

   !> index ranges of a particle's half stencil: 2 in 2D, 5 in 3D
   integer, parameter :: grid_nranges = merge(2, 5, ndim == 2)
   !> index ranges around a point or a vertical line: the columns around it, 3 in 2D, 9 in 3D
   integer, parameter :: grid_npoint = 3**(ndim - 1)

   type :: grid_t
      real(rp) :: x0, y0          !< lower-left corner of the domain [m]
      real(rp) :: z0 = 0.0_rp     !< the domain's side at zmin (3D) [m]
      real(rp) :: width = 0.0_rp  !< the domain's width zmax - zmin (3D) [m]
      logical :: periodic = .false.   !< periodic sides across the width (3D)
      integer :: ncz = 1          !< cell columns across the width: 1 in 2D
      real(rp) :: cs              !< cell width = 2h [m]
      real(rp) :: icsz = 0.0_rp   !< 1/(cell width across) [1/m]: 1/cs, or ncz/width with periodic sides
      real(rp) :: csy             !< cell height = cs/reach [m]
      real(rp) :: icsy            !< 1/csy [1/m]
      integer :: reach = 4        !< cell rows the stencil reaches up and down; ghost rows per column end
      integer :: ncx_all          !< cell columns over the whole domain
      integer :: col0             !< first column of this rank's slab (0-based, global)
      integer :: ncol, ncy        !< cell columns of this rank's slab; cell rows
      integer :: ny               !< rows with the ghost rows: ncy + 2 reach
      integer :: stride           !< index distance of neighbouring x columns: ncz ny
      ! cell (ix, iz, iy) (ix: 0 ghost, 1..ncol slab, ncol+1 halo or ghost; iz: 1 in 2D,
      ! 1..ncz in 3D; iy: 1..ncy, with reach ghost rows below and above) is number
      ! ix*stride + (iz-1)*ny + iy + reach: see grid_cell_of. In 3D the ghost columns
      ! across follow: (ix, 0) and (ix, ncz+1) start after cell nreg + (2 ix + 0 or 1) ny.
      integer :: nreg             !< cells of the columns (ncol + 2) stride
      integer :: ncell            !< all cells: nreg, and 2 (ncol + 2) ny ghost cells across in 3D
      !> in 3D, for each column (ix, iz) of ix = 0 .. ncol (number ix ncz + iz - 1): the cell
      !> before the first of each later column of its stencil, (ix, iz+1), (ix+1, iz-1),
      !> (ix+1, iz), (ix+1, iz+1)
      integer, allocatable :: later(:, :)
      integer, allocatable :: cstart(:)   !< particles of cell c: cstart(c) .. cstart(c+1)-1
      integer, allocatable :: cell(:)     !< cell of each particle (the sort's scratch); after a sort
                                          !< with cells = .true., the cell of each particle slot
      integer, allocatable :: perm(:)     !< sort permutation (scratch)
   end type grid_t

contains

   !> The grid over the domain, or with col_lo/col_hi over the cell columns
   !> col_lo .. col_hi-1 (0-based) of the domain: one rank's slab. In 3D the
   !> width zmin .. zmax is required.
   subroutine grid_init(g, xmin, xmax, ymin, ymax, h, col_lo, col_hi, zmin, zmax, periodic)
      type(grid_t), intent(out) :: g
      real(rp), intent(in) :: xmin, xmax, ymin, ymax, h
      integer, intent(in), optional :: col_lo, col_hi
      real(rp), intent(in), optional :: zmin, zmax
      logical, intent(in), optional :: periodic   !< periodic sides (3D): cells across of width/ncz >= 2h
      integer :: ist
      character(len=200) :: emsg
      g%cs = 2.0_rp*h
      g%x0 = xmin
      g%y0 = ymin
      g%ncx_all = grid_columns(xmin, xmax, h)
      g%csy = g%cs/g%reach
      g%icsy = 1.0_rp/g%csy
      g%ncy = max(1, ceiling((ymax - ymin)/g%csy))
      g%col0 = 0
      g%ncol = g%ncx_all
      if (present(col_lo) .and. present(col_hi)) then
         g%col0 = col_lo
         g%ncol = col_hi - col_lo
      end if
      g%ny = g%ncy + 2*g%reach
      g%icsz = 1.0_rp/g%cs
      if (ndim == 3) then
         ! without a width: one column across
         g%ncz = 1
         if (present(zmin) .and. present(zmax)) then
            g%z0 = zmin
            g%width = zmax - zmin
            g%ncz = max(1, ceiling(g%width/g%cs))
            if (present(periodic)) g%periodic = periodic
            if (g%periodic) then
               ! the columns tile the width exactly (an image is one width away), each at least 2h wide
               g%ncz = max(1, floor(g%width/g%cs*(1.0_rp + 1.0e-12_rp)))
               g%icsz = g%ncz/g%width
            end if
         end if
      end if
      g%stride = g%ncz*g%ny
      g%nreg = (g%ncol + 2)*g%stride
      g%ncell = g%nreg
      if (ndim == 3) then
         g%ncell = g%nreg + 2*(g%ncol + 2)*g%ny
         call later_columns(g)
      end if
      allocate (g%cstart(g%ncell + 2), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the cells of the neighbour grid', g%ncell + 2)
   end subroutine grid_init

   !> The table of the later columns of each column's stencil (3D).
   subroutine later_columns(g)
      type(grid_t), intent(inout) :: g
      integer :: ix, iz, ist
      character(len=200) :: emsg
      allocate (g%later(4, 0:(g%ncol + 1)*g%ncz - 1), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the stencil table of the neighbour grid', 4*(g%ncol + 1)*g%ncz)
      do ix = 0, g%ncol
         do iz = 1, g%ncz
            g%later(:, ix*g%ncz + iz - 1) = [column_base(g, ix, iz + 1), column_base(g, ix + 1, iz - 1), &
                                            column_base(g, ix + 1, iz), column_base(g, ix + 1, iz + 1)]
         end do
      end do
   end subroutine later_columns

   !> The cell before the first of column (ix, iz), iz = 0 .. ncz + 1 (0 and
   !> ncz + 1: the ghost columns across, 3D); its cells are that + 1 .. + ny.
   pure integer function column_base(g, ix, iz) result(c)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: ix, iz
      if (iz < 1) then
         c = g%nreg + 2*ix*g%ny
      else if (iz > g%ncz) then
         c = g%nreg + (2*ix + 1)*g%ny
      else
         c = ix*g%stride + (iz - 1)*g%ny
      end if
   end function column_base

   !> Cell columns (2h wide) over the domain [xmin, xmax]: the one count of
   !> grid_init, of the ranks' check and of the slabs.
   pure integer function grid_columns(xmin, xmax, h) result(n)
      real(rp), intent(in) :: xmin, xmax, h
      n = max(1, ceiling((xmax - xmin)/(2.0_rp*h)))
   end function grid_columns

   !> Cell column (0-based, over the whole domain) of abscissa x; points
   !> outside the domain take the nearest column. The one rule by which cells
   !> and slab ownership are decided.
   pure integer function grid_column(x0, cs, ncx_all, x) result(k)
      real(rp), intent(in) :: x0, cs, x
      integer, intent(in) :: ncx_all
      ! times the inverse: inlined in the sort's loop, the division is taken once
      k = min(max(int((x - x0)*(1.0_rp/cs)), 0), ncx_all - 1)
   end function grid_column

   !> Cell number (1-based, ghosts included) of a point x of this rank's slab;
   !> a point of the next slab's first column falls in the last column.
   pure integer function grid_cell_of(g, x) result(c)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:)
      integer :: ix, iy
      ix = min(max(grid_column(g%x0, g%cs, g%ncx_all, x(1)) - g%col0 + 1, 1), g%ncol + 1)
      iy = min(max(int((x(2) - g%y0)*g%icsy) + 1, 1), g%ncy)
      c = iy + ix*g%stride + g%reach + (across(g, x) - 1)*g%ny
   end function grid_cell_of

   !> The column across the width (1 .. ncz) of the point x in 3D; 1 in 2D.
   pure integer function across(g, x) result(iz)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:)
      iz = 1
      if (ndim == 3) iz = min(max(int((x(ndim) - g%z0)*g%icsz) + 1, 1), g%ncz)
   end function across

   !> The half stencil of particle i of cell c: the later particles of c and
   !> those of the reach cells above it (jlo(1) .. jhi(1)), and those of the
   !> 2 reach + 1 cells around c's row in each later column of the stencil
   !> (jlo(r) .. jhi(r), r = 2 .. grid_nranges: the next x column in 2D; in
   !> 3D the next column across and three of the next x column). Ghost
   !> cells are empty, so no range needs a bounds test. Every pass over the
   !> pairs (the pair list, the force loop, Shepard, contacts) takes its ranges here.
   pure subroutine grid_ranges(g, c, i, jlo, jhi)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: c, i
      integer, intent(out) :: jlo(grid_nranges), jhi(grid_nranges)
      integer :: k, col, row, c2
      jlo(1) = i + 1
      jhi(1) = g%cstart(c + g%reach + 1) - 1
      if (ndim == 2) then
         jlo(ndim) = g%cstart(c + g%stride - g%reach)
         jhi(ndim) = g%cstart(c + g%stride + g%reach + 1) - 1
      else
         ! the column of c and the row in it; the later columns from the table
         col = (c - 1)/g%ny
         row = c - col*g%ny
         do k = 2, grid_nranges
            c2 = g%later(k - 1, col) + row
            jlo(k) = g%cstart(c2 - g%reach)
            jhi(k) = g%cstart(c2 + g%reach + 1) - 1
         end do
      end if
   end subroutine grid_ranges

   !> The particles of this rank's slab around the point x (not the halo):
   !> grid_npoint index ranges, one for each of the point's cell column and its
   !> neighbours (3 in 2D, 3 x 3 in 3D), each the 2 reach + 1 cells around the
   !> point's row, so every particle within 2h of x is in one of them. A column
   !> outside the slab gives an empty range (jlo > jhi). The passes around a
   !> point (the mDBC ghost points) take their candidates here.
   pure subroutine grid_point_ranges(g, x, jlo, jhi)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:)
      integer, intent(out) :: jlo(grid_npoint), jhi(grid_npoint)
      integer :: iy, r, c0
      integer :: cols(grid_npoint)
      iy = min(max(int((x(2) - g%y0)*g%icsy) + 1, 1), g%ncy)
      call columns_around(g, x, cols)
      do r = 1, grid_npoint
         jlo(r) = 1
         jhi(r) = 0
         if (cols(r) < 0) cycle
         c0 = iy + cols(r)
         jlo(r) = g%cstart(c0)
         jhi(r) = g%cstart(c0 + 2*g%reach + 1) - 1
      end do
   end subroutine grid_point_ranges

   !> The particles of this rank's slab within one cell column of the
   !> vertical line through the point x (its height does not matter): the
   !> whole columns around it (3 in 2D, 3 x 3 in 3D), one index range each,
   !> empty where a column is not the slab's (the gauges of the water level).
   pure subroutine grid_line_ranges(g, x, jlo, jhi)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:)
      integer, intent(out) :: jlo(grid_npoint), jhi(grid_npoint)
      integer :: r
      integer :: cols(grid_npoint)
      call columns_around(g, x, cols)
      do r = 1, grid_npoint
         jlo(r) = 1
         jhi(r) = 0
         if (cols(r) < 0) cycle
         jlo(r) = g%cstart(cols(r) + g%reach + 1)
         jhi(r) = g%cstart(cols(r) + g%reach + g%ncy + 1) - 1
      end do
   end subroutine grid_line_ranges

   !> The cell columns around the point x, by their first cell less one (the
   !> number of row 0), -1 for a column outside the slab: x columns kx - 1 ..
   !> kx + 1 and, in 3D, across iz - 1 .. iz + 1 (a ghost column across is
   !> empty, or holds the images with periodic sides).
   pure subroutine columns_around(g, x, cols)
      type(grid_t), intent(in) :: g
      real(rp), intent(in) :: x(:)
      integer, intent(out) :: cols(grid_npoint)
      integer :: kx, iz, ix, a, b, r
      kx = grid_column(g%x0, g%cs, g%ncx_all, x(1)) - g%col0 + 1
      iz = across(g, x)
      r = 0
      do a = -1, 1
         ix = kx + a
         do b = -(ndim - 2), ndim - 2
            r = r + 1
            cols(r) = -1
            if (ix >= 1 .and. ix <= g%ncol) cols(r) = column_base(g, ix, iz + b)
         end do
      end do
   end subroutine columns_around

   !> The last cell whose particles start stencils: the cells after it (the last
   !> column, the halo or an empty ghost column) only end them.
   pure integer function grid_last_cell(g) result(c)
      type(grid_t), intent(in) :: g
      c = g%nreg - g%stride - g%reach
   end function grid_last_cell

   !> Sort particles by cell. Particles with drop(i) set are moved past the
   !> end and forgotten; p%n shrinks accordingly. The sort is stable, so the
   !> order is a function of the previous order and the positions only.
   !> Every particle sorted is owned: p%n_own = p%n afterwards.
   subroutine grid_sort(g, p, drop, cells)
      type(grid_t), intent(inout) :: g
      type(particles_t), intent(inout) :: p
      logical(lk), intent(in) :: drop(:)
      logical, intent(in), optional :: cells   !< leave in g%cell the cell of each slot (the contact loop needs it)
      integer :: ist
      character(len=200) :: emsg
      integer :: i, c, n, nkeep
      n = p%n
      if (allocated(g%cell)) then
         if (size(g%cell) < size(p%rho)) deallocate (g%cell, g%perm)
      end if
      if (.not. allocated(g%cell)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (g%cell(size(p%rho)), g%perm(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the sort of the particles', size(p%rho))
      end if
      g%cstart = 0
      do i = 1, n
         if (drop(i)) then
            c = g%ncell + 1
         else
            c = grid_cell_of(g, p%x(:, i))
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
      call particles_permute(p, g%perm(1:n), nkeep, g%cell)
      p%n_own = p%n
      g%cstart(g%ncell + 2) = n + 1
      if (present(cells)) then
         if (cells) then
            do c = 1, g%ncell
               g%cell(g%cstart(c):g%cstart(c + 1) - 1) = c
            end do
         end if
      end if
   end subroutine grid_sort

   !> After a sort: the particles of the slab's first column are 1 .. k (the
   !> ghost column on the left is empty); returns k.
   integer function grid_first_column_end(g) result(k)
      type(grid_t), intent(in) :: g
      k = g%cstart(2*g%stride + 1) - 1
   end function grid_first_column_end

   !> Particles p%n_own+1 .. p%n are the halo, in the order of the cells of
   !> the last column (the next rank sends its first column sorted): count
   !> them into the cell starts. Returns .false. if they are out of order.
   logical function grid_add_halo(g, p) result(ok)
      type(grid_t), intent(inout) :: g
      type(particles_t), intent(in) :: p
      integer :: i, c, cprev, first
      ok = .true.
      first = g%nreg - g%stride + 1        ! first cell of the last column
      g%cstart(first:g%ncell + 2) = 0
      cprev = first
      do i = p%n_own + 1, p%n
         c = grid_cell_of(g, p%x(:, i))
         if (c < cprev) ok = .false.
         cprev = c
         c = min(max(c, first), g%nreg)
         g%cstart(c + 1) = g%cstart(c + 1) + 1
      end do
      g%cstart(first) = p%n_own + 1
      do c = first, g%ncell + 1
         g%cstart(c + 1) = g%cstart(c + 1) + g%cstart(c)
      end do
      g%cstart(g%ncell + 2) = p%n + 1
   end function grid_add_halo

   !> Periodic sides (3D): the particles of the first and the last column
   !> across of every x column (the halo's too), appended after the particles
   !> (p%n grows) as images in the ghost columns across on the other side,
   !> shifted by the width. src(k) is the original of image n0 + k (n0: p%n
   !> before). The pairs of a particle near one side with those near the other
   !> are then met as pairs with the images, each once. Without periodic
   !> sides there are none (nimg = 0).
   subroutine grid_add_images(g, p, src, nimg)
      type(grid_t), intent(inout) :: g
      type(particles_t), intent(inout) :: p
      integer, allocatable, intent(inout) :: src(:)
      integer, intent(out) :: nimg
      integer :: ix, s, k, i, cg, csrc, n0, ist
      real(rp) :: shift
      character(len=200) :: emsg
      nimg = 0
      if (.not. g%periodic) return
      do ix = 1, g%ncol + 1
         nimg = nimg + column_count(g, ix, 1) + column_count(g, ix, g%ncz)
      end do
      if (allocated(src)) then
         if (size(src) < nimg) deallocate (src)
      end if
      if (.not. allocated(src)) then
         allocate (src(max(nimg, 1024)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the images of the periodic sides', nimg)
      end if
      call particles_grow(p, nimg)
      n0 = p%n
      ! in the order of the ghost cells: x column by x column, the side at zmin first
      do ix = 0, g%ncol + 1
         do s = 0, 1
            cg = column_base(g, ix, merge(0, g%ncz + 1, s == 0))
            csrc = column_base(g, ix, merge(g%ncz, 1, s == 0))
            shift = merge(-g%width, g%width, s == 0)
            do k = 1, g%ny
               g%cstart(cg + k) = p%n + 1
               do i = g%cstart(csrc + k), g%cstart(csrc + k + 1) - 1
                  p%n = p%n + 1
                  call particles_copy(p, i, p%n)
                  p%x(ndim, p%n) = p%x(ndim, i) + shift
                  src(p%n - n0) = i
               end do
            end do
         end do
      end do
      g%cstart(g%ncell + 1:g%ncell + 2) = p%n + 1
   end subroutine grid_add_images

   !> The images of x column ix (0 .. ncol + 1) are particles i0 .. i1 (none: i0 > i1).
   pure subroutine grid_image_range(g, ix, i0, i1)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: ix
      integer, intent(out) :: i0, i1
      integer :: c
      i0 = 1
      i1 = 0
      if (.not. g%periodic) return
      c = column_base(g, ix, 0)
      i0 = g%cstart(c + 1)
      i1 = g%cstart(c + 2*g%ny + 1) - 1
   end subroutine grid_image_range

   !> Particles of column (ix, iz) (a column of the slab or the halo).
   pure integer function column_count(g, ix, iz) result(n)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: ix, iz
      integer :: c
      c = column_base(g, ix, iz)
      n = g%cstart(c + g%ny + 1) - g%cstart(c + 1)
   end function column_count

   !> Periodic sides (3D): positions x(ndim, 1 .. n) taken back into the
   !> width [z0, z0 + width) (a particle that crossed a side comes in at the
   !> other).
   pure subroutine grid_wrap(g, n, x)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: n
      real(rp), intent(inout) :: x(:, :)
      integer :: i
      if (.not. g%periodic) return
      do i = 1, n
         x(ndim, i) = x(ndim, i) - g%width*floor((x(ndim, i) - g%z0)/g%width)
      end do
   end subroutine grid_wrap

   !> Whether the slab has a rank on its left and on its right (the grid's
   !> columns against the domain's).
   pure subroutine grid_neighbours(g, left, right)
      type(grid_t), intent(in) :: g
      logical, intent(out) :: left, right
      left = g%col0 > 0
      right = g%col0 + g%ncol < g%ncx_all
   end subroutine grid_neighbours
end module grid

!> Wave gauges and pressure probes, written to OUT/gauges.csv (by rank 0).
!> Elevation: the free surface above a point x is where the kernel sum of
!> the fluid's volume, S(y) = sum_j V_j W(|(x, y) - x_j|), falls through 0.5
!> (inside the water S = 1, in air 0; on a still surface the level is the
!> still-water line). Pressure: Shepard average of the fluid pressure at
!> (x, y), zero where the point is dry (S < 0.1).
module probe_gauges
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use kinds, only: rp
   use constants, only: kind_fluid, msg_len, ndim
   use porous, only: porous_t, porous_point, n_por
   use io_files, only: csv_rows_until, csv_flush
   use params, only: params_t
   use grid, only: grid_t, grid_line_ranges, grid_npoint
   use particles, only: particles_t
   use kernel, only: kernel_w
   use errors, only: fatal, alloc_check
   use options, only: gauge_elevation
   implicit none
   private
   public :: gauges_t, gauges_init, gauges_count, gauges_open, gauges_sums, gauges_values, gauges_write, gauges_close

   !> The gauges (kind and position of each), their file (open on rank 0
   !> only) and the scratch of a sample.
   type :: gauges_t
      integer, allocatable :: kind(:)      !< gauge_elevation or gauge_pressure (options)
      real(rp), allocatable :: x(:), y(:)  !< position [m] (y: pressure gauges only)
      real(rp), allocatable :: z(:)        !< position across the width (3D) [m]
      integer :: unit = 0
      logical :: opened = .false.
      integer :: ny = 0                    !< heights sampled per elevation gauge
      real(rp) :: ybot = 0.0_rp, dy = 0.0_rp   !< lowest height and spacing [m]
      real(rp), allocatable :: cy(:), cdx(:), cv(:), cp(:)   !< candidates of one gauge
   end type gauges_t

contains

   !> The gauges of a run: their kinds (the values of options) and positions.
   subroutine gauges_init(gt, kinds, x, y, z)
      type(gauges_t), intent(out) :: gt
      integer, intent(in) :: kinds(:)
      real(rp), intent(in) :: x(:), y(:), z(:)
      gt%kind = kinds
      gt%x = x
      gt%y = y
      gt%z = z
   end subroutine gauges_init

   !> How many gauges the run has.
   pure integer function gauges_count(gt) result(n)
      type(gauges_t), intent(in) :: gt
      n = 0
      if (allocated(gt%kind)) n = size(gt%kind)
   end function gauges_count

   !> A new file with the gauge table in '#' lines and the column header,
   !> or on restart the old one cut back to rows up to time t_keep.
   subroutine gauges_open(gt, out_dir, restart, t_keep)
      type(gauges_t), intent(inout) :: gt
      character(len=*), intent(in) :: out_dir
      logical, intent(in) :: restart
      real(rp), intent(in) :: t_keep
      character(len=:), allocatable :: path, keep, head
      character(len=msg_len) :: msg
      integer :: ios, k
      character(len=64) :: b
      path = trim(out_dir)//'/gauges.csv'
      keep = ''
      if (restart) keep = csv_rows_until(path, t_keep)
      open (newunit=gt%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//': '//trim(msg))
      gt%opened = .true.
      ! 3D: z after the 2D columns
      write (gt%unit, '(a)') '# id,kind,x,y'//trim(merge(',z', '  ', ndim == 3))
      head = 'time'
      do k = 1, gauges_count(gt)
         b = ''
         if (ndim == 3) write (b, '(",",f0.6)') gt%z(k)
         if (gt%kind(k) == gauge_elevation) then
            write (gt%unit, '("# ",i0,",elevation,",f0.6,",nan",a)') k, gt%x(k), trim(b)
            write (b, '(",eta_",i0)') k
         else
            write (gt%unit, '("# ",i0,",pressure,",f0.6,",",f0.6,a)') k, gt%x(k), gt%y(k), trim(b)
            write (b, '(",p_",i0)') k
         end if
         head = head//trim(b)
      end do
      write (gt%unit, '(a)') head
      if (len(keep) > 0) write (gt%unit, '(a)', advance='no') keep
      call csv_flush(gt%unit, 'gauges.csv')
   end subroutine gauges_open

   !> One row of gauges.csv: the time and the value of every gauge (rank 0, which opened the file).
   subroutine gauges_write(gt, t, val)
      type(gauges_t), intent(in) :: gt
      real(rp), intent(in) :: t, val(:)
      integer :: k
      if (.not. gt%opened) return
      write (gt%unit, '(es23.15e3)', advance='no') t
      do k = 1, size(val)
         write (gt%unit, '(",",es23.15e3)', advance='no') val(k)
      end do
      write (gt%unit, '()')
      call csv_flush(gt%unit, 'gauges.csv')
   end subroutine gauges_write

   subroutine gauges_close(gt)
      type(gauges_t), intent(inout) :: gt
      if (gt%opened) close (gt%unit)
      gt%opened = .false.
   end subroutine gauges_close

   !> What this rank's own particles add to every gauge (the kernel sum on
   !> a column of heights dp/4 apart for an elevation gauge; the weighted
   !> pressure and the weight for a pressure gauge), in one array: summed
   !> over the ranks, gauges_values turns it into the gauges' values, which
   !> so do not depend on the decomposition. The grid must hold the
   !> particles' current order (it is sorted every step).
   subroutine gauges_sums(gt, prm, g, p, por, acc)
      type(gauges_t), intent(inout) :: gt
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(porous_t), intent(in) :: por        !< in the pores the pressure comes from rho / n
      real(rp), allocatable, intent(out) :: acc(:)
      integer :: k, nc, off
      integer :: ist
      character(len=200) :: emsg
      gt%dy = 0.25_rp*prm%dp
      gt%ybot = g%y0
      gt%ny = ceiling(g%ncy*g%csy/gt%dy) + 1
      ! one block per gauge: ny kernel sums (elevation) or 2 (pressure)
      allocate (acc(gauges_count(gt)*gt%ny), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'acc in gauges_sums')
      acc = 0.0_rp
      do k = 1, gauges_count(gt)
         off = (k - 1)*gt%ny
         call candidates(gt, gt%x(k), gt%z(k), prm, g, p, por, nc)
         if (gt%kind(k) == gauge_elevation) then
            call add_column(gt, prm, nc, acc(off + 1:off + gt%ny))
         else
            call add_point(gt, prm, nc, gt%y(k), acc(off + 1:off + 2))
         end if
      end do
   end subroutine gauges_sums

   !> Elevation above still water [m] or pressure [Pa] of every gauge, from
   !> the sums of gauges_sums added over the ranks.
   subroutine gauges_values(gt, prm, acc, val)
      type(gauges_t), intent(in) :: gt
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: acc(:)
      real(rp), intent(out) :: val(:)
      integer :: k, off
      do k = 1, gauges_count(gt)
         off = (k - 1)*gt%ny
         if (gt%kind(k) == gauge_elevation) then
            val(k) = surface(acc(off + 1:off + gt%ny))
         else
            val(k) = 0.0_rp
            if (acc(off + 1) >= 0.1_rp) val(k) = acc(off + 2)/acc(off + 1)
         end if
      end do
   contains
      !> Coming down from the top, the first height where the kernel sum
      !> reaches 0.5, linear between samples; nan where it never does (dry).
      real(rp) function surface(s) result(eta)
         real(rp), intent(in) :: s(:)
         integer :: m
         eta = ieee_value(eta, ieee_quiet_nan)
         do m = size(s) - 1, 1, -1
            if (s(m) >= 0.5_rp) then
               eta = gt%ybot + (m - 1)*gt%dy + gt%dy*(s(m) - 0.5_rp)/max(s(m) - s(m + 1), 1.0e-12_rp) - prm%y_surface
               return
            end if
         end do
      end function surface
   end subroutine gauges_values

   !> This rank's own fluid particles within 2h of the vertical line
   !> through (x, z) (z: 3D only): their height, horizontal distance, volume
   !> and pressure.
   subroutine candidates(gt, x, z, prm, g, p, por, n)
      type(gauges_t), intent(inout) :: gt
      real(rp), intent(in) :: x, z
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(porous_t), intent(in) :: por
      integer, intent(out) :: n
      integer :: r, j, cap, jlo(grid_npoint), jhi(grid_npoint)
      real(rp) :: dx, rho, f(n_por), xl(ndim)
      cap = 0
      if (allocated(gt%cy)) cap = size(gt%cy)
      n = 0
      xl = 0.0_rp
      xl(1) = x
      if (ndim == 3) xl(ndim) = z
      call grid_line_ranges(g, xl, jlo, jhi)
      do r = 1, grid_npoint
         ! the slab's columns hold owned particles only; the ghost columns across, the images
         ! of periodic sides (their positions refreshed by the caller)
         in_cell: do j = jlo(r), jhi(r)
            if (p%kind(j) /= kind_fluid) cycle in_cell
            dx = x - p%x(1, j)
            if (ndim == 3) dx = hypot(dx, z - p%x(ndim, j))
            if (abs(dx) >= 2.0_rp*prm%h) cycle in_cell
            if (n == cap) call grow(gt, cap)
            n = n + 1
            gt%cy(n) = p%x(2, j)
            gt%cdx(n) = dx
            ! the volume m / rho of the superficial density: the kernel sum is 1 in
            ! the pores too; the pressure that of the pore water, rho / n
            gt%cv(n) = p%mass(j)/p%rho(j)
            rho = p%rho(j)
            if (por%on) then
               f = porous_point(por, p%x(:, j))
               rho = rho/f(1)
            end if
            gt%cp(n) = prm%b*((rho/prm%rho0)**prm%gamma - 1.0_rp)
         end do in_cell
      end do
   end subroutine candidates

   !> Kernel sums of the candidates on heights ybot + (m-1) dy, m = 1..size(s).
   subroutine add_column(gt, prm, nc, s)
      type(gauges_t), intent(in) :: gt
      type(params_t), intent(in) :: prm
      integer, intent(in) :: nc
      real(rp), intent(inout) :: s(:)
      integer :: i, m, lo, hi
      real(rp) :: r2, ybot, dy
      ybot = gt%ybot
      dy = gt%dy
      do i = 1, nc
         lo = max(0, floor((gt%cy(i) - 2.0_rp*prm%h - ybot)/dy))
         hi = min(size(s) - 1, ceiling((gt%cy(i) + 2.0_rp*prm%h - ybot)/dy))
         do m = lo, hi
            r2 = gt%cdx(i)**2 + (ybot + m*dy - gt%cy(i))**2
            if (r2 < prm%support2) s(m + 1) = s(m + 1) + gt%cv(i)*kernel_w(prm%kernel, sqrt(r2), prm%h)
         end do
      end do
   end subroutine add_column

   !> Kernel weight and weighted pressure of the candidates at height y.
   subroutine add_point(gt, prm, nc, y, a)
      type(gauges_t), intent(in) :: gt
      type(params_t), intent(in) :: prm
      integer, intent(in) :: nc
      real(rp), intent(in) :: y
      real(rp), intent(inout) :: a(2)
      integer :: i
      real(rp) :: r2, w
      near: do i = 1, nc
         r2 = gt%cdx(i)**2 + (y - gt%cy(i))**2
         if (r2 >= prm%support2) cycle near
         w = gt%cv(i)*kernel_w(prm%kernel, sqrt(r2), prm%h)
         a(1) = a(1) + w
         a(2) = a(2) + w*gt%cp(i)
      end do near
   end subroutine add_point

   !> Room for twice as many candidates, keeping those found.
   subroutine grow(gt, cap)
      type(gauges_t), intent(inout) :: gt
      integer, intent(inout) :: cap
      real(rp), allocatable :: t1(:), t2(:), t3(:), t4(:)
      integer :: m
      integer :: ist
      character(len=200) :: emsg
      m = max(256, 2*cap)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (t1(m), t2(m), t3(m), t4(m), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 't1, t2, t3, ... in grow')
      if (cap > 0) then
         t1(1:cap) = gt%cy(1:cap)
         t2(1:cap) = gt%cdx(1:cap)
         t3(1:cap) = gt%cv(1:cap)
         t4(1:cap) = gt%cp(1:cap)
      end if
      call move_alloc(t1, gt%cy)
      call move_alloc(t2, gt%cdx)
      call move_alloc(t3, gt%cv)
      call move_alloc(t4, gt%cp)
      cap = m
   end subroutine grow
end module probe_gauges

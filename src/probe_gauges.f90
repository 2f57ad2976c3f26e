!> Wave gauges and pressure probes, written to OUT/gauges.csv (by rank 0).
!> Elevation: the free surface above a point x is where the kernel sum of
!> the fluid's volume, S(y) = sum_j V_j W(|(x, y) - x_j|), falls through 0.5
!> (inside the water S = 1, in air 0; on a still surface the level is the
!> still-water line). Pressure: Shepard average of the fluid pressure at
!> (x, y), zero where the point is dry (S < 0.1).
module probe_gauges
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use kinds, only: rp
   use constants, only: kind_fluid, msg_len
   use io_files, only: csv_rows_until, csv_flush
   use input_wave, only: gauge_cfg
   use params, only: params_t
   use grid, only: grid_t, grid_column, grid_cell
   use comm, only: comm_sum
   use particles, only: particles_t
   use kernel, only: kernel_w
   use errors, only: fatal, alloc_check
   use options, only: gauge_elevation
   implicit none
   private
   public :: gauges_open, gauges_sample, gauges_close

   integer :: unit_ = 0
   logical :: opened = .false.
   real(rp), allocatable :: cy(:), cdx(:), cv(:), cp(:)   ! candidates of one gauge

contains

   !> A new file with the gauge table in '#' lines and the column header,
   !> or on restart the old one cut back to rows up to time t_keep.
   subroutine gauges_open(out_dir, gs, restart, t_keep)
      character(len=*), intent(in) :: out_dir
      type(gauge_cfg), intent(in) :: gs(:)
      logical, intent(in) :: restart
      real(rp), intent(in) :: t_keep
      character(len=:), allocatable :: path, keep, head
      character(len=msg_len) :: msg
      integer :: ios, k
      character(len=64) :: b
      path = trim(out_dir)//'/gauges.csv'
      keep = ''
      if (restart) keep = csv_rows_until(path, t_keep)
      open (newunit=unit_, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//': '//trim(msg))
      opened = .true.
      write (unit_, '(a)') '# id,kind,x,y'
      head = 'time'
      do k = 1, size(gs)
         if (gs(k)%kind_id == gauge_elevation) then
            write (unit_, '("# ",i0,",elevation,",f0.6,",nan")') k, gs(k)%x
            write (b, '(",eta_",i0)') k
         else
            write (unit_, '("# ",i0,",pressure,",f0.6,",",f0.6)') k, gs(k)%x, gs(k)%y
            write (b, '(",p_",i0)') k
         end if
         head = head//trim(b)
      end do
      write (unit_, '(a)') head
      if (len(keep) > 0) write (unit_, '(a)', advance='no') keep
      call csv_flush(unit_, 'gauges.csv')
   end subroutine gauges_open

   !> One row: the value of every gauge at time t (every rank calls it; rank
   !> 0 writes).
   subroutine gauges_sample(t, gs, prm, g, p)
      real(rp), intent(in) :: t
      type(gauge_cfg), intent(in) :: gs(:)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      real(rp) :: val(size(gs))
      integer :: k
      call gauge_values(gs, prm, g, p, val)
      if (.not. opened) return
      write (unit_, '(es23.15e3)', advance='no') t
      do k = 1, size(gs)
         write (unit_, '(",",es23.15e3)', advance='no') val(k)
      end do
      write (unit_, '()')
      call csv_flush(unit_, 'gauges.csv')
   end subroutine gauges_sample

   subroutine gauges_close()
      if (opened) close (unit_)
      opened = .false.
   end subroutine gauges_close

   !> Elevation above still water [m] or pressure [Pa] of every gauge. Each
   !> rank adds up what its own particles contribute (the kernel sum on a
   !> column of heights dp/4 apart for an elevation gauge; the weighted
   !> pressure and the weight for a pressure gauge), one sum over the ranks
   !> completes them, so the result does not depend on the decomposition.
   !> The grid must hold the particles' current order (it is sorted every step).
   subroutine gauge_values(gs, prm, g, p, val)
      type(gauge_cfg), intent(in) :: gs(:)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      real(rp), intent(out) :: val(:)
      real(rp), allocatable :: acc(:)
      integer :: k, nc, ny, off
      real(rp) :: dy, ybot
      integer :: ist
      character(len=200) :: emsg
      dy = 0.25_rp*prm%dp
      ybot = g%y0
      ny = ceiling(g%ncy*g%csy/dy) + 1
      ! one block per gauge: ny kernel sums (elevation) or 2 (pressure)
      allocate (acc(size(gs)*ny), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'acc in gauge_values')
      acc = 0.0_rp
      do k = 1, size(gs)
         off = (k - 1)*ny
         call candidates(gs(k)%x, prm, g, p, nc)
         if (gs(k)%kind_id == gauge_elevation) then
            call add_column(prm, nc, ybot, dy, acc(off + 1:off + ny))
         else
            call add_point(prm, nc, gs(k)%y, acc(off + 1:off + 2))
         end if
      end do
      call comm_sum(acc)
      do k = 1, size(gs)
         off = (k - 1)*ny
         if (gs(k)%kind_id == gauge_elevation) then
            val(k) = surface(acc(off + 1:off + ny))
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
               eta = ybot + (m - 1)*dy + dy*(s(m) - 0.5_rp)/max(s(m) - s(m + 1), 1.0e-12_rp) - prm%y_surface
               return
            end if
         end do
      end function surface

   end subroutine gauge_values

   !> This rank's own fluid particles within 2h of the vertical line
   !> through x: their height, horizontal offset, volume and pressure.
   subroutine candidates(x, prm, g, p, n)
      real(rp), intent(in) :: x
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      integer, intent(out) :: n
      integer :: kx, jx, iy, c, j, cap
      real(rp) :: dx
      cap = 0
      if (allocated(cy)) cap = size(cy)
      n = 0
      kx = grid_column(g%x0, g%cs, g%ncx_all, x)
      columns: do jx = kx - 1, kx + 1
         if (grid_cell(g, jx, 1) == 0) cycle columns     ! not this rank's column
         do iy = 1, g%ncy
            c = grid_cell(g, jx, iy)
            in_cell: do j = g%cstart(c), min(g%cstart(c + 1) - 1, p%n_own)
               if (p%kind(j) /= kind_fluid) cycle in_cell
               dx = x - p%x(1, j)
               if (abs(dx) >= 2.0_rp*prm%h) cycle in_cell
               if (n == cap) call grow(cap)
               n = n + 1
               cy(n) = p%x(2, j)
               cdx(n) = dx
               cv(n) = p%mass(j)/p%rho(j)
               cp(n) = prm%b*((p%rho(j)/prm%rho0)**prm%gamma - 1.0_rp)
            end do in_cell
         end do
      end do columns
   end subroutine candidates

   !> Kernel sums of the candidates on heights ybot + (m-1) dy, m = 1..size(s).
   subroutine add_column(prm, nc, ybot, dy, s)
      type(params_t), intent(in) :: prm
      integer, intent(in) :: nc
      real(rp), intent(in) :: ybot, dy
      real(rp), intent(inout) :: s(:)
      integer :: i, m, lo, hi
      real(rp) :: r2
      do i = 1, nc
         lo = max(0, floor((cy(i) - 2.0_rp*prm%h - ybot)/dy))
         hi = min(size(s) - 1, ceiling((cy(i) + 2.0_rp*prm%h - ybot)/dy))
         do m = lo, hi
            r2 = cdx(i)**2 + (ybot + m*dy - cy(i))**2
            if (r2 < prm%support2) s(m + 1) = s(m + 1) + cv(i)*kernel_w(prm%kernel, sqrt(r2), prm%h)
         end do
      end do
   end subroutine add_column

   !> Kernel weight and weighted pressure of the candidates at height y.
   subroutine add_point(prm, nc, y, a)
      type(params_t), intent(in) :: prm
      integer, intent(in) :: nc
      real(rp), intent(in) :: y
      real(rp), intent(inout) :: a(2)
      integer :: i
      real(rp) :: r2, w
      near: do i = 1, nc
         r2 = cdx(i)**2 + (y - cy(i))**2
         if (r2 >= prm%support2) cycle near
         w = cv(i)*kernel_w(prm%kernel, sqrt(r2), prm%h)
         a(1) = a(1) + w
         a(2) = a(2) + w*cp(i)
      end do near
   end subroutine add_point

   !> Room for twice as many candidates, keeping those found.
   subroutine grow(cap)
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
         t1(1:cap) = cy(1:cap)
         t2(1:cap) = cdx(1:cap)
         t3(1:cap) = cv(1:cap)
         t4(1:cap) = cp(1:cap)
      end if
      call move_alloc(t1, cy)
      call move_alloc(t2, cdx)
      call move_alloc(t3, cv)
      call move_alloc(t4, cp)
      cap = m
   end subroutine grow
end module probe_gauges

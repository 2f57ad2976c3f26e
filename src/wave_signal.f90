!> A sampled paddle signal: displacement x(t) given at times t(1) < ... < t(n),
!> evaluated at any time by cubic Hermite interpolation, so that the paddle
!> velocity is continuous. Signals come from jonswap_paddle_signal or from a
!> laboratory file (signal_read).
module wave_signal
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use kinds, only: rp
   use constants, only: msg_len, path_len
   use errors, only: input_error, alloc_check
   use input_check, only: int_str, real_str
   implicit none
   private
   public :: signal_t, signal_eval, signal_read

   !> Samples of a signal: times t(:) [s], strictly increasing, and
   !> displacements x(:) [m], at least two of each.
   type :: signal_t
      real(rp), allocatable :: t(:)
      real(rp), allocatable :: x(:)
   end type signal_t

contains

   !> Displacement x [m] and velocity u [m/s] of the signal at time t [s].
   !> Between samples: cubic Hermite interpolation whose node slopes are the
   !> derivative of the parabola through the node and its two neighbours
   !> (second order also on uneven samples; one-sided parabola at the two
   !> ends). It passes through every sample, reproduces a linear signal
   !> exactly, and its velocity is continuous. Before t(1): x = 0 and u = 0;
   !> from the last sample on: x = x(n) held, u = 0.
   pure subroutine signal_eval(sig, t, x, u)
      type(signal_t), intent(in) :: sig
      real(rp), intent(in) :: t
      real(rp), intent(out) :: x, u
      integer :: n, lo, hi, mid
      real(rp) :: h, s, m0, m1, s2, s3
      n = size(sig%t)
      if (t < sig%t(1)) then
         x = 0.0_rp
         u = 0.0_rp
         return
      end if
      if (t >= sig%t(n)) then
         x = sig%x(n)
         u = 0.0_rp
         return
      end if
      ! interval [t(lo), t(lo+1)) holding t, by bisection
      lo = 1
      hi = n
      do while (hi - lo > 1)
         mid = (lo + hi)/2
         if (sig%t(mid) <= t) then
            lo = mid
         else
            hi = mid
         end if
      end do
      h = sig%t(lo + 1) - sig%t(lo)
      m0 = node_slope(sig, lo)
      m1 = node_slope(sig, lo + 1)
      s = (t - sig%t(lo))/h
      s2 = s*s
      s3 = s2*s
      x = (2.0_rp*s3 - 3.0_rp*s2 + 1.0_rp)*sig%x(lo) + (s3 - 2.0_rp*s2 + s)*h*m0 &
          + (-2.0_rp*s3 + 3.0_rp*s2)*sig%x(lo + 1) + (s3 - s2)*h*m1
      u = ((6.0_rp*s2 - 6.0_rp*s)*(sig%x(lo) - sig%x(lo + 1)))/h + (3.0_rp*s2 - 4.0_rp*s + 1.0_rp)*m0 &
          + (3.0_rp*s2 - 2.0_rp*s)*m1
   end subroutine signal_eval

   !> Slope dx/dt at sample i: derivative of the parabola through samples
   !> i-1, i, i+1 (i+1, i+2 at the first sample, i-2, i-1 at the last), or the
   !> chord when the signal has only two samples.
   pure function node_slope(sig, i) result(m)
      type(signal_t), intent(in) :: sig
      integer, intent(in) :: i
      real(rp) :: m
      integer :: n
      real(rp) :: ha, hb, da, db
      n = size(sig%t)
      if (n == 2) then
         m = (sig%x(2) - sig%x(1))/(sig%t(2) - sig%t(1))
         return
      end if
      if (i == 1) then
         ha = sig%t(2) - sig%t(1); hb = sig%t(3) - sig%t(2)
         da = (sig%x(2) - sig%x(1))/ha; db = (sig%x(3) - sig%x(2))/hb
         m = ((2.0_rp*ha + hb)*da - ha*db)/(ha + hb)
      else if (i == n) then
         ha = sig%t(n - 1) - sig%t(n - 2); hb = sig%t(n) - sig%t(n - 1)
         da = (sig%x(n - 1) - sig%x(n - 2))/ha; db = (sig%x(n) - sig%x(n - 1))/hb
         m = ((2.0_rp*hb + ha)*db - hb*da)/(ha + hb)
      else
         ha = sig%t(i) - sig%t(i - 1); hb = sig%t(i + 1) - sig%t(i)
         da = (sig%x(i) - sig%x(i - 1))/ha; db = (sig%x(i + 1) - sig%x(i))/hb
         m = (hb*da + ha*db)/(ha + hb)
      end if
   end function node_slope

   !> Read a paddle signal from a text file of two columns, time [s] and
   !> displacement [m], one sample a line, separated by blanks or a comma.
   !> Blank lines and lines starting with '#' are skipped, and text after a
   !> '#' is ignored; further columns are ignored. Stops with a clear error
   !> (exit code 2) on a missing file, an unreadable or non-finite value
   !> (naming the line), fewer than 2 samples, or times not strictly
   !> increasing. The error names file and group (the namelist group that
   !> asked for the file); when case_file and var are given, it names the
   !> case file, the group and the variable holding the signal file's name.
   subroutine signal_read(file, group, sig, case_file, var)
      character(len=*), intent(in) :: file, group
      type(signal_t), intent(out) :: sig
      character(len=*), intent(in), optional :: case_file, var
      integer :: u, ios, line, n, k
      character(len=4096) :: buf
      character(len=msg_len) :: msg
      real(rp) :: v(2)
      real(rp), allocatable :: tt(:), xx(:)
      integer :: ist
      character(len=200) :: emsg

      open (newunit=u, file=file, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) call fail('cannot open the file: '//trim(msg))
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (tt(1024), xx(1024), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'tt, xx in signal_read')
      n = 0
      line = 0
      do
         read (u, '(a)', iostat=ios, iomsg=msg) buf
         if (is_iostat_end(ios)) exit
         line = line + 1
         if (ios /= 0) call fail('line '//int_str(line)//': cannot read the line: '//trim(msg))
         k = index(buf, '#')
         if (k > 0) buf(k:) = ''
         if (len_trim(buf) == 0) cycle
         read (buf, *, iostat=ios, iomsg=msg) v
         if (ios /= 0) call fail('line '//int_str(line)//': cannot read two numbers (time, displacement) from "'// &
                                 trim(adjustl(buf))//'"')
         if (.not. all(ieee_is_finite(v))) call fail('line '//int_str(line)//': value is not a finite number')
         if (n > 0) then
            if (v(1) <= tt(n)) call fail('line '//int_str(line)//': time '//real_str(v(1))// &
                                         ' is not after the previous time '//real_str(tt(n))// &
                                         ' (times must increase strictly)')
         end if
         if (n == size(tt)) then
            tt = [tt, tt]
            xx = [xx, xx]
         end if
         n = n + 1
         tt(n) = v(1)
         xx(n) = v(2)
      end do
      close (u)
      if (n < 2) call fail('has '//int_str(n)//' sample lines; at least 2 lines "time displacement" are needed')
      sig%t = tt(1:n)
      sig%x = xx(1:n)

   contains

      subroutine fail(what)
         character(len=*), intent(in) :: what
         character(len=path_len) :: vname
         vname = ''
         if (present(var)) vname = var
         if (present(case_file)) then
            call input_error(case_file, group, trim(vname), "paddle signal file '"//trim(file)//"': "//what)
         else
            call input_error(file, group, trim(vname), what)
         end if
      end subroutine fail
   end subroutine signal_read
end module wave_signal

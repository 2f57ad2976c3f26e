!> What the machine and the process limits leave for a run: the address-space
!> limit (ulimit -v) less what the process already maps, and the memory
!> available on the machine (/proc/meminfo). The size check before a case
!> allocates its particles compares its estimate with them.
module sys_limits
   use, intrinsic :: iso_c_binding, only: c_int, c_long
   use kinds, only: rp
   use input_check, only: int_str
   implicit none
   private
   public :: sys_memory_left

   !> struct rlimit of Linux: two rlim_t (unsigned long); infinity reads as -1 here
   type, bind(c) :: rlimit_t
      integer(c_long) :: cur = 0, max = 0
   end type rlimit_t

   interface
      integer(c_int) function c_getrlimit(resource, rlim) bind(c, name='getrlimit')
         import :: c_int, rlimit_t
         implicit none
         integer(c_int), value :: resource
         type(rlimit_t), intent(out) :: rlim
      end function c_getrlimit
   end interface

   integer(c_int), parameter :: rlimit_as = 9    !< RLIMIT_AS on Linux

contains

   !> Bytes this process can still allocate (huge when no limit is known),
   !> and what sets the figure; nodes is the number of processes that share
   !> the machine's available memory.
   subroutine sys_memory_left(nodes, bytes, source)
      integer, intent(in) :: nodes
      real(rp), intent(out) :: bytes
      character(len=:), allocatable, intent(out) :: source
      type(rlimit_t) :: rl
      real(rp) :: avail, mapped
      bytes = huge(1.0_rp)
      source = 'no limit known'
      if (c_getrlimit(rlimit_as, rl) == 0) then
         if (rl%cur > 0) then
            mapped = proc_kb('/proc/self/status', 'VmSize:')
            bytes = real(rl%cur, rp) - max(mapped, 0.0_rp)*1024.0_rp
            source = 'the address-space limit (ulimit -v) less the '//gb(max(mapped, 0.0_rp)*1024.0_rp)// &
                     ' GB this process maps already'
         end if
      end if
      avail = proc_kb('/proc/meminfo', 'MemAvailable:')*1024.0_rp/max(nodes, 1)
      if (avail >= 0.0_rp .and. avail < bytes) then
         bytes = avail
         source = 'the memory available on this machine (MemAvailable'
         if (nodes > 1) source = source//' shared by the '//int_str(nodes)//' ranks on it'
         source = source//')'
      end if
   end subroutine sys_memory_left

   !> The value in kB of the line 'key value kB' of a /proc file, -1 when absent.
   real(rp) function proc_kb(path, key) result(kb)
      character(len=*), intent(in) :: path, key
      character(len=256) :: line, msg
      integer :: u, ios
      kb = -1.0_rp
      open (newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) return
      lines: do
         read (u, '(a)', iostat=ios, iomsg=msg) line
         if (ios /= 0) exit lines
         if (index(line, key) /= 1) cycle lines
         read (line(len(key) + 1:), *, iostat=ios, iomsg=msg) kb
         if (ios /= 0) kb = -1.0_rp
         exit lines
      end do lines
      close (u)
   end function proc_kb

   function gb(b) result(s)
      real(rp), intent(in) :: b
      character(len=:), allocatable :: s
      character(len=32) :: w
      write (w, '(f0.2)') b/1024.0_rp**3
      s = trim(w)
      if (s(1:1) == '.') s = '0'//s
   end function gb
end module sys_limits

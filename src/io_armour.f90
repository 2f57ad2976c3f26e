!> OUT/armour.csv: the armour layer as generated (written once at the start
!> of a run): its parameters in a '#' line, then one row per unit with its
!> body number and starting pose. post/armour.py reads it with bodies.csv.
module io_armour
   use kinds, only: rp
   use constants, only: msg_len, ndim
   use errors, only: fatal
   implicit none
   private
   public :: armour_csv_write

contains

   !> header: the parameters of the layer, 'key=value' separated by commas
   !> (scene_flume: armour_csv_header); pose(:, k): x, y, (z in 3D,) angle (and in 3D the turn
   !> about the slope's normal, angle_y, in degrees) of unit k at the
   !> start; its body number is first + k - 1, the one of bodies.csv.
   subroutine armour_csv_write(out_dir, header, first, pose)
      character(len=*), intent(in) :: out_dir, header
      integer, intent(in) :: first
      real(rp), intent(in) :: pose(:, :)
      integer :: u, ios, k
      character(len=msg_len) :: msg
      open (newunit=u, file=trim(out_dir)//'/armour.csv', status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//trim(out_dir)//'/armour.csv: '//trim(msg))
      write (u, '(a)') '# '//header
      if (ndim == 2) then
         write (u, '(a)') 'unit,body,x0,y0,angle0'
      else
         write (u, '(a)') 'unit,body,x0,y0,z0,angle0,turn0'
      end if
      do k = 1, size(pose, 2)
         write (u, '(i0,",",i0,*(:,",",es23.15e3))') k, first + k - 1, pose(:, k)
      end do
      close (u)
   end subroutine armour_csv_write
end module io_armour

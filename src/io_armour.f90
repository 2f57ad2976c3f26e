!> OUT/armour.csv: the armour layer as generated (written once at the start
!> of a run): its parameters in a '#' line, then one row per unit with its
!> body number and starting pose. post/armour.py reads it with bodies.csv.
module io_armour
   use kinds, only: rp
   use constants, only: msg_len, pi
   use input, only: case_cfg
   use errors, only: fatal
   implicit none
   private
   public :: armour_csv_write

contains

   !> The body number is the one of bodies.csv (the order of the bodies in the case).
   subroutine armour_csv_write(out_dir, c)
      character(len=*), intent(in) :: out_dir
      type(case_cfg), intent(in) :: c
      integer :: u, ios, k
      character(len=msg_len) :: msg
      if (.not. c%armour%on) return
      open (newunit=u, file=trim(out_dir)//'/armour.csv', status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//trim(out_dir)//'/armour.csv: '//trim(msg))
      write (u, '("# dn=",f0.6,",density=",f0.6,",rho_water=",f0.6,",placement=",a,",porosity_target=",f0.6, &
            &",porosity=",f0.6,",threshold=",f0.6,",slope_angle_deg=",f0.6,",seed=",i0)') c%armour%dn, &
         c%armour%density, c%fluid%rho0, trim(c%armour%placement), c%armour%porosity, c%layer%porosity, &
         c%armour%threshold, c%layer%alpha*180.0_rp/pi, c%armour%seed
      write (u, '(a)') 'unit,body,x0,y0,angle0'
      do k = 1, c%layer%n_units
         write (u, '(i0,",",i0,3(",",es23.15e3))') k, c%layer%first + k - 1, c%layer%pose(:, k)
      end do
      close (u)
   end subroutine armour_csv_write
end module io_armour

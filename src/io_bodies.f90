!> OUT/bodies.csv: one row per body at every energy output time, with the
!> force and torque split by source and the displacement from the start.
module io_bodies
   use kinds, only: rp
   use constants, only: msg_len, ndim, iup
   use io_files, only: csv_rows_until, csv_flush
   use body_dynamics, only: body_t
   use rigid, only: rigid_angle, rigid_pose_pack
   use errors, only: fatal
   implicit none
   private
   public :: bodies_csv_open, bodies_csv_row, bodies_csv_close

   !> bodies.csv of a run (open on rank 0 only).
   type, public :: bodies_csv_t
      integer :: unit = 0
      logical :: opened = .false.   !< newunit= numbers are negative: keep a flag
   end type bodies_csv_t
   character(len=*), parameter :: header2 = 'time,body,x,y,angle,u,v,omega,fx_fluid,fy_fluid,torque_fluid,'// &
                                            'fx_contact,fy_contact,torque_contact,fx_friction,fy_friction,'// &
                                            'torque_friction,fx_gravity,fy_gravity,displacement,rotation'
   !> 3D: the pose as centre and unit quaternion, vectors of three components, torques about x, y, z
   character(len=*), parameter :: header3 = 'time,body,x,y,z,qw,qx,qy,qz,u,v,w,omega_x,omega_y,omega_z,'// &
                                            'fx_fluid,fy_fluid,fz_fluid,tx_fluid,ty_fluid,tz_fluid,'// &
                                            'fx_contact,fy_contact,fz_contact,tx_contact,ty_contact,tz_contact,'// &
                                            'fx_friction,fy_friction,fz_friction,tx_friction,ty_friction,tz_friction,'// &
                                            'fx_gravity,fy_gravity,fz_gravity,displacement,rotation'

contains

   !> A new file, or on restart the old one cut back to rows up to time t_keep.
   subroutine bodies_csv_open(bf, out_dir, restart, t_keep)
      type(bodies_csv_t), intent(inout) :: bf
      character(len=*), intent(in) :: out_dir
      logical, intent(in) :: restart
      real(rp), intent(in) :: t_keep
      character(len=:), allocatable :: path, keep
      character(len=msg_len) :: msg
      integer :: ios
      path = trim(out_dir)//'/bodies.csv'
      keep = ''
      if (restart) keep = csv_rows_until(path, t_keep)
      open (newunit=bf%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//': '//trim(msg))
      bf%opened = .true.
      if (ndim == 2) then
         write (bf%unit, '(a)') header2
      else
         write (bf%unit, '(a)') header3
      end if
      if (len(keep) > 0) write (bf%unit, '(a)', advance='no') keep
      call csv_flush(bf%unit, 'bodies.csv')
   end subroutine bodies_csv_open

   subroutine bodies_csv_row(bf, t, bodies)
      type(bodies_csv_t), intent(in) :: bf
      real(rp), intent(in) :: t
      type(body_t), intent(in) :: bodies(:)
      integer :: b
      real(rp) :: fg(ndim)
      if (.not. bf%opened) return
      do b = 1, size(bodies)
         associate (x => bodies(b))
            fg = 0.0_rp
            fg(iup) = -x%mass*x%g
            write (bf%unit, '(es23.15e3,",",i0,*(:,",",es23.15e3))') t, b, rigid_pose_pack(x%pose), x%v, x%omega, &
               x%f_fluid, x%t_fluid, x%f_normal, x%t_normal, x%f_fric, x%t_fric, fg, &
               norm2(x%pose%c - x%pose_start%c), rigid_angle(x%pose, x%pose_start)
         end associate
      end do
      call csv_flush(bf%unit, 'bodies.csv')
   end subroutine bodies_csv_row

   subroutine bodies_csv_close(bf)
      type(bodies_csv_t), intent(inout) :: bf
      if (bf%opened) close (bf%unit)
      bf%opened = .false.
   end subroutine bodies_csv_close
end module io_bodies

!> Reads and validates a whole case file; writes the effective namelist.
!> Every check happens here, before any particle is made.
module input
   use kinds, only: rp
   use constants, only: path_len, msg_len
   use input_check, only: scan_groups, real_str
   use input_run, only: run_cfg, read_run, write_run
   use input_domain, only: domain_cfg, read_domain, write_domain
   use input_fluid, only: fluid_cfg, read_fluid, write_fluid
   use input_numerics, only: numerics_cfg, read_numerics, write_numerics
   use input_geometry, only: geom_object, read_geometry, write_geometry
   use geom, only: polygons_overlap
   use errors, only: input_error, fatal
   implicit none
   private
   public :: case_cfg, read_case, write_case

   type :: case_cfg
      character(len=path_len) :: file = ''
      type(run_cfg) :: run
      type(domain_cfg) :: domain
      type(fluid_cfg) :: fluid
      type(numerics_cfg) :: numerics
      type(geom_object), allocatable :: objs(:)
   end type case_cfg

contains

   subroutine read_case(file, c)
      character(len=*), intent(in) :: file
      type(case_cfg), intent(out) :: c
      integer :: i, k
      real(rp) :: tol
      character(len=:), allocatable :: gi, gk
      c%file = file
      call scan_groups(file)
      call read_run(file, c%run)
      call read_domain(file, c%domain)
      call read_fluid(file, c%fluid)
      call read_numerics(file, c%numerics)
      call read_geometry(file, c%numerics%dp, c%numerics%h_over_dp*c%numerics%dp, c%objs)

      tol = 1.0e-9_rp*max(abs(c%domain%xmax - c%domain%xmin), abs(c%domain%ymax - c%domain%ymin))
      do i = 1, size(c%objs)
         gi = obj_name(c%objs(i))
         associate (v => c%objs(i)%v)
            if (minval(v(1, :)) < c%domain%xmin - tol .or. maxval(v(1, :)) > c%domain%xmax + tol .or. &
                minval(v(2, :)) < c%domain%ymin - tol .or. maxval(v(2, :)) > c%domain%ymax + tol) then
               call input_error(file, gi, '', 'the '//trim(c%objs(i)%role)//' object reaches outside the &domain ['// &
                                real_str(c%domain%xmin)//', '//real_str(c%domain%xmax)//'] x ['// &
                                real_str(c%domain%ymin)//', '//real_str(c%domain%ymax)//']')
            end if
         end associate
      end do
      do i = 1, size(c%objs)
         if (c%objs(i)%role /= 'fluid') cycle
         others: do k = 1, size(c%objs)
            if (k == i) cycle others
            if (c%objs(k)%role == 'fluid' .and. k < i) cycle others
            if (polygons_overlap(c%objs(i)%v, c%objs(k)%v, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
               gi = obj_name(c%objs(i))
               gk = obj_name(c%objs(k))
               call input_error(file, gi, '', 'the fluid overlaps '//trim(c%objs(k)%role)//' object &'//gk// &
                                ' (fluid and walls must not share area)')
            end if
         end do others
      end do
   end subroutine read_case

   function obj_name(o) result(s)
      type(geom_object), intent(in) :: o
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i0)') o%index
      s = trim(o%group)//' #'//trim(b)
   end function obj_name

   !> The effective namelist: every group with every value, defaults filled in.
   subroutine write_case(path, c)
      character(len=*), intent(in) :: path
      type(case_cfg), intent(in) :: c
      integer :: u, ios
      character(len=msg_len) :: msg
      open (newunit=u, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//trim(path)//': '//trim(msg))
      write (u, '(a)') "! Effective input of MBSPH case '"//trim(c%run%case_name)//"' read from "//trim(c%file)
      call write_run(u, c%run)
      call write_domain(u, c%domain)
      call write_fluid(u, c%fluid)
      call write_numerics(u, c%numerics)
      call write_geometry(u, c%objs)
      close (u)
   end subroutine write_case
end module input

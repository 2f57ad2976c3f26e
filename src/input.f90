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
   use input_body, only: body_cfg, contact_cfg, read_bodies, write_bodies, read_contact, write_contact
   use body_shapes, only: body_outline
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
      type(body_cfg), allocatable :: bodies(:)
      type(contact_cfg) :: contact
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
      call read_bodies(file, c%numerics%dp, c%bodies)
      call read_contact(file, c%contact)

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
      call check_bodies(c, tol)
   end subroutine read_case

   !> Bodies inside the domain, not overlapping a wall or another body
   !> (touching is allowed; fluid is carved around them).
   subroutine check_bodies(c, tol)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: tol
      integer :: i, k
      real(rp), allocatable :: vi(:, :), vk(:, :)
      character(len=16) :: bi, bk
      do i = 1, size(c%bodies)
         write (bi, '(i0)') i
         vi = body_outline(c%bodies(i))
         if (minval(vi(1, :)) < c%domain%xmin - tol .or. maxval(vi(1, :)) > c%domain%xmax + tol .or. &
             minval(vi(2, :)) < c%domain%ymin - tol .or. maxval(vi(2, :)) > c%domain%ymax + tol) then
            call input_error(c%file, 'body #'//trim(bi), '', 'the body reaches outside the &domain')
         end if
         walls: do k = 1, size(c%objs)
            if (c%objs(k)%role /= 'solid') cycle walls
            if (polygons_overlap(vi, c%objs(k)%v, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
               call input_error(c%file, 'body #'//trim(bi), '', 'the body overlaps the solid &'// &
                                obj_name(c%objs(k))//' (bodies may touch walls, not cut into them)')
            end if
         end do walls
         do k = 1, i - 1
            write (bk, '(i0)') k
            vk = body_outline(c%bodies(k))
            if (polygons_overlap(vi, vk, 1.0e-9_rp, 0.5_rp*c%numerics%dp)) then
              call input_error(c%file, 'body #'//trim(bi), '', 'the body overlaps &body #'//trim(bk))
            end if
         end do
      end do
   end subroutine check_bodies

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
      call write_bodies(u, c%bodies)
      call write_contact(u, c%contact)
      close (u)
   end subroutine write_case
end module input

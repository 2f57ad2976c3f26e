!> &domain: the box particles live in; a fluid particle that leaves it is removed.
module input_domain
   use kinds, only: rp
   use constants, only: msg_len, ndim
   use input_check, only: open_case, read_failed, group_count, real_str
   use errors, only: input_error
   implicit none
   private
   public :: domain_cfg, read_domain, write_domain

   type :: domain_cfg
      real(rp) :: xmin = 0.0_rp, xmax = -1.0_rp   !< [m]; xmax > xmin required
      real(rp) :: ymin = 0.0_rp, ymax = -1.0_rp   !< [m]; ymax > ymin required
      real(rp) :: zmin = 0.0_rp, zmax = 0.0_rp    !< [m]; the width (3D build only): zmax > zmin required
      !> periodic sides across the width (3D build only): what leaves at zmax comes in at zmin
      logical :: periodic_z = .false.
   end type domain_cfg

   real(rp) :: xmin, xmax, ymin, ymax, zmin, zmax
   logical :: periodic_z
   namelist /domain/ xmin, xmax, ymin, ymax, zmin, zmax, periodic_z

contains

   subroutine read_domain(file, c)
      character(len=*), intent(in) :: file
      type(domain_cfg), intent(out) :: c
      integer :: u, ios
      character(len=msg_len) :: msg
      type(domain_cfg) :: d
      if (group_count(file, 'domain') == 0) call input_error(file, 'domain', '', 'required group is missing')
      if (group_count(file, 'domain') > 1) call input_error(file, 'domain', '', 'group appears more than once')
      xmin = d%xmin; xmax = d%xmax; ymin = d%ymin; ymax = d%ymax; zmin = d%zmin; zmax = d%zmax
      periodic_z = d%periodic_z
      u = open_case(file)
      read (u, nml=domain, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, 'domain', ios, msg)) return
      c%xmin = xmin; c%xmax = xmax; c%ymin = ymin; c%ymax = ymax; c%zmin = zmin; c%zmax = zmax
      c%periodic_z = periodic_z
      if (.not. (xmax > xmin)) call input_error(file, 'domain', 'xmax', 'must be greater than xmin = ' &
                                                //real_str(xmin)//' (got '//real_str(xmax)//')')
      if (.not. (ymax > ymin)) call input_error(file, 'domain', 'ymax', 'must be greater than ymin = ' &
                                                //real_str(ymin)//' (got '//real_str(ymax)//')')
      if (ndim == 3) then
         if (.not. (zmax > zmin)) call input_error(file, 'domain', 'zmax', 'must be greater than zmin = ' &
                                                   //real_str(zmin)//' in 3D (got '//real_str(zmax)//')')
      else if (abs(zmin) > 0.0_rp .or. abs(zmax) > 0.0_rp) then
         call input_error(file, 'domain', merge('zmin', 'zmax', abs(zmin) > 0.0_rp), &
                          'a width across the section is for the 3D build (build/mbsph3d); leave it out in 2D')
      end if
      if (ndim == 2 .and. periodic_z) call input_error(file, 'domain', 'periodic_z', &
                                                       'periodic sides across the width are for the 3D build (build/mbsph3d)')
   end subroutine read_domain

   subroutine write_domain(u, c)
      integer, intent(in) :: u
      type(domain_cfg), intent(in) :: c
      xmin = c%xmin; xmax = c%xmax; ymin = c%ymin; ymax = c%ymax; zmin = c%zmin; zmax = c%zmax
      periodic_z = c%periodic_z
      write (u, nml=domain)
   end subroutine write_domain
end module input_domain

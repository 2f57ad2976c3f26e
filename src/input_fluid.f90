!> &fluid: water properties, equation of state and gravity.
module input_fluid
   use kinds, only: rp
   use constants, only: msg_len
   use input_check, only: open_case, read_failed, check_real, group_count
   use errors, only: input_error
   implicit none
   private
   public :: fluid_cfg, read_fluid, write_fluid

   type :: fluid_cfg
      real(rp) :: rho0 = 1000.0_rp      !< reference density [kg/m3]
      real(rp) :: gamma = 7.0_rp        !< Tait exponent [-]
      real(rp) :: coef = 10.0_rp        !< sound-speed coefficient: c0 = coef sqrt(g h_swl) [-]
      real(rp) :: gravity = 9.81_rp     !< acceleration of gravity, acting along -y [m/s2]
      real(rp) :: h_swl = 0.0_rp        !< depth for c0 and hydrostatic start [m] (0: from the fluid)
      real(rp) :: rho_min = 0.7_rp      !< fluid density below rho_min*rho0 removes the particle [-]
      real(rp) :: rho_max = 1.3_rp      !< fluid density above rho_max*rho0 removes the particle [-]
   end type fluid_cfg

   real(rp) :: rho0, gamma, coef, gravity, h_swl, rho_min, rho_max
   namelist /fluid/ rho0, gamma, coef, gravity, h_swl, rho_min, rho_max

contains

   subroutine to_vars(c)
      type(fluid_cfg), intent(in) :: c
      rho0 = c%rho0; gamma = c%gamma; coef = c%coef; gravity = c%gravity; h_swl = c%h_swl
      rho_min = c%rho_min; rho_max = c%rho_max
   end subroutine to_vars

   subroutine read_fluid(file, c)
      character(len=*), intent(in) :: file
      type(fluid_cfg), intent(out) :: c
      integer :: u, ios
      character(len=msg_len) :: msg
      type(fluid_cfg) :: d
      if (group_count(file, 'fluid') > 1) call input_error(file, 'fluid', '', 'group appears more than once')
      call to_vars(d)
      if (group_count(file, 'fluid') == 1) then
         u = open_case(file)
         read (u, nml=fluid, iostat=ios, iomsg=msg)
         close (u)
         if (read_failed(file, 'fluid', ios, msg)) return
      end if
      c%rho0 = rho0; c%gamma = gamma; c%coef = coef; c%gravity = gravity; c%h_swl = h_swl
      c%rho_min = rho_min; c%rho_max = rho_max
      call check_real(file, 'fluid', 'rho0', c%rho0, 1.0_rp, 1.0e5_rp)
      call check_real(file, 'fluid', 'gamma', c%gamma, 1.0_rp, 10.0_rp)
      call check_real(file, 'fluid', 'coef', c%coef, 5.0_rp, 100.0_rp)
      call check_real(file, 'fluid', 'gravity', c%gravity, 0.0_rp, 100.0_rp)
      call check_real(file, 'fluid', 'h_swl', c%h_swl, 0.0_rp, 1.0e4_rp)
      call check_real(file, 'fluid', 'rho_min', c%rho_min, 0.0_rp, 1.0_rp, hi_open=.true.)
      call check_real(file, 'fluid', 'rho_max', c%rho_max, 1.0_rp, 10.0_rp, lo_open=.true.)
   end subroutine read_fluid

   subroutine write_fluid(u, c)
      integer, intent(in) :: u
      type(fluid_cfg), intent(in) :: c
      call to_vars(c)
      write (u, nml=fluid)
   end subroutine write_fluid
end module input_fluid

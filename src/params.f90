!> Derived numerical constants of a run, computed once from the input.
module params
   use kinds, only: rp
   use constants, only: name_len
   use input, only: case_cfg
   use kernel, only: kernel_norm
   use options, only: kernel_wendland, visc_artificial, visc_laminar_sps, &
                      diff_none, diff_molteni, diff_fourtakas, kgc_none, kgc_gradient, &
                      kgc_shepard, integ_symplectic, integ_predictor_corrector, integ_verlet, &
                      bnd_dynamic, bnd_repulsive
   implicit none
   private
   public :: params_t, params_init, visc_artificial, visc_laminar_sps, diff_none, diff_molteni, &
             diff_fourtakas, kgc_none, kgc_gradient, kgc_shepard, integ_symplectic, &
             integ_predictor_corrector, integ_verlet, bnd_dynamic, bnd_repulsive

   ! the enumerated values of the model choices are those of module options,
   ! whose option_index turns the names into them where the input is read;
   ! re-exported here for the solver

   type :: params_t
      real(rp) :: dp, h, h2, support2      !< spacing, smoothing length, h^2, (2h)^2
      real(rp) :: eta2                     !< 0.01 h^2: keeps 1/r^2 terms finite
      integer :: kernel = kernel_wendland
      real(rp) :: aw, fw                   !< kernel normalisation aw and aw/h^2
      real(rp) :: w0                       !< W(0)
      real(rp) :: rho0, gamma, g, c0, b    !< Tait: p = b ((rho/rho0)^gamma - 1)
      integer :: igamma = 0                !< gamma when it is a whole number, else 0
      real(rp) :: h_swl, y_surface         !< still-water depth and surface level [m]
      real(rp) :: rho_min, rho_max         !< removal limits [kg/m3]
      real(rp) :: cfl
      real(rp) :: dt_fixed                 !< fixed time step [s]; 0: the variable step
      integer :: visc = visc_artificial
      real(rp) :: alpha, nu, sps_smag, sps_blin
      integer :: diffusion = diff_none
      real(rp) :: delta_coef               !< delta h c0, the factor of the diffusion term
      integer :: kgc = kgc_none
      real(rp) :: kgc_cont = 1.0_rp        !< 1: corrected gradient in the continuity equation, 0: plain
      integer :: shepard_every
      integer :: integrator = integ_symplectic
      integer :: verlet_every
      integer :: boundary = bnd_dynamic    !< how the fluid meets solids
      ! repulsive boundary (doc/theory.md): A = rep_a - rep_b u_n
      real(rp) :: rep_a = 0.0_rp           !< (10/coef)^2 0.01 c0^2 / h [m/s2]
      real(rp) :: rep_b = 0.0_rp           !< (10/coef) c0 / h [1/s]
      real(rp) :: rep_q0 = 1.0e-3_rp       !< bounds 1/sqrt(q) at the wall [-]
      real(rp) :: rep_u = 0.0_rp           !< 40 / c0: weight of the approach speed in eps [s/m]
      real(rp) :: rep_rhswl = 0.0_rp       !< 1 / h_swl: depth factor of eps [1/m]
      character(len=name_len) :: case_name
   end type params_t

contains

   !> ybed and ytop bound the fluid (its lowest and highest particle edges);
   !> they fix h_swl when the input leaves it at 0.
   subroutine params_init(c, ybed, ytop, prm)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: ybed, ytop
      type(params_t), intent(out) :: prm
      prm%case_name = c%run%case_name
      prm%dp = c%numerics%dp
      prm%h = c%numerics%h_over_dp*prm%dp
      prm%h2 = prm%h*prm%h
      prm%support2 = 4.0_rp*prm%h2
      prm%eta2 = 0.01_rp*prm%h2
      prm%kernel = c%numerics%kernel_id
      prm%aw = kernel_norm(prm%kernel, prm%h)
      prm%fw = prm%aw/prm%h2
      prm%w0 = prm%aw                      ! both kernels have w(0) = 1
      prm%rho0 = c%fluid%rho0
      prm%gamma = c%fluid%gamma
      if (abs(prm%gamma - anint(prm%gamma)) < 1.0e-12_rp*prm%gamma) prm%igamma = nint(prm%gamma)
      prm%g = c%fluid%gravity
      if (c%fluid%h_swl > 0.0_rp) then
         prm%h_swl = c%fluid%h_swl
         prm%y_surface = ybed + prm%h_swl
      else if (ytop > ybed) then
         prm%h_swl = ytop - ybed
         prm%y_surface = ytop
      else                                 ! no fluid: c0 still needs a depth scale
         prm%h_swl = max(10.0_rp*prm%dp, 0.1_rp)
         prm%y_surface = ybed
      end if
      prm%c0 = c%fluid%coef*sqrt(max(prm%g, 1.0e-3_rp)*prm%h_swl)
      prm%b = prm%c0**2*prm%rho0/prm%gamma
      prm%rho_min = c%fluid%rho_min*prm%rho0
      prm%rho_max = c%fluid%rho_max*prm%rho0
      prm%cfl = c%numerics%cfl
      prm%dt_fixed = c%numerics%dt_fixed
      prm%visc = c%numerics%viscosity_id
      prm%alpha = c%numerics%alpha
      prm%nu = c%numerics%nu
      prm%sps_smag = (c%numerics%cs_sps*prm%dp)**2
      prm%sps_blin = (2.0_rp/3.0_rp)*c%numerics%ci_sps*prm%dp**2
      prm%diffusion = c%numerics%diffusion_id
      prm%delta_coef = c%numerics%delta*prm%h*prm%c0
      prm%kgc = c%numerics%kgc_id
      prm%shepard_every = c%numerics%shepard_every
      prm%kgc_cont = merge(1.0_rp, 0.0_rp, c%numerics%kgc_continuity)
      prm%integrator = c%numerics%integrator_id
      prm%verlet_every = c%numerics%verlet_every
      prm%boundary = c%numerics%boundary_id
      prm%rep_a = (10.0_rp/c%fluid%coef)**2*0.01_rp*prm%c0**2/prm%h
      prm%rep_b = (10.0_rp/c%fluid%coef)*prm%c0/prm%h
      prm%rep_u = 40.0_rp/prm%c0
      prm%rep_rhswl = 1.0_rp/prm%h_swl
   end subroutine params_init
end module params

!> Derived numerical constants of a run, computed once from the input by
!> the scene builder (scene_params); this module knows no input type.
module params
   use kinds, only: rp
   use constants, only: name_len
   use options, only: kernel_wendland, visc_artificial, visc_laminar_sps, &
                      diff_none, diff_molteni, diff_fourtakas, kgc_none, kgc_gradient, &
                      kgc_shepard, integ_symplectic, integ_predictor_corrector, integ_verlet, &
                      bnd_dynamic, bnd_repulsive, bnd_mdbc, slip_wall, slip_noslip, slip_freeslip, &
                      shift_none, shift_fickian
   implicit none
   private
   public :: params_t, visc_artificial, visc_laminar_sps, diff_none, diff_molteni, &
             diff_fourtakas, kgc_none, kgc_gradient, kgc_shepard, integ_symplectic, &
             integ_predictor_corrector, integ_verlet, bnd_dynamic, bnd_repulsive, bnd_mdbc, &
             slip_wall, slip_noslip, slip_freeslip, shift_none, shift_fickian

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
      integer :: slip = slip_wall          !< mDBC: the velocity the water sees at a solid particle
      integer :: shift = shift_none        !< particle shifting
      real(rp) :: shift_coef = 2.0_rp      !< A of the shifting's D = A h |v| dt [-]
      real(rp) :: shift_tfs = 1.9_rp       !< div r below it: in the free surface's band, not shifted [-]
      logical :: porous = .false.          !< the scene has porous regions (module porous)
      ! repulsive boundary (doc/theory.md): A = rep_a - rep_b u_n
      real(rp) :: rep_a = 0.0_rp           !< (10/coef)^2 0.01 c0^2 / h [m/s2]
      real(rp) :: rep_b = 0.0_rp           !< (10/coef) c0 / h [1/s]
      real(rp) :: rep_q0 = 1.0e-3_rp       !< bounds 1/sqrt(q) at the wall [-]
      real(rp) :: rep_u = 0.0_rp           !< 40 / c0: weight of the approach speed in eps [s/m]
      real(rp) :: rep_rhswl = 0.0_rp       !< 1 / h_swl: depth factor of eps [1/m]
      character(len=name_len) :: case_name
   end type params_t

end module params

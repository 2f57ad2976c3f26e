!> Counters and clocks of a run: everything besides the particles that a
!> restart needs to continue exactly as the uninterrupted run.
module run_state
   use kinds, only: rp, i8
   implicit none
   private
   public :: state_t

   type :: state_t
      real(rp) :: t = 0.0_rp          !< simulated time [s]
      real(rp) :: dt = 0.0_rp         !< last time step [s]
      integer :: istep = 0            !< steps taken
      integer :: isnap = 0            !< index of the next snapshot
      integer :: ienergy = 0          !< index of the next energy.csv row
      real(rp) :: t_next_snap = 0.0_rp   !< time the next snapshot is due [s]
      real(rp) :: t_next_energy = 0.0_rp  !< time the next energy row is due [s]
      integer :: lost_domain = 0      !< fluid particles that left the domain
      integer :: lost_density = 0     !< fluid particles removed for non-physical density
      integer :: n_fluid0 = 0         !< fluid particles at the start of the run
      real(rp) :: h_swl = 0.0_rp      !< still-water depth the run was set up with [m]
      real(rp) :: y_surface = 0.0_rp  !< still-water surface level [m]
      ! not restored on restart: statistics of this process
      integer :: istep0 = 0           !< first step of this process
      real(rp) :: wall0 = 0.0_rp      !< wall clock at the start of stepping [s]
      real(rp) :: t0 = 0.0_rp         !< simulated time at the start of stepping [s]
      integer(i8) :: particle_steps = 0_i8
   end type state_t
end module run_state

!> Counters and clocks of a run: everything besides the particles that a
!> restart needs to continue exactly as the uninterrupted run (state_t); and
!> what the case asks of the run's course (run_ctl_t: when to stop, write,
!> report, balance; the scene builder makes it from &run and &domain).
module run_state
   use kinds, only: rp, i8
   use constants, only: ndim
   implicit none
   private
   public :: state_t, run_ctl_t

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
      real(rp) :: pad_xc = 0.0_rp     !< absorbing paddle: displacement of its correction [m]
      real(rp) :: pad_eta_mean = 0.0_rp   !< absorbing paddle: the slow mean of what it measures less its own wave [m]
      real(rp), allocatable :: pad_hist(:, :)   !< absorbing paddle: (time [s], wave coming in [m]) of its last steps
      ! not restored on restart: statistics of this process
      integer :: istep0 = 0           !< first step of this process
      real(rp) :: wall0 = 0.0_rp      !< wall clock at the start of stepping [s]
      real(rp) :: t0 = 0.0_rp         !< simulated time at the start of stepping [s]
      integer(i8) :: particle_steps = 0_i8
   end type state_t

   !> The course of a run as the case sets it (doc/input.md, &run and &domain).
   type :: run_ctl_t
      real(rp) :: t_end = 1.0_rp               !< simulated end time [s]
      integer :: max_steps = 0                 !< stop after this many steps (0: no limit)
      real(rp) :: dt_out = 0.1_rp              !< interval between snapshots [s]
      real(rp) :: energy_interval = 0.1_rp     !< interval of energy.csv rows [s]
      real(rp) :: gauge_interval = 0.01_rp     !< interval of gauges.csv rows [s]
      real(rp) :: progress_interval = 2.0_rp   !< wall seconds between progress lines
      integer :: checkpoint_every = 0          !< steps between checkpoints (0: only at the end)
      integer :: balance_every = 100           !< steps between moves of the slab edges (0: never)
      real(rp) :: max_lost_fraction = 0.02_rp  !< stop when more fluid than this is lost
      logical :: restart = .false.             !< the run continues a checkpoint
      real(rp) :: box(2*ndim) = 0.0_rp         !< the domain: xmin, xmax, ymin, ymax (, zmin, zmax) [m]
      logical :: periodic_z = .false.          !< periodic sides across the width (3D)
   end type run_ctl_t
end module run_state

!> Everything before a run's first step: the checks that can still fail
!> before the output folder is touched, the folder, the scene (new) or the
!> checkpoint (restart), the run's own types from the case (the scene
!> builder's scene_*), this rank's slab, the banner. After the input, the one
!> place that reads the case (case_cfg): solver_run, which steps the run,
!> sees only run_t.
module run_setup
   use kinds, only: rp
   use constants, only: kind_fluid, kind_fixed, kind_moving, kind_floating, kind_filter, kind_name, ndim
   use input, only: case_cfg, write_case
   use input_check, only: int_str, real_str, approx_str
   use particles, only: particles_t, particles_count_kind, particles_permute
   use params, only: params_t, visc_artificial, diff_none, kgc_gradient, kgc_shepard, integ_verlet, &
                     bnd_dynamic, bnd_repulsive, bnd_mdbc
   use scene, only: scene_build, scene_bodies, scene_no_fluid, scene_estimate, scene_params, scene_gauges, &
                    scene_damping, scene_contact, scene_run, scene_porous, scene_walls
   use sys_limits, only: sys_memory_left
   use body_dynamics, only: body_t, bodies_place, bodies_prescribe
   use contact, only: contact_init, contact_memory_set
   use io_bodies, only: bodies_csv_open
   use grid, only: grid_init, grid_columns
   use decomp, only: decomp_init, decomp_owner, decomp_count, decomp_balance, decomp_set_edges, decomp_lo, &
                     decomp_hi
   use fluid_forces, only: forces_init
   use bc_motion, only: walls_t, walls_init, motion_apply, motion_offset
   use io_hdf5, only: h5_start
   use io_files, only: outdir_prepare, dir_writable, text_hash, file_text, energy_open
   use io_snapshot, only: snapshot_index_rebuild
   use io_checkpoint, only: checkpoint_read, checkpoint_check
   use logger, only: log_open, log_line
   use timers, only: timer_start, timer_stop, t_setup
   use comm, only: comm_size, comm_rank, comm_barrier, comm_max, comm_node_size
   use errors, only: fatal, input_error, alloc_check
   use wave_paddle, only: paddle_t, paddle_absorb_tune
   use scene_flume, only: scene_paddle, armour_csv_header
   use probe_gauges, only: gauges_count, gauges_init
   use options, only: gauge_elevation, wave_irregular, role_solid
   use io_armour, only: armour_csv_write
   use solver, only: run_t
   implicit none
   private
   public :: setup_run

contains

   !> Everything before the first step: the output folder, the particles
   !> (new or from the checkpoint), this rank's slab, the first output.
   subroutine setup_run(r, c)
      type(run_t), intent(inout) :: r
      type(case_cfg), intent(in) :: c
      integer, allocatable :: counts(:), edges(:)
      real(rp), allocatable :: mem(:, :)
      type(paddle_t) :: paddle
      integer :: ist
      character(len=200) :: emsg
      r%rc = scene_run(c)
      r%out = trim(c%run%out_dir)
      call timer_start(t_setup)
      ! every check that can still fail comes before the output folder is
      ! touched: with overwrite = .true. a case refused here keeps the old run
      call scene_paddle(c%file, c%wavemaker, c%fluid%gravity, c%run%t_end, paddle, r%wave_report)
      call check_size(c)
      call check_ranks(c)
      call check_same_case(c)
      if (.not. c%run%restart) call scene_build(c, r%p, r%prm, r%bodies)
      ! one rank prepares the folder; the others wait for it (or for its abort)
      if (comm_rank() == 0) call outdir_prepare(c%file, r%out, c%run%overwrite, c%run%restart)
      call comm_barrier()
      call check_folder_seen(r, c)
      call log_open(r%out//'/run.log', c%run%restart)
      call h5_start()
      if (c%run%restart) then
         call scene_bodies(c, r%bodies)
         ! the checkpoint must be this case's: its scene made again, only to count it
         block
            type(particles_t) :: made
            type(params_t) :: prm_made
            type(body_t), allocatable :: bodies_made(:)
            call scene_build(c, made, prm_made, bodies_made)
            call checkpoint_check(c%file, r%out, c%numerics%dp, size(r%bodies), made%n)
         end block
         r%p%history = c%numerics%integrator_id == integ_verlet
         r%p%mdbc = c%numerics%boundary_id == bnd_mdbc
         call checkpoint_read(c%file, r%out, r%p, r%st, r%bodies, counts, edges, mem)
         call scene_params(c, r%st%y_surface - r%st%h_swl, r%st%y_surface, r%prm)
         call log_line("MBSPH: restart of case '"//trim(c%run%case_name)//"' from "//r%out// &
                       '/checkpoint.h5 at t = '//real_str(r%st%t)//' s, step '//int_str(r%st%istep))
      else
         if (size(r%bodies) > 0) then
            ! prescribed bodies start on their function of time at t = 0
            call bodies_prescribe(r%bodies, 0.0_rp)
            call bodies_place(r%bodies, r%p)
         end if
         r%st%n_fluid0 = particles_count_kind(r%p, kind_fluid)
         r%st%h_swl = r%prm%h_swl
         r%st%y_surface = r%prm%y_surface
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (counts(1), edges(0), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'counts, edges in setup')
         counts = r%p%n
      end if
      ! every rank holds the whole set until decompose: count it now
      r%n_global = r%p%n
      r%n_kind = [particles_count_kind(r%p, kind_fluid), particles_count_kind(r%p, kind_fixed), &
                particles_count_kind(r%p, kind_moving), particles_count_kind(r%p, kind_floating), &
                particles_count_kind(r%p, kind_filter)]
      call walls_setup(r, c, paddle)
      call scene_gauges(c, r%gt)
      r%zone = scene_damping(c)
      r%por = scene_porous(c)
      ! moving walls start on their motion: position and velocity at t = 0
      if (r%walls%moving .and. .not. c%run%restart) call motion_apply(r%walls, r%p, 0.0_rp)
      if (r%n_kind(1) == 0) call log_line('mbsph: warning: '//trim(c%file)//': the case has '//scene_no_fluid// &
                                        '; only the bodies and moving walls are simulated')
      if (comm_rank() == 0) call write_case(r%out//'/case.nml', c)
      call comm_barrier()
      r%case_text = file_text(r%out//'/case.nml')
      call decompose(r, counts, edges)
      call forces_init(r%w, r%prm)
      if (size(r%bodies) > 0) then
         call contact_init(scene_contact(c), r%prm, r%ct)
         if (c%run%restart) call contact_memory_set(r%ct, nint(mem(1:2, :)), mem(3:2 + ndim, :))
         if (comm_rank() == 0) call bodies_csv_open(r%bf, r%out, c%run%restart, r%st%t)
      end if
      call banner(r, c)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (r%drop(size(r%p%rho)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'drop in setup')
      ! text files are rank 0's
      if (comm_rank() == 0) call energy_open(r%ef, r%out, c%run%restart, r%st%istep)
      if (c%run%restart) then
         r%snaps%porosity = r%por%on
         call snapshot_index_rebuild(r%snaps, r%out, r%st%isnap)
      else
         if (comm_rank() == 0 .and. c%armour%on) call armour_csv_write(r%out, &
            armour_csv_header(c%armour, c%layer, c%fluid%rho0), c%layer%first, c%layer%pose(:, 1:c%layer%n_units))
      end if
      call timer_stop(t_setup)
   end subroutine setup_run

   !> The moving walls and the paddle; an absorbing paddle's gauge; on
   !> restart, the check that the walls stand where the case's laws put them.
   subroutine walls_setup(r, c, paddle)
      type(run_t), intent(inout) :: r
      type(case_cfg), intent(in) :: c
      type(paddle_t), intent(in) :: paddle
      real(rp) :: source
      call walls_init(scene_walls(c), paddle, r%n_kind(3) > 0, r%walls)
      if (r%walls%paddle%absorb) then
         ! read where the kernel's support holds only water: 2h + dp in front of the face
         r%walls%paddle%gauge_offset = 2.0_rp*r%prm%h + r%prm%dp
         ! where the wave starts: the dynamic boundary holds the water about h off its
         ! particles, whose first row stands dp/2 behind the face; mDBC's wall is the face
         source = 0.0_rp
         if (r%prm%boundary == bnd_dynamic) source = r%prm%h - 0.5_rp*r%prm%dp
         call paddle_absorb_tune(r%walls%paddle, c%fluid%gravity, r%walls%paddle%gauge_offset - source)
         r%wave_report = r%wave_report//new_line('a')//'  absorber tuned to its gauge '// &
                         real_str(r%walls%paddle%gauge_offset - source)//" m from the paddle's wave source: gain "// &
                         real_str(r%walls%paddle%gain)//' 1/s, the wave coming in read '//real_str(r%walls%paddle%lag)// &
                         ' s late'
         ! (3D: at mid-width; the paddle moves uniformly over the width)
         call gauges_init(r%pg, [gauge_elevation], [r%walls%paddle%x_face], [0.0_rp], &
                          [merge(0.5_rp*(c%domain%zmin + c%domain%zmax), 0.0_rp, ndim == 3)])
      end if
      if (c%run%restart .and. r%walls%moving) call check_walls_at_restart(r, c)
   end subroutine walls_setup

   !> A restart may change the wavemaker (the next step of a test series)
   !> only where the paddle of the checkpoint stands where the case's
   !> wavemaker puts it: while it rests, before its start or after the end of
   !> a wave with a duration. Otherwise the paddle would jump.
   subroutine check_walls_at_restart(r, c)
      type(run_t), intent(in) :: r
      type(case_cfg), intent(in) :: c
      type(walls_t) :: w
      real(rp) :: d
      character(len=:), allocatable :: hint
      w = r%walls
      w%paddle%xc = r%st%pad_xc
      w%paddle%tc = r%st%t
      w%paddle%uc = 0.0_rp
      d = motion_offset(w, r%p, r%st%t)
      if (d <= 1.0e-3_rp*r%prm%dp) return
      hint = ''
      ! without a duration the irregular signal is made for the run's length: a new t_end makes another
      if (c%wavemaker%wave_id == wave_irregular .and. c%wavemaker%duration <= 0.0_rp) hint = '; an irregular '// &
         "wave without a duration is made for the run's t_end, so that a longer run makes another wave: set "// &
         'duration (at least the longest t_end - t_start) to continue a run'
      call input_error(c%file, 'wavemaker', '', 'the moving walls of '//r%out// &
         '/checkpoint.h5 stand up to '//real_str(d)//' m from where the case puts them at t = '// &
         real_str(r%st%t)//' s: a restart may change the paddle (or a moving wall) only while it rests, '// &
         'before its t_start or after the end of a wave with a duration'//hint)
   end subroutine check_walls_at_restart

   !> Every rank read the same case file; otherwise all stop with one message
   !> (ranks that disagree would wait for each other for ever).
   subroutine check_same_case(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: m(2)
      integer :: h
      if (comm_size() == 1) return
      h = text_hash(file_text(c%file))
      ! the largest and the smallest hash
      m = [real(h, rp), -real(h, rp)]
      call comm_max(m)
      if (nint(m(1)) /= nint(-m(2))) call fatal(trim(c%file)//': the ranks did not all read the same case file '// &
         '(its text differs between ranks): start every rank on one case file', 2)
   end subroutine check_same_case

   !> Every rank sees the output folder rank 0 prepared; otherwise all stop
   !> with one message (a rank that cannot open its file would hang the others
   !> in the first collective write).
   subroutine check_folder_seen(r, c)
      type(run_t), intent(inout) :: r
      type(case_cfg), intent(in) :: c
      real(rp) :: m(2)
      if (comm_size() == 1) return
      ! the first rank that cannot write the folder, and whether there is one
      m = [-huge(1.0_rp), 0.0_rp]
      if (.not. dir_writable(r%out)) m = [-real(comm_rank(), rp), 1.0_rp]
      call comm_max(m)
      if (m(2) > 0.0_rp) call input_error(c%file, 'run', 'out_dir', 'rank '//int_str(nint(-m(1)))// &
         " cannot write the folder '"//r%out//"' that rank 0 prepared: give every rank the same working "// &
         'directory and file system, or an absolute out_dir they all see')
   end subroutine check_folder_seen

   !> Enough cell columns for the ranks: each rank's slab is one column at least.
   subroutine check_ranks(c)
      type(case_cfg), intent(in) :: c
      integer :: nr, ncx
      nr = comm_size()
      if (nr == 1) return
      ! counted, not allocated: the grid itself comes after the size check
      ncx = grid_columns(c%domain%xmin, c%domain%xmax, c%numerics%h_over_dp*c%numerics%dp)
      if (nr > ncx) call input_error(c%file, 'domain', 'xmax', 'the domain is '//int_str(ncx)// &
         ' cells of 2h wide, too few for '//int_str(nr)//' ranks (a rank needs one at least): run on at most '// &
         int_str(ncx)//' ranks')
   end subroutine check_ranks

   !> The case's size against the 32-bit numbers of particles and cells and
   !> against the memory this process can still take, before any of it is
   !> allocated: a case too large ends with the estimate, not a crash.
   subroutine check_size(c)
      type(case_cfg), intent(in) :: c
      ! bytes per particle of one rank: the run's arrays (274 to 456 measured,
      ! doc/performance.md) with the scene's growing store, and every rank
      ! holds the whole set while the scene is built
      real(rp), parameter :: bytes_per_particle = 500.0_rp
      ! cells and particles are numbered by default integers; a margin of two
      real(rp), parameter :: index_max = 0.5_rp*real(huge(1), rp)
      real(rp) :: n, cells, need, left, h
      character(len=:), allocatable :: source
      h = c%numerics%h_over_dp*c%numerics%dp
      associate (d => c%domain)
         ! the grid: cells 2h wide and h/2 tall, with ghost columns and rows (grid_init)
         cells = (real(ceiling((d%xmax - d%xmin)/(2.0_rp*h)), rp) + 2.0_rp)* &
                 (real(ceiling((d%ymax - d%ymin)/(0.5_rp*h)), rp) + 8.0_rp)
         if (ndim == 3) cells = cells*(real(ceiling((d%zmax - d%zmin)/(2.0_rp*h)), rp) + 2.0_rp)
         if (cells > index_max) call input_error(c%file, 'domain', 'xmin, xmax, ymin, ymax', 'the domain of '// &
            real_str(d%xmax - d%xmin)//' x '//real_str(d%ymax - d%ymin)//' m makes '//approx_str(cells)// &
            ' cells of the neighbour grid at dp = '//real_str(c%numerics%dp)//' m, more than the '// &
            approx_str(index_max)//' it can number: shrink the domain to the water and walls, or raise dp')
      end associate
      n = scene_estimate(c)
      if (n > index_max) call input_error(c%file, 'numerics', 'dp', 'the case would make about '//approx_str(n)// &
         ' particles, more than the '//approx_str(index_max)//' they can be numbered with: raise dp')
      need = n*bytes_per_particle + cells*8.0_rp
      call sys_memory_left(comm_node_size(), left, source)
      if (need > left) call input_error(c%file, 'numerics', 'dp', 'the case needs about '//approx_str(n)// &
         ' particles, about '//approx_str(need/1024.0_rp**3)//' GB on each rank (every rank holds the whole set '// &
         'while the scene is built); '//source//' leaves '//approx_str(max(left, 0.0_rp)/1024.0_rp**3)// &
         ' GB: raise dp, shrink the objects, or run where more memory is available')
   end subroutine check_size

   !> Split the whole set among the ranks: slabs of equal width (a new run;
   !> the first step balances them), the edges of the run continued (a
   !> restart on as many ranks, with its memory order), or edges from the
   !> particle count of every cell column (a restart on another number of
   !> ranks); each rank keeps its own particles. Sets up the grid of this
   !> rank's slab.
   subroutine decompose(r, counts, edges)
      type(run_t), intent(inout) :: r
      integer, intent(in) :: counts(:), edges(:)
      integer, allocatable :: hist(:), perm(:)
      integer :: nr, me, i, rk, first, nkeep
      logical :: same, moved
      integer :: ist
      character(len=200) :: emsg
      nr = comm_size()
      me = comm_rank()
      ! (the width, the box's last pair, is taken in 3D only)
      call grid_init(r%g, r%rc%box(1), r%rc%box(2), r%rc%box(3), r%rc%box(4), r%prm%h, &
                     zmin=r%rc%box(2*ndim - 1), zmax=r%rc%box(2*ndim), &
                     periodic=r%rc%periodic_z)
      call decomp_init(r%dc, r%g%x0, r%g%cs, r%g%ncx_all, nr, me)
      if (nr == 1) return
      same = size(counts) == nr .and. size(edges) == nr + 1
      if (same) same = edges(nr + 1) == r%g%ncx_all
      if (same) then
         call decomp_set_edges(r%dc, edges)
      else if (r%rc%restart .and. r%rc%balance_every > 0) then
         ! (a new run starts from slabs of equal width and balances at step 0)
         allocate (hist(0:r%g%ncx_all - 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'hist in decompose')
         call decomp_count(r%dc, r%p%x, r%p%kind, r%p%n, hist)
         call decomp_balance(r%dc, hist, moved)
      end if
      ! the particles of this slab; restarting on as many ranks, this rank's
      ! part of the file first, then the others' (as migration appends them)
      allocate (perm(r%p%n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'perm in decompose')
      nkeep = 0
      if (same) then
         first = sum(counts(1:me))
         do i = first + 1, first + counts(me + 1)
            call keep(i)
         end do
         do rk = 0, nr - 1
            if (rk == me) cycle
            first = sum(counts(1:rk))
            do i = first + 1, first + counts(rk + 1)
               call keep(i)
            end do
         end do
      else
         do i = 1, r%p%n
            call keep(i)
         end do
      end if
      call particles_permute(r%p, perm, nkeep)
      r%p%n_own = r%p%n
      call grid_init(r%g, r%rc%box(1), r%rc%box(2), r%rc%box(3), r%rc%box(4), r%prm%h, &
                     decomp_lo(r%dc), decomp_hi(r%dc), zmin=r%rc%box(2*ndim - 1), zmax=r%rc%box(2*ndim), &
                     periodic=r%rc%periodic_z)
   contains
      subroutine keep(j)
         integer, intent(in) :: j
         if (decomp_owner(r%dc, r%p%x(1, j)) /= me) return
         nkeep = nkeep + 1
         perm(nkeep) = j
      end subroutine keep
   end subroutine decompose

   subroutine banner(r, c)
      type(run_t), intent(inout) :: r
      type(case_cfg), intent(in) :: c
      character(len=:), allocatable :: fx
      call log_line("MBSPH case '"//trim(c%run%case_name)//"' from "//trim(c%file))
      fx = ''
      if (r%n_kind(5) > 0) fx = ', '//kind_name(kind_filter)//' '//int_str(r%n_kind(5))
      call log_line('  particles: '//int_str(r%n_global)//' ('//kind_name(kind_fluid)//' '// &
                    int_str(r%n_kind(1))//', '//kind_name(kind_fixed)//' '// &
                    int_str(r%n_kind(2))//', '//kind_name(kind_moving)//' '// &
                    int_str(r%n_kind(3))//', '//kind_name(kind_floating)//' '// &
                    int_str(r%n_kind(4))//fx//')')
      call log_line('  dp = '//real_str(r%prm%dp)//' m, h = '//real_str(r%prm%h)//' m, c0 = '//real_str(r%prm%c0)// &
                    ' m/s, h_swl = '//real_str(r%prm%h_swl)//' m, rho0 = '//real_str(r%prm%rho0)// &
                    ' kg/m3, first dt about '//real_str(r%prm%cfl*r%prm%h/r%prm%c0)//' s')
      call log_line('  kernel '//trim(c%numerics%kernel)//', integrator '//trim(c%numerics%integrator)// &
                    ', cfl '//real_str(r%prm%cfl)//', ranks '//int_str(comm_size()))
      if (r%prm%visc == visc_artificial) then
         fx = 'artificial viscosity (alpha '//real_str(r%prm%alpha)//')'
      else
         fx = 'laminar + SPS viscosity (nu '//real_str(r%prm%nu)//' m2/s)'
      end if
      if (r%prm%diffusion /= diff_none) then
         fx = fx//', density diffusion '//trim(c%numerics%diffusion)//' (delta '//real_str(c%numerics%delta)//')'
      end if
      if (r%prm%kgc == kgc_gradient) fx = fx//', kernel gradient correction'
      if (r%prm%kgc == kgc_shepard) fx = fx//', Shepard filter every '//int_str(r%prm%shepard_every)//' steps'
      if (r%prm%boundary == bnd_repulsive) fx = fx//', repulsive-force boundary'
      if (r%prm%boundary == bnd_mdbc) fx = fx//', modified dynamic boundary (mDBC)'
      if (r%walls%moving) fx = fx//', moving boundaries'
      if (c%wavemaker%on) fx = fx//', wavemaker ('//trim(c%wavemaker%paddle)//', '//trim(c%wavemaker%wave)//')'
      if (r%zone%on) fx = fx//', damping zone x = '//real_str(r%zone%x0)//' to '//real_str(r%zone%x1)// &
                               ' m'
      if (gauges_count(r%gt) > 0) fx = fx//', '//int_str(gauges_count(r%gt))//' gauges every '// &
                                     real_str(c%run%gauge_interval)//' s'
      if (size(r%bodies) > 0) then
         fx = fx//', '//int_str(size(r%bodies))//' rigid bodies, contact '//trim(c%contact%model)// &
              ' (c0 '//real_str(r%ct%c)//' m/s, r_f '//real_str(r%ct%r_f)//')'
         if (any(c%bodies(:)%mu > 0.0_rp)) fx = fx//', Coulomb friction'
      end if
      if (r%prm%integrator == integ_verlet) fx = fx//', Verlet Euler step every '//int_str(r%prm%verlet_every)
      if (r%por%on) fx = fx//', '//int_str(size(r%por%r))//' porous region'//trim(merge('s', ' ', size(r%por%r) > 1))// &
                         ' (porosity '//real_str(minval(r%por%r%n))//' to '//real_str(maxval(r%por%r%n))//')'
      call log_line('  effects on: '//fx)
      if (allocated(c%wave_defaults)) then
         if (len(c%wave_defaults) > 0) call log_line('  wave numerics (a wave flume that leaves them out): '// &
                                                     c%wave_defaults//' (doc/input.md, "Wave defaults")')
      end if
      if (len(r%wave_report) > 0) call log_line(r%wave_report)
      if (c%armour%on) call log_line('  armour: '//int_str(c%layer%n_units)//' '//trim(c%armour%placement)// &
         ' units of dn = '//real_str(c%armour%dn)//' m, density '//real_str(c%armour%density)// &
         ' kg/m3 on a slope of '//real_str(c%layer%alpha*57.29577951308232_rp)//' deg, porosity '// &
         real_str(c%layer%porosity)//' (target '//real_str(c%armour%porosity)//')')
      call banner_3d(r, c)
      call log_line('  output: '//r%out//', snapshot every '//real_str(c%run%dt_out)//' s until t = '// &
                    real_str(c%run%t_end)//' s')
   end subroutine banner

   !> The banner's lines of the 3D build: the armour's turns, the repulsive
   !> boundary's side walls.
   subroutine banner_3d(r, c)
      type(run_t), intent(in) :: r
      type(case_cfg), intent(in) :: c
      if (ndim /= 3) return
      if (c%armour%on .and. c%layer%turn_max > 0.0_rp) call log_line("  armour: turned about the slope's normal "// &
         'by up to '//real_str(c%layer%turn_max)//' deg (max_turn '//real_str(c%armour%max_turn)// &
         ', held to what a slot across leaves)')
      if (r%prm%boundary == bnd_repulsive .and. side_walls(c)) call log_line('  note: on the '// &
         'repulsive boundary a current runs along side walls in still water (doc/3d.md, "Wall surfaces")')
   end subroutine banner_3d

   !> 3D: whether a solid ends across the width inside the domain (a side wall's face).
   logical function side_walls(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: tol
      integer :: k
      tol = 1.0e-9_rp*(c%domain%zmax - c%domain%zmin)
      side_walls = .false.
      do k = 1, size(c%objs)
         if (c%objs(k)%role_id /= role_solid) cycle
         if (c%objs(k)%zr(2) <= c%objs(k)%zr(1)) cycle
         if (c%objs(k)%zr(1) > c%domain%zmin + tol .or. c%objs(k)%zr(2) < c%domain%zmax - tol) side_walls = .true.
      end do
   end function side_walls
end module run_setup

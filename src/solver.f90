!> The run: set up (or restart), step until the end time, write output,
!> report. The data flows one way: grid -> pair loop -> integration -> output.
!> On several ranks each rank owns the particles of one slab of the domain
!> (decomp): every rank builds (or reads) the whole set, keeps its slab,
!> and every step sends the particles that crossed an edge to their new
!> owner and builds its halo after the sort (comm_halo); every few steps
!> the slab edges move to even out the particle counts.
module solver
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use kinds, only: rp, i8, lk
   use constants, only: kind_fluid, kind_fixed, kind_moving, kind_floating, kind_name
   use input, only: case_cfg, write_case
   use input_check, only: int_str, real_str, approx_str
   use particles, only: particles_t, particles_count_kind, particles_permute
   use params, only: params_t, visc_artificial, diff_none, kgc_gradient, kgc_shepard, &
                     integ_verlet, bnd_repulsive
   use scene, only: scene_build, scene_bodies, scene_no_fluid, scene_estimate, scene_params, scene_gauges, &
                    scene_damping, scene_contact, scene_run
   use sys_limits, only: sys_memory_left
   use body_dynamics, only: body_t, bodies_place, bodies_energy, bodies_prescribe
   use contact, only: contact_t, contact_init, contact_memory_advance, contact_memory_get, contact_memory_set
   use io_bodies, only: bodies_csv_open, bodies_csv_row, bodies_csv_close
   use grid, only: grid_t, grid_init, grid_columns, grid_sort, grid_first_column_end, grid_add_halo
   use decomp, only: decomp_t, decomp_init, decomp_owner, decomp_column, decomp_balance, decomp_set_edges, &
                     decomp_lo, decomp_hi
   use comm_halo, only: comm_halo_migrate, comm_halo_build, comm_halo_redistribute, comm_halo_reverse, comm_halo_forward
   use eos, only: eos_update
   use fluid_forces, only: forces_work_t, forces_init, forces_ensure
   use kernel_correction, only: shepard_sums, shepard_apply
   use step, only: step_state_t, step_advance, step_dt_ratio
   use bc_motion, only: walls_t, walls_init, motion_apply
   use run_state, only: state_t, run_ctl_t
   use io_hdf5, only: h5_start, h5_stop
   use io_files, only: outdir_prepare, outdir_unlock, dir_writable, text_hash, file_text, energy_open, energy_row, &
                       energy_close, snap_name
   use io_snapshot, only: snapshot_write, snapshot_index_rebuild
   use io_checkpoint, only: checkpoint_write, checkpoint_read, checkpoint_check
   use logger, only: log_open, log_close, log_line, log_progress
   use timers, only: timer_start, timer_stop, timer_get, timer_label, n_timers, t_grid, t_output, t_setup, t_comm
   use comm, only: comm_wtime, comm_size, comm_rank, comm_barrier, comm_sum, comm_max, comm_allgather, comm_node_size
   use errors, only: fatal, input_error, alloc_check
   use wave_paddle, only: paddle_t, paddle_init
   use wave_damping, only: damping_t, damping_apply
   use probe_gauges, only: gauges_t, gauges_count, gauges_open, gauges_sums, gauges_values, gauges_write, gauges_close
   use io_armour, only: armour_csv_write
   implicit none
   private
   public :: solver_run

   type(run_ctl_t) :: rc                     !< the course of the run the case asks for
   type(params_t) :: prm
   type(particles_t) :: p
   type(grid_t) :: g
   type(forces_work_t) :: w
   type(step_state_t) :: ss
   type(state_t) :: st
   type(body_t), allocatable :: bodies(:)
   type(contact_t) :: ct
   character(len=:), allocatable :: out, case_text
   logical(lk), allocatable :: drop(:)
   real(rp), allocatable :: scratch1(:), scratch2(:)
   integer :: n_global = 0                   !< particles on all ranks
   integer :: n_kind(4) = 0                  !< particles of each kind at the start, all ranks
   type(walls_t) :: walls                    !< moving walls and the paddle: their laws of time
   type(decomp_t) :: dc                      !< the slabs of the ranks
   type(gauges_t) :: gt                      !< the gauges, their file and scratch
   type(damping_t) :: zone                   !< the absorbing zone
   real(rp) :: t_next_gauge = 0.0_rp
   character(len=:), allocatable :: wave_report

contains

   subroutine solver_run(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: dt_floor, wall_last
      logical :: done, written
      call setup(c)

      ! a collapsing step means the flow went unstable; without fluid the
      ! acoustic scale means nothing and stiff contacts set the step
      dt_floor = 1.0e-4_rp*prm%cfl*prm%h/prm%c0
      if (st%n_fluid0 == 0) dt_floor = 0.0_rp
      st%istep0 = st%istep
      st%t0 = st%t
      st%wall0 = comm_wtime()
      wall_last = st%wall0
      done = finished()
      written = .true.
      do while (.not. done)
         call neighbours()
         call step_advance(prm, g, p, w, ss, walls, bodies, ct, st%t, st%istep + 1, st%dt)
         if (st%dt > ss%dt_limit) call refuse_fixed_step(ss%dt_limit)
         if (size(bodies) > 0) call contact_memory_advance(ct, bodies, st%dt)
         if (zone%on) call damping_apply(zone, p, st%dt)
         st%t = st%t + st%dt
         st%istep = st%istep + 1
         call gauges_due()
         st%particle_steps = st%particle_steps + n_global
         call check_state(dt_floor)
         done = finished()
         written = .false.
         if (st%t >= st%t_next_snap*(1.0_rp - 1.0e-12_rp) .or. st%t >= st%t_next_energy*(1.0_rp - 1.0e-12_rp)) then
            call write_outputs(st%t >= st%t_next_snap*(1.0_rp - 1.0e-12_rp), &
                               st%t >= st%t_next_energy*(1.0_rp - 1.0e-12_rp))
            written = st%t >= st%t_next_snap - rc%dt_out   ! a snapshot of this very step exists
         end if
         if (.not. done) call checkpoint_due()
         if (comm_wtime() - wall_last >= rc%progress_interval .or. done) then
            call progress()
            wall_last = comm_wtime()
         end if
      end do
      ! the final state always gets a snapshot and a checkpoint
      call timer_start(t_output)
      if (.not. written) call write_outputs(.true., .true.)
      call checkpoint(out)
      call timer_stop(t_output)
      call summary()
      call energy_close()
      call bodies_csv_close()
      call gauges_close(gt)
      call h5_stop()
      call log_close()
      if (comm_rank() == 0) call outdir_unlock(out)
   end subroutine solver_run

   !> Everything before the first step: the output folder, the particles
   !> (new or from the checkpoint), this rank's slab, the first output.
   subroutine setup(c)
      type(case_cfg), intent(in) :: c
      integer, allocatable :: counts(:), edges(:)
      real(rp), allocatable :: mem(:, :)
      type(paddle_t) :: paddle
      integer :: ist
      character(len=200) :: emsg
      rc = scene_run(c)
      out = trim(c%run%out_dir)
      call timer_start(t_setup)
      ! every check that can still fail comes before the output folder is
      ! touched: with overwrite = .true. a case refused here keeps the old run
      call paddle_init(c%file, c%wavemaker, c%fluid%gravity, c%run%t_end, paddle, wave_report)
      call check_size(c)
      call check_ranks(c)
      call check_same_case(c)
      if (.not. c%run%restart) call scene_build(c, p, prm, bodies)
      ! one rank prepares the folder; the others wait for it (or for its abort)
      if (comm_rank() == 0) call outdir_prepare(c%file, out, c%run%overwrite, c%run%restart)
      call comm_barrier()
      call check_folder_seen(c)
      call log_open(out//'/run.log', c%run%restart)
      call h5_start()
      if (c%run%restart) then
         call scene_bodies(c, bodies)
         ! the checkpoint must be this case's: its scene made again, only to count it
         block
            type(particles_t) :: made
            type(params_t) :: prm_made
            type(body_t), allocatable :: bodies_made(:)
            call scene_build(c, made, prm_made, bodies_made)
            call checkpoint_check(c%file, out, c%numerics%dp, size(bodies), made%n)
         end block
         p%history = c%numerics%integrator_id == integ_verlet
         call checkpoint_read(c%file, out, p, st, bodies, counts, edges, mem)
         call scene_params(c, st%y_surface - st%h_swl, st%y_surface, prm)
         call log_line("MBSPH: restart of case '"//trim(c%run%case_name)//"' from "//out// &
                       '/checkpoint.h5 at t = '//real_str(st%t)//' s, step '//int_str(st%istep))
      else
         if (size(bodies) > 0) then
            ! prescribed bodies start on their function of time at t = 0
            call bodies_prescribe(bodies, 0.0_rp)
            call bodies_place(bodies, p)
         end if
         st%n_fluid0 = particles_count_kind(p, kind_fluid)
         st%h_swl = prm%h_swl
         st%y_surface = prm%y_surface
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (counts(1), edges(0), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'counts, edges in setup')
         counts = p%n
      end if
      ! every rank holds the whole set until decompose: count it now
      n_global = p%n
      n_kind = [particles_count_kind(p, kind_fluid), particles_count_kind(p, kind_fixed), &
                particles_count_kind(p, kind_moving), particles_count_kind(p, kind_floating)]
      call walls_init(c%objs, paddle, n_kind(3) > 0, walls)
      call scene_gauges(c, gt)
      zone = scene_damping(c)
      ! moving walls start on their motion: position and velocity at t = 0
      if (walls%moving .and. .not. c%run%restart) call motion_apply(walls, p, 0.0_rp)
      if (n_kind(1) == 0) call log_line('mbsph: warning: '//trim(c%file)//': the case has '//scene_no_fluid// &
                                        '; only the bodies and moving walls are simulated')
      if (comm_rank() == 0) call write_case(out//'/case.nml', c)
      call comm_barrier()
      case_text = file_text(out//'/case.nml')
      call decompose(counts, edges)
      call forces_init(prm)
      if (size(bodies) > 0) then
         call contact_init(scene_contact(c), prm, ct)
         if (c%run%restart) call contact_memory_set(ct, nint(mem(1:2, :)), mem(3:4, :))
         if (comm_rank() == 0) call bodies_csv_open(out, c%run%restart, st%t)
      end if
      call banner(c)
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (drop(size(p%rho)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'drop in setup')
      ! text files are rank 0's
      if (comm_rank() == 0) call energy_open(out, c%run%restart, st%istep)
      if (c%run%restart) then
         call snapshot_index_rebuild(out, st%isnap)
      else
         if (comm_rank() == 0) call armour_csv_write(out, c)
         call write_outputs(.true., .true.)
      end if
      call gauges_start()
      call timer_stop(t_setup)
   end subroutine setup

   !> The checkpoint of the present state, with the contacts' slip memory.
   subroutine checkpoint(dir)
      character(len=*), intent(in) :: dir
      real(rp), allocatable :: mem(:, :)
      ! without bodies the memory is empty and nothing of it is written
      call contact_memory_get(ct, mem)
      call checkpoint_write(dir, prm%dp, p, st, bodies, mem, dc%edge)
   end subroutine checkpoint

   !> A checkpoint every checkpoint_every steps, when asked for.
   subroutine checkpoint_due()
      if (rc%checkpoint_every <= 0) return
      if (mod(st%istep, rc%checkpoint_every) /= 0) return
      call timer_start(t_output)
      call checkpoint(out)
      call timer_stop(t_output)
   end subroutine checkpoint_due

   !> gauges.csv (rank 0's; cut back on restart) and, for a new run, its
   !> first row. The gauges need the particles sorted by cell.
   subroutine gauges_start()
      if (gauges_count(gt) == 0) return
      if (comm_rank() == 0) call gauges_open(gt, out, rc%restart, st%t)
      t_next_gauge = (floor(st%t/rc%gauge_interval + 1.0e-9_rp) + 1)*rc%gauge_interval
      if (rc%restart) return
      drop = .false.
      call grid_sort(g, p, drop, cells=size(bodies) > 0)
      call gauges_row()
   end subroutine gauges_start

   !> A gauges.csv row when one is due.
   subroutine gauges_due()
      if (gauges_count(gt) == 0) return
      if (st%t < t_next_gauge*(1.0_rp - 1.0e-12_rp)) return
      call timer_start(t_output)
      call gauges_row()
      t_next_gauge = (floor(st%t/rc%gauge_interval + 1.0e-9_rp) + 1)*rc%gauge_interval
      call timer_stop(t_output)
   end subroutine gauges_due

   !> The gauges now: each rank's sums, their sum over the ranks, one row by rank 0.
   subroutine gauges_row()
      real(rp), allocatable :: acc(:)
      real(rp) :: val(gauges_count(gt))
      call gauges_sums(gt, prm, g, p, acc)
      call comm_sum(acc)
      call gauges_values(gt, prm, acc, val)
      call gauges_write(gt, st%t, val)
   end subroutine gauges_row

   !> Before a step: slab edges (every balance_every steps), removals,
   !> migration, the sort by cell, the halo, the Shepard filter when due.
   subroutine neighbours()
      call timer_start(t_grid)
      ! at step 0 and every balance_every steps (a restart on as many ranks
      ! balances at the same steps as the run it continues)
      if (comm_size() > 1 .and. rc%balance_every > 0) then
         if (mod(st%istep, rc%balance_every) == 0) call rebalance()
      end if
      call remove_particles()
      call comm_halo_migrate(dc, p, drop)
      call grid_sort(g, p, drop, cells=size(bodies) > 0)
      if (comm_size() > 1) then
         call comm_halo_build(p, grid_first_column_end(g))
         if (.not. grid_add_halo(g, p)) call fatal('the halo arrived out of cell order (internal error)')
      end if
      if (prm%kgc == kgc_shepard .and. mod(st%istep + 1, prm%shepard_every) == 0) then
         call ensure_scratch()
         call shepard_sums(prm, g, p, scratch1, scratch2)
         ! the halo copies' sums to their owners, the new densities back
         call comm_halo_reverse(scratch2, p%n_own)
         call comm_halo_reverse(scratch1, p%n_own)
         call shepard_apply(p, scratch1, scratch2)
         call comm_halo_forward(p%rho, p%n_own)
      end if
      call timer_stop(t_grid)
   end subroutine neighbours

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
   subroutine check_folder_seen(c)
      type(case_cfg), intent(in) :: c
      real(rp) :: m(2)
      if (comm_size() == 1) return
      ! the first rank that cannot write the folder, and whether there is one
      m = [-huge(1.0_rp), 0.0_rp]
      if (.not. dir_writable(out)) m = [-real(comm_rank(), rp), 1.0_rp]
      call comm_max(m)
      if (m(2) > 0.0_rp) call input_error(c%file, 'run', 'out_dir', 'rank '//int_str(nint(-m(1)))// &
         " cannot write the folder '"//out//"' that rank 0 prepared: give every rank the same working "// &
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
   subroutine decompose(counts, edges)
      integer, intent(in) :: counts(:), edges(:)
      integer, allocatable :: hist(:), perm(:)
      integer :: nr, me, i, k, r, first, nkeep
      logical :: same, moved
      integer :: ist
      character(len=200) :: emsg
      nr = comm_size()
      me = comm_rank()
      call grid_init(g, rc%box(1), rc%box(2), rc%box(3), rc%box(4), prm%h)
      call decomp_init(dc, g%x0, g%cs, g%ncx_all, nr, me)
      if (nr == 1) return
      same = size(counts) == nr .and. size(edges) == nr + 1
      if (same) same = edges(nr + 1) == g%ncx_all
      if (same) then
         call decomp_set_edges(dc, edges)
      else if (rc%restart .and. rc%balance_every > 0) then
         ! (a new run starts from slabs of equal width and balances at step 0)
         allocate (hist(0:g%ncx_all - 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'hist in decompose')
         hist = 0
         do i = 1, p%n
            k = decomp_column(dc, p%x(1, i))
            hist(k) = hist(k) + 1
         end do
         call decomp_balance(dc, hist, moved)
      end if
      ! the particles of this slab; restarting on as many ranks, this rank's
      ! part of the file first, then the others' (as migration appends them)
      allocate (perm(p%n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'perm in decompose')
      nkeep = 0
      if (same) then
         first = sum(counts(1:me))
         do i = first + 1, first + counts(me + 1)
            call keep(i)
         end do
         do r = 0, nr - 1
            if (r == me) cycle
            first = sum(counts(1:r))
            do i = first + 1, first + counts(r + 1)
               call keep(i)
            end do
         end do
      else
         do i = 1, p%n
            call keep(i)
         end do
      end if
      call particles_permute(p, perm, nkeep)
      p%n_own = p%n
      call grid_init(g, rc%box(1), rc%box(2), rc%box(3), rc%box(4), prm%h, &
                     decomp_lo(dc), decomp_hi(dc))
   contains
      subroutine keep(j)
         integer, intent(in) :: j
         if (decomp_owner(dc, p%x(1, j)) /= me) return
         nkeep = nkeep + 1
         perm(nkeep) = j
      end subroutine keep
   end subroutine decompose

   !> Move the slab edges so that every rank owns about as many particles,
   !> and send the particles to their new owners.
   subroutine rebalance()
      integer, allocatable :: hist(:)
      integer :: i, k
      logical :: moved
      integer :: ist
      character(len=200) :: emsg
      allocate (hist(0:g%ncx_all - 1), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'hist in rebalance')
      hist = 0
      do i = 1, p%n_own
         k = decomp_column(dc, p%x(1, i))
         hist(k) = hist(k) + 1
      end do
      call comm_sum(hist)
      call decomp_balance(dc, hist, moved)
      if (.not. moved) return
      call comm_halo_redistribute(dc, p)
      call grid_init(g, rc%box(1), rc%box(2), rc%box(3), rc%box(4), prm%h, &
                     decomp_lo(dc), decomp_hi(dc))
   end subroutine rebalance

   !> The Shepard filter's sums, as large as the particle store (made at its
   !> first use: a case without the filter holds none).
   subroutine ensure_scratch()
      integer :: ist
      character(len=200) :: emsg
      if (allocated(scratch1)) then
         if (size(scratch1) >= size(p%rho)) return
         deallocate (scratch1, scratch2)
      end if
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (scratch1(size(p%rho)), scratch2(size(p%rho)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'scratch1, scratch2 in ensure_scratch')
   end subroutine ensure_scratch

   logical function finished()
      finished = st%t >= rc%t_end*(1.0_rp - 1.0e-12_rp)
      if (rc%max_steps > 0) finished = finished .or. st%istep >= rc%max_steps
   end function finished

   !> Fluid particles that left the domain or reached a non-physical density
   !> are taken out, counted (over all ranks) and reported; too many stop the run.
   subroutine remove_particles()
      integer :: i, nd, nr, cnt(2)
      real(rp) :: x, y
      logical(lk), allocatable :: grown(:)
      integer :: ist
      character(len=200) :: emsg
      if (size(drop) < size(p%rho)) then
         allocate (grown(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'grown in remove_particles')
         call move_alloc(grown, drop)
      end if
      nd = 0
      nr = 0
      do i = 1, p%n_own
         drop(i) = .false.
         if (p%kind(i) /= kind_fluid) cycle
         x = p%x(1, i)
         y = p%x(2, i)
         if (x < rc%box(1) .or. x > rc%box(2) .or. y < rc%box(3) .or. y > rc%box(4)) then
            drop(i) = .true.
            nd = nd + 1
         else if (p%rho(i) < prm%rho_min .or. p%rho(i) > prm%rho_max) then
            drop(i) = .true.
            nr = nr + 1
         end if
      end do
      cnt = [nd, nr]
      call comm_sum(cnt)
      nd = cnt(1)
      nr = cnt(2)
      if (nd + nr == 0) return
      n_global = n_global - nd - nr
      st%lost_domain = st%lost_domain + nd
      st%lost_density = st%lost_density + nr
      call log_line('step '//int_str(st%istep)//', t = '//real_str(st%t)//' s: removed '//int_str(nd + nr)// &
                    ' fluid particles (left the domain: '//int_str(nd)//', density outside ['// &
                    real_str(prm%rho_min)//', '//real_str(prm%rho_max)//'] kg/m3: '//int_str(nr)//')')
      if (st%lost_domain + st%lost_density > rc%max_lost_fraction*st%n_fluid0) then
         call snapshot_write(out, st%isnap, p, prm, st%t, st%dt, st%istep, case_text, bodies)
         call fatal('lost '//int_str(st%lost_domain + st%lost_density)//' of '//int_str(st%n_fluid0)// &
                    ' fluid particles, more than max_lost_fraction = '//real_str(rc%max_lost_fraction)// &
                    ' (&run); last state written to '//snap_name(out, st%isnap))
      end if
   end subroutine remove_particles

   !> Stop on a NaN or a collapsed time step, leaving a last snapshot. A NaN
   !> is reported by the lowest rank that holds one; the others wait for
   !> its abort.
   subroutine check_state(dt_floor)
      real(rp), intent(in) :: dt_floor
      integer :: i, bad
      real(rp) :: who(1)
      character(len=:), allocatable :: what
      what = ''
      bad = 0
      do i = 1, p%n_own
         if (ieee_is_nan(p%x(1, i)) .or. ieee_is_nan(p%x(2, i))) then
            what = 'position'
         else if (ieee_is_nan(p%v(1, i)) .or. ieee_is_nan(p%v(2, i))) then
            what = 'velocity'
         else if (ieee_is_nan(p%rho(i))) then
            what = 'density'
         else
            cycle
         end if
         bad = i
         exit
      end do
      who = -huge(1.0_rp)
      if (bad > 0) who = -real(comm_rank(), rp)
      call comm_max(who)
      if (who(1) > -huge(1.0_rp)) then
         call snapshot_write(out, st%isnap, p, prm, st%t, st%dt, st%istep, case_text, bodies)
         if (nint(-who(1)) /= comm_rank()) then
            call comm_barrier()        ! never passed: the reporting rank aborts
         end if
         call fatal('NaN in the '//what//' of particle id '//int_str(p%id(bad))//' ('//kind_name(p%kind(bad))// &
                    ') at step '//int_str(st%istep)//', t = '//real_str(st%t)//' s; last state written to '// &
                    snap_name(out, st%isnap))
      end if
      if (st%dt < dt_floor) then
         call snapshot_write(out, st%isnap, p, prm, st%t, st%dt, st%istep, case_text, bodies)
         call fatal('the time step fell to '//real_str(st%dt)//' s (below 1e-4 of the acoustic step) at step '// &
                    int_str(st%istep)//', t = '//real_str(st%t)//' s: the flow has become unstable'// &
                    ' (try a smaller cfl or more viscosity); last state written to '//snap_name(out, st%isnap))
      end if
   end subroutine check_state

   !> A fixed step above the stable step of the state would make the run
   !> blow up: stop before taking it, with the state (still sound) as the
   !> last snapshot.
   subroutine refuse_fixed_step(dt_limit)
      real(rp), intent(in) :: dt_limit
      call snapshot_write(out, st%isnap, p, prm, st%t, prm%dt_fixed, st%istep, case_text, bodies)
      call fatal('&numerics dt_fixed = '//real_str(prm%dt_fixed)//' s is above the stable step '// &
                 real_str(dt_limit)//' s of the state at step '//int_str(st%istep)//', t = '//real_str(st%t)// &
                 ' s (force, acoustic-viscous and contact limits at cfl = '//real_str(prm%cfl)//'): the run would go'// &
                 ' unstable; stopped before the step. Lower dt_fixed or set it to 0 (variable step);'// &
                 ' last state written to '//snap_name(out, st%isnap))
   end subroutine refuse_fixed_step

   subroutine write_outputs(snap, energy)
      logical, intent(in) :: snap, energy
      real(rp) :: ekin, epot, mass, bkin, bpot, e(4), pen(1)
      integer :: i, nf
      real(rp) :: de
      call timer_start(t_output)
      if (snap) then
         ! the pressures of the snapshot; the sound speeds into the force
         ! work array, which the next evaluation overwrites
         call forces_ensure(w, size(p%rho), prm)
         call eos_update(prm, p%n, p%rho, p%p, w%cs)
         call snapshot_write(out, st%isnap, p, prm, st%t, st%dt, st%istep, case_text, bodies)
         st%isnap = st%isnap + 1
         st%t_next_snap = (floor(st%t/rc%dt_out + 1.0e-9_rp) + 1)*rc%dt_out
      end if
      if (energy) then
         ekin = 0.0_rp
         epot = 0.0_rp
         mass = 0.0_rp
         nf = 0
         do i = 1, p%n_own
            if (p%kind(i) /= kind_fluid) cycle
            ekin = ekin + 0.5_rp*p%mass(i)*(p%v(1, i)**2 + p%v(2, i)**2)
            epot = epot + p%mass(i)*prm%g*p%x(2, i)
            mass = mass + p%mass(i)
            nf = nf + 1
         end do
         e = [ekin, epot, mass, real(nf, rp)]
         call comm_sum(e)
         pen = ct%max_penetration
         call comm_max(pen)
         call bodies_energy(bodies, bkin, bpot)
         call energy_row(st%t, st%istep, e(1), e(2), e(3), nint(e(4)), st%lost_domain + st%lost_density, bkin, &
                         bpot, pen(1))
         if (size(bodies) > 0) call bodies_csv_row(st%t, bodies)
         st%ienergy = st%ienergy + 1
         de = rc%energy_interval
         st%t_next_energy = (floor(st%t/de + 1.0e-9_rp) + 1)*de
      end if
      call timer_stop(t_output)
   end subroutine write_outputs

   subroutine banner(c)
      type(case_cfg), intent(in) :: c
      character(len=:), allocatable :: fx
      call log_line("MBSPH case '"//trim(c%run%case_name)//"' from "//trim(c%file))
      call log_line('  particles: '//int_str(n_global)//' ('//kind_name(kind_fluid)//' '// &
                    int_str(n_kind(1))//', '//kind_name(kind_fixed)//' '// &
                    int_str(n_kind(2))//', '//kind_name(kind_moving)//' '// &
                    int_str(n_kind(3))//', '//kind_name(kind_floating)//' '// &
                    int_str(n_kind(4))//')')
      call log_line('  dp = '//real_str(prm%dp)//' m, h = '//real_str(prm%h)//' m, c0 = '//real_str(prm%c0)// &
                    ' m/s, h_swl = '//real_str(prm%h_swl)//' m, rho0 = '//real_str(prm%rho0)// &
                    ' kg/m3, first dt about '//real_str(prm%cfl*prm%h/prm%c0)//' s')
      call log_line('  kernel '//trim(c%numerics%kernel)//', integrator '//trim(c%numerics%integrator)// &
                    ', cfl '//real_str(prm%cfl)//', ranks '//int_str(comm_size()))
      if (prm%visc == visc_artificial) then
         fx = 'artificial viscosity (alpha '//real_str(prm%alpha)//')'
      else
         fx = 'laminar + SPS viscosity (nu '//real_str(prm%nu)//' m2/s)'
      end if
      if (prm%diffusion /= diff_none) then
         fx = fx//', density diffusion '//trim(c%numerics%diffusion)//' (delta '//real_str(c%numerics%delta)//')'
      end if
      if (prm%kgc == kgc_gradient) fx = fx//', kernel gradient correction'
      if (prm%kgc == kgc_shepard) fx = fx//', Shepard filter every '//int_str(prm%shepard_every)//' steps'
      if (prm%boundary == bnd_repulsive) fx = fx//', repulsive-force boundary'
      if (walls%moving) fx = fx//', moving boundaries'
      if (c%wavemaker%on) fx = fx//', wavemaker ('//trim(c%wavemaker%paddle)//', '//trim(c%wavemaker%wave)//')'
      if (zone%on) fx = fx//', damping zone x = '//real_str(zone%x0)//' to '//real_str(zone%x1)// &
                               ' m'
      if (gauges_count(gt) > 0) fx = fx//', '//int_str(gauges_count(gt))//' gauges every '// &
                                     real_str(c%run%gauge_interval)//' s'
      if (size(bodies) > 0) then
         fx = fx//', '//int_str(size(bodies))//' rigid bodies, contact '//trim(c%contact%model)// &
              ' (c0 '//real_str(ct%c)//' m/s, r_f '//real_str(ct%r_f)//')'
         if (any(c%bodies(:)%mu > 0.0_rp)) fx = fx//', Coulomb friction'
      end if
      if (prm%integrator == integ_verlet) fx = fx//', Verlet Euler step every '//int_str(prm%verlet_every)
      call log_line('  effects on: '//fx)
      if (len(wave_report) > 0) call log_line(wave_report)
      if (c%armour%on) call log_line('  armour: '//int_str(c%layer%n_units)//' '//trim(c%armour%placement)// &
         ' units of dn = '//real_str(c%armour%dn)//' m, density '//real_str(c%armour%density)// &
         ' kg/m3 on a slope of '//real_str(c%layer%alpha*57.29577951308232_rp)//' deg, porosity '// &
         real_str(c%layer%porosity)//' (target '//real_str(c%armour%porosity)//')')
      call log_line('  output: '//out//', snapshot every '//real_str(c%run%dt_out)//' s until t = '// &
                    real_str(c%run%t_end)//' s')
   end subroutine banner

   subroutine progress()
      real(rp) :: wall, rate, eta, frac
      character(len=256) :: line
      integer :: hh, mm, ss
      wall = comm_wtime() - st%wall0
      rate = real(st%particle_steps, rp)/max(wall, 1.0e-9_rp)
      frac = st%t/rc%t_end
      eta = 0.0_rp
      if (st%t > st%t0) eta = wall*(rc%t_end - st%t)/(st%t - st%t0)
      if (rc%max_steps > 0) then
         frac = max(frac, real(st%istep, rp)/rc%max_steps)
         if (st%istep > st%istep0) eta = min(eta, wall*(rc%max_steps - st%istep)/(st%istep - st%istep0))
      end if
      eta = max(eta, 0.0_rp)
      hh = int(eta/3600.0_rp)
      mm = int((eta - 3600.0_rp*hh)/60.0_rp)
      ss = int(eta - 3600.0_rp*hh - 60.0_rp*mm)
      write (line, '("t = ",f0.4," s  ",f5.1," %  step ",i0,"  dt ",es9.3," s  ",es9.3, &
            &" particle-steps/s  ETA ",i0,":",i2.2,":",i2.2)') st%t, 100.0_rp*min(frac, 1.0_rp), st%istep, st%dt, &
            rate, hh, mm, ss
      call log_progress(trim(line))
   end subroutine progress

   subroutine summary()
      real(rp) :: wall, tt, ratio(2), busy(comm_size())
      integer :: k, counts(comm_size()), at_step(2)
      character(len=160) :: line
      wall = comm_wtime() - st%wall0
      call comm_allgather(p%n_own, counts)
      call log_line('done: t = '//real_str(st%t)//' s after '//int_str(st%istep)//' steps; fluid particles lost: '// &
                    int_str(st%lost_domain + st%lost_density))
      call step_dt_ratio(ss, ratio, at_step)
      write (line, '("time step: largest dt / CFL limit of a state it reached ",f0.4," (step ",i0, &
            &"), Courant number ",f0.4," (cfl ",f0.3,")")') ratio(1), at_step(1), ratio(1)*prm%cfl, prm%cfl
      call log_line(trim(line))
      if (size(bodies) > 0) then
         write (line, '("time step: largest dt / every limit, contacts too, of a state it reached ",f0.4, &
               &" (step ",i0,")")') ratio(2), at_step(2)
         call log_line(trim(line))
      end if
      if (comm_size() > 1) then
         write (line, '("ranks: ",i0,", particles per rank ",i0," to ",i0," (largest ",f0.1, &
               &" % above the mean)")') comm_size(), minval(counts), maxval(counts), &
            100.0_rp*(maxval(counts)*comm_size()/real(max(sum(counts), 1), rp) - 1.0_rp)
         call log_line(trim(line))
      end if
      if (comm_size() > 1) then
         ! the time each rank computed (all but waiting in and for messages):
         ! ranks of equal particle counts can differ here, and the slowest sets the pace
         busy = 0.0_rp
         busy(comm_rank() + 1) = wall - timer_get(t_comm)
         call comm_sum(busy)
         write (line, '("computing time per rank (wall minus comm) ",f0.3," to ",f0.3, &
               &" s (largest ",f0.1," % above the mean)")') minval(busy), maxval(busy), &
            100.0_rp*(maxval(busy)*comm_size()/max(sum(busy), 1.0e-9_rp) - 1.0_rp)
         call log_line(trim(line))
      end if
      call log_line('wall time by phase [s] (rank 0):')
      do k = 1, n_timers
         tt = timer_get(k)
         write (line, '(4x,a12,f12.3,f8.1," %")') timer_label(k), tt, 100.0_rp*tt/max(wall + timer_get(t_setup), 1.0e-9_rp)
         call log_line(trim(line))
      end do
      if (st%particle_steps > 0_i8) then
         write (line, '("cost: ",f0.4," microseconds per particle-step (",i0," particle-steps in ",f0.3," s)")') &
            1.0e6_rp*wall/real(st%particle_steps, rp), st%particle_steps, wall
         call log_line(trim(line))
      end if
   end subroutine summary
end module solver

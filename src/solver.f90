!> The run: set up (or restart), step until the end time, write output,
!> report. The data flows one way: grid -> pair loop -> integration -> output.
!> On several ranks each rank owns the particles of one slab of the domain
!> (decomp): every rank builds (or reads) the whole set, keeps its slab,
!> and every step sends the particles that crossed an edge to their new
!> owner and builds its halo after the sort (comm_halo); every few steps
!> the slab edges move to even out the particle counts. The module keeps no
!> state: solver_run holds the run (run_t) and passes it to every step.
module solver
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use kinds, only: rp, i8, lk
   use constants, only: kind_fluid, kind_filter, kind_name, ndim, iup
   use input_check, only: int_str, real_str
   use particles, only: particles_t, particles_nan, particles_outside
   use params, only: params_t, kgc_shepard
   use body_dynamics, only: body_t, bodies_energy
   use contact, only: contact_t, contact_memory_advance, contact_memory_get
   use io_bodies, only: bodies_csv_t, bodies_csv_row, bodies_csv_close
   use grid, only: grid_t, grid_init, grid_sort, grid_first_column_end, grid_add_halo, grid_wrap
   use decomp, only: decomp_t, decomp_count, decomp_balance, decomp_lo, decomp_hi
   use comm_halo, only: halo_t, comm_halo_migrate, comm_halo_build, comm_halo_redistribute, comm_halo_reverse, &
                        comm_halo_forward, comm_halo_images, comm_halo_refresh_images
   use eos, only: eos_update
   use fluid_forces, only: forces_work_t, forces_ensure
   use kernel_correction, only: shepard_sums, shepard_apply
   use step, only: step_state_t, step_advance, step_dt_ratio, step_limit_names
   use bc_motion, only: walls_t
   use run_state, only: state_t, run_ctl_t
   use io_hdf5, only: h5_stop
   use io_files, only: outdir_unlock, energy_file_t, energy_row, energy_close, snap_name
   use io_snapshot, only: snap_index_t, snapshot_write
   use io_checkpoint, only: checkpoint_write
   use logger, only: log_close, log_line, log_progress
   use timers, only: timer_start, timer_stop, timer_get, timer_label, n_timers, t_grid, t_output, t_setup, &
                     t_comm
   use comm, only: comm_wtime, comm_size, comm_rank, comm_barrier, comm_sum, comm_max, comm_allgather
   use errors, only: fatal, alloc_check
   use wave_damping, only: damping_t, damping_apply
   use porous, only: porous_t, porous_point, porous_field, n_por
   use probe_gauges, only: gauges_t, gauges_count, gauges_open, gauges_sums, gauges_values, gauges_write, &
                           gauges_close
   use wave_paddle, only: paddle_motion, paddle_own_wave, paddle_absorb_set, paddle_absorb_advance
   implicit none
   private
   public :: run_t, solver_run

   !> Everything a run holds, passed down to every procedure of the solver.
   type :: run_t
      type(run_ctl_t) :: rc                     !< the course of the run the case asks for
      type(params_t) :: prm
      type(particles_t) :: p
      type(halo_t) :: halo                      !< this rank's halo: counts and message buffers
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
      integer :: n_kind(kind_filter) = 0        !< particles of each kind (constants' kind_*, the last) at the start, all ranks
      type(walls_t) :: walls                    !< moving walls and the paddle: their laws of time
      type(decomp_t) :: dc                      !< the slabs of the ranks
      type(gauges_t) :: gt                      !< the gauges, their file and scratch
      type(gauges_t) :: pg                      !< absorbing paddle: the elevation gauge in front of its face
      type(damping_t) :: zone                   !< the absorbing zone
      type(porous_t) :: por                     !< the porous regions
      real(rp) :: t_next_gauge = 0.0_rp
      character(len=:), allocatable :: wave_report
      type(snap_index_t) :: snaps               !< what the snapshots' XDMF index lists
      type(energy_file_t) :: ef                 !< energy.csv
      type(bodies_csv_t) :: bf                  !< bodies.csv
   end type run_t

contains

   !> Step the run that run_setup prepared until its end: outputs, checkpoints,
   !> the progress line and the summary on the way.
   subroutine solver_run(r)
      type(run_t), intent(inout) :: r
      real(rp) :: dt_floor, wall_last
      logical :: done, written
      ! the first output of a new run, the gauges' file and first row
      if (.not. r%rc%restart) call write_outputs(r, .true., .true.)
      call gauges_start(r)

      ! a collapsing step means the flow went unstable; without fluid the
      ! acoustic scale means nothing and stiff contacts set the step
      dt_floor = 1.0e-4_rp*r%prm%cfl*r%prm%h/r%prm%c0
      if (r%st%n_fluid0 == 0) dt_floor = 0.0_rp
      r%st%istep0 = r%st%istep
      r%st%t0 = r%st%t
      r%st%wall0 = comm_wtime()
      wall_last = r%st%wall0
      done = finished(r)
      written = .true.
      do while (.not. done)
         call neighbours(r)
         if (r%walls%paddle%absorb) call absorb_measure(r)
         call step_advance(r%prm, r%por, r%g, r%p, r%halo, r%w, r%ss, r%walls, r%bodies, r%ct, r%st%t, r%st%istep + 1, r%st%dt)
         if (r%st%dt > r%ss%dt_limit) call refuse_fixed_step(r, r%ss%dt_limit)
         if (size(r%bodies) > 0) call contact_memory_advance(r%ct, r%bodies, r%st%dt)
         if (r%zone%on) call damping_apply(r%zone, r%p, r%st%dt)
         if (r%walls%paddle%absorb) call paddle_absorb_advance(r%walls%paddle, r%st%dt, r%st%pad_xc, r%st%pad_eta_mean)
         r%st%t = r%st%t + r%st%dt
         r%st%istep = r%st%istep + 1
         call gauges_due(r)
         r%st%particle_steps = r%st%particle_steps + r%n_global
         call check_state(r, dt_floor)
         done = finished(r)
         written = .false.
         if (r%st%t >= r%st%t_next_snap*(1.0_rp - 1.0e-12_rp) .or. r%st%t >= r%st%t_next_energy*(1.0_rp - 1.0e-12_rp)) then
            call write_outputs(r, r%st%t >= r%st%t_next_snap*(1.0_rp - 1.0e-12_rp), &
                               r%st%t >= r%st%t_next_energy*(1.0_rp - 1.0e-12_rp))
            written = r%st%t >= r%st%t_next_snap - r%rc%dt_out   ! a snapshot of this very step exists
         end if
         if (.not. done) call checkpoint_due(r)
         if (comm_wtime() - wall_last >= r%rc%progress_interval .or. done) then
            call progress(r)
            wall_last = comm_wtime()
         end if
      end do
      ! the final state always gets a snapshot and a checkpoint
      call timer_start(t_output)
      if (.not. written) call write_outputs(r, .true., .true.)
      call checkpoint(r, r%out)
      call timer_stop(t_output)
      call summary(r)
      call energy_close(r%ef)
      call bodies_csv_close(r%bf)
      call gauges_close(r%gt)
      call h5_stop()
      call log_close()
      if (comm_rank() == 0) call outdir_unlock(r%out)
   end subroutine solver_run

   !> The checkpoint of the present state, with the contacts' slip memory.
   subroutine checkpoint(r, dir)
      type(run_t), intent(inout) :: r
      character(len=*), intent(in) :: dir
      real(rp), allocatable :: mem(:, :)
      ! without bodies the memory is empty and nothing of it is written
      call contact_memory_get(r%ct, mem)
      call checkpoint_write(dir, r%prm%dp, r%p, r%st, r%bodies, mem, r%dc%edge)
   end subroutine checkpoint

   !> A checkpoint every checkpoint_every steps, when asked for.
   subroutine checkpoint_due(r)
      type(run_t), intent(inout) :: r
      if (r%rc%checkpoint_every <= 0) return
      if (mod(r%st%istep, r%rc%checkpoint_every) /= 0) return
      call timer_start(t_output)
      call checkpoint(r, r%out)
      call timer_stop(t_output)
   end subroutine checkpoint_due

   !> gauges.csv (rank 0's; cut back on restart) and, for a new run, its
   !> first row. The gauges need the particles sorted by cell.
   subroutine gauges_start(r)
      type(run_t), intent(inout) :: r
      if (gauges_count(r%gt) == 0) return
      if (comm_rank() == 0) call gauges_open(r%gt, r%out, r%rc%restart, r%st%t)
      r%t_next_gauge = (floor(r%st%t/r%rc%gauge_interval + 1.0e-9_rp) + 1)*r%rc%gauge_interval
      if (r%rc%restart) return
      r%drop = .false.
      call grid_sort(r%g, r%p, r%drop, cells=size(r%bodies) > 0)
      call comm_halo_images(r%halo, r%g, r%p)
      call gauges_row(r)
   end subroutine gauges_start

   !> A gauges.csv row when one is due.
   subroutine gauges_due(r)
      type(run_t), intent(inout) :: r
      if (gauges_count(r%gt) == 0) return
      if (r%st%t < r%t_next_gauge*(1.0_rp - 1.0e-12_rp)) return
      call timer_start(t_output)
      call gauges_row(r)
      r%t_next_gauge = (floor(r%st%t/r%rc%gauge_interval + 1.0e-9_rp) + 1)*r%rc%gauge_interval
      call timer_stop(t_output)
   end subroutine gauges_due

   !> The gauges now: each rank's sums, their sum over the ranks, one row by rank 0.
   subroutine gauges_row(r)
      type(run_t), intent(inout) :: r
      real(rp), allocatable :: acc(:)
      real(rp) :: val(gauges_count(r%gt))
      call comm_halo_refresh_images(r%halo, r%p)
      call gauges_sums(r%gt, r%prm, r%g, r%p, r%por, acc)
      call comm_sum(acc)
      call gauges_values(r%gt, r%prm, acc, val)
      call gauges_write(r%gt, r%st%t, val)
   end subroutine gauges_row

   !> Before a step of an absorbing paddle: the elevation in front of its
   !> face (summed over the ranks, as a gauge) and the correction of its
   !> motion over the step. Where the point is dry, the sample is the one that
   !> asks for no correction.
   subroutine absorb_measure(r)
      type(run_t), intent(inout) :: r
      real(rp), allocatable :: acc(:)
      real(rp) :: val(1), xf, uf, eta_m
      associate (pad => r%walls%paddle)
         ! the face now, with the correction it has had so far
         pad%xc = r%st%pad_xc
         pad%tc = r%st%t
         pad%uc = 0.0_rp
         call paddle_motion(pad, r%st%t, xf, uf)
         ! the domain was checked for max_stroke / 2 each way: stop before the paddle leaves it
         ! (every rank has the same xf: the snapshot's collective writing is reached by all)
         if (abs(xf) > pad%x_max) then
            call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%st%dt, r%st%istep, r%case_text, &
                                r%bodies, r%por)
            call fatal('at t = '//real_str(r%st%t)//' s the absorbing paddle stands at X = '// &
                       real_str(xf)//' m, beyond max_stroke/2 = '//real_str(pad%x_max)//' m: the waves coming back ask '// &
                       'for more stroke than the case allows; raise max_stroke (and the domain), lower the wave, or '// &
                       'set absorb = .false.')
         end if
         r%pg%x(1) = pad%x_face + xf + pad%gauge_offset
         call comm_halo_refresh_images(r%halo, r%p)
         call gauges_sums(r%pg, r%prm, r%g, r%p, r%por, acc)
         call comm_sum(acc)
         call gauges_values(r%pg, r%prm, acc, val)
         eta_m = val(1)
         ! dry: the sample of no wave coming in, which asks for no correction
         if (ieee_is_nan(eta_m)) eta_m = r%st%pad_eta_mean + paddle_own_wave(pad, r%st%t)
         call paddle_absorb_set(pad, r%st%t, eta_m, r%st%pad_xc, r%st%pad_eta_mean, r%st%pad_hist)
      end associate
   end subroutine absorb_measure

   !> Before a step: slab edges (every balance_every steps), removals,
   !> migration, the sort by cell, the halo, the Shepard filter when due.
   subroutine neighbours(r)
      type(run_t), intent(inout) :: r
      call timer_start(t_grid)
      ! at step 0 and every balance_every steps (a restart on as many ranks
      ! balances at the same steps as the run it continues)
      if (comm_size() > 1 .and. r%rc%balance_every > 0) then
         if (mod(r%st%istep, r%rc%balance_every) == 0) call rebalance(r)
      end if
      ! the halo and the images of the last step are forgotten; a particle
      ! that crossed a periodic side comes in at the other
      r%p%n = r%p%n_own
      r%halo%n_img = 0
      call grid_wrap(r%g, r%p%n_own, r%p%x)
      call remove_particles(r)
      call comm_halo_migrate(r%halo, r%dc, r%p, r%drop)
      call grid_sort(r%g, r%p, r%drop, cells=size(r%bodies) > 0)
      if (comm_size() > 1) then
         call comm_halo_build(r%halo, r%p, grid_first_column_end(r%g))
         if (.not. grid_add_halo(r%g, r%p)) call fatal('the halo arrived out of cell order (internal error)')
      end if
      call comm_halo_images(r%halo, r%g, r%p)
      if (r%prm%kgc == kgc_shepard .and. mod(r%st%istep + 1, r%prm%shepard_every) == 0) then
         call ensure_scratch(r)
         call shepard_sums(r%prm, r%g, r%p, r%scratch1, r%scratch2)
         ! the halo copies' sums to their owners, the new densities back
         call comm_halo_reverse(r%halo, r%scratch2, r%p%n_own)
         call comm_halo_reverse(r%halo, r%scratch1, r%p%n_own)
         call shepard_apply(r%p, r%scratch1, r%scratch2)
         call comm_halo_forward(r%halo, r%p%rho, r%p%n_own)
      end if
      call timer_stop(t_grid)
   end subroutine neighbours

   !> Move the slab edges so that every rank owns about as many particles,
   !> and send the particles to their new owners.
   subroutine rebalance(r)
      type(run_t), intent(inout) :: r
      integer, allocatable :: hist(:)
      logical :: moved
      integer :: ist
      character(len=200) :: emsg
      allocate (hist(0:r%g%ncx_all - 1), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'hist in rebalance')
      call decomp_count(r%dc, r%p%x, r%p%kind, r%p%n_own, hist)
      call comm_sum(hist)
      call decomp_balance(r%dc, hist, moved)
      if (.not. moved) return
      call comm_halo_redistribute(r%halo, r%dc, r%p)
      call grid_init(r%g, r%rc%box(1), r%rc%box(2), r%rc%box(3), r%rc%box(4), r%prm%h, &
                     decomp_lo(r%dc), decomp_hi(r%dc), zmin=r%rc%box(2*ndim - 1), zmax=r%rc%box(2*ndim), &
                     periodic=r%rc%periodic_z)
   end subroutine rebalance

   !> The Shepard filter's sums, as large as the particle store (made at its
   !> first use: a case without the filter holds none).
   subroutine ensure_scratch(r)
      type(run_t), intent(inout) :: r
      integer :: ist
      character(len=200) :: emsg
      if (allocated(r%scratch1)) then
         if (size(r%scratch1) >= size(r%p%rho)) return
         deallocate (r%scratch1, r%scratch2)
      end if
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (r%scratch1(size(r%p%rho)), r%scratch2(size(r%p%rho)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'scratch1, scratch2 in ensure_scratch')
   end subroutine ensure_scratch

   logical function finished(r)
      type(run_t), intent(in) :: r
      finished = r%st%t >= r%rc%t_end*(1.0_rp - 1.0e-12_rp)
      if (r%rc%max_steps > 0) finished = finished .or. r%st%istep >= r%rc%max_steps
   end function finished

   !> Fluid particles that left the domain or reached a non-physical density
   !> are taken out, counted (over all ranks) and reported; too many stop the run.
   subroutine remove_particles(r)
      type(run_t), intent(inout) :: r
      integer :: nd, nr, cnt(2)
      logical(lk), allocatable :: grown(:)
      integer :: ist
      character(len=200) :: emsg
      if (size(r%drop) < size(r%p%rho)) then
         allocate (grown(size(r%p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'grown in remove_particles')
         call move_alloc(grown, r%drop)
      end if
      ! most steps remove nothing: a count that vectorises first, the search
      ! particle by particle only when it finds a candidate
      if (particles_outside(r%p%n_own, r%p%kind, r%p%x, r%p%rho, r%rc%box, r%prm%rho_min, r%prm%rho_max) == 0) then
         r%drop(1:r%p%n_own) = .false.
         nd = 0
         nr = 0
      else
         call mark_leaving(r, nd, nr)
      end if
      cnt = [nd, nr]
      call comm_sum(cnt)
      nd = cnt(1)
      nr = cnt(2)
      if (nd + nr == 0) return
      r%n_global = r%n_global - nd - nr
      r%st%lost_domain = r%st%lost_domain + nd
      r%st%lost_density = r%st%lost_density + nr
      call log_line('step '//int_str(r%st%istep)//', t = '//real_str(r%st%t)//' s: removed '//int_str(nd + nr)// &
                    ' fluid particles (left the domain: '//int_str(nd)//', density outside ['// &
                    real_str(r%prm%rho_min)//', '//real_str(r%prm%rho_max)//'] kg/m3: '//int_str(nr)//')')
      if (r%st%lost_domain + r%st%lost_density > r%rc%max_lost_fraction*r%st%n_fluid0) then
         call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%st%dt, r%st%istep, r%case_text, r%bodies, r%por)
         call fatal('lost '//int_str(r%st%lost_domain + r%st%lost_density)//' of '//int_str(r%st%n_fluid0)// &
                    ' fluid particles, more than max_lost_fraction = '//real_str(r%rc%max_lost_fraction)// &
                    ' (&run); last state written to '//snap_name(r%out, r%st%isnap))
      end if
   end subroutine remove_particles

   !> The fluid particles to take out (r%drop) and their counts: left the
   !> domain (nd) or with a density outside the limits (nr).
   subroutine mark_leaving(r, nd, nr)
      type(run_t), intent(inout) :: r
      integer, intent(out) :: nd, nr
      integer :: i, d
      real(rp) :: f(n_por)
      logical :: out
      nd = 0
      nr = 0
      do i = 1, r%p%n_own
         r%drop(i) = .false.
         if (r%p%kind(i) /= kind_fluid) cycle
         out = .false.
         do d = 1, ndim
            out = out .or. r%p%x(d, i) < r%rc%box(2*d - 1) .or. r%p%x(d, i) > r%rc%box(2*d)
         end do
         if (out) then
            r%drop(i) = .true.
            nd = nd + 1
         else if (r%p%rho(i) < r%prm%rho_min .or. r%p%rho(i) > r%prm%rho_max) then
            ! in the pores the limits hold for the pore water's density rho / n
            if (r%por%on .and. r%p%rho(i) < r%prm%rho_min) then
               f = porous_point(r%por, r%p%x(:, i))
               if (r%p%rho(i)/f(1) >= r%prm%rho_min) cycle
            end if
            r%drop(i) = .true.
            nr = nr + 1
         end if
      end do
   end subroutine mark_leaving

   !> Stop on a NaN or a collapsed time step, leaving a last snapshot. A NaN
   !> is reported by the lowest rank that holds one; the others wait for
   !> its abort.
   subroutine check_state(r, dt_floor)
      type(run_t), intent(inout) :: r
      real(rp), intent(in) :: dt_floor
      integer :: i, bad
      real(rp) :: who(1)
      character(len=:), allocatable :: what, limiter
      what = ''
      bad = 0
      ! a count that vectorises; the particle and the field only when it finds one
      if (particles_nan(r%p%n_own, r%p%x, r%p%v, r%p%rho) > 0) then
         do i = 1, r%p%n_own
            if (any(ieee_is_nan(r%p%x(:, i)))) then
               what = 'position'
            else if (any(ieee_is_nan(r%p%v(:, i)))) then
               what = 'velocity'
            else if (ieee_is_nan(r%p%rho(i))) then
               what = 'density'
            else
               cycle
            end if
            bad = i
            exit
         end do
      end if
      who = -huge(1.0_rp)
      if (bad > 0) who = -real(comm_rank(), rp)
      call comm_max(who)
      if (who(1) > -huge(1.0_rp)) then
         call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%st%dt, r%st%istep, r%case_text, r%bodies, r%por)
         if (nint(-who(1)) /= comm_rank()) then
            call comm_barrier()        ! never passed: the reporting rank aborts
         end if
         call fatal('NaN in the '//what//' of particle id '//int_str(r%p%id(bad))//' ('//kind_name(r%p%kind(bad))// &
                    ') at step '//int_str(r%st%istep)//', t = '//real_str(r%st%t)//' s; last state written to '// &
                    snap_name(r%out, r%st%isnap))
      end if
      if (r%st%dt < dt_floor) then
         limiter = limit_note(r%ss)
         if (len(limiter) == 0) limiter = 'sound speed'
         call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%st%dt, r%st%istep, r%case_text, r%bodies, r%por)
         call fatal('the time step fell to '//real_str(r%st%dt)//' s (below 1e-4 of the acoustic step) at step '// &
                    int_str(r%st%istep)//', t = '//real_str(r%st%t)//' s, set by the '//limiter//' limit'// &
                    ': the flow has become unstable'// &
                    ' (try a smaller cfl or more viscosity); last state written to '//snap_name(r%out, r%st%isnap))
      end if
   end subroutine check_state

   !> A fixed step above the stable step of the state would make the run
   !> blow up: stop before taking it, with the state (still sound) as the
   !> last snapshot.
   subroutine refuse_fixed_step(r, dt_limit)
      type(run_t), intent(inout) :: r
      real(rp), intent(in) :: dt_limit
      call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%prm%dt_fixed, r%st%istep, r%case_text, r%bodies, r%por)
      call fatal('&numerics dt_fixed = '//real_str(r%prm%dt_fixed)//' s is above the stable step '// &
                 real_str(dt_limit)//' s of the state at step '//int_str(r%st%istep)//', t = '//real_str(r%st%t)// &
                 ' s (force, acoustic-viscous and contact limits at cfl = '//real_str(r%prm%cfl)//'): the run would go'// &
                 ' unstable; stopped before the step. Lower dt_fixed or set it to 0 (variable step);'// &
                 ' last state written to '//snap_name(r%out, r%st%isnap))
   end subroutine refuse_fixed_step

   subroutine write_outputs(r, snap, energy)
      type(run_t), intent(inout) :: r
      logical, intent(in) :: snap, energy
      real(rp) :: ekin, epot, mass, bkin, bpot, e(4), pen(1)
      integer :: i, nf
      real(rp) :: de
      call timer_start(t_output)
      if (snap) then
         ! the pressures of the snapshot; the sound speeds into the force
         ! work array, which the next evaluation overwrites
         call forces_ensure(r%w, size(r%p%rho), r%prm)
         if (r%prm%porous) then
            ! the pore water's pressure, from rho / n
            call porous_field(r%por, r%p%n, r%p%x, r%p%kind, r%w%por)
            r%w%irho(1:r%p%n) = r%p%rho(1:r%p%n)
            where (r%p%kind(1:r%p%n) == kind_fluid) r%w%irho(1:r%p%n) = r%p%rho(1:r%p%n)/r%w%por(1, 1:r%p%n)
            call eos_update(r%prm, r%p%n, r%w%irho, r%p%p, r%w%cs)
         else
            call eos_update(r%prm, r%p%n, r%p%rho, r%p%p, r%w%cs)
         end if
         call snapshot_write(r%snaps, r%out, r%st%isnap, r%p, r%prm, r%st%t, r%st%dt, r%st%istep, r%case_text, r%bodies, r%por)
         r%st%isnap = r%st%isnap + 1
         r%st%t_next_snap = (floor(r%st%t/r%rc%dt_out + 1.0e-9_rp) + 1)*r%rc%dt_out
      end if
      if (energy) then
         ekin = 0.0_rp
         epot = 0.0_rp
         mass = 0.0_rp
         nf = 0
         do i = 1, r%p%n_own
            if (r%p%kind(i) /= kind_fluid) cycle
            ekin = ekin + 0.5_rp*r%p%mass(i)*sum(r%p%v(:, i)**2)
            epot = epot + r%p%mass(i)*r%prm%g*r%p%x(iup, i)
            mass = mass + r%p%mass(i)
            nf = nf + 1
         end do
         e = [ekin, epot, mass, real(nf, rp)]
         call comm_sum(e)
         pen = r%ct%max_penetration
         call comm_max(pen)
         call bodies_energy(r%bodies, bkin, bpot)
         call energy_row(r%ef, r%st%t, r%st%istep, e(1), e(2), e(3), nint(e(4)), r%st%lost_domain + r%st%lost_density, bkin, &
                         bpot, pen(1))
         if (size(r%bodies) > 0) call bodies_csv_row(r%bf, r%st%t, r%bodies)
         r%st%ienergy = r%st%ienergy + 1
         de = r%rc%energy_interval
         r%st%t_next_energy = (floor(r%st%t/de + 1.0e-9_rp) + 1)*de
      end if
      call timer_stop(t_output)
   end subroutine write_outputs

   subroutine progress(r)
      type(run_t), intent(inout) :: r
      real(rp) :: wall, rate, eta, frac
      character(len=256) :: line
      character(len=:), allocatable :: note
      integer :: hh, mm, secs
      wall = comm_wtime() - r%st%wall0
      rate = real(r%st%particle_steps, rp)/max(wall, 1.0e-9_rp)
      frac = r%st%t/r%rc%t_end
      eta = 0.0_rp
      if (r%st%t > r%st%t0) eta = wall*(r%rc%t_end - r%st%t)/(r%st%t - r%st%t0)
      if (r%rc%max_steps > 0) then
         frac = max(frac, real(r%st%istep, rp)/r%rc%max_steps)
         if (r%st%istep > r%st%istep0) eta = min(eta, wall*(r%rc%max_steps - r%st%istep)/(r%st%istep - r%st%istep0))
      end if
      eta = max(eta, 0.0_rp)
      hh = int(eta/3600.0_rp)
      mm = int((eta - 3600.0_rp*hh)/60.0_rp)
      secs = int(eta - 3600.0_rp*hh - 60.0_rp*mm)
      write (line, '("t = ",f0.4," s  ",f5.1," %  step ",i0,"  dt ",es9.3," s  ",es9.3, &
            &" particle-steps/s  ETA ",i0,":",i2.2,":",i2.2)') r%st%t, 100.0_rp*min(frac, 1.0_rp), r%st%istep, r%st%dt, &
            rate, hh, mm, secs
      ! a step set by anything but the sound speed says by what (a collapsing step, by whom)
      note = limit_note(r%ss)
      if (len(note) > 0) note = '  limit: '//note
      call log_progress(trim(line)//note)
   end subroutine progress

   !> What set the last step when it was not the sound speed: the limit's
   !> name, for a contact with its two bodies ('contact of body 4 and a
   !> wall'); '' for the sound speed.
   function limit_note(ss) result(s)
      type(step_state_t), intent(in) :: ss
      character(len=:), allocatable :: s
      s = ''
      if (ss%limit_by < 2 .or. ss%limit_by > size(step_limit_names)) return
      s = trim(step_limit_names(ss%limit_by))
      if (ss%limit_by == size(step_limit_names) .and. any(ss%limit_bodies > 0)) then
         s = s//' of '//body_name(ss%limit_bodies(1))//' and '//body_name(ss%limit_bodies(2))
      end if
   contains
      function body_name(b) result(n)
         integer, intent(in) :: b
         character(len=:), allocatable :: n
         n = 'a wall'
         if (b > 0) n = 'body '//int_str(b)
      end function body_name
   end function limit_note

   subroutine summary(r)
      type(run_t), intent(inout) :: r
      real(rp) :: wall, tt, ratio(2), busy(comm_size())
      integer :: k, counts(comm_size()), at_step(2)
      character(len=160) :: line
      wall = comm_wtime() - r%st%wall0
      call comm_allgather(r%p%n_own, counts)
      call log_line('done: t = '//real_str(r%st%t)//' s after '//int_str(r%st%istep)//' steps; fluid particles lost: '// &
                    int_str(r%st%lost_domain + r%st%lost_density))
      call step_dt_ratio(r%ss, ratio, at_step)
      write (line, '("time step: largest dt / CFL limit of a state it reached ",f0.4," (step ",i0, &
            &"), Courant number ",f0.4," (cfl ",f0.3,")")') ratio(1), at_step(1), ratio(1)*r%prm%cfl, r%prm%cfl
      call log_line(trim(line))
      if (size(r%bodies) > 0) then
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
      if (r%st%particle_steps > 0_i8) then
         write (line, '("cost: ",f0.4," microseconds per particle-step (",i0," particle-steps in ",f0.3," s)")') &
            1.0e6_rp*wall/real(r%st%particle_steps, rp), r%st%particle_steps, wall
         call log_line(trim(line))
      end if
   end subroutine summary
end module solver

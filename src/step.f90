!> Time integration: symplectic, predictor-corrector and Verlet (with an
!> Euler step every verlet_every steps), with the variable time step of
!> Monaghan and Kos (1999): force, acoustic-viscous and laminar limits, or a
!> fixed step (&numerics dt_fixed) that is refused where it exceeds them.
!> Every force evaluation also compares the step in use with the limit of the
!> state it reached (the middle and the end of a step): the largest ratio is
!> the run's check that the chosen step stayed within its stability limit.
module step
   use kinds, only: rp
   use constants, only: kind_fluid, kind_moving, ndim
   use params, only: params_t, integ_symplectic, integ_predictor_corrector, integ_verlet, visc_laminar_sps, kgc_gradient, &
                     bnd_mdbc, shift_none, slip_wall
   use grid, only: grid_t
   use particles, only: particles_t
   use fluid_forces, only: forces_work_t, forces_porosity, forces_prepare, forces_sweep, forces_sweep_first, forces_sweep_last, &
                           forces_ensure
   use bc_mdbc, only: mdbc_update, mdbc_rates, mdbc_sums, mdbc_finish, mdbc_nsum
   use shifting, only: shifting_apply
   use bc_motion, only: walls_t, motion_apply
   use timers, only: timer_start, timer_stop, t_pairs, t_integrate, t_bodies
   use body_dynamics, only: body_t, bodies_place, bodies_fluid_forces, bodies_save, bodies_predict, &
                            bodies_correct_symplectic, bodies_correct_pc, bodies_verlet, bodies_accel2, &
                            bodies_pack_sums, bodies_unpack_sums, bodies_prescribe
   use contact, only: contact_t, contact_sweep, contact_keys_shared, contact_keys_pack, contact_keys_unpack, contact_apply
   use comm, only: comm_max, comm_size, comm_rank, comm_sum, comm_allgather, comm_allgatherv
   use errors, only: fatal, alloc_check
   use input_check, only: int_str
   use porous, only: porous_t, porous_accel, porous_rate_max
   use comm_halo, only: halo_t, comm_halo_reverse, comm_halo_forward, comm_halo_refresh
   implicit none
   private
   public :: step_state_t, step_advance, step_dt_ratio, step_limit_names

   !> What the integrators keep from one step to the next, owned by the caller.
   type :: step_state_t
      real(rp), allocatable :: x0(:, :), v0(:, :), rho0(:)   !< state at the start of a step
      real(rp) :: dt_prev = 0.0_rp     !< the last step taken [s]
      real(rp) :: dt_limit = 0.0_rp    !< the stable step of the state the last step started from [s]
      !> largest dt / limit of a state the step reached, and the step where:
      !> (1) the CFL limits (fluid, body motion), (2) every limit (contacts too)
      real(rp) :: ratio_max(2) = 0.0_rp
      integer :: ratio_step(2) = 0
      !> the limit that set the last variable step (an index into step_limit_names),
      !> and for a contact its bodies where this rank holds it (else 0, 0; 0: a wall)
      integer :: limit_by = 0
      integer :: limit_bodies(2) = 0
   end type step_state_t

   !> The limits of the variable step, in the order of stage_dt's by.
   character(len=*), parameter :: step_limit_names(*) = [character(len=18) :: 'sound speed', &
      'fluid acceleration', 'laminar viscosity', 'stones resistance', 'body acceleration', 'body motion', 'contact']

contains

   !> One step of the chosen integrator from time t. Returns the dt taken and
   !> ss%dt_limit, the stable step of the state at t. istep is the number of the
   !> step being taken (1 for the first). A fixed step above ss%dt_limit is not
   !> taken: the particles and bodies are left as they were at t.
   ! allow(too-many-arguments): the state of the step is these explicit types passed down the step
   subroutine step_advance(prm, por, g, p, halo, w, ss, walls, bodies, ct, t, istep, dt)
      type(params_t), intent(in) :: prm
      type(porous_t), intent(in) :: por
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(halo_t), intent(inout) :: halo
      type(forces_work_t), intent(inout) :: w
      type(step_state_t), intent(inout) :: ss
      type(walls_t), intent(in) :: walls
      type(body_t), intent(inout) :: bodies(:)
      type(contact_t), intent(inout) :: ct
      real(rp), intent(in) :: t
      integer, intent(in) :: istep
      real(rp), intent(out) :: dt
      select case (prm%integrator)
      case (integ_verlet)
         call verlet(prm, por, g, p, halo, w, ss, walls, bodies, ct, t, istep, dt)
      case (integ_symplectic, integ_predictor_corrector)
         call two_stage(prm, por, g, p, halo, w, ss, walls, bodies, ct, t, istep, dt)
      case default  ! none: params sets one of the three (options)
         call fatal('internal error: integrator '//int_str(prm%integrator)//' has no scheme')
      end select
      if (dt <= ss%dt_limit .or. prm%dt_fixed <= 0.0_rp) ss%dt_prev = dt
   end subroutine step_advance

   !> The largest ratio of a step to the stable step of a state it reached
   !> since the run (or its restart) began, and the step where it was reached:
   !> (1) against the CFL limits (fluid acoustic-viscous and force, bodies'
   !> acceleration and motion), (2) against every limit, the contacts' too.
   subroutine step_dt_ratio(ss, rmax, at_step)
      type(step_state_t), intent(in) :: ss
      real(rp), intent(out) :: rmax(2)
      integer, intent(out) :: at_step(2)
      rmax = ss%ratio_max
      at_step = ss%ratio_step
   end subroutine step_dt_ratio

   !> The step size of the first stage, the variable step or the fixed one,
   !> and its check against the limit of the state at its start.
   subroutine first_stage(prm, p, w, ss, bodies, ct, istep, dt)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(in) :: w
      type(step_state_t), intent(inout) :: ss
      type(body_t), intent(in) :: bodies(:)
      type(contact_t), intent(in) :: ct
      integer, intent(in) :: istep
      real(rp), intent(out) :: dt
      real(rp) :: dt_cfl
      ss%dt_limit = stage_dt(prm, p, w, bodies, ct, dt_cfl, ss%limit_by)
      ss%limit_bodies = 0
      if (ss%limit_by == size(step_limit_names)) then
         if (ct%dt_limit <= ss%dt_limit) ss%limit_bodies = ct%dt_bodies   ! this rank holds the global least
      end if
      ! the previous step against the limits of the state it ended in
      call note_ratio(ss, ss%dt_prev, [dt_cfl, ss%dt_limit], istep - 1)
      dt = ss%dt_limit
      if (prm%dt_fixed > 0.0_rp) then
         dt = prm%dt_fixed
         call note_ratio(ss, dt, [dt_cfl, ss%dt_limit], istep)
      end if
   end subroutine first_stage

   subroutine note_ratio(ss, dt, limits, istep)
      type(step_state_t), intent(inout) :: ss
      real(rp), intent(in) :: dt, limits(2)
      integer, intent(in) :: istep
      integer :: k
      if (dt <= 0.0_rp) return
      do k = 1, 2
         if (limits(k) <= 0.0_rp) cycle
         if (dt/limits(k) > ss%ratio_max(k)) then
            ss%ratio_max(k) = dt/limits(k)
            ss%ratio_step(k) = istep
         end if
      end do
   end subroutine note_ratio

   !> Forces of one stage: the pair loop, then (only when the case has
   !> bodies) the fluid force on each body and the contacts.
   subroutine evaluate(prm, por, g, p, halo, w, bodies, ct)
      type(params_t), intent(in) :: prm
      type(porous_t), intent(in) :: por
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(halo_t), intent(inout) :: halo
      type(forces_work_t), intent(inout) :: w
      type(body_t), intent(inout) :: bodies(:)
      type(contact_t), intent(inout) :: ct
      real(rp), allocatable :: sums(:)
      call timer_start(t_pairs)
      if (prm%porous) call forces_porosity(prm, por, p, w)
      if (prm%boundary == bnd_mdbc) then
         ! the solids' densities (and slip velocities) from the water at their ghost points
         call forces_ensure(w, size(p%rho), prm)
         if (prm%porous) then
            call mdbc_update(prm, g, p, w%vol, w%vb, w%md, w%por)
         else
            call mdbc_update(prm, g, p, w%vol, w%vb, w%md)
         end if
         if (comm_size() > 1) call mdbc_edges(prm, g, p, w)
         ! the halo's copies of the solids, and their images across periodic sides (on
         ! one rank too), take their owners' values
         call comm_halo_forward(halo, p%rho, p%n_own)
         if (prm%slip /= slip_wall) call comm_halo_forward(halo, w%vb, p%n_own)
      end if
      call forces_prepare(prm, p, w)
      call forces_sweep(prm, g, p, w, halo)
      ! the contacts need positions only: here, before the first exchange, the
      ! slab holding the armour does them while the others still sum water pairs
      ! (after it, every rank would wait for that slab)
      if (size(bodies) > 0) call contacts(prm, g, p, w, bodies, ct)
      if (prm%kgc == kgc_gradient .or. prm%visc == visc_laminar_sps) then
         ! the pass before the forces: the sums of the halo copies belong to
         ! the next rank's particles, and what they give is copied back; the
         ! slab's first and last columns waited for these
         ! (the sweep gave the images' sums to their originals already)
         if (prm%kgc == kgc_gradient) call comm_halo_reverse(halo, w%lm, p%n_own, images=.false.)
         if (prm%visc == visc_laminar_sps) call comm_halo_reverse(halo, w%gv, p%n_own, images=.false.)
         call forces_sweep_first(prm, g, p, w)
         if (prm%kgc == kgc_gradient) call comm_halo_forward(halo, w%lm, p%n_own)
         if (prm%visc == visc_laminar_sps) call comm_halo_forward(halo, w%tau, p%n_own)
      end if
      call forces_sweep_last(prm, g, p, w)
      call timer_stop(t_pairs)
      ! the pairs' share of the halo particles, to their owners
      call comm_halo_reverse(halo, w%acc, w%drho, p%n_own)
      if (w%shift_now) call comm_halo_reverse(halo, w%sh, p%n_own)
      if (prm%boundary == bnd_mdbc) call mdbc_rates(p%n_own, p%kind, w%drho)
      ! the pore water's acceleration needs the whole pair sums
      if (por%on) call porous_accel(p%n_own, p%kind, w%por, p%v, w%acc, w%drho)
      if (size(bodies) == 0) return
      call timer_start(t_bodies)
      call bodies_fluid_forces(bodies, p, w%acc)
      ! every rank summed the pairs and particles it owns: one sum over the
      ! ranks of one packed array, then every rank advances the same bodies
      if (comm_size() > 1) then
         call bodies_pack_sums(bodies, ct%damp, sums)
         call comm_sum(sums)
         call bodies_unpack_sums(sums, bodies, ct%damp)
      end if
      call timer_stop(t_bodies)
   end subroutine evaluate

   !> The contacts of one evaluation: the sweep over the bodies' particle pairs,
   !> the table of touching bodies shared by the ranks, the forces on the bodies.
   subroutine contacts(prm, g, p, w, bodies, ct)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(body_t), intent(inout) :: bodies(:)
      type(contact_t), intent(inout) :: ct
      real(rp), allocatable :: mine(:), all(:)
      call timer_start(t_bodies)
      ! the dynamic model's density rates join the pairs' where forces_sweep_last
      ! will read them (with shifting, the packed rates)
      if (w%shift_now) then
         call contact_sweep(ct, prm, g, p, bodies, w%rt(ndim + 1, :))
      else
         call contact_sweep(ct, prm, g, p, bodies, w%drho)
      end if
      ! a contact split between ranks: its centre and pair count over all of them
      if (contact_keys_shared(ct) .and. comm_size() > 1) then
         call contact_keys_pack(ct, mine)
         call comm_allgatherv(mine, all)
         call contact_keys_unpack(ct, all)
      end if
      call contact_apply(ct, prm, p, bodies)
      call timer_stop(t_bodies)
   end subroutine contacts

   !> mDBC on several ranks: the ghost points whose kernel support crosses a
   !> slab edge (w%md%xe, from mdbc_update) are summed by every rank over the
   !> water it owns, the sums added over the ranks, and each owner finishes
   !> its own. The points of every rank go to all (a few rows of wall at
   !> each edge), so a support that spans several slabs is summed too.
   subroutine mdbc_edges(prm, g, p, w)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(forces_work_t), intent(inout) :: w
      real(rp), allocatable :: xall(:), s(:, :), flat(:)
      integer :: counts(comm_size()), n_all, k0, ne, ist
      character(len=200) :: emsg
      ne = w%md%ne
      call comm_allgather(ne, counts)
      n_all = sum(counts)
      if (n_all == 0) return
      k0 = sum(counts(1:comm_rank()))
      call comm_allgatherv(reshape(w%md%xe(:, 1:ne), [ndim*ne]), xall)
      allocate (s(mdbc_nsum, n_all), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, "the ghost points' sums in mdbc_edges", n_all)
      call mdbc_sums(prm, g, p, w%vol, w%md%mw, reshape(xall, [ndim, n_all]), s)
      flat = reshape(s, [mdbc_nsum*n_all])
      call comm_sum(flat)
      s = reshape(flat, [mdbc_nsum, n_all])
      call mdbc_finish(prm, p, w%md%ie(1:ne), s(:, k0 + 1:k0 + ne), w%vb)
   end subroutine mdbc_edges

   !> The time step from the forces just computed (Monaghan and Kos 1999:
   !> force, acoustic-viscous and laminar limits), limited further by the
   !> bodies' accelerations and motion (dt_cfl, the CFL limits) and by the
   !> stiffest contact and fastest approach (the result: every limit). The
   !> maxima are taken over every rank at once, so every rank takes the same step.
   real(rp) function stage_dt(prm, p, w, bodies, ct, dt_cfl, by) result(dt)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(in) :: w
      type(body_t), intent(in) :: bodies(:)
      type(contact_t), intent(in) :: ct
      real(rp), intent(out) :: dt_cfl
      integer, intent(out), optional :: by       !< which limit set dt (step_limit_names)
      integer, parameter :: n_maxima = 6
      real(rp) :: a2, m(n_maxima), amax2, cmax, lim(size(step_limit_names))
      amax2 = 0.0_rp
      cmax = prm%c0
      call fluid_maxima(p%n_own, p%kind, w%acc, w%cs, amax2, cmax)
      ! largest squared acceleration, sound speed and viscous speed; stiffest
      ! contact; fastest body
      m = [amax2, cmax, w%mumax, -huge(1.0_rp), -huge(1.0_rp), 0.0_rp]
      if (size(bodies) > 0) m(4:5) = [-ct%dt_limit, -ct%dt_motion]
      if (prm%porous) m(6) = porous_rate_max(p%n_own, p%kind, w%por, p%v)
      call comm_max(m)
      lim = huge(1.0_rp)
      lim(1) = prm%cfl*prm%h/(m(2) + m(3))
      if (m(1) > 0.0_rp) lim(2) = prm%cfl*sqrt(prm%h/sqrt(m(1)))
      if (prm%visc == visc_laminar_sps .and. prm%nu > 0.0_rp) lim(3) = 0.125_rp*prm%h2/prm%nu
      ! the stones' resistance, explicit: a step below half its relaxation time
      if (m(6) > 0.0_rp) lim(4) = 0.5_rp/m(6)
      if (size(bodies) > 0) then
         a2 = bodies_accel2(bodies)
         if (a2 > 0.0_rp) lim(5) = prm%cfl*sqrt(prm%h/sqrt(a2))
         lim(6) = -m(5)
         lim(7) = -m(4)
      end if
      dt_cfl = minval(lim(1:6))
      dt = minval(lim)
      if (present(by)) by = minloc(lim, dim=1)
   end function stage_dt

   !> The largest squared acceleration and sound speed of the fluid among
   !> particles 1..n, from amax2 and cmax up. A wall particle counts as zero
   !> (both start at zero or above), so that the loop has no branch and vectorises.
   pure subroutine fluid_maxima(n, kind, acc, cs, amax2, cmax)
      integer, intent(in) :: n, kind(n)
      real(rp), intent(in) :: acc(ndim, n), cs(n)
      real(rp), intent(inout) :: amax2, cmax
      integer :: i
      real(rp) :: f, a, c
      a = amax2
      c = cmax
      ! (a wall's rates enter times 0; a non-finite one comes from a pair whose
      ! fluid partner has it too, and that stops the run either way)
      do i = 1, n
         f = merge(1.0_rp, 0.0_rp, kind(i) == kind_fluid)
         a = max(a, f*sum(acc(:, i)**2))
         c = max(c, f*cs(i))
      end do
      amax2 = a
      cmax = c
   end subroutine fluid_maxima

   subroutine save_state(ss, p)
      type(step_state_t), intent(inout) :: ss
      type(particles_t), intent(in) :: p
      integer :: n
      integer :: ist
      character(len=200) :: emsg
      n = p%n_own
      if (allocated(ss%rho0)) then
         if (size(ss%rho0) < n) deallocate (ss%x0, ss%v0, ss%rho0)
      end if
      if (.not. allocated(ss%rho0)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (ss%x0(ndim, size(p%rho)), ss%v0(ndim, size(p%rho)), ss%rho0(size(p%rho)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'the state at the start of a step', size(p%rho))
      end if
      ss%x0(:, 1:n) = p%x(:, 1:n)
      ss%v0(:, 1:n) = p%v(:, 1:n)
      ss%rho0(1:n) = p%rho(1:n)
   end subroutine save_state

   !> Symplectic (position Verlet, as in DualSPHysics) or the
   !> predictor-corrector of SPHysics; both evaluate forces twice a step.
   ! allow(too-many-arguments): the state of the step is these explicit types passed down the step
   subroutine two_stage(prm, por, g, p, halo, w, ss, walls, bodies, ct, t, istep, dt)
      type(params_t), intent(in) :: prm
      type(porous_t), intent(in) :: por
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(halo_t), intent(inout) :: halo
      type(forces_work_t), intent(inout) :: w
      type(step_state_t), intent(inout) :: ss
      type(walls_t), intent(in) :: walls
      type(body_t), intent(inout) :: bodies(:)
      type(contact_t), intent(inout) :: ct
      real(rp), intent(in) :: t
      integer, intent(in) :: istep
      real(rp), intent(out) :: dt
      integer :: i
      real(rp) :: hdt, lim, lim_cfl
      logical :: symplectic
      symplectic = prm%integrator /= integ_predictor_corrector
      ! particle shifting takes the sums of the step's middle only
      w%shift_now = .false.
      call evaluate(prm, por, g, p, halo, w, bodies, ct)
      call first_stage(prm, p, w, ss, bodies, ct, istep, dt)
      if (dt > ss%dt_limit) return
      hdt = 0.5_rp*dt
      call timer_start(t_integrate)
      call save_state(ss, p)
      ! predictor: half a step with the rates at t
      call move_predict(p%n_own, p%kind, hdt, prm%rho0, w%drho, w%acc, p%rho, p%x, p%v)
      if (walls%moving) call motion_apply(walls, p, t + hdt)
      if (size(bodies) > 0) then
         call bodies_save(bodies)
         call bodies_predict(bodies, ct%damp, hdt)
         call bodies_prescribe(bodies, t + hdt)
         call bodies_place(bodies, p)
      end if
      call timer_stop(t_integrate)
      call comm_halo_refresh(halo, p)
      w%shift_now = prm%shift /= shift_none
      call evaluate(prm, por, g, p, halo, w, bodies, ct)
      ! the step against the limits of the state at its middle
      lim = stage_dt(prm, p, w, bodies, ct, lim_cfl)
      call note_ratio(ss, dt, [lim_cfl, lim], istep)
      call timer_start(t_integrate)
      if (symplectic) then
         call move_symplectic(p%n_own, p%kind, dt, prm%rho0, w%drho, w%acc, ss%rho0, ss%v0, p%rho, p%x, p%v)
      else
         ! corrector to t + dt/2 with the mid-step rates, then extrapolate to t + dt
         do i = 1, p%n_own
            p%rho(i) = 2.0_rp*(ss%rho0(i) + hdt*w%drho(i)) - ss%rho0(i)
            if (p%kind(i) == kind_fluid) then
               p%v(:, i) = 2.0_rp*(ss%v0(:, i) + hdt*w%acc(:, i)) - ss%v0(:, i)
               p%x(:, i) = 2.0_rp*(ss%x0(:, i) + hdt*0.5_rp*(ss%v0(:, i) + p%v(:, i))) - ss%x0(:, i)
            else
               p%rho(i) = max(p%rho(i), prm%rho0)
            end if
         end do
      end if
      ! particle shifting from the sums of the step's middle
      if (prm%shift /= shift_none) call shifting_apply(prm, p, w%sh, dt)
      if (walls%moving) call motion_apply(walls, p, t + dt)
      if (size(bodies) > 0) then
         if (symplectic) then
            call bodies_correct_symplectic(bodies, ct%damp, dt)
         else
            call bodies_correct_pc(bodies, ct%damp, dt)
         end if
         call bodies_prescribe(bodies, t + dt)
         call bodies_place(bodies, p)
      end if
      call timer_stop(t_integrate)
   end subroutine two_stage

   !> Verlet: a leapfrog over two steps, with an Euler step every
   !> verlet_every steps to keep the two interleaved solutions together.
   ! allow(too-many-arguments): the state of the step is these explicit types passed down the step
   subroutine verlet(prm, por, g, p, halo, w, ss, walls, bodies, ct, t, istep, dt)
      type(params_t), intent(in) :: prm
      type(porous_t), intent(in) :: por
      type(grid_t), intent(in) :: g
      type(particles_t), intent(inout) :: p
      type(halo_t), intent(inout) :: halo
      type(forces_work_t), intent(inout) :: w
      type(step_state_t), intent(inout) :: ss
      type(walls_t), intent(in) :: walls
      type(body_t), intent(inout) :: bodies(:)
      type(contact_t), intent(inout) :: ct
      real(rp), intent(in) :: t
      integer, intent(in) :: istep
      real(rp), intent(out) :: dt
      logical :: euler
      w%shift_now = prm%shift /= shift_none
      call evaluate(prm, por, g, p, halo, w, bodies, ct)
      call first_stage(prm, p, w, ss, bodies, ct, istep, dt)
      if (dt > ss%dt_limit) return
      call timer_start(t_integrate)
      euler = mod(istep, prm%verlet_every) == 0
      call move_verlet(p%n_own, p%kind, dt, euler, prm%rho0, w%drho, w%acc, p%rho, p%rhom1, p%x, p%v, p%vm1)
      if (prm%shift /= shift_none) call shifting_apply(prm, p, w%sh, dt)
      if (walls%moving) call motion_apply(walls, p, t + dt)
      if (size(bodies) > 0) then
         call bodies_verlet(bodies, ct%damp, dt)
         call bodies_prescribe(bodies, t + dt)
         call bodies_place(bodies, p)
      end if
      call timer_stop(t_integrate)
   end subroutine verlet

   ! The particle updates of the integrators: one loop each over explicit-shape
   ! arrays that the compiler runs several particles at a time. A fluid particle
   ! moves; a solid one keeps its position and velocity (its motion is its wall's
   ! or body's) and its density stays at or above rho0. The kind enters as a
   ! factor f (1 for fluid, 0 otherwise), not as a branch or a masked store,
   ! which the compiler does not vectorise: for a fluid particle f*dt is dt and
   ! f*a + (1-f)*b is a, the same numbers as the branch gave. A solid particle's
   ! x + 0*v is x, and 0*a + b is b, as long as its rates and velocities are
   ! finite (they are: a NaN anywhere stops the run after the step, check_state),
   ! a -0.0 becoming +0.0. Scalars are copied to locals for the same reason (a
   ! dummy is a reference the loop would load).

   !> Symplectic predictor: half a step hdt with the rates at the step's start.
   pure subroutine move_predict(n, kind, hdt_in, rho0_in, drho, acc, rho, x, v)
      integer, intent(in) :: n, kind(n)
      real(rp), intent(in) :: hdt_in, rho0_in, drho(n), acc(ndim, n)
      real(rp), intent(inout) :: rho(n), x(ndim, n), v(ndim, n)
      integer :: i, d
      real(rp) :: f, r, hdt, rho0
      hdt = hdt_in
      rho0 = rho0_in
      do i = 1, n
         f = merge(1.0_rp, 0.0_rp, kind(i) == kind_fluid)
         r = rho(i) + hdt*drho(i)
         rho(i) = merge(r, max(r, rho0), kind(i) == kind_fluid)
         do d = 1, ndim
            x(d, i) = x(d, i) + (f*hdt)*v(d, i)
            v(d, i) = v(d, i) + (f*hdt)*acc(d, i)
         end do
      end do
   end subroutine move_predict

   !> Symplectic corrector: the whole step dt from the start state (rhos, vs)
   !> with the rates of the step's middle; positions from the middle.
   pure subroutine move_symplectic(n, kind, dt_in, rho0_in, drho, acc, rhos, vs, rho, x, v)
      integer, intent(in) :: n, kind(n)
      real(rp), intent(in) :: dt_in, rho0_in, drho(n), acc(ndim, n), rhos(n), vs(ndim, n)
      real(rp), intent(inout) :: rho(n), x(ndim, n), v(ndim, n)
      integer :: i, d
      real(rp) :: f, eps, r, dt, hdt, rho0, vn
      dt = dt_in
      hdt = 0.5_rp*dt
      rho0 = rho0_in
      do i = 1, n
         f = merge(1.0_rp, 0.0_rp, kind(i) == kind_fluid)
         eps = -(drho(i)/rho(i))*dt
         r = rhos(i)*(2.0_rp - eps)/(2.0_rp + eps)
         rho(i) = merge(r, max(r, rho0), kind(i) == kind_fluid)
         do d = 1, ndim
            vn = vs(d, i) + dt*acc(d, i)
            x(d, i) = x(d, i) + (f*hdt)*vn
            v(d, i) = f*vn + (1.0_rp - f)*v(d, i)
         end do
      end do
   end subroutine move_symplectic

   !> Verlet: rho, v from their values a step back (rhom1, vm1) over 2 dt, or
   !> with euler from the present ones over dt; x by a second-order Taylor step.
   pure subroutine move_verlet(n, kind, dt_in, euler, rho0_in, drho, acc, rho, rhom1, x, v, vm1)
      integer, intent(in) :: n, kind(n)
      real(rp), intent(in) :: dt_in, rho0_in, drho(n), acc(ndim, n)
      logical, intent(in) :: euler
      real(rp), intent(inout) :: rho(n), rhom1(n), x(ndim, n), v(ndim, n), vm1(ndim, n)
      integer :: i, d
      real(rp) :: f, e, r, vn, dt, dtv, hdt2, rho0
      dt = dt_in
      rho0 = rho0_in
      hdt2 = 0.5_rp*dt*dt
      ! the step starts from the present values over dt (euler: e = 1) or from
      ! those a step back over 2 dt (e = 0), by the same factors as the kind
      e = merge(1.0_rp, 0.0_rp, euler)
      dtv = merge(dt, 2.0_rp*dt, euler)
      do i = 1, n
         f = merge(1.0_rp, 0.0_rp, kind(i) == kind_fluid)
         r = (e*rho(i) + (1.0_rp - e)*rhom1(i)) + dtv*drho(i)
         rhom1(i) = rho(i)
         rho(i) = merge(r, max(r, rho0), kind(i) == kind_fluid)
         do d = 1, ndim
            vn = (e*v(d, i) + (1.0_rp - e)*vm1(d, i)) + dtv*acc(d, i)
            x(d, i) = x(d, i) + (f*dt)*v(d, i) + (f*hdt2)*acc(d, i)
            vm1(d, i) = f*v(d, i) + (1.0_rp - f)*vm1(d, i)
            v(d, i) = f*vn + (1.0_rp - f)*v(d, i)
         end do
      end do
   end subroutine move_verlet
end module step

!> Fluid forces: continuity and momentum of weakly compressible SPH over all
!> particle pairs. Dynamic boundary: wall particles take part in continuity
!> and lend their pressure to the fluid; repulsive boundary: the outer row of
!> every solid pushes fluid particles off with the Monaghan-Kos force. The
!> pair loop is chosen once per run among specialised variants
!> (fluid_pairs.inc), one per combination of boundary, kernel, viscosity
!> model, density diffusion, gradient correction, porous regions and
!> particle shifting.
module fluid_forces
   use kinds, only: rp
   use errors, only: alloc_check, fatal
   use input_check, only: int_str
   use constants, only: kind_fluid, ndim, nsym, iup
   use tensor, only: sym_slot
   use params, only: params_t, visc_laminar_sps, diff_none, diff_fourtakas, kgc_gradient, bnd_repulsive, bnd_mdbc, &
                     slip_wall, shift_none
   use grid, only: grid_t, grid_ranges, grid_last_cell, grid_neighbours, grid_nranges, grid_image_range
   use comm_halo, only: halo_t, comm_halo_fold_images, comm_halo_copy_images
   use particles, only: particles_t
   use eos, only: eos_update, eos_dynamic_density
   use nbr_list, only: nbr_t, nbr_build
   use kernel, only: kernel_cubic, kernel_wendland
   use kernel_correction, only: kgc_sums, kgc_finish
   use porous, only: porous_t, porous_field, n_por
   use bc_mdbc, only: mdbc_work_t
   implicit none
   private
   public :: forces_work_t, forces_init, forces_ensure, forces_porosity, forces_prepare, forces_sweep, forces_sweep_first, &
             forces_sweep_last

   !> constants of the repulsive boundary handed to the pair loops: A's two
   !> factors, q0, 40/c0, the still-water level, 1/h_swl, dp
   integer, parameter :: n_rep = 7

   !> Per-particle work arrays of a force evaluation (not kept across steps).
   abstract interface
      subroutine pairs_iface(n, g, nb, x, v, rho, irho, p, mass, kind, cs, rhod, lm, tau, nrm, surf, nf, &
                             h, support2, eta2, fw, alpha, nu4, dcoef, ckgc, rep, acc, drho, mumax)
         import :: rp, n_rep, grid_t, nbr_t, ndim
         implicit none
         integer, intent(in) :: n
         type(grid_t), intent(in) :: g
         type(nbr_t), intent(in) :: nb
         real(rp), intent(in) :: x(ndim, n), v(ndim, n), rho(n), irho(n), p(n), mass(n), cs(n), rhod(:), lm(:, :), tau(:, :)
         real(rp), intent(in) :: nrm(ndim, n), nf(:)
         integer, intent(in) :: kind(n), surf(n)
         real(rp), intent(in), value :: h, support2, eta2, fw, alpha, nu4, dcoef, ckgc
         real(rp), intent(in) :: rep(n_rep)
         real(rp), intent(inout) :: acc(ndim, n), drho(n)
         real(rp), intent(inout) :: mumax
      end subroutine pairs_iface
      !> the same with particle shifting's sums: rt holds acceleration, density
      !> rate and shifting's sums of each particle (forces_work_t%rt)
      subroutine pairs_x_iface(n, g, nb, x, v, rho, irho, p, mass, kind, cs, rhod, lm, tau, nrm, surf, nf, &
                               h, support2, eta2, fw, alpha, nu4, dcoef, ckgc, rep, rt, mumax)
         import :: rp, n_rep, grid_t, nbr_t, ndim
         implicit none
         integer, intent(in) :: n
         type(grid_t), intent(in) :: g
         type(nbr_t), intent(in) :: nb
         real(rp), intent(in) :: x(ndim, n), v(ndim, n), rho(n), irho(n), p(n), mass(n), cs(n), rhod(:), lm(:, :), tau(:, :)
         real(rp), intent(in) :: nrm(ndim, n), nf(:)
         integer, intent(in) :: kind(n), surf(n)
         real(rp), intent(in), value :: h, support2, eta2, fw, alpha, nu4, dcoef, ckgc
         real(rp), intent(in) :: rep(n_rep)
         real(rp), intent(inout) :: rt(2*ndim + 2, n)
         real(rp), intent(inout) :: mumax
      end subroutine pairs_x_iface
   end interface

   type :: forces_work_t
      real(rp), allocatable :: acc(:, :)   !< acceleration [m/s2]
      real(rp), allocatable :: drho(:)     !< density rate [kg/m3/s]
      real(rp), allocatable :: cs(:)       !< sound speed [m/s]
      real(rp), allocatable :: irho(:)     !< 1/density [m3/kg]
      real(rp), allocatable :: vol(:)      !< volume mass/density [m3]
      real(rp), allocatable :: rhod(:)     !< density used by the diffusion term
      real(rp), allocatable :: lm(:, :)    !< gradient correction matrices
      real(rp), allocatable :: tau(:, :)   !< SPS stress / rho^2
      real(rp), allocatable :: gv(:, :)    !< SPS velocity gradients du/dx, du/dy, dv/dx, dv/dy [1/s]
      real(rp), allocatable :: por(:, :)   !< porosity, resistance rates, added mass (porous_field)
      ! porous runs: what the pair loop reads for each particle, a wall or body
      ! particle among the pores standing for pore water of the porosity there
      real(rp), allocatable :: nf(:)       !< porosity where the particle is (por's first row, contiguous for the pair loop) [-]
      real(rp), allocatable :: mp(:)       !< mass (of a wall or body particle: n m) [kg]
      real(rp), allocatable :: rp(:)       !< superficial density (of a wall or body particle: n rho) [kg/m3]
      !> mDBC with a slip condition: the velocities the pair loop reads, the
      !> water's own and the solids' as the condition makes them (bc_mdbc) [m/s]
      real(rp), allocatable :: vb(:, :)
      !> particle shifting: the concentration gradient (rows 1 .. ndim) and
      !> the divergence of position (row ndim + 1) of each particle (shifting)
      real(rp), allocatable :: sh(:, :)
      !> the evaluation with shifting's sums adds to one array: acceleration
      !> (rows 1 .. ndim), density rate (ndim + 1) and sh (ndim + 2 ..)
      real(rp), allocatable :: rt(:, :)
      type(mdbc_work_t) :: md              !< mDBC: the ghost points of the evaluation (bc_mdbc)
      !> this evaluation sums shifting's terms (the step sets it: the sums of the
      !> step's last evaluation are those it shifts by)
      logical :: shift_now = .false.
      real(rp) :: mumax = 0.0_rp           !< max |h v.r / (r^2 + eta^2)| over pairs [m/s]
      type(nbr_t) :: seg(4)                !< pair lists of the columns in the sweep (forces_sweep)
      !> the pair loop of this run's models (forces_init), and the same with shifting's sums
      procedure(pairs_iface), pointer, nopass :: pairs => null()
      procedure(pairs_x_iface), pointer, nopass :: pairs_x => null()
   end type forces_work_t



contains

! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "kernel_formulas.inc"

   !> Choose the pair loop for this run's models. A model that needs a pass
   !> over the pairs before the forces (gradient correction, SPS) gets the
   !> loops over the evaluation's pair list, which both passes share; the
   !> others a loop over the grid's stencil, which needs no list in memory.
   subroutine forces_init(w, prm)
      type(forces_work_t), intent(inout) :: w
      type(params_t), intent(in) :: prm
      integer :: list, bc, kern, visc, diff, kgc, por, shift, key
      ! the repulsive boundary runs without density diffusion and gradient
      ! correction (the input refuses them; doc/theory.md says why)
      list = merge(1, 0, needs_list(prm))
      bc = merge(2, 1, prm%boundary == bnd_repulsive)
      kern = 0                      ! a listed loop reads its kernel factors from the list
      if (list == 0) then
         select case (prm%kernel)
         case (kernel_wendland); kern = 1
         case (kernel_cubic); kern = 2
         case default
            call fatal('forces_init: unknown kernel '//int_str(prm%kernel)//' (internal error)')
         end select
      end if
      visc = merge(2, 1, prm%visc == visc_laminar_sps)
      diff = merge(1, 0, prm%diffusion /= diff_none)
      kgc = merge(1, 0, prm%kgc == kgc_gradient)
      por = merge(1, 0, prm%porous)
      shift = merge(1, 0, prm%shift /= shift_none)
      ! the key of src/fluid_variants.fypp, whose list of variants makes these cases
      key = list*10000000 + bc*1000000 + kern*100000 + visc*10000 + diff*1000 + kgc*100 + por*10
      ! with shifting, the loop with its sums for the evaluations whose sums the
      ! step uses (forces_work_t%shift_now) and the one without for the others
      if (shift == 1) call choose(w, key + 1)
      call choose(w, key)
   end subroutine forces_init

   !> w%pairs (w%pairs_x, with shifting's sums) => the variant of src/fluid_variants.fypp with this key.
   subroutine choose(w, key)
      type(forces_work_t), intent(inout) :: w
      integer, intent(in) :: key
      select case (key)
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_dispatch.inc"
      case default
         call fatal('forces_init: no pair loop for the models of key '//int_str(key)// &
                    ' (list, boundary, kernel, viscosity, diffusion, correction, porous, shifting): add it to '// &
                    'src/fluid_variants.fypp')
      end select
   end subroutine choose

   !> The models that sum over the pairs before the forces, and so share a pair list.
   pure logical function needs_list(prm)
      type(params_t), intent(in) :: prm
      needs_list = prm%kgc == kgc_gradient .or. prm%visc == visc_laminar_sps
   end function needs_list

   !> The work arrays for nmax particles, of the models that are on (the others minimal).
   subroutine forces_ensure(w, nmax, prm)
      type(forces_work_t), intent(inout) :: w
      integer, intent(in) :: nmax
      type(params_t), intent(in) :: prm
      integer :: ist
      character(len=200) :: emsg
      if (allocated(w%acc)) then
         if (size(w%drho) >= nmax) return
         deallocate (w%acc, w%drho, w%cs, w%irho, w%vol, w%rhod, w%lm, w%tau, w%gv, w%por, w%nf, w%mp, w%rp, w%vb, w%sh, w%rt)
      end if
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (w%acc(ndim, nmax), w%drho(nmax), w%cs(nmax), w%irho(nmax), w%vol(nmax), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the force arrays', nmax)
      ! arrays of models that are off stay minimal
      if (prm%diffusion /= diff_none) then
         allocate (w%rhod(nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%rhod in forces_ensure')
      else
         allocate (w%rhod(1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%rhod in forces_ensure')
      end if
      if (prm%kgc == kgc_gradient) then
         allocate (w%lm(nsym, nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%lm in forces_ensure')
      else
         allocate (w%lm(nsym, 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%lm in forces_ensure')
      end if
      if (prm%visc == visc_laminar_sps) then
         ! allow(multiple-allocations-with-stat): either refused is the same stop
         allocate (w%tau(nsym, nmax), w%gv(ndim*ndim, nmax), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%tau, w%gv in forces_ensure')
      else
         ! allow(multiple-allocations-with-stat): either refused is the same stop
         allocate (w%tau(nsym, 1), w%gv(ndim*ndim, 1), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'w%tau, w%gv in forces_ensure')
      end if
      ! allow(multiple-allocations-with-stat): either refused is the same stop
      allocate (w%por(n_por, merge(nmax, 1, prm%porous)), w%nf(merge(nmax, 1, prm%porous)), &
                w%mp(merge(nmax, 1, prm%porous)), w%rp(merge(nmax, 1, prm%porous)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'the porous arrays in forces_ensure')
      allocate (w%vb(ndim, merge(nmax, 1, prm%boundary == bnd_mdbc .and. prm%slip /= slip_wall)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'w%vb in forces_ensure')
      ! allow(multiple-allocations-with-stat): either refused is the same stop
      allocate (w%sh(ndim + 1, merge(nmax, 1, prm%shift /= shift_none)), &
                w%rt(2*ndim + 2, merge(nmax, 1, prm%shift /= shift_none)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'w%sh, w%rt in forces_ensure')
   end subroutine forces_ensure

   !> With porous regions, the first thing an evaluation needs: the porosity
   !> field of the particles where they are now, into w%por (the mDBC's
   !> density of the pore water, then forces_prepare and the pairs read it).
   subroutine forces_porosity(prm, por, p, w)
      type(params_t), intent(in) :: prm
      type(porous_t), intent(in) :: por
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      call forces_ensure(w, size(p%rho), prm)
      call porous_field(por, p%n, p%x, p%kind, w%por)
   end subroutine forces_porosity

   !> What a force evaluation needs before its pairs: pressure and sound
   !> speed from density, 1/rho and volumes, the density of the diffusion
   !> term; the sums the pairs add to (rates, and the sums of a pass before
   !> the forces) start from zero. With porous regions the porosity field of
   !> this evaluation must be in w%por (forces_porosity).
   subroutine forces_prepare(prm, p, w)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(inout) :: p
      type(forces_work_t), intent(inout) :: w
      integer :: i, n
      n = p%n
      call forces_ensure(w, size(p%rho), prm)
      if (prm%porous) then
         ! pressure and the diffusion's density from the density of the pore
         ! water, rho / n (irho holds it until it gets its own values below);
         ! the pair loop reads each particle's porosity, walls and bodies too
         do i = 1, n
            w%irho(i) = p%rho(i)
            if (p%kind(i) == kind_fluid) w%irho(i) = p%rho(i)/w%por(1, i)
         end do
         call eos_update(prm, n, w%irho, p%p, w%cs)
         w%nf(1:n) = w%por(1, 1:n)
         w%mp(1:n) = p%mass(1:n)
         w%rp(1:n) = p%rho(1:n)
         do i = 1, n
            if (p%kind(i) /= kind_fluid) then
               w%mp(i) = w%por(1, i)*p%mass(i)
               w%rp(i) = w%por(1, i)*p%rho(i)
            end if
         end do
         if (prm%diffusion == diff_fourtakas) then
            call eos_dynamic_density(prm, n, w%irho, p%x, w%rhod)
         else if (prm%diffusion /= diff_none) then
            w%rhod(1:n) = w%irho(1:n)
         end if
      else
         call eos_update(prm, n, p%rho, p%p, w%cs)
         if (prm%diffusion == diff_fourtakas) then
            call eos_dynamic_density(prm, n, p%rho, p%x, w%rhod)
         else if (prm%diffusion /= diff_none) then
            w%rhod(1:n) = p%rho(1:n)
         end if
      end if
      if (prm%porous) then
         do i = 1, n
            w%irho(i) = 1.0_rp/w%rp(i)
            w%vol(i) = w%mp(i)*w%irho(i)
         end do
      else
         do i = 1, n
            w%irho(i) = 1.0_rp/p%rho(i)
            w%vol(i) = p%mass(i)*w%irho(i)
         end do
      end if
      if (prm%kgc == kgc_gradient) w%lm(:, 1:n) = 0.0_rp
      if (prm%visc == visc_laminar_sps) w%gv(:, 1:n) = 0.0_rp
      if (w%shift_now) then
         ! the evaluation whose shifting sums the step uses: all rates in rt
         w%rt(:, 1:n) = 0.0_rp
      else
         w%acc(:, 1:n) = 0.0_rp
         w%drho(1:n) = 0.0_rp
      end if
      w%mumax = 0.0_rp
   end subroutine forces_prepare

   !> The pairs of one evaluation: w%acc and w%drho for all particles. Without
   !> a pass before the forces, one loop over the grid's stencil. With one
   !> (gradient correction, SPS), a sweep over the cell columns, left to
   !> right, that keeps the pair lists of two columns only: for column c its
   !> pair list (nbr_build), then that pass's sums over its rows, which
   !> completes the sums of column c (the half stencil reaches only to the
   !> right), so its correction matrices and stress follow; then the forces of
   !> column c-1, whose partners (columns c-1 and c) are now complete. The
   !> rows are met in the order of a pass over the whole list, so the sums
   !> are the same, and the lists cost the memory of a few columns instead of
   !> 12 bytes a pair. On several ranks the slab's first column waits for the
   !> halo's share of its sums (from the previous rank) and the last for the
   !> halo's matrices (from the next): forces_sweep_first and
   !> forces_sweep_last finish them after the step's halo exchanges. With
   !> periodic sides the images of column c (met by the rows of c-1 and c)
   !> give their sums to their originals before c is finished, and take the
   !> finished values after.
   subroutine forces_sweep(prm, g, p, w, halo)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(halo_t), intent(in) :: halo
      integer :: c, s
      logical :: left, right
      if (.not. needs_list(prm)) then
         call pair_rows(prm, g, p, w, w%seg(1))
         return
      end if
      call grid_neighbours(g, left, right)
      do c = 1, g%ncol
         s = slot(g, c)
         call nbr_build(w%seg(s), g, p%x, p%n, prm%kernel, prm%h, prm%support2, prm%fw, c)
         call pre_sums(prm, p, w, w%seg(s))
         if (g%periodic) call images_fold(prm, g, p, w, halo, c)
         if (.not. (c == 1 .and. left)) then
            call pre_finish(prm, p, w, w%seg(s)%i0, w%seg(s)%i1)
            if (g%periodic) call images_copy(prm, g, p, w, halo, c)
         end if
         if (c >= 2) then
            if (.not. (c == 2 .and. left)) call pair_rows(prm, g, p, w, w%seg(slot(g, c - 1)))
         end if
      end do
      if (.not. right .and. .not. (g%ncol == 1 .and. left)) call pair_rows(prm, g, p, w, w%seg(slot(g, g%ncol)))
   end subroutine forces_sweep

   !> Periodic sides: the sums of the pass before the forces of the images of
   !> column c added to their originals; with the last column, those of the
   !> halo's images too (they go with the halo's sums).
   subroutine images_fold(prm, g, p, w, halo, c)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(halo_t), intent(in) :: halo
      integer, intent(in) :: c
      integer :: i0, i1, k
      do k = c, merge(c + 1, c, c == g%ncol)
         call grid_image_range(g, k, i0, i1)
         if (prm%kgc == kgc_gradient) call comm_halo_fold_images(halo, w%lm, p%n_own, i0, i1)
         if (prm%visc == visc_laminar_sps) call comm_halo_fold_images(halo, w%gv, p%n_own, i0, i1)
      end do
   end subroutine images_fold

   !> Periodic sides: the finished matrices and stresses of column c to its images.
   subroutine images_copy(prm, g, p, w, halo, c)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(halo_t), intent(in) :: halo
      integer, intent(in) :: c
      integer :: i0, i1
      call grid_image_range(g, c, i0, i1)
      if (prm%kgc == kgc_gradient) call comm_halo_copy_images(halo, w%lm, p%n_own, i0, i1)
      if (prm%visc == visc_laminar_sps) call comm_halo_copy_images(halo, w%tau, p%n_own, i0, i1)
   end subroutine images_copy

   !> After the halo's sums have reached their owners: the matrices and stress
   !> of the first column of a slab with a rank on its left (its forces wait
   !> for forces_sweep_last).
   subroutine forces_sweep_first(prm, g, p, w)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      logical :: left, right
      if (.not. needs_list(prm)) return
      call grid_neighbours(g, left, right)
      if (.not. left) return
      call pre_finish(prm, p, w, w%seg(slot(g, 1))%i0, w%seg(slot(g, 1))%i1)
   end subroutine forces_sweep_first

   !> After the halo has its matrices: the forces of the first column of a slab
   !> with a rank on its left and of the last column of a slab with one on its
   !> right (both here, so that between two exchanges each rank does its edge
   !> columns' pairs at the same time as its neighbours); then gravity on the owned
   !> fluid. On several ranks the halo's share of the rates still has to reach
   !> its owners.
   subroutine forces_sweep_last(prm, g, p, w)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      logical :: left, right
      integer :: i
      if (needs_list(prm)) then
         call grid_neighbours(g, left, right)
         ! a single column with both neighbours is the last one too: once
         if (left .and. .not. (g%ncol == 1 .and. right)) call pair_rows(prm, g, p, w, w%seg(slot(g, 1)))
         if (right) call pair_rows(prm, g, p, w, w%seg(slot(g, g%ncol)))
      end if
      if (w%shift_now) then
         ! the rates where the rest of the step reads them
         do i = 1, p%n
            w%acc(:, i) = w%rt(1:ndim, i)
            w%drho(i) = w%rt(ndim + 1, i)
            w%sh(:, i) = w%rt(ndim + 2:, i)
         end do
      end if
      ! gravity on the owned particles only: the pair sums of the halo
      ! copies are added to their owners afterwards (comm_halo_reverse)
      do i = 1, p%n_own
         if (p%kind(i) == kind_fluid) w%acc(iup, i) = w%acc(iup, i) - prm%g   ! gravity along -y
      end do
   end subroutine forces_sweep_last

   !> The list slot of column c: two alternate, the first and last columns of
   !> a slab with neighbours keep theirs until the halo exchanges.
   pure integer function slot(g, c) result(s)
      type(grid_t), intent(in) :: g
      integer, intent(in) :: c
      logical :: left, right
      call grid_neighbours(g, left, right)
      if (c == 1 .and. left) then
         s = 3
      else if (c == g%ncol .and. right) then
         s = 4
      else
         s = 1 + mod(c, 2)
      end if
   end function slot

   !> The pass before the forces over the rows of list nb.
   subroutine pre_sums(prm, p, w, nb)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(nbr_t), intent(in) :: nb
      if (prm%kgc == kgc_gradient .and. prm%visc == visc_laminar_sps) then
         ! both need a pass over the pairs before the forces: one shared pass
         call sps_sums(nb, p, w%vol, w%gv, w%lm)
      else if (prm%kgc == kgc_gradient) then
         call kgc_sums(nb, p, w%vol, w%lm)
      else if (prm%visc == visc_laminar_sps) then
         call sps_sums(nb, p, w%vol, w%gv)
      end if
   end subroutine pre_sums

   !> From the complete sums of the pass before the forces to what the pair
   !> loop reads, for particles i_lo .. i_hi: the correction matrices
   !> L = B^-1 in w%lm, the SPS stress in w%tau.
   subroutine pre_finish(prm, p, w, i_lo, i_hi)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      integer, intent(in) :: i_lo, i_hi
      if (prm%kgc == kgc_gradient) call kgc_finish(w%lm, i_lo, i_hi)
      if (prm%visc == visc_laminar_sps) call sps_tau(prm, p, w%gv, w%tau, i_lo, i_hi)
   end subroutine pre_finish

   !> The forces of the rows of list nb (or of the whole grid's stencil, for
   !> the loops without a list) into w%acc and w%drho.
   subroutine pair_rows(prm, g, p, w, nb)
      type(params_t), intent(in) :: prm
      type(grid_t), intent(in) :: g
      type(particles_t), intent(in) :: p
      type(forces_work_t), intent(inout) :: w
      type(nbr_t), intent(in) :: nb
      real(rp) :: rep(n_rep)
      ! constants of the repulsive boundary, unused by the dynamic one
      rep = [prm%rep_a, prm%rep_b, prm%rep_q0, prm%rep_u, prm%y_surface, prm%rep_rhswl, prm%dp]
      if (prm%porous) then
         call run(p%v, w%rp, w%mp)
      else if (prm%boundary == bnd_mdbc .and. prm%slip /= slip_wall) then
         ! the solids' velocities as the slip condition makes them (bc_mdbc)
         call run(w%vb, p%rho, p%mass)
      else
         call run(p%v, p%rho, p%mass)
      end if
   contains
      subroutine run(v, rho, mass)
         real(rp), contiguous, intent(in) :: v(:, :), rho(:), mass(:)
         if (w%shift_now) then
            call w%pairs_x(p%n, g, nb, p%x, v, rho, w%irho, p%p, mass, p%kind, w%cs, w%rhod, w%lm, w%tau, &
                         p%nrm, p%surf, w%nf, prm%h, prm%support2, prm%eta2, prm%fw, prm%alpha, 4.0_rp*prm%nu, &
                         prm%delta_coef, prm%kgc_cont, rep, w%rt, w%mumax)
         else
            call w%pairs(p%n, g, nb, p%x, v, rho, w%irho, p%p, mass, p%kind, w%cs, w%rhod, w%lm, w%tau, &
                       p%nrm, p%surf, w%nf, prm%h, prm%support2, prm%eta2, prm%fw, prm%alpha, 4.0_rp*prm%nu, &
                       prm%delta_coef, prm%kgc_cont, rep, w%acc, w%drho, w%mumax)
         end if
      end subroutine run
   end subroutine pair_rows

   !> Pair sums of the sub-particle-scale stress: the velocity gradients
   !> grad v_i = sum_j V_j (v_j - v_i) grad_i W_ij of the rows of nb added to
   !> gv (zero before the first rows); with lm present,
   !> the moment matrices of the gradient correction (kgc_sums) from the
   !> same sweep, at about the cost of one of the two sweeps.
   subroutine sps_sums(nb, p, vol, gv, lm)
      type(nbr_t), intent(in) :: nb
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: vol(:)       !< mass/density of every particle
      real(rp), intent(inout) :: gv(:, :)
      real(rp), intent(inout), optional :: lm(:, :)
      integer :: i, j, k
      real(rp) :: fac, vi, vj
#define PRE_SPS 1
#define PRE_KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_decl.inc"
#undef PRE_KGC
      ! one copy of the pass per choice: no test inside the pair loop
      if (present(lm)) then
#define PRE_KGC 1
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
      else
#define PRE_KGC 0
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "pre_pairs.inc"
#undef PRE_KGC
      end if
#undef PRE_SPS
   end subroutine sps_sums

   !> Sub-particle-scale stress (Smagorinsky eddy viscosity with the Blin
   !> term, Dalrymple and Rogers 2006) from the summed velocity gradients,
   !> stored as (tau/rho)/rho per fluid particle.
   subroutine sps_tau(prm, p, gv, tau, i_lo, i_hi)
      type(params_t), intent(in) :: prm
      type(particles_t), intent(in) :: p
      real(rp), intent(in) :: gv(:, :)         !< d v_a / d x_b in slot ndim (a - 1) + b
      real(rp), intent(inout) :: tau(:, :)     !< in the slots of a symmetric tensor (tensor: sym_slot)
      integer, intent(in) :: i_lo, i_hi     !< the particles whose sums are complete
      integer :: i, a, b
      real(rp) :: s(nsym), sd, tr, s2, nut, sk
      do i = i_lo, i_hi
         ! the strain rate S = (grad v + grad v^T)/2 and 2 S:S, the diagonal first
         sd = 0.0_rp
         tr = 0.0_rp
         do a = 1, ndim
            s(sym_slot(a, a)) = gv(ndim*(a - 1) + a, i)
            sd = sd + s(sym_slot(a, a))*s(sym_slot(a, a))
            tr = tr + s(sym_slot(a, a))
         end do
         s2 = 2.0_rp*sd
         do a = 1, ndim
            do b = a + 1, ndim
               s(sym_slot(a, b)) = 0.5_rp*(gv(ndim*(a - 1) + b, i) + gv(ndim*(b - 1) + a, i))
               s2 = s2 + 4.0_rp*s(sym_slot(a, b))*s(sym_slot(a, b))
            end do
         end do
         nut = prm%sps_smag*sqrt(s2)
         sk = -(2.0_rp/3.0_rp)*nut*tr - prm%sps_blin*s2
         do a = 1, ndim
            tau(sym_slot(a, a), i) = (2.0_rp*nut*s(sym_slot(a, a)) + sk)/p%rho(i)
            do b = a + 1, ndim
               tau(sym_slot(a, b), i) = 2.0_rp*nut*s(sym_slot(a, b))/p%rho(i)
            end do
         end do
         if (p%kind(i) /= kind_fluid) tau(:, i) = 0.0_rp
      end do
   end subroutine sps_tau

! the variants, generated from the list in src/fluid_variants.fypp: over the grid's stencil (s)
! without a pass before the forces, over the pair list (l) with one
! allow(bad-quote-string): cpp needs a double-quoted file name in #include
#include "fluid_variants.inc"
end module fluid_forces

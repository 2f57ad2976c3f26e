!> Contact without MPI: three square bodies (one resting on a floor of wall
!> particles, one beside it, one on top, all moving), for every model:
!> - the sweep's candidate pairs are exactly the brute-force set (surface
!>   particles of two different solids within 2h, one of them floating, every
!>   pair once);
!> - with the floor left out, the contact forces between the floating bodies
!>   keep momentum: their sum over the bodies vanishes (to 1e-12 of the
!>   largest force), and so does that of the forces of the implicit damping
!>   matrix applied to any velocities of the bodies. (Angular momentum is not
!>   asserted: a pair force along a face's normal or the slip acts at two
!>   particle centres that are not on its line, a couple of order f dp that
!>   belongs to the discretisation.)
!> - the stiff core (non-cohesive models, bodies overlapping by 0.05 dp): the
!>   same balance of the forces and of the damping, and a normal force more
!>   than ten times that of the soft contact alone.
program test_contact
   use kinds, only: rp, lk
   use constants, only: kind_fixed, kind_floating
   use particles, only: particles_t, particles_alloc
   use grid, only: grid_t, grid_init, grid_sort
   use params, only: params_t
   use kernel, only: kernel_wendland, kernel_norm
   use body_dynamics, only: body_t
   use options, only: model_dynamic, model_repulsive, model_noncohesive, model_spring, model_hertz, &
                      motion_floating
   use contact, only: contact_t, contact_settings_t, contact_init, contact_sweep, contact_apply
   use testing, only: check, test_summary
   implicit none
   integer, parameter :: ns = 12                ! particles along a side
   integer, parameter :: models(5) = [model_dynamic, model_repulsive, model_noncohesive, model_spring, model_hertz]
   character(len=18), parameter :: names(5) = ['dynamic           ', 'repulsive         ', 'noncohesive       ', &
                                               'noncohesive_spring', 'hertz             ']
   real(rp), parameter :: dp = 0.01_rp
   type(particles_t) :: p
   type(grid_t) :: g
   type(params_t) :: prm
   type(body_t) :: bodies(3)
   type(contact_settings_t) :: cfg
   type(contact_t) :: ct
   real(rp), allocatable :: drho(:)
   logical(lk), allocatable :: drop(:)
   integer :: k, m, floor_n, b
   logical :: with_floor
   real(rp) :: gap = 0.8_rp*dp                  ! between the facing rows of neighbouring bodies (dp: touching)
   real(rp) :: fk(2)

   prm%dp = dp
   prm%h = 1.3_rp*dp
   prm%h2 = prm%h**2
   prm%support2 = 4.0_rp*prm%h2
   prm%kernel = kernel_wendland
   prm%aw = kernel_norm(prm%kernel, prm%h)
   prm%fw = prm%aw/prm%h2
   prm%g = 9.81_rp
   prm%cfl = 0.2_rp
   floor_n = 3*ns
   do m = 1, size(models)
      do k = 1, 2
         with_floor = k == 1
         call make_scene(with_floor)
         cfg%model = models(m)
         cfg%b = 20.0_rp
         call contact_init(cfg, prm, ct)
         call contact_sweep(ct, prm, g, p, bodies, drho)
         if (with_floor) then
            call check_candidates(trim(names(m)))
         else
            call contact_apply(ct, prm, p, bodies)
            call check_balance(trim(names(m)))
         end if
      end do
   end do
   ! the stiff core: the bodies' outlines overlap by 0.05 dp
   gap = 0.95_rp*dp
   do m = 3, 4
      do k = 1, 2
         call make_scene(.false.)
         cfg%model = models(m)
         cfg%b = 20.0_rp
         cfg%core = merge(0.01_rp, 0.0_rp, k == 2)
         call contact_init(cfg, prm, ct)
         call contact_sweep(ct, prm, g, p, bodies, drho)
         call contact_apply(ct, prm, p, bodies)
         call check_balance(trim(names(m))//merge(', core', ', soft', k == 2))
         fk(k) = maxval([(norm2(bodies(b)%f_normal), b=1, 3)])
      end do
      call check(fk(2) > 10.0_rp*fk(1), trim(names(m))//': the core carries the overlap')
   end do
   call test_summary('test_contact')

contains

   !> Three square outlines of ns particles a side (body ids 1-3), the second
   !> beside the first and the third on top of it, each 0.8 dp from
   !> touching; with_floor: a row of wall particles under the first two.
   subroutine make_scene(with_floor)
      logical, intent(in) :: with_floor
      real(rp), parameter :: side = (ns - 1)*dp
      real(rp) :: c(2, 3), v(2, 3), om(3)
      integer :: b, n, s, q
      c(:, 1) = [0.5_rp*side, 0.5_rp*side + dp]
      c(:, 2) = c(:, 1) + [side + gap, 0.3_rp*dp]
      c(:, 3) = c(:, 1) + [0.25_rp*dp, side + gap]
      v(:, 1) = [0.02_rp, -0.01_rp]; v(:, 2) = [-0.05_rp, 0.0_rp]; v(:, 3) = [0.01_rp, -0.04_rp]
      om = [0.3_rp, -0.2_rp, 0.5_rp]
      n = 3*4*(ns - 1)
      if (with_floor) n = n + floor_n
      call particles_alloc(p, n)
      p%n = 0
      do b = 1, 3
         bodies(b)%id = b
         bodies(b)%motion = motion_floating
         bodies(b)%pose%c = c(:, b)
         bodies(b)%v = v(:, b)
         bodies(b)%omega = [om(b)]
         bodies(b)%mass = 1.0_rp + b
         bodies(b)%m_surf = bodies(b)%mass/(4*(ns - 1))
         bodies(b)%mu = 0.6_rp
         bodies(b)%rbound = sqrt(2.0_rp)*0.5_rp*side
         ! the four sides, corners once, outward normals (the corner's diagonal)
         do s = 0, 3
            do q = 0, ns - 2
               if (q == 0) then
                  call add(b, c(:, b) + corner(s, side), diag(s), 2)
               else
                  call add(b, c(:, b) + corner(s, side) + q*dp*edge(s), normal(s), 1)
               end if
            end do
         end do
      end do
      if (with_floor) then
         do q = 1, floor_n
            call add(0, [-dp + (q - 1)*dp, 0.0_rp], [0.0_rp, 1.0_rp], 1)
         end do
      end if
      p%n_own = p%n
      p%n_id = p%n
      if (allocated(drho)) deallocate (drho, drop)
      allocate (drho(size(p%rho)), drop(p%n))
      drho = 0.0_rp
      drop = .false.
      call grid_init(g, -3.0_rp*dp, 3.0_rp*side, -2.0_rp*dp, 3.0_rp*side, prm%h)
      call grid_sort(g, p, drop, cells=.true.)
   end subroutine make_scene

   !> One surface particle of body b (0: the wall) at x, its velocity that of the body.
   subroutine add(b, x, nrm, surf)
      integer, intent(in) :: b, surf
      real(rp), intent(in) :: x(2), nrm(2)
      p%n = p%n + 1
      p%x(:, p%n) = x
      p%nrm(:, p%n) = nrm
      p%surf(p%n) = surf
      p%body(p%n) = b
      p%id(p%n) = p%n
      p%mass(p%n) = 0.1_rp
      p%rho(p%n) = 1000.0_rp
      p%p(p%n) = 500.0_rp + 10.0_rp*mod(p%n, 7)
      if (b > 0) then
         p%kind(p%n) = kind_floating
         p%v(:, p%n) = bodies(b)%v + bodies(b)%omega(1)*[-(x(2) - bodies(b)%pose%c(2)), x(1) - bodies(b)%pose%c(1)]
      else
         p%kind(p%n) = kind_fixed
         p%v(:, p%n) = 0.0_rp
      end if
   end subroutine add

   pure function corner(s, side) result(x)
      integer, intent(in) :: s
      real(rp), intent(in) :: side
      real(rp) :: x(2)
      real(rp), parameter :: cs(2, 0:3) = reshape([-1, -1, 1, -1, 1, 1, -1, 1], [2, 4])*0.5_rp
      x = cs(:, s)*side
   end function corner

   pure function edge(s) result(e)
      integer, intent(in) :: s
      real(rp) :: e(2)
      real(rp), parameter :: es(2, 0:3) = reshape([1, 0, 0, 1, -1, 0, 0, -1], [2, 4])*1.0_rp
      e = es(:, s)
   end function edge

   pure function normal(s) result(nrm)
      integer, intent(in) :: s
      real(rp) :: nrm(2), e(2)
      e = edge(s)
      nrm = [e(2), -e(1)]
   end function normal

   pure function diag(s) result(nrm)
      integer, intent(in) :: s
      real(rp) :: nrm(2)
      nrm = corner(s, 1.0_rp)*sqrt(2.0_rp)
   end function diag

   !> The sweep's pairs against every pair of particles.
   subroutine check_candidates(name)
      character(len=*), intent(in) :: name
      integer :: i, j, k, found, expected, twice
      logical :: seen(p%n, p%n)
      seen = .false.
      twice = 0
      do k = 1, ct%nc
         i = min(ct%cij(1, k), ct%cij(2, k))
         j = max(ct%cij(1, k), ct%cij(2, k))
         if (seen(i, j)) twice = twice + 1
         seen(i, j) = .true.
      end do
      found = 0
      expected = 0
      do i = 1, p%n
         do j = i + 1, p%n
            if (p%body(i) == p%body(j)) cycle
            if (p%kind(i) /= kind_floating .and. p%kind(j) /= kind_floating) cycle
            if (sum((p%x(:, i) - p%x(:, j))**2) >= prm%support2) cycle
            expected = expected + 1
            if (seen(i, j)) found = found + 1
         end do
      end do
      call check(expected > 100, name//': the scene has contact pairs')
      call check(found == expected .and. ct%nc == expected, name//': the sweep finds every pair of the brute force')
      call check(twice == 0, name//': no pair twice')
   end subroutine check_candidates

   !> Momentum and angular momentum of the contact forces and of the damping.
   subroutine check_balance(name)
      character(len=*), intent(in) :: name
      real(rp) :: f(2), fmax, q(9), cq(9)
      real(rp), parameter :: tol = 1.0e-12_rp
      integer :: b
      f = 0.0_rp
      fmax = 0.0_rp
      do b = 1, 3
         associate (bd => bodies(b))
            f = f + bd%f_normal + bd%f_fric
            fmax = max(fmax, norm2(bd%f_normal), norm2(bd%f_fric))
         end associate
      end do
      call check(fmax > 0.0_rp, name//': the bodies touch')
      call check(norm2(f)/fmax <= tol, name//': contact forces sum to zero')
      q = [0.3_rp, -0.1_rp, 0.7_rp, 0.2_rp, 0.5_rp, -0.4_rp, -0.6_rp, 0.1_rp, 0.9_rp]
      cq = matmul(ct%damp, q)
      fmax = maxval(abs(cq))
      ! the dynamic boundary damps only through friction below the stick speed
      if (name /= 'dynamic') call check(fmax > 0.0_rp, name//': the contacts damp')
      if (fmax <= 0.0_rp) return
      f = cq(1:2) + cq(4:5) + cq(7:8)
      call check(norm2(f)/fmax <= tol, name//': damping forces sum to zero')
   end subroutine check_balance
end program test_contact

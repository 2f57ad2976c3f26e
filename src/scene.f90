!> Builds the particles of a case: fluid lattices, wall lattices and slope
!> layers from the geometry objects; hydrostatic density to start from.
module scene
   use kinds, only: rp
   use constants, only: kind_fluid, kind_fixed, kind_moving, kind_floating, kind_filter, ndim, nsec
   use input, only: case_cfg
   use input_mesh, only: mesh_cfg, mesh_lattice, mesh_layers, mesh_holding
   use input_body, only: body_cfg, body_zrange, body_turn, body_tilted
   use body_shapes, only: body_outline, body_mass_properties, body_particles, mesh_shell
   use body_dynamics, only: body_t
   use rigid, only: rigid_set_angle_z, rigid_tilt, nrot, ndof
   use options, only: motion_floating, motion_fixed, motion_prescribed, role_solid, role_fluid, role_filter, wall_fixed, &
                      integ_verlet, bnd_mdbc, shape_stl, mass_hydrostatic
   use geom_stl, only: stl_t, stl_inside, stl_nearest
   use input_geometry, only: geom_object, geom_zrange
   use particles, only: particles_t, particles_grow, particles_fit
   use params, only: params_t
   use kernel, only: kernel_norm
   use probe_gauges, only: gauges_t, gauges_init
   use wave_damping, only: damping_t
   use contact, only: contact_settings_t
   use run_state, only: run_ctl_t
   use eos, only: eos_density_at_depth
   use geom, only: point_in_polygon, nearest_edge_normal, distance_to_polygon, polygon_area
   use porous, only: porous_t, porous_point, porous_lookup, n_por
   use scene_ghosts, only: scene_ghost_offsets
   use bc_motion, only: wall_motion_t
   use errors, only: fatal, alloc_check, input_error
   use input_check, only: int_str
   implicit none
   private
   public :: scene_build, scene_bodies, scene_no_fluid, scene_estimate, scene_params, scene_gauges, scene_damping, &
             scene_contact, scene_run, scene_porous, scene_walls

   !> What a scene without fluid particles lacks, for the messages.
   character(len=*), parameter :: scene_no_fluid = "no fluid particles: no &box or &polygon with role = 'fluid' "// &
                                                   '(or all of its area lies outside the &domain, in solids or bodies)'

   type :: outline_t
      real(rp), allocatable :: v(:, :)
      real(rp) :: zr(2) = [-huge(1.0_rp), huge(1.0_rp)]   !< 3D: its extent across the width [m]
      !> 3D, a box turned out of the section: the hole is the box itself (centre c, half
      !> sides half in its own frame, turn from that frame), not its shadow's extrusion
      logical :: box = .false.
      real(rp) :: c(3) = 0.0_rp, half(3) = 0.0_rp, turn(3, 3) = 0.0_rp
      !> 3D, an STL body: the hole is the mesh itself (in its own frame, centre c, turn as above;
      !> rmax: its farthest vertex from c)
      logical :: stl = .false.
      type(stl_t) :: mesh
      real(rp) :: rmax = 0.0_rp
   end type outline_t

contains

   subroutine scene_build(c, p, prm, bodies)
      type(case_cfg), intent(in) :: c
      type(particles_t), intent(inout) :: p
      type(params_t), intent(out) :: prm
      type(body_t), allocatable, intent(out) :: bodies(:)
      integer :: k, i, nf
      real(rp) :: dp, ybed, ytop, f(n_por), zdom(2), vol
      real(rp), allocatable :: cell(:)
      type(outline_t), allocatable :: holes(:)
      type(porous_t) :: por
      dp = c%numerics%dp
      p%n = 0
      p%n_id = 0
      ! the Verlet integrator's history fields only where it runs
      p%history = c%numerics%integrator_id == integ_verlet
      ! the ghost offsets of the modified dynamic boundary only where it runs
      p%mdbc = c%numerics%boundary_id == bnd_mdbc
      call scene_holes(c, holes)
      por = scene_porous(c)
      zdom = [c%domain%zmin, c%domain%zmax]
      do k = 1, size(c%objs)
         if (c%objs(k)%group == 'slope') then
            call add_slope(c%objs(k), k, dp, zdom, p, c%objs(1:k - 1))
         else
            call add_lattice(c%objs(k), k, dp, zdom, p, c%objs, holes, por)
         end if
      end do
      do k = 1, size(c%meshes)
         call add_mesh_solid(c, k, p)
      end do
      call add_pore_water(c, dp, zdom, p, holes, por, cell)
      call scene_bodies(c, bodies, p)
      call bodies_clear_of_meshes(c, p)
      ! the bodies' particles fill dp^d each as the open water's (their mass is their share of the water's)
      cell = [cell, (dp**ndim, i = size(cell) + 1, p%n)]
      nf = count(p%kind(1:p%n) == kind_fluid)
      ybed = 0.0_rp
      ytop = 0.0_rp
      if (nf > 0) then
         ybed = minval(p%x(2, 1:p%n), mask=p%kind(1:p%n) == kind_fluid) - 0.5_rp*dp
         ytop = maxval(p%x(2, 1:p%n), mask=p%kind(1:p%n) == kind_fluid) + 0.5_rp*dp
      end if
      call scene_params(c, ybed, ytop, prm)
      do i = 1, p%n
         p%id(i) = i
         p%v(:, i) = 0.0_rp
         ! the space the particle fills on its start lattice (the pores' lattice
         ! is fitted to its region, add_pore_water)
         vol = cell(i)
         p%mass(i) = prm%rho0*vol
         ! a filter carries no water: massless in every pair term, the water
         ! passes it (its particles only stop bodies, through the contact)
         if (p%kind(i) == kind_filter) p%mass(i) = 0.0_rp
         ! still water: hydrostatic density below the surface, rho0 above
         ! (body particles take the density of the water they displace)
         p%rho(i) = eos_density_at_depth(prm, max(prm%y_surface - p%x(2, i), 0.0_rp))
         ! 'hydrostatic': the water's volume m/rho is the space each particle fills on
         ! its start lattice (below: across the pores too), not that space shrunk by
         ! the compression of its depth: the discrete pressure gradient then holds
         ! the water up at rho g (doc/mdbc.md, "Measured")
         if (c%numerics%mass_id == mass_hydrostatic .and. p%kind(i) == kind_fluid) p%mass(i) = p%rho(i)*vol
         if (por%on .and. p%kind(i) == kind_fluid) then
            ! in the pores the continuity equation carries the superficial density
            ! n rho, and the mass is that density times the particle's space, so
            ! that its volume m/rho_s is the space it fills: across the smooth
            ! edge too, where n(x) is between the region's n and 1 on either lattice
            f = porous_point(por, p%x(1:nsec, i))
            p%rho(i) = f(1)*p%rho(i)
            p%mass(i) = f(1)*p%mass(i)
         end if
         if (p%history) then
            p%vm1(:, i) = p%v(:, i)
            p%rhom1(i) = p%rho(i)
         end if
         p%p(i) = 0.0_rp
      end do
      p%n_id = p%n
      p%n_own = p%n
      call scene_ghost_offsets(c, p, bodies, prm%h)
      call particles_fit(p)
      if (p%n == 0) call fatal(trim(c%file)//': the case makes no particles (add &box, &polygon or &slope groups)', 2)
      if (nf == 0) call no_fluid(c, p, bodies)
   end subroutine scene_build

   !> A scene without water and with nothing that moves is nothing to
   !> simulate; without water but with bodies or walls that move it is a dry
   !> contact case (the solver says so in run.log).
   subroutine no_fluid(c, p, bodies)
      type(case_cfg), intent(in) :: c
      type(particles_t), intent(in) :: p
      type(body_t), intent(in) :: bodies(:)
      integer :: k
      logical :: moves
      moves = any(p%kind(1:p%n) == kind_moving)
      do k = 1, size(bodies)
         moves = moves .or. bodies(k)%motion /= motion_fixed
      end do
      if (.not. moves) call fatal(trim(c%file)//': the case has '//scene_no_fluid//' and nothing that moves: '// &
                                  'nothing to simulate', 2)
   end subroutine no_fluid

   !> About how many particles the case makes: the area of every object and
   !> body over dp^2 (a porous region's 1/n - 1 times more), in 3D times the
   !> width over dp (overlaps counted twice: an upper estimate), before any is made.
   real(rp) function scene_estimate(c) result(n)
      type(case_cfg), intent(in) :: c
      integer :: k
      n = 0.0_rp
      do k = 1, size(c%objs)
         n = n + abs(polygon_area(c%objs(k)%v))
      end do
      do k = 1, size(c%bodies)
         n = n + abs(polygon_area(body_outline(c%bodies(k))))
      end do
      ! water in the pores: 1/n particles where open water has one
      do k = 1, size(c%porous)
         n = n + abs(polygon_area(c%porous(k)%v))*(1.0_rp/c%porous(k)%porosity - 1.0_rp)
      end do
      n = n/c%numerics%dp**2
      if (ndim == 3) n = n*max(1.0_rp, (c%domain%zmax - c%domain%zmin)/c%numerics%dp)
      do k = 1, size(c%meshes)
         n = n + product(c%meshes(k)%hi - c%meshes(k)%lo)/c%numerics%dp**3
      end do
   end function scene_estimate

   !> The bodies of a case at their start state, and (when p is given) their
   !> particles. A restart calls it without p for the constant properties.
   subroutine scene_bodies(c, bodies, p)
      type(case_cfg), intent(in) :: c
      type(body_t), allocatable, intent(out) :: bodies(:)
      type(particles_t), intent(inout), optional :: p
      integer :: k, layers
      integer :: ist
      character(len=200) :: emsg
      layers = max(1, ceiling(2.0_rp*c%numerics%h_over_dp - 1.0e-9_rp))
      allocate (bodies(size(c%bodies)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'bodies in scene_bodies')
      do k = 1, size(c%bodies)
         call add_body(c%bodies(k), size(c%objs) + k, c%numerics%dp, &
                       merge(c%bodies(k)%layers, layers, c%bodies(k)%layers > 0), bodies(k), p)
         bodies(k)%g = c%fluid%gravity
         if (c%domain%periodic_z) bodies(k)%period_z = c%domain%zmax - c%domain%zmin
      end do
   end subroutine scene_bodies

   !> State of one body and (when p is given) its particles, body number id.
   subroutine add_body(bc, id, dp, layers, b, p)
      type(body_cfg), intent(in) :: bc
      integer, intent(in) :: id, layers
      real(rp), intent(in) :: dp
      type(body_t), intent(out) :: b
      type(particles_t), intent(inout), optional :: p
      real(rp), allocatable :: xb(:, :), nb(:, :)
      integer, allocatable :: surf(:)
      integer :: k, m
      real(rp), parameter :: deg = 3.14159265358979323846_rp/180.0_rp
      call body_mass_properties(bc, b%mass, b%pose%c, b%inertia)
      call body_particles(bc, dp, layers, xb, nb, surf)
      b%motion = bc%motion_id  ! the values of options: motion_floating, motion_fixed, motion_prescribed
      b%id = id
      call rigid_set_angle_z(b%pose, bc%angle*deg)
      if (body_tilted(bc)) call rigid_tilt(b%pose, bc%angle_x*deg, bc%angle_y*deg)
      b%pose_start = b%pose
      if (b%motion /= motion_fixed) then
         ! in 3D the body starts moving in the section (x, y) and turning about z
         b%v = 0.0_rp; b%v(1:nsec) = [bc%u, bc%v]
         if (ndim == 3) b%v(ndim) = bc%w
         b%omega = 0.0_rp; b%omega(nrot) = bc%omega
         if (ndim == 3) then   ! about x and y (the index written so that it is in range in 2D too)
            b%omega(1) = bc%omega_x
            b%omega(max(nrot - 1, 1)) = bc%omega_y
         end if
      end if
      if (b%motion == motion_prescribed) then
         b%rate = 0.0_rp; b%amp = 0.0_rp
         b%rate(1:nsec) = [bc%u, bc%v]; b%rate(ndof) = bc%omega
         b%amp(1:nsec) = [bc%amplitude_x, bc%amplitude_y]; b%amp(ndof) = bc%amplitude_angle
         b%period = bc%period
         b%phase = bc%phase
      end if
      b%mu = bc%mu
      b%restitution = bc%restitution
      b%young = bc%young
      b%poisson = bc%poisson
      b%m_surf = b%mass/max(count(surf > 0), 1)
      b%rbound = maxval(norm2(xb, dim=1)) + 0.5_rp*dp
      b%outline = body_outline(bc)
      if (ndim == 3) then
         b%half = 0.5_rp*[bc%width, bc%height, bc%depth]
         b%turn = body_turn(bc)
      end if
      do k = 1, size(b%outline, 2)
         b%outline(:, k) = b%outline(:, k) - b%pose%c(1:nsec)
      end do
      if (.not. present(p)) return
      m = size(surf)
      call particles_grow(p, m)
      do k = 1, m
         p%n = p%n + 1
         p%xb(:, p%n) = xb(:, k)
         p%nb(:, p%n) = nb(:, k)
         p%nrm(:, p%n) = nb(:, k)
         p%x(:, p%n) = b%pose%c + xb(:, k)
         p%surf(p%n) = surf(k)
         p%body(p%n) = id
         select case (b%motion)
         case (motion_fixed); p%kind(p%n) = kind_fixed
         case (motion_prescribed); p%kind(p%n) = kind_moving
         case (motion_floating); p%kind(p%n) = kind_floating
         case default; call fatal('add_body: unknown motion')
         end select
      end do
   end subroutine add_body

   !> Lattice points (spacing dp, half a spacing in from the bounding box)
   !> inside the object's polygon; fluid points leave room for the bodies. In
   !> 3D the section's lattice is repeated across the object's width (zdom:
   !> the domain's, for an object without its own).
   subroutine add_lattice(o, obj, dp, zdom, p, objs, holes, por)
      type(geom_object), intent(in) :: o, objs(:)
      type(outline_t), intent(in) :: holes(:)
      type(porous_t), intent(in) :: por
      integer, intent(in) :: obj
      real(rp), intent(in) :: dp, zdom(2)
      type(particles_t), intent(inout) :: p
      integer :: i, j, nx, ny, nz, l, k
      real(rp) :: x0, y0, pt(2), z(2), ps(ndim)
      x0 = minval(o%v(1, :))
      y0 = minval(o%v(2, :))
      nx = nint((maxval(o%v(1, :)) - x0)/dp)
      ny = nint((maxval(o%v(2, :)) - y0)/dp)
      nz = layers_across(o, zdom, dp, z)
      call particles_grow(p, nx*ny*nz)
      across: do l = 1, nz
         ! in 2D the section's point below overwrites this
         ps(ndim) = z(1) + (l - 0.5_rp)*dp
         do j = 1, ny
            columns: do i = 1, nx
               pt = [x0 + (i - 0.5_rp)*dp, y0 + (j - 0.5_rp)*dp]
               ps(1:nsec) = pt
               if (.not. point_in_polygon(pt, o%v)) cycle columns
               if (o%role_id == role_solid) then
                  if (solid_covers(objs(1:obj - 1), 0, zdom, ps(1:nsec), ps(ndim))) cycle columns
               else if (in_hole(ps, holes, por, dp)) then
                  cycle columns
               end if
               p%n = p%n + 1
               k = p%n
               p%x(:, k) = ps
               p%xb(:, k) = ps
               if (o%role_id == role_fluid) then
                  p%kind(k) = kind_fluid
                  p%body(k) = 0
                  p%nrm(:, k) = 0.0_rp
                  p%surf(k) = 0
               else
                  call solid_particle(o, obj, objs, dp, zdom, z, pt, k, p)
               end if
               p%nb(:, k) = p%nrm(:, k)
            end do columns
         end do
      end do across
   end subroutine add_lattice

   !> Particle k of the solid o (objs(obj)), at pt in the section, its z range
   !> zo: its kind, body and normal; the outer layer is the surface (contact,
   !> repulsive boundary), near a vertex a corner; a side covered by another
   !> solid is no surface. In 3D a side is covered only by a solid across the
   !> particle's z, and an end face of the solid's z range can be the surface
   !> too (a tank's side wall).
   subroutine solid_particle(o, obj, objs, dp, zdom, zo, pt, k, p)
      type(geom_object), intent(in) :: o, objs(:)
      integer, intent(in) :: obj, k
      real(rp), intent(in) :: dp, zdom(2), zo(2), pt(2)
      type(particles_t), intent(inout) :: p
      real(rp) :: n2(2)
      p%kind(k) = merge(kind_moving, kind_fixed, o%motion_id /= wall_fixed)
      p%body(k) = obj
      n2 = nearest_edge_normal(pt, o%v)
      p%surf(k) = 0
      if (exposed_edge(o, obj, objs, dp, zdom, p%x(ndim, k), pt, n2)) then
         p%surf(k) = 1
         if (minval(hypot(o%v(1, :) - pt(1), o%v(2, :) - pt(2))) < dp) p%surf(k) = 2
      end if
      p%nrm(:, k) = 0.0_rp
      p%nrm(1:nsec, k) = n2
      if (ndim == 3) call end_face_surface(obj, objs, dp, zdom, zo, pt, k, p)
   end subroutine solid_particle

   !> 3D: particle k of objs(obj), less than dp from an end of its z range zo
   !> that lies strictly inside the domain's width zdom, where no other solid
   !> lies just beyond at pt, is on that end face: a surface facing across the
   !> width (normal -z or +z); one on an exposed side as well is on an edge of
   !> the solid, a corner (surf 2, the side's normal kept).
   subroutine end_face_surface(obj, objs, dp, zdom, zo, pt, k, p)
      type(geom_object), intent(in) :: objs(:)
      integer, intent(in) :: obj, k
      real(rp), intent(in) :: dp, zdom(2), zo(2), pt(2)
      type(particles_t), intent(inout) :: p
      integer :: e
      real(rp) :: zf, sg, tol
      tol = 1.0e-9_rp*dp
      ends: do e = 1, 2
         zf = zo(e)
         sg = real(2*e - 3, rp)               ! outward: -1 at zmin, +1 at zmax
         if (abs(p%x(ndim, k) - zf) >= dp) cycle ends
         if (zf <= zdom(1) + tol .or. zf >= zdom(2) - tol) cycle ends
         if (solid_covers(objs, obj, zdom, pt, zf + sg*1.0e-3_rp*dp)) cycle ends
         if (p%surf(k) /= 0) then
            p%surf(k) = 2
         else
            p%surf(k) = 1
            p%nrm(:, k) = 0.0_rp
            p%nrm(ndim, k) = sg
         end if
      end do ends
   end subroutine end_face_surface

   !> Among the edges of o (objs(obj)) less than dp from pt, the nearest (the
   !> first on a tie) whose outside one spacing away is not inside another
   !> solid (in 3D: one across the particle's zp): its outward normal goes to
   !> n. False when there is none.
   logical function exposed_edge(o, obj, objs, dp, zdom, zp, pt, n) result(found)
      type(geom_object), intent(in) :: o, objs(:)
      integer, intent(in) :: obj
      real(rp), intent(in) :: dp, zdom(2), zp, pt(2)
      real(rp), intent(inout) :: n(2)
      integer :: e, f, nv
      real(rp) :: a(2), w(2), t, d, dmin, en(2), sg
      nv = size(o%v, 2)
      sg = sign(1.0_rp, polygon_area(o%v))
      found = .false.
      dmin = dp
      edges: do e = 1, nv
         f = modulo(e, nv) + 1
         a = o%v(:, f) - o%v(:, e)
         w = pt - o%v(:, e)
         t = max(0.0_rp, min(1.0_rp, dot_product(w, a)/max(dot_product(a, a), tiny(1.0_rp))))
         d = norm2(w - t*a)
         if (d >= dmin - 1.0e-12_rp*dmin) cycle edges
         en = sg*[a(2), -a(1)]/norm2(a)
         if (solid_covers(objs, obj, zdom, pt + dp*en, zp)) cycle edges
         dmin = d
         n = en
         found = .true.
      end do edges
   end function exposed_edge

   !> The holes in every fluid fill: the bodies displace the water, and so do
   !> the &stl solids (water around a structure is a box with the mesh left out).
   subroutine scene_holes(c, holes)
      type(case_cfg), intent(in) :: c
      type(outline_t), allocatable, intent(out) :: holes(:)
      integer :: k, ist
      character(len=200) :: emsg
      allocate (holes(size(c%bodies) + size(c%meshes)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'holes in scene_build')
      do k = 1, size(c%meshes)
         holes(size(c%bodies) + k) = mesh_hole(c%meshes(k))
      end do
      do k = 1, size(c%bodies)
         holes(k)%v = body_outline(c%bodies(k))
         if (ndim == 3) holes(k)%zr = body_zrange(c%bodies(k))
         if (ndim == 3 .and. c%bodies(k)%shape_id == shape_stl) then
            associate (bc => c%bodies(k))
               holes(k)%stl = .true.
               holes(k)%mesh = bc%mesh
               holes(k)%rmax = maxval(norm2(bc%mesh%v, dim=1))
               holes(k)%c = [bc%x, bc%y, bc%z]
               holes(k)%turn = body_turn(bc)
            end associate
         else if (ndim == 3 .and. body_tilted(c%bodies(k))) then
            associate (bc => c%bodies(k))
               holes(k)%box = .true.
               holes(k)%c = [bc%x, bc%y, bc%z]
               holes(k)%half = 0.5_rp*[bc%width, bc%height, bc%depth]
               holes(k)%turn = body_turn(bc)
            end associate
         end if
      end do
   end subroutine scene_holes

   !> The hole of an &stl solid in the water: its mesh, in a frame centred on
   !> its bounding box (so that in_body_hole's bounding sphere is a tight first test).
   function mesh_hole(m) result(h)
      type(mesh_cfg), intent(in) :: m
      type(outline_t) :: h
      integer :: t, v
      h%stl = .true.
      h%c = 0.5_rp*(m%lo + m%hi)
      h%turn = reshape([1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp, 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3])
      h%zr = [m%lo(3), m%hi(3)]
      h%mesh = m%mesh
      do t = 1, h%mesh%nt
         do v = 1, 3
            h%mesh%v(:, v, t) = h%mesh%v(:, v, t) - h%c
         end do
      end do
      h%rmax = maxval(norm2(h%mesh%v, dim=1))
   end function mesh_hole

   !> The particles of &stl solid k (3D): the case's lattice points inside its
   !> mesh and less than its layers from the surface (body_shapes' mesh_shell),
   !> but those a &box, &polygon or &slope solid or an earlier &stl solid holds
   !> (which keeps its own, as an earlier solid does). Body number: after the objects and the bodies.
   !> Where another solid lies just beyond a face, the particle there is no surface.
   subroutine add_mesh_solid(c, k, p)
      type(case_cfg), intent(in) :: c
      integer, intent(in) :: k
      type(particles_t), intent(inout) :: p
      real(rp) :: x0(3), dp, zdom(2), out(3)
      real(rp), allocatable :: xs(:, :), ns(:, :)
      integer, allocatable :: surf(:)
      integer :: nn(3), i, m
      dp = c%numerics%dp
      zdom = [c%domain%zmin, c%domain%zmax]
      call mesh_lattice(c%meshes(k), dp, x0, nn)
      call mesh_shell(c%meshes(k)%mesh, x0, [dp, dp, dp], nn, dp, mesh_layers(c%meshes(k), c%numerics%h_over_dp), &
                      xs, ns, surf)
      call particles_grow(p, size(surf))
      points: do i = 1, size(surf)
         if (solid_covers(c%objs, 0, zdom, xs(1:nsec, i), xs(3, i))) cycle points
         if (mesh_holding(c%meshes(1:k - 1), xs(:, i), 0) > 0) cycle points
         p%n = p%n + 1
         m = p%n
         p%x(:, m) = xs(1:ndim, i)
         p%xb(:, m) = p%x(:, m)
         p%kind(m) = kind_fixed
         p%body(m) = size(c%objs) + size(c%bodies) + k
         p%nrm(:, m) = ns(1:ndim, i)
         p%nb(:, m) = p%nrm(:, m)
         p%surf(m) = surf(i)
         if (surf(i) > 0) then
            out = xs(:, i) + dp*ns(:, i)
            if (solid_covers(c%objs, 0, zdom, out(1:nsec), out(3)) .or. mesh_holding(c%meshes(1:k - 1), out, 0) > 0) p%surf(m) = 0
         end if
      end do points
   end subroutine add_mesh_solid

   !> No body starts inside an &stl solid (bodies may touch walls, not cut into
   !> them), nor a moving wall or a filter: a mesh leaves out the points another
   !> solid holds, so a wall that moves off them, or a filter (which carries no
   !> water), would leave a hole in it. None of their particles lies inside a
   !> mesh at the start (a wall's later motion is not checked).
   subroutine bodies_clear_of_meshes(c, p)
      type(case_cfg), intent(in) :: c
      type(particles_t), intent(in) :: p
      integer :: i, k, b, nobj
      real(rp) :: x(3)
      if (size(c%meshes) == 0) return
      nobj = size(c%objs)
      particles: do i = 1, p%n
         b = p%body(i)
         if (b < 1 .or. b > nobj + size(c%bodies)) cycle particles    ! water, and the meshes' own particles
         if (b <= nobj .and. p%kind(i) /= kind_moving .and. p%kind(i) /= kind_filter) cycle particles
         x = 0.0_rp
         x(1:ndim) = p%x(:, i)
         k = mesh_holding(c%meshes, x, 0)
         if (k == 0) cycle particles
         if (b > nobj) call input_error(c%file, 'body #'//int_str(b - nobj), '', &
            'the body overlaps the solid &stl #'//int_str(k)//' (bodies may touch walls, not cut into them)')
         call input_error(c%file, trim(c%objs(b)%group)//' #'//int_str(c%objs(b)%index), '', 'the '// &
            trim(merge('moving wall', 'filter     ', p%kind(i) == kind_moving))//' overlaps the solid &stl #'// &
            int_str(k)//' (the mesh leaves out the points it holds: a hole where it moves off or lets water '// &
            'through); keep it clear of the mesh')
      end do particles
   end subroutine bodies_clear_of_meshes

   !> Inside a body, or closer to its outline than half a spacing dp (in 3D:
   !> and within its extent across the width, grown by as much); or among
   !> stones, whose water add_pore_water places.
   logical function in_hole(pt, holes, por, dp)
      real(rp), intent(in) :: pt(ndim), dp
      type(outline_t), intent(in) :: holes(:)
      type(porous_t), intent(in) :: por
      in_hole = in_pores(por, pt(1:nsec))
      if (.not. in_hole) in_hole = in_body_hole(pt, holes, dp)
   end function in_hole

   !> Inside a body, or closer to its outline than half a spacing dp (in 3D:
   !> and within its extent across the width, grown by as much).
   logical function in_body_hole(pt, holes, dp) result(inside)
      real(rp), intent(in) :: pt(ndim), dp
      type(outline_t), intent(in) :: holes(:)
      integer :: h
      real(rp) :: own(3), q(3), nq(3)
      inside = .false.
      do h = 1, size(holes)
         if (ndim == 3) then
            if (pt(ndim) < holes(h)%zr(1) - 0.499_rp*dp .or. pt(ndim) > holes(h)%zr(2) + 0.499_rp*dp) cycle
            if (holes(h)%stl) then
               ! inside the mesh or within 0.499 dp of it
               own = matmul(pad(pt) - holes(h)%c, holes(h)%turn)
               if (.not. inside .and. norm2(own) < holes(h)%rmax + 0.5_rp*dp) then
                  call stl_nearest(holes(h)%mesh, own, q, nq)
                  inside = stl_inside(holes(h)%mesh, own) .or. norm2(q - own) < 0.499_rp*dp
               end if
               cycle
            end if
            if (holes(h)%box) then
               ! within 0.499 dp of the turned box
               inside = inside .or. norm2(max(abs(matmul(pad(pt) - holes(h)%c, holes(h)%turn)) - holes(h)%half, &
                                                0.0_rp)) < 0.499_rp*dp
               cycle
            end if
         end if
         inside = inside .or. point_in_polygon(pt(1:nsec), holes(h)%v) .or. &
                   distance_to_polygon(pt(1:nsec), holes(h)%v) < 0.499_rp*dp
      end do
   contains
      !> A point of ndim components as three.
      pure function pad(x) result(y)
         real(rp), intent(in) :: x(ndim)
         real(rp) :: y(3)
         y = 0.0_rp
         y(1:ndim) = x
      end function pad
   end function in_body_hole

   !> Water in the pores: where a porous region covers a fluid object, a
   !> lattice of spacing about dp/n^(1/d). The lattice is fitted to the box the
   !> two outlines share (a whole number of rows and columns, half a spacing in
   !> from its sides; in 3D as many layers across the object's width, which
   !> they tile), so that the water in the pores starts level with the open
   !> water beside it. cell(k) is the space particle k fills on its lattice
   !> (sx sy sz here, dp^d for every particle made before), from which
   !> scene_build gives it the mass of the pores' water in that space.
   subroutine add_pore_water(c, dp, zdom, p, holes, por, cell)
      type(case_cfg), intent(in) :: c
      real(rp), intent(in) :: dp, zdom(2)
      type(particles_t), intent(inout) :: p
      type(outline_t), intent(in) :: holes(:)
      type(porous_t), intent(in) :: por
      real(rp), allocatable, intent(out) :: cell(:)
      integer :: r, o, i, j, l, nx, ny, nz, k, n0
      real(rp) :: s, lo(2), hi(2), sx, sy, sz, pt(2), ps(ndim), z(2), space
      real(rp), allocatable :: grown(:)
      cell = [(dp**ndim, k = 1, p%n)]
      if (.not. por%on) return
      regions: do r = 1, size(por%r)
         if (por%r(r)%n >= 1.0_rp) cycle regions
         ! each particle fills dp^d / n (in 3D the regions are prisms across the width)
         s = dp/sqrt(por%r(r)%n)
         if (ndim == 3) s = dp/por%r(r)%n**(1.0_rp/3.0_rp)
         objects: do o = 1, size(c%objs)
            if (c%objs(o)%role_id /= role_fluid) cycle objects
            lo = max(minval(por%r(r)%v, dim=2), minval(c%objs(o)%v, dim=2))
            hi = min(maxval(por%r(r)%v, dim=2), maxval(c%objs(o)%v, dim=2))
            if (any(hi <= lo)) cycle objects
            nx = max(1, nint((hi(1) - lo(1))/s))
            ny = max(1, nint((hi(2) - lo(2))/s))
            sx = (hi(1) - lo(1))/nx
            sy = (hi(2) - lo(2))/ny
            ! layers across fitted to the object's width (in 2D one, at the section)
            nz = layers_across(c%objs(o), zdom, s, z)
            sz = (z(2) - z(1))/nz
            call particles_grow(p, nx*ny*nz)
            n0 = p%n
            across: do l = 1, nz
               ! in 2D the section's point below overwrites this
               ps(ndim) = z(1) + (l - 0.5_rp)*sz
               do j = 1, ny
                  points: do i = 1, nx
                     pt = [lo(1) + (i - 0.5_rp)*sx, lo(2) + (j - 0.5_rp)*sy]
                     ps(1:nsec) = pt
                     if (.not. pore_free(c, por, holes, dp, zdom, ps, r, o)) cycle points
                     p%n = p%n + 1
                     k = p%n
                     p%x(:, k) = ps
                     p%xb(:, k) = ps
                     p%kind(k) = kind_fluid
                     p%body(k) = 0
                     p%nrm(:, k) = 0.0_rp
                     p%surf(k) = 0
                     p%nb(:, k) = 0.0_rp
                  end do points
               end do
            end do across
            space = sx*sy
            if (ndim == 3) space = space*sz
            grown = [cell, (space, k = n0 + 1, p%n)]
            call move_alloc(grown, cell)
         end do objects
      end do regions
   end subroutine add_pore_water

   !> A point of the pore water's lattice of region r and fluid object o that is
   !> not already water of an earlier object or region, nor in a body or closer
   !> to it than half a spacing.
   logical function pore_free(c, por, holes, dp, zdom, ps, r, o) result(free)
      type(case_cfg), intent(in) :: c
      type(porous_t), intent(in) :: por
      type(outline_t), intent(in) :: holes(:)
      real(rp), intent(in) :: dp, zdom(2), ps(ndim)
      integer, intent(in) :: r, o
      integer :: k
      real(rp) :: pt(2), z(2)
      pt = ps(1:nsec)
      free = point_in_polygon(pt, por%r(r)%v) .and. point_in_polygon(pt, c%objs(o)%v)
      do k = 1, o - 1
         if (c%objs(k)%role_id /= role_fluid) cycle
         if (ndim == 3) then
            ! an earlier fluid object holds this point only within its own width
            z = geom_zrange(c%objs(k), zdom)
            if (ps(ndim) < z(1) .or. ps(ndim) > z(2)) cycle
         end if
         free = free .and. .not. point_in_polygon(pt, c%objs(k)%v)
      end do
      do k = 1, r - 1
         if (por%r(k)%n < 1.0_rp) free = free .and. .not. point_in_polygon(pt, por%r(k)%v)
      end do
      if (free) free = .not. in_body_hole(ps, holes, dp)
   end function pore_free

   !> Inside a porous region (of porosity below 1), whose water add_pore_water places.
   pure logical function in_pores(por, pt)
      type(porous_t), intent(in) :: por
      real(rp), intent(in) :: pt(2)
      integer :: r
      in_pores = .false.
      if (.not. por%on) return
      do r = 1, size(por%r)
         if (por%r(r)%n < 1.0_rp .and. point_in_polygon(pt, por%r(r)%v)) in_pores = .true.
      end do
   end function in_pores

   !> The motion of each geometry object of the case (bc_motion): fixed, an
   !> oscillation, or the paddle's law with the bottom of its face as hinge.
   function scene_walls(c) result(m)
      type(case_cfg), intent(in) :: c
      type(wall_motion_t), allocatable :: m(:)
      integer :: k, ist
      character(len=200) :: emsg
      allocate (m(size(c%objs)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'm in scene_walls')
      do k = 1, size(c%objs)
         associate (o => c%objs(k))
            m(k) = wall_motion_t(o%motion_id, o%amplitude, o%period, [o%box(2), o%box(3)], o%hinge_depth)
         end associate
      end do
   end function scene_walls

   !> The porous regions of the case (module porous).
   function scene_porous(c) result(por)
      type(case_cfg), intent(in) :: c
      type(porous_t) :: por
      integer :: k, ist
      character(len=200) :: emsg
      por%on = size(c%porous) > 0
      allocate (por%r(size(c%porous)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'por%r in scene_porous')
      do k = 1, size(c%porous)
         associate (r => por%r(k), q => c%porous(k))
            r%v = q%v
            r%n = q%porosity
            r%d50 = q%d50
            r%alpha = q%alpha
            r%beta = q%beta
            r%gamma = q%gamma
            r%nu = q%nu
            r%width = q%width
            r%bb = [minval(q%v(1, :)) - 0.5_rp*q%width, maxval(q%v(1, :)) + 0.5_rp*q%width, &
                    minval(q%v(2, :)) - 0.5_rp*q%width, maxval(q%v(2, :)) + 0.5_rp*q%width]
         end associate
      end do
      call porous_lookup(por, c%numerics%h_over_dp*c%numerics%dp)
   end function scene_porous

   !> Rows of particles parallel to the slope line, below it (a filter: one
   !> row), each ending at the slope's mitres; in 3D repeated across the
   !> object's width (zdom: the domain's, for a slope without its own).
   subroutine add_slope(o, obj, dp, zdom, p, earlier)
      type(geom_object), intent(in) :: o, earlier(:)
      integer, intent(in) :: obj
      real(rp), intent(in) :: dp, zdom(2)
      type(particles_t), intent(inout) :: p
      real(rp) :: a(2), b(2), t(2), nrm(2), len, ds, ps(ndim), z(2), d, s0
      integer :: i, l, ns, k, nz, m
      a = o%line(1:2)
      b = o%line(3:4)
      len = norm2(b - a)
      t = (b - a)/len
      nrm = [-t(2), t(1)]
      nz = layers_across(o, zdom, dp, z)
      call particles_grow(p, (nint(len/dp) + 2*o%layers)*o%layers*nz)
      do m = 1, nz
         ps(ndim) = z(1) + (m - 0.5_rp)*dp         ! in 2D the section's point below overwrites it
         do l = 1, o%layers
            ! each row from mitre to mitre (geom_join_slopes), at the spacing nearest dp
            d = (l - 0.5_rp)*dp
            s0 = -d*tan(o%mitre(1))
            ns = max(1, nint((len + d*tan(o%mitre(2)) - s0)/dp))
            ds = (len + d*tan(o%mitre(2)) - s0)/ns
            along: do i = 1, ns
               ps(1:nsec) = a + (s0 + (i - 0.5_rp)*ds)*t - d*nrm
               if (solid_covers(earlier, 0, zdom, ps(1:nsec), ps(ndim))) cycle along
               p%n = p%n + 1
               k = p%n
               p%x(:, k) = ps
               p%xb(:, k) = ps
               p%kind(k) = merge(kind_filter, kind_fixed, o%role_id == role_filter)
               p%body(k) = obj
               p%nrm(:, k) = 0.0_rp
               p%nrm(1:nsec, k) = nrm
               p%nb(:, k) = p%nrm(:, k)
               p%surf(k) = merge(1, 0, l == 1)
            end do along
         end do
      end do
   end subroutine add_slope

   !> The lattice layers across the object's width z (its own, or the domain's
   !> zdom) at spacing dp: 1 in 2D.
   integer function layers_across(o, zdom, s, z) result(nz)
      type(geom_object), intent(in) :: o
      real(rp), intent(in) :: zdom(2), s   !< s: the lattice's spacing
      real(rp), intent(out) :: z(2)
      z = geom_zrange(o, zdom)
      nz = 1
      if (ndim == 3) nz = max(1, nint((z(2) - z(1))/s))
   end function layers_across


   !> Whether a solid of objs other than objs(skip) holds the point q of the
   !> section at zq across the width (3D; its z range counts, zdom for an
   !> object without its own). Solids may overlap (a slope resting on a floor,
   !> boxes sharing a corner): where they do, the earlier object keeps its
   !> particles and the later one leaves the shared area empty, so no two wall
   !> particles sit together; and a solid's side or end face with another
   !> solid just beyond it is no surface.
   logical function solid_covers(objs, skip, zdom, q, zq) result(inside)
      type(geom_object), intent(in) :: objs(:)
      integer, intent(in) :: skip
      real(rp), intent(in) :: zdom(2), q(nsec), zq
      integer :: e
      real(rp) :: z(2)
      inside = .false.
      do e = 1, size(objs)
         if (e == skip .or. objs(e)%role_id /= role_solid) cycle
         if (ndim == 3) then
            z = geom_zrange(objs(e), zdom)
            if (zq < z(1) .or. zq > z(2)) cycle
         end if
         if (point_in_polygon(q, objs(e)%v)) then
            inside = .true.
            return
         end if
      end do
   end function solid_covers

   !> The run's constants from the case: ybed and ytop bound the fluid (its
   !> lowest and highest particle edges); they fix h_swl when the input leaves it at 0.
   subroutine scene_params(c, ybed, ytop, prm)
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
      prm%slip = c%numerics%slip_id
      prm%shift = c%numerics%shift_id
      prm%shift_coef = c%numerics%shift_coef
      prm%shift_tfs = c%numerics%shift_tfs
      prm%porous = size(c%porous) > 0
      prm%rep_a = (10.0_rp/c%fluid%coef)**2*0.01_rp*prm%c0**2/prm%h
      prm%rep_b = (10.0_rp/c%fluid%coef)*prm%c0/prm%h
      prm%rep_u = 40.0_rp/prm%c0
      prm%rep_rhswl = 1.0_rp/prm%h_swl
   end subroutine scene_params

   !> The case's gauges: kind and position of each.
   subroutine scene_gauges(c, gt)
      type(case_cfg), intent(in) :: c
      type(gauges_t), intent(out) :: gt
      call gauges_init(gt, c%gauges%kind_id, c%gauges%x, c%gauges%y, c%gauges%z)
   end subroutine scene_gauges

   !> The case's absorbing zone (off when it has none).
   pure function scene_damping(c) result(d)
      type(case_cfg), intent(in) :: c
      type(damping_t) :: d
      d = damping_t(c%damping%on, c%damping%x0, c%damping%x1, c%damping%strength)
   end function scene_damping

   !> The case's contact model and coefficients (B of &contact, or &fluid's
   !> coef when it is left at 0).
   pure function scene_contact(c) result(cs)
      type(case_cfg), intent(in) :: c
      type(contact_settings_t) :: cs
      cs%model = c%contact%model_id
      cs%b = c%contact%b
      if (cs%b <= 0.0_rp) cs%b = c%fluid%coef
      cs%c0 = c%contact%c0
      cs%r_f = c%contact%r_f
      cs%q0 = c%contact%q0
      cs%barrier = c%contact%barrier
      cs%stick_velocity = c%contact%stick_velocity
      cs%stick_length = c%contact%stick_length
      cs%impact = c%contact%impact
      cs%core = c%contact%core
   end function scene_contact

   !> The course of the run the case asks for (energy rows every dt_out when
   !> energy_interval is left at 0).
   pure function scene_run(c) result(rc)
      type(case_cfg), intent(in) :: c
      type(run_ctl_t) :: rc
      rc%t_end = c%run%t_end
      rc%max_steps = c%run%max_steps
      rc%dt_out = c%run%dt_out
      rc%energy_interval = c%run%energy_interval
      if (rc%energy_interval <= 0.0_rp) rc%energy_interval = c%run%dt_out
      rc%gauge_interval = c%run%gauge_interval
      rc%progress_interval = c%run%progress_interval
      rc%checkpoint_every = c%run%checkpoint_every
      rc%balance_every = c%run%balance_every
      rc%max_lost_fraction = c%run%max_lost_fraction
      rc%restart = c%run%restart
      rc%box(1:4) = [c%domain%xmin, c%domain%xmax, c%domain%ymin, c%domain%ymax]
      if (ndim == 3) rc%box(2*ndim - 1:2*ndim) = [c%domain%zmin, c%domain%zmax]
      rc%periodic_z = c%domain%periodic_z
   end function scene_run
end module scene

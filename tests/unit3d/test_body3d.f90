!> A box body in 3D (body_shapes built with ndim = 3: make unit-3d) against what
!> it must be: its mass is density times volume; its inertia tensor, turned by
!> the start angle about z, equals the sum m (|r|^2 I - r r^T) over a fine lattice
!> of point masses filling the turned box; its particles lie inside the box,
!> the outer layer within half a spacing of a face, with unit normals pointing
!> out of the box; the shell is the layers asked for, no deeper.
program test_body3d
   use kinds, only: rp
   use constants, only: ndim, pi
   use rigid, only: nrot
   use input_body, only: body_cfg
   use options, only: shape_box
   use body_shapes, only: body_mass_properties, body_particles
   use testing, only: check, check_close, test_summary
   implicit none
   type(body_cfg) :: c
   real(rp) :: mass, cen(ndim), inertia(nrot, nrot), ref(3, 3), r(3), dm, side(3), rot(3, 3), a, q(3)
   real(rp), allocatable :: xb(:, :), nb(:, :)
   integer, allocatable :: surf(:)
   integer :: i, j, k, n, m, nout, nbad_in, nbad_n, nbad_face, deepest
   real(rp), parameter :: dp = 0.01_rp

   call check(ndim == 3 .and. nrot == 3, 'a 3D build (ndim = 3, nrot = 3)')
   c%shape_id = shape_box
   c%x = 0.4_rp; c%y = 0.2_rp; c%z = 0.15_rp
   c%width = 0.12_rp; c%height = 0.08_rp; c%depth = 0.1_rp
   c%angle = 30.0_rp
   c%density = 2400.0_rp
   side = [c%width, c%height, c%depth]
   call body_mass_properties(c, mass, cen, inertia)
   call check_close(mass, 2400.0_rp*product(side), 1.0e-14_rp, 'mass = density x volume')
   call check(all(abs(cen - [c%x, c%y, c%z]) < 1.0e-15_rp), 'centre at (x, y, z)')

   ! the inertia tensor of point masses on a fine lattice filling the turned box
   a = c%angle*pi/180.0_rp
   rot = reshape([cos(a), sin(a), 0.0_rp, -sin(a), cos(a), 0.0_rp, 0.0_rp, 0.0_rp, 1.0_rp], [3, 3])
   n = 60
   dm = mass/n**3
   ref = 0.0_rp
   do k = 1, n
      do j = 1, n
         do i = 1, n
            r = matmul(rot, -0.5_rp*side + ([i, j, k] - 0.5_rp)*side/n)
            ref = ref - dm*spread(r, 2, 3)*spread(r, 1, 3)
            do m = 1, 3
               ref(m, m) = ref(m, m) + dm*dot_product(r, r)
            end do
         end do
      end do
   end do
   ! the midpoint lattice misses the second moment of each cell, (side/n)^2/12 of it: 3e-4 relative at n = 60
   call check(maxval(abs(inertia - ref)) <= 5.0e-4_rp*maxval(abs(ref)), 'inertia tensor = point-mass sum (turned box)')
   call check(abs(inertia(1, 2) - inertia(2, 1)) <= 1.0e-15_rp*maxval(abs(inertia)) .and. &
              abs(inertia(1, 2)) > 1.0e-3_rp*inertia(1, 1), 'inertia: symmetric, coupled in x-y by the turn')

   ! the particles: two layers in from every face
   call body_particles(c, dp, 2, xb, nb, surf)
   nout = 0; nbad_in = 0; nbad_n = 0; nbad_face = 0; deepest = 0
   do m = 1, size(xb, 2)
      q = matmul(transpose(rot), xb(:, m))              ! in the box's own frame
      if (any(abs(q) > 0.5_rp*side)) nbad_in = nbad_in + 1
      if (abs(norm2(nb(:, m)) - 1.0_rp) > 1.0e-12_rp .or. dot_product(nb(:, m), xb(:, m)) <= 0.0_rp) nbad_n = nbad_n + 1
      if (surf(m) > 0) then
         nout = nout + 1
         if (minval(0.5_rp*side - abs(q)) > 0.5_rp*dp + 1.0e-12_rp) nbad_face = nbad_face + 1
      end if
      ! how many spacings in from the nearest face
      deepest = max(deepest, nint(minval(0.5_rp*side - abs(q))/dp + 0.5_rp))
   end do
   call check(nbad_in == 0, 'every particle inside the box')
   call check(nbad_n == 0, 'unit normals pointing out of the box')
   call check(nbad_face == 0, 'the outer layer within dp/2 of a face')
   call check(deepest == 2, 'the shell is two layers deep')
   ! the outer layer of a 12 x 8 x 10 lattice: all of it less the 10 x 6 x 8 inside
   call check(nout == 12*8*10 - 10*6*8, 'the outer layer holds every surface point of the lattice')
   call check(size(xb, 2) == 12*8*10 - 8*4*6, 'two layers: all of the lattice less the 8 x 4 x 6 core')
   call test_summary('test_body3d')
end program test_body3d

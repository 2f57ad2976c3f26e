!> &stl, repeatable (3D): a fixed solid from a closed triangle mesh (a
!> structure, a bed or a crown wall drawn in CAD), read from an STL file.
!> The mesh is scaled by stl_scale and moved by (x, y, z); its particles are
!> the points of the case's lattice (dp apart, half a spacing off whole
!> spacings from the origin, as boxes with edges at whole spacings have)
!> inside the mesh and less than layers spacings from its surface (scene).
module input_mesh
   use kinds, only: rp
   use constants, only: msg_len, path_len, ndim
   use input_check, only: case_path, open_case, read_failed_open, check_int, check_real, group_count, int_str, real_str
   use geom_stl, only: stl_t, stl_read, stl_bounds, stl_inside
   use errors, only: input_error, alloc_check
   implicit none
   private
   public :: mesh_cfg, read_meshes, write_meshes, mesh_layers, mesh_lattice, mesh_holding

   type :: mesh_cfg
      character(len=path_len) :: file = ''   !< the STL file, as given (relative: from the case file's folder)
      real(rp) :: scale = 1.0_rp             !< the file's unit in metres
      real(rp) :: shift(3) = 0.0_rp          !< where the file's origin goes [m]
      integer :: layers = 0                  !< rows of particles in from the surface; 0: enough for 2h
      type(stl_t) :: mesh                    !< in the case's frame: scaled and moved
      real(rp) :: lo(3) = 0.0_rp, hi(3) = 0.0_rp   !< the mesh's bounding box [m]
   end type mesh_cfg

   real(rp) :: x, y, z, stl_scale
   character(len=path_len) :: stl_file
   integer :: layers
   namelist /stl/ stl_file, stl_scale, x, y, z, layers

contains

   subroutine defaults()
      type(mesh_cfg) :: d
      stl_file = d%file; stl_scale = d%scale; x = d%shift(1); y = d%shift(2); z = d%shift(3); layers = d%layers
   end subroutine defaults

   !> Every &stl group, checked: the file a closed mesh (geom_stl), at least
   !> 2 dp across and holding a point of the lattice.
   subroutine read_meshes(file, dp, meshes)
      character(len=*), intent(in) :: file
      real(rp), intent(in) :: dp
      type(mesh_cfg), allocatable, intent(out) :: meshes(:)
      integer :: n, k, u, ios, ist, t, v
      character(len=msg_len) :: msg
      character(len=200) :: emsg
      character(len=:), allocatable :: g, path
      n = group_count(file, 'stl')
      allocate (meshes(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'meshes in read_meshes')
      if (n == 0) return
      u = open_case(file)
      do k = 1, n
         call defaults()
         read (u, nml=stl, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'stl', ios, msg)) return
         g = 'stl #'//int_str(k)
         if (ndim == 2) call input_error(file, g, 'stl_file', 'an STL solid is for the 3D build (build/mbsph3d); '// &
                                         'in 2D a solid is a &box, &polygon or &slope')
         if (len_trim(stl_file) == 0) call input_error(file, g, 'stl_file', "required: the mesh's file")
         call check_real(file, g, 'stl_scale', stl_scale, 1.0e-9_rp, 1.0e9_rp)
         call check_int(file, g, 'layers', layers, 0, 100)
         if (max(abs(x), abs(y), abs(z)) > 1.0e6_rp) call input_error(file, g, 'x, y, z', &
            'a shift beyond 1000 km ('//real_str(max(abs(x), abs(y), abs(z)))//' m) is not meant')
         meshes(k)%file = stl_file
         meshes(k)%scale = stl_scale
         meshes(k)%shift = [x, y, z]
         meshes(k)%layers = layers
         path = case_path(file, stl_file)
         if (len(path) > len(stl_file)) call input_error(file, g, 'stl_file', 'the path '//path//' is longer than '// &
                                                          int_str(len(stl_file))//' characters')
         meshes(k)%file = path
         call stl_read(path, stl_scale, file, g, 'stl_file', meshes(k)%mesh)
         associate (m => meshes(k)%mesh)
            do t = 1, m%nt
               do v = 1, 3
                  m%v(:, v, t) = m%v(:, v, t) + meshes(k)%shift
               end do
            end do
            call stl_bounds(m, meshes(k)%lo, meshes(k)%hi)
            if (minval(meshes(k)%hi - meshes(k)%lo) < 2.0_rp*dp) call input_error(file, g, 'stl_file', &
               "the mesh of '"//path//"' is "//real_str(minval(meshes(k)%hi - meshes(k)%lo))// &
               ' m across at its thinnest: at least 2 dp = '//real_str(2.0_rp*dp)//' m is needed (stl_scale: '// &
               'its unit in metres)')
            call check_flat_faces(file, g, meshes(k), dp)
            if (.not. lattice_meets(meshes(k), dp)) call input_error(file, g, 'stl_file', 'no point of the '// &
               "lattice dp apart falls inside the mesh of '"//path//"': it is too thin for dp = "//real_str(dp)//' m')
         end associate
      end do
      close (u)
   end subroutine read_meshes

   subroutine write_meshes(u, meshes)
      integer, intent(in) :: u
      type(mesh_cfg), intent(in) :: meshes(:)
      integer :: k
      do k = 1, size(meshes)
         stl_file = meshes(k)%file; stl_scale = meshes(k)%scale
         x = meshes(k)%shift(1); y = meshes(k)%shift(2); z = meshes(k)%shift(3); layers = meshes(k)%layers
         write (u, nml=stl)
      end do
   end subroutine write_meshes

   !> The rows of particles of mesh m: its own layers, or enough for the
   !> kernel's support 2h (h_over_dp: h/dp), as a body's.
   pure integer function mesh_layers(m, h_over_dp) result(n)
      type(mesh_cfg), intent(in) :: m
      real(rp), intent(in) :: h_over_dp
      n = m%layers
      if (n == 0) n = max(1, ceiling(2.0_rp*h_over_dp - 1.0e-9_rp))
   end function mesh_layers

   !> The case's lattice points over the mesh's bounding box, x0 + (i - 1/2) dp
   !> for i = 1 .. nn along each axis.
   pure subroutine mesh_lattice(m, dp, x0, nn)
      type(mesh_cfg), intent(in) :: m
      real(rp), intent(in) :: dp
      real(rp), intent(out) :: x0(3)
      integer, intent(out) :: nn(3)
      integer :: i0(3)
      i0 = ceiling(m%lo/dp - 0.5_rp)
      x0 = i0*dp
      nn = max(0, floor(m%hi/dp - 0.5_rp) - i0 + 1)
   end subroutine mesh_lattice

   !> A face across an axis (its three vertices at one coordinate) must not lie
   !> on, or within 0.1 dp of, a plane of lattice points (half a spacing off
   !> whole spacings): a row of wall particles on the face (or nearly) would have
   !> no mirror across it (or one nearly at itself).
   subroutine check_flat_faces(file, g, m, dp)
      character(len=*), intent(in) :: file, g
      type(mesh_cfg), intent(in) :: m
      real(rp), intent(in) :: dp
      character(len=1), parameter :: axis(3) = ['x', 'y', 'z']
      integer :: t, a
      real(rp) :: c, off
      do t = 1, m%mesh%nt
         axes: do a = 1, 3
            c = m%mesh%v(a, 1, t)
            if (maxval(abs(m%mesh%v(a, 2:3, t) - c)) > 1.0e-9_rp*dp) cycle axes
            off = c/dp - 0.5_rp
            if (abs(off - anint(off)) >= 0.1_rp) cycle axes
            call input_error(file, g, 'x, y, z', 'a flat face of the mesh lies at '//axis(a)//' = '//real_str(c)// &
               ', on (within 0.1 dp of) a plane of the lattice (whose points are half a spacing off whole spacings of dp = '// &
               real_str(dp)//' m): its wall particles would sit on the face; move the mesh by dp/2 along '// &
               axis(a)//' (x, y, z) or draw its faces at whole spacings')
         end do axes
      end do
   end subroutine check_flat_faces

   !> The first of the meshes, skip left out, whose mesh holds the point x; 0 for none.
   integer function mesh_holding(meshes, x, skip) result(k)
      type(mesh_cfg), intent(in) :: meshes(:)
      real(rp), intent(in) :: x(3)
      integer, intent(in) :: skip
      do k = 1, size(meshes)
         if (k == skip) cycle
         if (any(x < meshes(k)%lo) .or. any(x > meshes(k)%hi)) cycle
         if (stl_inside(meshes(k)%mesh, x)) return
      end do
      k = 0
   end function mesh_holding

   logical function lattice_meets(m, dp) result(meets)
      type(mesh_cfg), intent(in) :: m
      real(rp), intent(in) :: dp
      real(rp) :: x0(3)
      integer :: nn(3), i, j, k
      call mesh_lattice(m, dp, x0, nn)
      meets = .true.
      do k = 1, nn(3)
         do j = 1, nn(2)
            do i = 1, nn(1)
               if (stl_inside(m%mesh, x0 + ([i, j, k] - 0.5_rp)*dp)) return
            end do
         end do
      end do
      meets = .false.
   end function lattice_meets
end module input_mesh

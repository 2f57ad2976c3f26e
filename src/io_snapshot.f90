!> Particle snapshots (HDF5) and the XDMF index that lets ParaView open the
!> whole series. Each rank writes its particles in id order at its offset
!> of every dataset, rank after rank: on one rank the file is in global id
!> order; on several, readers order by the /id dataset (post/io.py does).
module io_snapshot
   use kinds, only: rp
   use constants, only: msg_len, ndim, nsec
   use particles, only: particles_t, particles_field, field_on, fields, nfield
   use params, only: params_t
   use io_hdf5, only: hid_t, h5_create, h5_open_read, h5_close, h5_write, h5_write_part, h5_attr_write, &
                      h5_attr_read, h5_length, file_rename
   use comm, only: comm_rank, comm_exscan, comm_sum
   use io_files, only: snap_name, file_exists
   use errors, only: fatal, alloc_check
   use body_dynamics, only: body_t
   use rigid, only: rigid_rotation, rigid_rotate, rigid_pose_pack, npose
   use porous, only: porous_t, porous_point, n_por
   implicit none
   private
   public :: snap_index_t, snapshot_write, snapshot_index_rebuild

   !> What the XDMF index of a run lists: the time and particle count of each
   !> snapshot, and whether they hold the porosity (a run with porous regions)
   !> and the ghost offsets (a run with the modified dynamic boundary).
   type :: snap_index_t
      logical :: porosity = .false.
      logical :: ghost = .false.
      integer :: nlist = 0
      real(rp), allocatable :: list_t(:)
      integer, allocatable :: list_n(:)
   end type snap_index_t

contains

   !> Snapshot number k at time t.
   subroutine snapshot_write(ix, out_dir, k, p, prm, t, dt, istep, case_text, bodies, por)
      type(snap_index_t), intent(inout) :: ix
      character(len=*), intent(in) :: out_dir
      integer, intent(in) :: k, istep
      type(particles_t), target, intent(inout) :: p
      type(params_t), intent(in) :: prm
      real(rp), intent(in) :: t, dt
      character(len=*), intent(in) :: case_text
      type(body_t), intent(in) :: bodies(:)
      type(porous_t), intent(in) :: por
      integer(hid_t) :: f
      real(rp), allocatable :: pn(:)
      real(rp) :: fp(n_por)
      integer, allocatable :: ord(:), conn(:)
      real(rp), pointer :: r(:, :)
      integer, pointer :: iv(:)
      integer :: i, n, off, tot(1), m
      integer :: ist
      character(len=200) :: emsg
      n = p%n_own
      allocate (ord(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'ord in snapshot_write')
      call order_by_id(p%id(1:n), ord)
      off = comm_exscan(n)
      tot = n
      call comm_sum(tot)
      f = h5_create(snap_name(out_dir, k))
      ! the fields the table names for the snapshot, in the order of the ids
      do m = 1, nfield
         if (len_trim(fields(m)%snap) == 0 .or. .not. field_on(p, m)) cycle
         call particles_field(p, m, r, iv)
         if (fields(m)%int) then
            call h5_write_part(f, trim(fields(m)%snap), iv(ord), off, tot(1))
         else if (fields(m)%ncomp == 1) then
            call h5_write_part(f, trim(fields(m)%snap), r(1, ord), off, tot(1))
         else
            call h5_write_part(f, trim(fields(m)%snap), r(:, ord), off, tot(1))
         end if
      end do
      ix%ghost = p%mdbc
      ! the porosity where each particle is (doc/porous.md), for ParaView
      ix%porosity = por%on
      if (por%on) then
         allocate (pn(n), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'pn in snapshot_write')
         do i = 1, n
            fp = porous_point(por, p%x(:, ord(i)))
            pn(i) = fp(1)
         end do
         call h5_write_part(f, 'porosity', pn, off, tot(1))
         deallocate (pn)
      end if
      ! after the order is freed: the snapshot's peak memory is one gathered field
      deallocate (ord)
      allocate (conn(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'conn in snapshot_write')
      do i = 1, n
         conn(i) = off + i - 1
      end do
      call h5_write_part(f, 'connectivity', conn, off, tot(1))
      call h5_attr_write(f, 'time', t)
      call h5_attr_write(f, 'dt', dt)
      call h5_attr_write(f, 'step', istep)
      call h5_attr_write(f, 'n_particles', tot(1))
      call h5_attr_write(f, 'dp', prm%dp)
      call h5_attr_write(f, 'h', prm%h)
      call h5_attr_write(f, 'rho0', prm%rho0)
      call h5_attr_write(f, 'c0', prm%c0)
      call h5_attr_write(f, 'gravity', prm%g)
      call h5_attr_write(f, 'case_name', trim(prm%case_name))
      call h5_attr_write(f, 'case_nml', case_text)
      if (size(bodies) > 0) call write_outlines(f, bodies)
      call h5_close(f)
      call list_set(ix, k, t, tot(1))
      if (comm_rank() == 0) call xdmf_write(ix, out_dir)
   end subroutine snapshot_write

   !> The permutation that sorts ids ascending (a bottom-up merge sort).
   subroutine order_by_id(id, ord)
      integer, intent(in) :: id(:)
      integer, intent(out) :: ord(:)
      integer, allocatable :: tmp(:)
      integer :: n, w, lo, mid, hi, i, j, k
      integer :: ist
      character(len=200) :: emsg
      n = size(id)
      allocate (tmp(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'tmp in order_by_id')
      do i = 1, n
         ord(i) = i
      end do
      w = 1
      do while (w < n)
         lo = 1
         do while (lo <= n)
            mid = min(lo + w - 1, n)
            hi = min(lo + 2*w - 1, n)
            i = lo; j = mid + 1; k = lo
            do while (k <= hi)
               if (j > hi) then
                  tmp(k) = ord(i); i = i + 1
               else if (i > mid) then
                  tmp(k) = ord(j); j = j + 1
               else if (id(ord(j)) < id(ord(i))) then
                  tmp(k) = ord(j); j = j + 1
               else
                  tmp(k) = ord(i); i = i + 1
               end if
               k = k + 1
            end do
            lo = lo + 2*w
         end do
         ord = tmp
         w = 2*w
      end do
   end subroutine order_by_id

   !> Body outlines at their current pose: /body_outline (vertices of all
   !> bodies one after the other), /body_outline_start (0-based offset of each
   !> body, and the total at the end), /body_pose (x, y, angle per body).
   subroutine write_outlines(f, bodies)
      integer(hid_t), intent(in) :: f
      type(body_t), intent(in) :: bodies(:)
      integer :: b, k, m, nv
      integer, allocatable :: start(:)
      real(rp), allocatable :: xy(:, :), pose(:, :)
      real(rp) :: rot(ndim, ndim), r(ndim)
      integer :: ist
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (start(size(bodies) + 1), pose(npose, size(bodies)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'start, pose in write_outlines')
      start(1) = 0
      do b = 1, size(bodies)
         start(b + 1) = start(b) + size(bodies(b)%outline, 2)
      end do
      ! the outline of the section (in 3D at the body's centre across the width)
      allocate (xy(ndim, start(size(bodies) + 1)), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'xy in write_outlines')
      m = 0
      do b = 1, size(bodies)
         rot = rigid_rotation(bodies(b)%pose, bodies(b)%pose_start)
         nv = size(bodies(b)%outline, 2)
         do k = 1, nv
            m = m + 1
            r = 0.0_rp
            r(1:nsec) = bodies(b)%outline(:, k)
            xy(:, m) = bodies(b)%pose%c + rigid_rotate(rot, r)
         end do
         pose(:, b) = rigid_pose_pack(bodies(b)%pose)
      end do
      call h5_write(f, 'body_outline', xy)
      call h5_write(f, 'body_outline_start', start)
      call h5_write(f, 'body_pose', pose)
   end subroutine write_outlines

   subroutine list_set(ix, k, t, n)
      type(snap_index_t), intent(inout) :: ix
      integer, intent(in) :: k, n
      real(rp), intent(in) :: t
      real(rp), allocatable :: tt(:)
      integer, allocatable :: nn(:)
      integer :: ist
      character(len=200) :: emsg
      if (.not. allocated(ix%list_t)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (ix%list_t(64), ix%list_n(64), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'ix%list_t, ix%list_n in list_set')
      end if
      if (k + 1 > size(ix%list_t)) then
         ! allow(multiple-allocations-with-stat): any of them refused is the same stop
         allocate (tt(2*(k + 1)), nn(2*(k + 1)), stat=ist, errmsg=emsg)
         call alloc_check(ist, emsg, 'tt, nn in list_set')
         tt(1:ix%nlist) = ix%list_t(1:ix%nlist)
         nn(1:ix%nlist) = ix%list_n(1:ix%nlist)
         call move_alloc(tt, ix%list_t)
         call move_alloc(nn, ix%list_n)
      end if
      ix%list_t(k + 1) = t
      ix%list_n(k + 1) = n
      ix%nlist = k + 1
   end subroutine list_set

   !> After a restart: list the snapshots 0 .. nsnap-1 already on disk (rank 0
   !> writes the index).
   subroutine snapshot_index_rebuild(ix, out_dir, nsnap)
      type(snap_index_t), intent(inout) :: ix
      character(len=*), intent(in) :: out_dir
      integer, intent(in) :: nsnap
      integer :: k, n
      integer(hid_t) :: f
      real(rp) :: t
      ix%nlist = 0
      if (comm_rank() /= 0) return
      do k = 0, nsnap - 1
         if (.not. file_exists(snap_name(out_dir, k))) call fatal('restart: '//snap_name(out_dir, k)// &
                                                                  ' is missing from the run being continued')
         f = h5_open_read(snap_name(out_dir, k))
         call h5_attr_read(f, 'time', t)
         n = h5_length(f, 'density')
         call h5_close(f)
         call list_set(ix, k, t, n)
      end do
   end subroutine snapshot_index_rebuild

   !> particles.xmf: a temporal collection of polyvertex grids. Written to a
   !> temporary file and renamed, so a reader never sees half a file.
   subroutine xdmf_write(ix, out_dir)
      type(snap_index_t), intent(in) :: ix
      character(len=*), intent(in) :: out_dir
      integer :: u, k, ios
      character(len=msg_len) :: msg
      character(len=:), allocatable :: path, snap
      character(len=24) :: ns
      character(len=3) :: nd
      character(len=:), allocatable :: geo
      ! the vectors have ndim components: XY in 2D, XYZ in 3D
      write (nd, '(1x,i0)') ndim
      geo = 'XYZ'
      geo = geo(1:ndim)
      path = trim(out_dir)//'/particles.xmf'
      open (newunit=u, file=path//'.tmp', status='replace', action='write', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal('cannot write '//path//'.tmp: '//trim(msg))
      write (u, '(a)') '<?xml version="1.0" ?>'
      write (u, '(a)') '<Xdmf Version="3.0">'
      write (u, '(a)') ' <Domain>'
      write (u, '(a)') '  <Grid Name="particles" GridType="Collection" CollectionType="Temporal">'
      do k = 0, ix%nlist - 1
         snap = snap_name('', k)
         snap = snap(2:)                              ! relative to the .xmf file
         write (ns, '(i0)') ix%list_n(k + 1)
         write (u, '(a)') '   <Grid Name="'//snap(1:len(snap) - 3)//'" GridType="Uniform">'
         write (u, '(a,es24.16e3,a)') '    <Time Value="', ix%list_t(k + 1), '"/>'
         write (u, '(a)') '    <Topology TopologyType="Polyvertex" NumberOfElements="'//trim(ns)// &
            '" NodesPerElement="1">'
         call item(u, ns, '', 'Int', '4', snap, 'connectivity')
         write (u, '(a)') '    </Topology>'
         write (u, '(a)') '    <Geometry GeometryType="'//geo//'">'
         call item(u, ns, trim(nd), 'Float', '8', snap, 'position')
         write (u, '(a)') '    </Geometry>'
         call attribute(u, 'velocity', 'Vector', ns, trim(nd), 'Float', '8', snap)
         call attribute(u, 'density', 'Scalar', ns, '', 'Float', '8', snap)
         call attribute(u, 'pressure', 'Scalar', ns, '', 'Float', '8', snap)
         call attribute(u, 'kind', 'Scalar', ns, '', 'Int', '4', snap)
         call attribute(u, 'body', 'Scalar', ns, '', 'Int', '4', snap)
         call attribute(u, 'id', 'Scalar', ns, '', 'Int', '4', snap)
         if (ix%porosity) call attribute(u, 'porosity', 'Scalar', ns, '', 'Float', '8', snap)
         if (ix%ghost) call attribute(u, 'ghost', 'Vector', ns, trim(nd), 'Float', '8', snap)
         write (u, '(a)') '   </Grid>'
      end do
      write (u, '(a)') '  </Grid>'
      write (u, '(a)') ' </Domain>'
      write (u, '(a)') '</Xdmf>'
      close (u)
      call file_rename(path//'.tmp', path)
   end subroutine xdmf_write

   subroutine item(u, ns, dim2, ntype, prec, snap, name)
      integer, intent(in) :: u
      character(len=*), intent(in) :: ns, dim2, ntype, prec, snap, name
      write (u, '(a)') '     <DataItem Dimensions="'//trim(ns)//dim2//'" NumberType="'//ntype// &
         '" Precision="'//prec//'" Format="HDF">'//snap//':/'//name//'</DataItem>'
   end subroutine item

   subroutine attribute(u, name, atype, ns, dim2, ntype, prec, snap)
      integer, intent(in) :: u
      character(len=*), intent(in) :: name, atype, ns, dim2, ntype, prec, snap
      write (u, '(a)') '    <Attribute Name="'//name//'" AttributeType="'//atype//'" Center="Node">'
      call item(u, ns, dim2, ntype, prec, snap, name)
      write (u, '(a)') '    </Attribute>'
   end subroutine attribute
end module io_snapshot

!> Thin helpers over the HDF5 Fortran API: whole-array datasets and scalar
!> attributes, with every error turned into a fatal message naming the file.
!> On several ranks a file is created by all of them together (parallel
!> HDF5, the MPI-IO driver): h5_write_part writes each rank's particles at
!> its offset of one dataset, h5_write a small array rank 0 holds like the
!> others, and attributes are written by all ranks with the same values.
!> Files are read by each rank on its own.
module io_hdf5
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_long
   use kinds, only: rp
   use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5close_f, h5fcreate_f, h5fopen_f, h5fclose_f, &
                   h5screate_simple_f, h5screate_f, h5sclose_f, h5dcreate_f, h5dopen_f, h5dclose_f, &
                   h5dwrite_f, h5dread_f, h5dget_space_f, h5sget_simple_extent_dims_f, h5acreate_f, &
                   h5aopen_f, h5aclose_f, h5awrite_f, h5aread_f, h5tcopy_f, h5tset_size_f, h5tclose_f, &
                   h5aexists_f, H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, H5S_SCALAR_F, H5T_NATIVE_DOUBLE, &
                   H5T_NATIVE_INTEGER, H5T_FORTRAN_S1, h5pcreate_f, h5pclose_f, h5pset_fapl_mpio_f, &
                   h5pset_dxpl_mpio_f, h5sselect_hyperslab_f, h5sselect_none_f, h5lexists_f, H5P_FILE_ACCESS_F, &
                   H5P_DATASET_XFER_F, H5FD_MPIO_COLLECTIVE_F, H5S_SELECT_SET_F, H5P_DEFAULT_F, h5eset_auto_f
   use errors, only: fatal
   use comm, only: comm_size, comm_rank, comm_handle, comm_info_handle
   implicit none
   private
   public :: hid_t, h5_start, h5_stop, h5_create, h5_open_read, h5_close, h5_write, h5_read, &
             h5_attr_write, h5_attr_read, h5_attr_exists, h5_length, h5_exists, h5_write_part, file_rename

   integer, parameter :: statvfs_spare = 6   !< the ints that end struct statvfs

   !> struct statvfs of Linux x86-64: eleven 8-byte fields, then six ints
   type, bind(c) :: statvfs_t
      integer(c_long) :: bsize = 0, frsize = 0, blocks = 0, bfree = 0, bavail = 0, files = 0, ffree = 0, &
                         favail = 0, fsid = 0, flag = 0, namemax = 0
      integer(c_int) :: spare(statvfs_spare) = 0
   end type statvfs_t

   interface h5_write
      module procedure write_r2, write_i1
   end interface h5_write
   interface h5_read
      module procedure read_r1, read_r2, read_i1
   end interface h5_read
   !> This rank's part of a dataset that all ranks write together
   interface h5_write_part
      module procedure part_r1, part_r2, part_i1
   end interface h5_write_part
   interface h5_attr_write
      module procedure attr_write_r, attr_write_i, attr_write_s
   end interface h5_attr_write
   interface h5_attr_read
      module procedure attr_read_r, attr_read_i
   end interface h5_attr_read

   interface
      function c_rename(old, new) bind(C, name='rename') result(r)
         import :: c_int, c_char
         implicit none
         ! allow(assumed-size): the standard interoperable form of the char * arguments of C rename
         character(kind=c_char), intent(in) :: old(*), new(*)
         integer(c_int) :: r
      end function c_rename
      function c_open(path, flags) bind(C, name='open') result(fd)
         import :: c_int, c_char
         implicit none
         ! allow(assumed-size): the char * of C open
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value :: flags
         integer(c_int) :: fd
      end function c_open
      function c_fsync(fd) bind(C, name='fsync') result(r)
         import :: c_int
         implicit none
         integer(c_int), value :: fd
         integer(c_int) :: r
      end function c_fsync
      function c_close(fd) bind(C, name='close') result(r)
         import :: c_int
         implicit none
         integer(c_int), value :: fd
         integer(c_int) :: r
      end function c_close
      function c_statvfs(path, buf) bind(C, name='statvfs') result(r)
         import :: c_int, c_char, statvfs_t
         implicit none
         ! allow(assumed-size): the char * of C statvfs
         character(kind=c_char), intent(in) :: path(*)
         type(statvfs_t), intent(out) :: buf
         integer(c_int) :: r
      end function c_statvfs
      function c_unlink(path) bind(C, name='unlink') result(r)
         import :: c_int, c_char
         implicit none
         ! allow(assumed-size): the char * of C unlink
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int) :: r
      end function c_unlink
   end interface

   character(len=:), allocatable :: current   ! file being written, for messages
   logical :: writing = .false.               ! current is being written (not read)
   character(len=:), allocatable :: last_whole   ! the last file written and closed whole
   integer(hid_t) :: xfer = 0                 ! transfer properties of the writes

contains

   subroutine check(err, what)
      integer, intent(in) :: err
      character(len=*), intent(in) :: what
      if (err >= 0) return
      if (writing) call write_failed(what)
      call fatal('HDF5: '//what//' failed for '//current)
   end subroutine check

   !> A file being written could not be: one line naming it and the cause (a
   !> full disk said as such), the partial file removed, and the files that
   !> are whole named. The exit skips the library's own exit handlers, which
   !> would touch the broken file again (a segmentation fault after the message).
   subroutine write_failed(what)
      character(len=*), intent(in) :: what
      character(len=:), allocatable :: dir, msg
      type(statvfs_t) :: sv
      integer :: k
      integer(c_int) :: rc
      logical :: ckpt
      k = index(current, '/', back=.true.)
      dir = '.'
      if (k > 1) dir = current(1:k - 1)
      msg = 'cannot write '//current//' (HDF5: '//what//' failed)'
      if (c_statvfs(dir//c_null_char, sv) == 0) then
         ! a few blocks left count as full: HDF5 writes in larger pieces
         if (real(sv%bavail, rp)*real(sv%frsize, rp) < 1.0e6_rp) msg = 'cannot write '//current// &
            ': no space left on device ('//dir//')'
      end if
      rc = c_unlink(current//c_null_char)
      if (rc == 0) msg = msg//'; the partial file is removed'
      if (allocated(last_whole)) msg = msg//'; the last file written whole is '//last_whole
      inquire (file=dir//'/checkpoint.h5', exist=ckpt)
      if (ckpt) msg = msg//'; '//dir//'/checkpoint.h5 is whole (replaced only by renaming a finished file)'
      call fatal(msg, hard=.true.)
   end subroutine write_failed

   subroutine h5_start()
      integer :: err
      call h5open_f(err)
      if (err < 0) call fatal('HDF5: cannot initialise the library')
      ! errors are reported by check, in one line: not the library's stack of forty
      call h5eset_auto_f(0, err)
      xfer = H5P_DEFAULT_F
      if (comm_size() > 1) then
         call h5pcreate_f(H5P_DATASET_XFER_F, xfer, err)
         call h5pset_dxpl_mpio_f(xfer, H5FD_MPIO_COLLECTIVE_F, err)
         if (err < 0) call fatal('HDF5: no collective MPI-IO transfers (is this HDF5 built for MPI?)')
      end if
   end subroutine h5_start

   subroutine h5_stop()
      integer :: err
      if (comm_size() > 1) call h5pclose_f(xfer, err)
      call h5close_f(err)
   end subroutine h5_stop

   !> Rename a file (atomic on one file system).
   !> Rename old to new, old first forced to the disk (fsync) and the rename
   !> after it: a crash of the machine leaves the old file or the whole new one
   !> under the name, never a new name over data still in the page cache.
   subroutine file_rename(old, new)
      character(len=*), intent(in) :: old, new
      integer :: k
      call file_sync(old)
      if (c_rename(trim(old)//c_null_char, trim(new)//c_null_char) /= 0) then
         call fatal('cannot rename '//trim(old)//' to '//trim(new))
      end if
      ! the folder holds the name: its entry to the disk too
      k = index(trim(new), '/', back=.true.)
      if (k > 1) call file_sync(new(1:k - 1))
   end subroutine file_rename

   !> fsync(2) of a file or folder (read-only open); a failure is not fatal:
   !> the data are written, only their durability in a machine crash is weaker.
   subroutine file_sync(path)
      character(len=*), intent(in) :: path
      integer(c_int) :: fd, rc
      integer(c_int), parameter :: o_rdonly = 0
      fd = c_open(trim(path)//c_null_char, o_rdonly)
      if (fd < 0) return
      rc = c_fsync(fd)
      rc = c_close(fd)
   end subroutine file_sync

   !> A new file; on several ranks every rank calls this, together.
   integer(hid_t) function h5_create(path) result(f)
      character(len=*), intent(in) :: path
      integer :: err
      integer(hid_t) :: fapl
      current = trim(path)
      writing = .true.
      if (comm_size() > 1) then
         call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
         call h5pset_fapl_mpio_f(fapl, comm_handle(), comm_info_handle(), err)
         call check(err, 'MPI-IO access')
         call h5fcreate_f(trim(path), H5F_ACC_TRUNC_F, f, err, access_prp=fapl)
         call h5pclose_f(fapl, err)
      else
         call h5fcreate_f(trim(path), H5F_ACC_TRUNC_F, f, err)
      end if
      call check(err, 'create')
   end function h5_create

   !> Whether a dataset of that name exists.
   logical function h5_exists(f, name) result(yes)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer :: err
      call h5lexists_f(f, name, yes, err)
      if (err < 0) yes = .false.
   end function h5_exists

   !> Whether the file carries the attribute name.
   logical function h5_attr_exists(f, name) result(yes)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer :: err
      call h5aexists_f(f, name, yes, err)
      if (err < 0) yes = .false.
   end function h5_attr_exists

   !> Dataset of total elements along the last dimension (rows values each,
   !> rows = 0 for a one-dimensional one); this rank's n from offset.
   !> Returns the dataset, the file and memory selections.
   subroutine part_open(f, name, htype, rows, n, offset, total, d, fs, ms)
      integer(hid_t), intent(in) :: f, htype
      character(len=*), intent(in) :: name
      integer, intent(in) :: rows, n, offset, total
      integer(hid_t), intent(out) :: d, fs, ms
      integer(hsize_t) :: dims(2), start(2), cnt(2)
      integer :: err, r
      r = merge(1, 2, rows == 0)
      if (r == 1) then
         dims(1) = int(total, hsize_t)
         start(1) = int(offset, hsize_t)
         cnt(1) = int(max(n, 1), hsize_t)
      else
         dims = [int(rows, hsize_t), int(total, hsize_t)]
         start = [0_hsize_t, int(offset, hsize_t)]
         cnt = [int(rows, hsize_t), int(max(n, 1), hsize_t)]
      end if
      call h5screate_simple_f(r, dims(1:r), fs, err); call check(err, 'dataspace '//name)
      call h5dcreate_f(f, name, htype, fs, d, err); call check(err, 'dataset '//name)
      call h5screate_simple_f(r, cnt(1:r), ms, err); call check(err, 'memory space '//name)
      if (n > 0) then
         call h5sselect_hyperslab_f(fs, H5S_SELECT_SET_F, start(1:r), cnt(1:r), err)
         call check(err, 'select '//name)
      else
         call h5sselect_none_f(fs, err)
         call h5sselect_none_f(ms, err)
      end if
   end subroutine part_open

   subroutine part_close(d, fs, ms)
      integer(hid_t), intent(in) :: d, fs, ms
      integer :: err
      call h5sclose_f(ms, err)
      call h5sclose_f(fs, err)
      call h5dclose_f(d, err)
   end subroutine part_close

   subroutine part_r1(f, name, a, offset, total)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(in) :: a(:)
      integer, intent(in) :: offset, total
      integer(hid_t) :: d, fs, ms
      integer(hsize_t) :: dims(1)
      integer :: err
      real(rp) :: none(1)
      call part_open(f, name, H5T_NATIVE_DOUBLE, 0, size(a), offset, total, d, fs, ms)
      dims = max(shape(a, kind=hsize_t), 1_hsize_t)
      if (size(a) > 0) then
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, a, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      else
         none = 0.0_rp
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, none, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      end if
      call check(err, 'write '//name)
      call part_close(d, fs, ms)
   end subroutine part_r1

   subroutine part_r2(f, name, a, offset, total)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(in) :: a(:, :)
      integer, intent(in) :: offset, total
      integer(hid_t) :: d, fs, ms
      integer(hsize_t) :: dims(2)
      integer :: err
      real(rp) :: none(size(a, 1), 1)
      call part_open(f, name, H5T_NATIVE_DOUBLE, size(a, 1), size(a, 2), offset, total, d, fs, ms)
      dims = max(shape(a, kind=hsize_t), 1_hsize_t)
      if (size(a) > 0) then
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, a, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      else
         none = 0.0_rp
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, none, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      end if
      call check(err, 'write '//name)
      call part_close(d, fs, ms)
   end subroutine part_r2

   subroutine part_i1(f, name, a, offset, total)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer, intent(in) :: a(:)
      integer, intent(in) :: offset, total
      integer(hid_t) :: d, fs, ms
      integer(hsize_t) :: dims(1)
      integer :: err
      integer :: none(1)
      call part_open(f, name, H5T_NATIVE_INTEGER, 0, size(a), offset, total, d, fs, ms)
      dims = max(shape(a, kind=hsize_t), 1_hsize_t)
      if (size(a) > 0) then
         call h5dwrite_f(d, H5T_NATIVE_INTEGER, a, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      else
         none = 0
         call h5dwrite_f(d, H5T_NATIVE_INTEGER, none, dims, err, mem_space_id=ms, file_space_id=fs, xfer_prp=xfer)
      end if
      call check(err, 'write '//name)
      call part_close(d, fs, ms)
   end subroutine part_i1

   integer(hid_t) function h5_open_read(path) result(f)
      character(len=*), intent(in) :: path
      integer :: err
      logical :: exists
      current = trim(path)
      writing = .false.
      inquire (file=trim(path), exist=exists)
      if (.not. exists) call fatal('file not found: '//trim(path))
      call h5fopen_f(trim(path), H5F_ACC_RDONLY_F, f, err)
      call check(err, 'open')
   end function h5_open_read

   subroutine h5_close(f)
      integer(hid_t), intent(in) :: f
      integer :: err
      call h5fclose_f(f, err)
      call check(err, 'close')
      if (writing) last_whole = current
      writing = .false.
   end subroutine h5_close

   subroutine write_r2(f, name, a)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(in) :: a(:, :)
      integer(hid_t) :: s, d
      integer(hsize_t) :: dims(2)
      integer :: err
      dims = shape(a, kind=hsize_t)
      call h5screate_simple_f(2, dims, s, err); call check(err, 'dataspace '//name)
      call h5dcreate_f(f, name, H5T_NATIVE_DOUBLE, s, d, err); call check(err, 'dataset '//name)
      if (comm_size() > 1) then
         ! one writer: every rank holds the same array
         if (comm_rank() /= 0) call h5sselect_none_f(s, err)
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, a, dims, err, file_space_id=s, mem_space_id=s, xfer_prp=xfer)
      else
         call h5dwrite_f(d, H5T_NATIVE_DOUBLE, a, dims, err)
      end if
      call check(err, 'write '//name)
      call h5dclose_f(d, err)
      call h5sclose_f(s, err)
   end subroutine write_r2

   subroutine write_i1(f, name, a)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer, intent(in) :: a(:)
      integer(hid_t) :: s, d
      integer(hsize_t) :: dims(1)
      integer :: err
      dims = shape(a, kind=hsize_t)
      call h5screate_simple_f(1, dims, s, err); call check(err, 'dataspace '//name)
      call h5dcreate_f(f, name, H5T_NATIVE_INTEGER, s, d, err); call check(err, 'dataset '//name)
      if (comm_size() > 1) then
         ! one writer: every rank holds the same array
         if (comm_rank() /= 0) call h5sselect_none_f(s, err)
         call h5dwrite_f(d, H5T_NATIVE_INTEGER, a, dims, err, file_space_id=s, mem_space_id=s, xfer_prp=xfer)
      else
         call h5dwrite_f(d, H5T_NATIVE_INTEGER, a, dims, err)
      end if
      call check(err, 'write '//name)
      call h5dclose_f(d, err)
      call h5sclose_f(s, err)
   end subroutine write_i1

   !> Number of elements along the last dimension of a dataset.
   integer function h5_length(f, name) result(n)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer(hid_t) :: d, s
      integer(hsize_t) :: dims(2), maxdims(2)
      integer :: err, rank
      call h5dopen_f(f, name, d, err); call check(err, 'open dataset '//name)
      call h5dget_space_f(d, s, err)
      dims = 0
      call h5sget_simple_extent_dims_f(s, dims, maxdims, rank)
      if (rank < 1) call fatal('HDF5: cannot read the size of '//name//' in '//current)
      n = int(dims(rank))
      call h5sclose_f(s, err)
      call h5dclose_f(d, err)
   end function h5_length

   subroutine read_r1(f, name, a)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(out) :: a(:)
      integer(hid_t) :: d
      integer(hsize_t) :: dims(1)
      integer :: err
      dims = shape(a, kind=hsize_t)
      call h5dopen_f(f, name, d, err); call check(err, 'open dataset '//name)
      call h5dread_f(d, H5T_NATIVE_DOUBLE, a, dims, err); call check(err, 'read '//name)
      call h5dclose_f(d, err)
   end subroutine read_r1

   subroutine read_r2(f, name, a)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(out) :: a(:, :)
      integer(hid_t) :: d
      integer(hsize_t) :: dims(2)
      integer :: err
      dims = shape(a, kind=hsize_t)
      call h5dopen_f(f, name, d, err); call check(err, 'open dataset '//name)
      call h5dread_f(d, H5T_NATIVE_DOUBLE, a, dims, err); call check(err, 'read '//name)
      call h5dclose_f(d, err)
   end subroutine read_r2

   subroutine read_i1(f, name, a)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer, intent(out) :: a(:)
      integer(hid_t) :: d
      integer(hsize_t) :: dims(1)
      integer :: err
      dims = shape(a, kind=hsize_t)
      call h5dopen_f(f, name, d, err); call check(err, 'open dataset '//name)
      call h5dread_f(d, H5T_NATIVE_INTEGER, a, dims, err); call check(err, 'read '//name)
      call h5dclose_f(d, err)
   end subroutine read_i1

   subroutine attr_write_r(f, name, x)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(in) :: x
      integer(hid_t) :: s, a
      integer :: err
      integer(hsize_t), parameter :: one(1) = 1
      call h5screate_f(H5S_SCALAR_F, s, err)
      call h5acreate_f(f, name, H5T_NATIVE_DOUBLE, s, a, err); call check(err, 'attribute '//name)
      call h5awrite_f(a, H5T_NATIVE_DOUBLE, x, one, err); call check(err, 'write attribute '//name)
      call h5aclose_f(a, err)
      call h5sclose_f(s, err)
   end subroutine attr_write_r

   subroutine attr_write_i(f, name, x)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer, intent(in) :: x
      integer(hid_t) :: s, a
      integer :: err
      integer(hsize_t), parameter :: one(1) = 1
      call h5screate_f(H5S_SCALAR_F, s, err)
      call h5acreate_f(f, name, H5T_NATIVE_INTEGER, s, a, err); call check(err, 'attribute '//name)
      call h5awrite_f(a, H5T_NATIVE_INTEGER, x, one, err); call check(err, 'write attribute '//name)
      call h5aclose_f(a, err)
      call h5sclose_f(s, err)
   end subroutine attr_write_i

   subroutine attr_write_s(f, name, x)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      character(len=*), intent(in) :: x
      integer(hid_t) :: s, a, t
      integer :: err
      integer(hsize_t), parameter :: one(1) = 1
      call h5tcopy_f(H5T_FORTRAN_S1, t, err)
      call h5tset_size_f(t, int(max(len(x), 1), size_t), err)
      call h5screate_f(H5S_SCALAR_F, s, err)
      call h5acreate_f(f, name, t, s, a, err); call check(err, 'attribute '//name)
      call h5awrite_f(a, t, x, one, err); call check(err, 'write attribute '//name)
      call h5aclose_f(a, err)
      call h5sclose_f(s, err)
      call h5tclose_f(t, err)
   end subroutine attr_write_s

   subroutine attr_read_r(f, name, x)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      real(rp), intent(out) :: x
      integer(hid_t) :: a
      integer :: err
      logical :: exists
      integer(hsize_t), parameter :: one(1) = 1
      call h5aexists_f(f, name, exists, err)
      if (.not. exists) call fatal('HDF5: attribute '//name//' missing in '//current)
      call h5aopen_f(f, name, a, err); call check(err, 'open attribute '//name)
      call h5aread_f(a, H5T_NATIVE_DOUBLE, x, one, err); call check(err, 'read attribute '//name)
      call h5aclose_f(a, err)
   end subroutine attr_read_r

   subroutine attr_read_i(f, name, x)
      integer(hid_t), intent(in) :: f
      character(len=*), intent(in) :: name
      integer, intent(out) :: x
      integer(hid_t) :: a
      integer :: err
      logical :: exists
      integer(hsize_t), parameter :: one(1) = 1
      call h5aexists_f(f, name, exists, err)
      if (.not. exists) call fatal('HDF5: attribute '//name//' missing in '//current)
      call h5aopen_f(f, name, a, err); call check(err, 'open attribute '//name)
      call h5aread_f(a, H5T_NATIVE_INTEGER, x, one, err); call check(err, 'read attribute '//name)
      call h5aclose_f(a, err)
   end subroutine attr_read_i
end module io_hdf5

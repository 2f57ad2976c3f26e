!> Helpers shared by the input_* readers: open a case file, find unknown or
!> misspelt groups, turn namelist read errors into messages that name the
!> file, group and variable, and check values against their allowed range.
module input_check
   use, intrinsic :: iso_c_binding, only: c_char, c_size_t, c_ptr, c_null_char, c_associated
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use kinds, only: rp
   use constants, only: msg_len
   use errors, only: input_error, fatal
   use input_syntax, only: lower, syntax_check, syntax_scan, assign_t, is_name
   use geom, only: polygon_area, polygon_self_intersects
   implicit none
   private
   public :: case_path, open_case, scan_groups, group_count, var_given, read_failed, read_failed_open, check_real, check_int, &
             checked_outline, &
             lower, real_str, int_str, approx_str

   character(len=*), parameter :: known_groups(*) = [character(len=16) :: &
      'run', 'domain', 'fluid', 'numerics', 'box', 'polygon', 'slope', 'stl', 'body', 'contact', 'wavemaker', &
      'gauge', 'damping', 'breakwater', 'armour', 'porous']

contains

   !> The file a case names (an STL mesh), as an absolute path: a relative path
   !> is taken from the case file's folder, and made absolute from the working
   !> directory, so that the effective namelist (OUT/case.nml) names the same
   !> file wherever it is run from (relative as given if the working directory
   !> cannot be read).
   function case_path(file, name) result(path)
      character(len=*), intent(in) :: file, name
      character(len=:), allocatable :: path
      integer, parameter :: cwd_len = 4096     ! PATH_MAX of Linux
      interface
         function c_getcwd(buf, size) bind(C, name='getcwd') result(res)
            import :: c_char, c_size_t, c_ptr, cwd_len
            implicit none
            character(kind=c_char), intent(out) :: buf(cwd_len)
            integer(c_size_t), value :: size
            type(c_ptr) :: res
         end function c_getcwd
      end interface
      character(kind=c_char) :: buf(cwd_len)
      integer :: slash, n
      path = trim(name)
      if (len(path) == 0) return
      if (path(1:1) == '/') return
      slash = index(file, '/', back=.true.)
      if (slash > 0) path = file(1:slash)//path
      if (path(1:1) == '/') return
      if (.not. c_associated(c_getcwd(buf, int(size(buf), c_size_t)))) return
      n = 0
      do while (n < size(buf))
         if (buf(n + 1) == c_null_char) exit
         n = n + 1
      end do
      if (n == 0 .or. n == size(buf)) return
      block
         character(len=n) :: cwd
         integer :: i
         do i = 1, n
            cwd(i:i) = buf(i)
         end do
         path = cwd//'/'//path
      end block
   end function case_path

   function real_str(x) result(s)
      real(rp), intent(in) :: x
      character(len=:), allocatable :: s
      character(len=32) :: b
      write (b, '(g0.6)') x
      s = trim(adjustl(b))
   end function real_str

   !> A large or rough figure with three digits: 6.91e+07, 32.6, 0.230.
   function approx_str(x) result(s)
      real(rp), intent(in) :: x
      character(len=:), allocatable :: s
      character(len=32) :: b
      if (abs(x) >= 1.0e4_rp) then
         write (b, '(es10.2e2)') x
      else
         write (b, '(g0.3)') x
      end if
      s = trim(adjustl(b))
      if (s(1:1) == '.') s = '0'//s
   end function approx_str

   function int_str(i) result(s)
      integer, intent(in) :: i
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i0)') i
      s = trim(b)
   end function int_str

   !> Open a case file for reading; stop with a clear message if it is missing.
   integer function open_case(file) result(u)
      character(len=*), intent(in) :: file
      integer :: ios
      character(len=msg_len) :: msg
      open (newunit=u, file=file, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) call fatal(trim(file)//': cannot open the case file: '//trim(msg), 2)
   end function open_case

   !> Check that every namelist group in the file is one we know, so that a
   !> misspelt group is reported instead of silently skipped.
   subroutine scan_groups(file)
      character(len=*), intent(in) :: file
      integer :: u, ios, line, i, j, k
      character(len=4096) :: buf
      character(len=64) :: name
      logical :: in_str
      character :: q
      character(len=msg_len) :: msg
      u = open_case(file)
      line = 0
      do
         read (u, '(a)', iostat=ios, iomsg=msg) buf
         if (ios /= 0) exit
         line = line + 1
         in_str = .false.
         q = ' '
         i = 1
         chars: do while (i <= len_trim(buf))
            if (.not. in_str .and. buf(i:i) == '!') exit chars
            if (in_str) then
               if (buf(i:i) == q) in_str = .false.
            else if (buf(i:i) == '"' .or. buf(i:i) == "'") then
               in_str = .true.
               q = buf(i:i)
            else if (buf(i:i) == '&' .or. buf(i:i) == '$') then
               j = i + 1
               k = j
               name_end: do while (k <= len_trim(buf))
                  if (verify(buf(k:k), 'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') /= 0) exit name_end
                  k = k + 1
               end do name_end
               name = lower(buf(j:k - 1))
               if (len_trim(name) > 0 .and. trim(name) /= 'end') then
                  if (.not. any(known_groups == name)) then
                     close (u)
                     call fatal(trim(file)//': line '//int_str(line)//': unknown namelist group &'// &
                                trim(name)//suggestion(name)//'; known groups: '//group_list(), 2)
                  end if
               end if
               i = k
               cycle chars
            end if
            i = i + 1
         end do chars
      end do
      close (u)
      call syntax_check(file)
   end subroutine scan_groups

   function group_list() result(s)
      character(len=:), allocatable :: s
      integer :: i
      s = ''
      do i = 1, size(known_groups)
         s = s//'&'//trim(known_groups(i))
         if (i < size(known_groups)) s = s//' '
      end do
   end function group_list

   !> ' (did you mean &x?)' for the known group closest in spelling.
   function suggestion(name) result(s)
      character(len=*), intent(in) :: name
      character(len=:), allocatable :: s
      integer :: i, d, best, bi
      best = huge(1)
      bi = 0
      do i = 1, size(known_groups)
         d = edit_distance(trim(name), trim(known_groups(i)))
         if (d < best) then
            best = d
            bi = i
         end if
      end do
      if (bi > 0 .and. best <= 3) then
         s = ' (did you mean &'//trim(known_groups(bi))//'?)'
      else
         s = ''
      end if
   end function suggestion

   pure integer function edit_distance(a, b) result(d)
      character(len=*), intent(in) :: a, b
      integer :: t(0:len(a), 0:len(b)), i, j, c
      do i = 0, len(a)
         t(i, 0) = i
      end do
      do j = 0, len(b)
         t(0, j) = j
      end do
      do j = 1, len(b)
         do i = 1, len(a)
            c = merge(0, 1, a(i:i) == b(j:j))
            t(i, j) = min(t(i - 1, j) + 1, t(i, j - 1) + 1, t(i - 1, j - 1) + c)
         end do
      end do
      d = t(len(a), len(b))
   end function edit_distance

   !> How many times a group appears in the file (case-insensitive).
   integer function group_count(file, group) result(n)
      character(len=*), intent(in) :: file, group
      integer :: u, ios, i, k
      character(len=4096) :: buf
      character(len=4096) :: low
      character(len=msg_len) :: msg
      u = open_case(file)
      n = 0
      do
         read (u, '(a)', iostat=ios, iomsg=msg) buf
         if (ios /= 0) exit
         low = lower(buf)
         k = index(low, '!')
         if (k > 0) low(k:) = ' '
         i = 1
         matches: do
            k = index(low(i:), '&'//trim(group))
            if (k == 0) exit matches
            i = i + k - 1 + len_trim(group) + 1
            if (i > len(low)) then
               n = n + 1
               exit matches
            end if
            if (verify(low(i:i), 'abcdefghijklmnopqrstuvwxyz0123456789_') /= 0) n = n + 1
         end do matches
      end do
      close (u)
   end function group_count

   !> read_failed for a group read from an open unit: the unit is closed first
   !> when the read failed (the report reopens the file).
   logical function read_failed_open(u, file, group, ios, msg) result(failed)
      integer, intent(in) :: u, ios
      character(len=*), intent(in) :: file, group, msg
      if (ios > 0) close (u)
      failed = read_failed(file, group, ios, msg)
   end function read_failed_open

   !> Report a failed namelist read. Returns .false. at a clean end of file.
   logical function read_failed(file, group, ios, msg) result(failed)
      character(len=*), intent(in) :: file, group, msg
      integer, intent(in) :: ios
      integer :: k
      character(len=msg_len) :: tok, var, val
      failed = .false.
      if (ios == 0) return
      if (is_iostat_end(ios)) return
      failed = .true.
      k = index(msg, 'Cannot match namelist object name')
      if (k > 0) then
         ! the reader also lands here when a value cannot be read: it takes
         ! the unreadable text for the next variable name
         tok = adjustl(msg(k + 33:))
         ! the reader runs on into the next group's name: '.5&domain'
         if (scan(trim(tok), '&$/') > 1) tok = tok(1:scan(trim(tok), '&$/') - 1)
         if (.not. is_name(trim(tok))) then
            ! the tail of a value the variable's type cannot take: 2.5 read
            ! as the whole number 2, then '.5' as a name
            call value_of(file, group, trim(tok), var, val)
            if (len_trim(var) > 0) call input_error(file, group, trim(var), 'cannot read the value '//trim(val)// &
                                                    " as this variable's type (see doc/input.md: a whole number, "// &
                                                    'a real, a quoted string or .true./.false.)')
         end if
         var = variable_before(file, trim(tok))
         if (len_trim(var) > 0) then
            call input_error(file, group, trim(var), 'cannot read the value '//trim(tok)// &
                             ' (a number, a quoted string or .true./.false. is expected)')
         end if
         call input_error(file, group, trim(tok), &
                          'unknown variable in this group (see doc/input.md for the variables of &'//trim(group)//')')
      else
         call input_error(file, group, '', 'cannot read the group: '//trim(msg))
      end if
   end function read_failed

   !> Whether the case file assigns variable var (lower case) in a group of that name.
   logical function var_given(file, group, var) result(given)
      character(len=*), intent(in) :: file, group, var
      type(assign_t), allocatable :: a(:)
      character(len=msg_len) :: err
      call syntax_scan(file, a, err)
      given = any(a%group == lower(group) .and. a%var == var)
   end function var_given

   !> The variable of group whose value (as written) ends with the text tok,
   !> and that value; blank when there is none.
   subroutine value_of(file, group, tok, var, val)
      character(len=*), intent(in) :: file, group, tok
      character(len=msg_len), intent(out) :: var, val
      type(assign_t), allocatable :: a(:)
      character(len=msg_len) :: err
      integer :: i, m
      var = ''
      val = ''
      call syntax_scan(file, a, err)
      do i = 1, size(a)
         if (a(i)%group /= lower(group)) cycle
         m = len_trim(a(i)%text)
         if (m < len(tok)) cycle
         if (lower(a(i)%text(m - len(tok) + 1:m)) /= lower(tok)) cycle
         var = a(i)%var
         val = a(i)%text
         return
      end do
   end subroutine value_of

   !> Name of the variable whose value is the text tok ('name = tok' in the
   !> file, case-insensitive), or blank when tok is not such a value.
   function variable_before(file, tok) result(var)
      character(len=*), intent(in) :: file, tok
      character(len=msg_len) :: var
      character(len=4096) :: buf, low
      character(len=msg_len) :: msg
      integer :: u, ios, k, e, b
      var = ''
      if (len_trim(tok) == 0) return
      u = open_case(file)
      lines: do
         read (u, '(a)', iostat=ios, iomsg=msg) buf
         if (ios /= 0) exit lines
         low = lower(buf)
         k = index(low, lower(trim(tok)))
         if (k <= 1) cycle lines
         e = len_trim(low(1:k - 1))
         if (e < 1) cycle lines
         if (low(e:e) /= '=') cycle lines
         e = len_trim(low(1:e - 1))
         b = e
         name_start: do while (b > 1)
            if (verify(low(b - 1:b - 1), 'abcdefghijklmnopqrstuvwxyz0123456789_') /= 0) exit name_start
            b = b - 1
         end do name_start
         if (e >= b) then
            var = low(b:e)
            exit lines
         end if
      end do lines
      close (u)
   end function variable_before

   !> Stop unless lo <= x <= hi (bounds open where lo_open / hi_open are set).
   subroutine check_real(file, group, var, x, lo, hi, lo_open, hi_open)
      character(len=*), intent(in) :: file, group, var
      real(rp), intent(in) :: x, lo, hi
      logical, intent(in), optional :: lo_open, hi_open
      logical :: lopen, hopen, ok
      character(len=:), allocatable :: range
      lopen = .false.
      hopen = .false.
      if (present(lo_open)) lopen = lo_open
      if (present(hi_open)) hopen = hi_open
      ok = .not. ieee_is_nan(x)
      if (lopen) then
         ok = ok .and. x > lo
      else
         ok = ok .and. x >= lo
      end if
      if (hopen) then
         ok = ok .and. x < hi
      else
         ok = ok .and. x <= hi
      end if
      if (.not. ok) then
         range = merge('(', '[', lopen)//real_str(lo)//', '//real_str(hi)//merge(')', ']', hopen)
         if (hi >= huge(1.0_rp)) range = merge('(', '[', lopen)//real_str(lo)//', infinity)'
         call input_error(file, group, var, 'value '//real_str(x)//' is out of the allowed range '//range)
      end if
   end subroutine check_real

   subroutine check_int(file, group, var, i, lo, hi)
      character(len=*), intent(in) :: file, group, var
      integer, intent(in) :: i, lo, hi
      if (i < lo .or. i > hi) call input_error(file, group, var, 'value '//int_str(i)// &
                                               ' is out of the allowed range ['//int_str(lo)//', '//int_str(hi)//']')
   end subroutine check_int
   !> The outline of vertices x(1:nv), y(1:nv) of group g as a (2, nv) array,
   !> counter-clockwise; an outline of zero area or one that crosses itself is
   !> an input error naming x, y (what: 'polygon', 'outline', as the message says it).
   function checked_outline(file, g, what, nv, x, y) result(v)
      character(len=*), intent(in) :: file, g, what
      integer, intent(in) :: nv
      real(rp), intent(in) :: x(:), y(:)
      real(rp), allocatable :: v(:, :)
      integer :: ist
      character(len=200) :: emsg
      allocate (v(2, nv), stat=ist, errmsg=emsg)
      if (ist /= 0) call fatal('checked_outline: cannot allocate the outline: '//trim(emsg))
      v(1, :) = x(1:nv)
      v(2, :) = y(1:nv)
      if (abs(polygon_area(v)) < 1.0e-12_rp*maxval(abs(v))**2) call input_error(file, g, 'x, y', &
                                                                                'the '//what//' has zero area')
      if (polygon_self_intersects(v)) call input_error(file, g, 'x, y', 'the outline crosses itself')
      if (polygon_area(v) < 0.0_rp) v = v(:, nv:1:-1)
   end function checked_outline
end module input_check

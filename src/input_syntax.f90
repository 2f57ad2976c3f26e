!> The syntax of a case file, checked before any group is read: every group
!> is a list of `name = value, value ...` closed by '/', every value a
!> number, a quoted string or a logical, one value for a scalar. The
!> compiler's namelist reader reports such mistakes far from where they are
!> (`rho0 = = 1` as an unknown group, `overwrite = yes` as a variable
!> `yes&domain`); here they are named by line, variable and what was expected.
module input_syntax
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use kinds, only: rp
   use constants, only: msg_len
   use errors, only: fatal, alloc_check
   implicit none
   private
   public :: assign_t, syntax_scan, syntax_check, is_name, lower

   !> One `name = values` of a group, as written.
   type :: assign_t
      character(len=32) :: group = ''          !< group name, lower case
      integer :: occurrence = 0                !< which group of that name (1 = the first)
      character(len=64) :: var = ''            !< variable, lower case, as written (with an index)
      character(len=msg_len) :: text = ''      !< the values, separated by ', '
      integer :: nvalues = 0
      integer :: line = 0                      !< line of the name
   end type assign_t

   !> The variables that take several values (arrays): any other takes one.
   !> A new array variable of a group must be added here.
   character(len=*), parameter :: array_vars(*) = [character(len=24) :: &
      'box%amplitude', 'polygon%amplitude', 'polygon%x', 'polygon%y', 'body%vx', 'body%vy', 'porous%x', 'porous%y']

   !> The groups a case may hold several of, named 'box #2' in messages as their readers do.
   character(len=*), parameter :: repeatable(*) = [character(len=8) :: 'box', 'polygon', 'slope', 'stl', 'body', 'gauge', 'porous']

   character(len=*), parameter :: name_chars = 'abcdefghijklmnopqrstuvwxyz0123456789_'

contains

   !> Stop with a message naming the line when the case file breaks the syntax.
   subroutine syntax_check(file)
      character(len=*), intent(in) :: file
      type(assign_t), allocatable :: a(:)
      character(len=msg_len) :: err
      call syntax_scan(file, a, err)
      if (len_trim(err) > 0) call fatal(trim(file)//': '//trim(err), 2)
   end subroutine syntax_check

   !> True for a variable name (a letter, then letters, digits, _).
   pure logical function is_name(s)
      character(len=*), intent(in) :: s
      character(len=len(s)) :: t
      t = lower(s)
      is_name = len_trim(t) > 0
      if (.not. is_name) return
      is_name = verify(t(1:1), 'abcdefghijklmnopqrstuvwxyz') == 0 .and. verify(trim(t), name_chars) == 0
   end function is_name

   !> Every assignment of the file, in order; err holds the first syntax
   !> error ('line N: &group: ...'), blank when there is none.
   subroutine syntax_scan(file, a, err)
      character(len=*), intent(in) :: file
      type(assign_t), allocatable, intent(out) :: a(:)
      character(len=msg_len), intent(out) :: err
      character(len=:), allocatable :: s
      integer, allocatable :: ln(:)
      integer :: ist
      character(len=200) :: emsg
      err = ''
      allocate (a(0), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'a in syntax_scan')
      call load(file, s, ln, err)
      if (len_trim(err) > 0) return
      call scan_text(s, ln, a, err)
   end subroutine syntax_scan

   !> syntax_scan of the text s, whose character k is on line ln(k).
   subroutine scan_text(s, ln, a, err)
      character(len=*), intent(in) :: s
      integer, intent(in) :: ln(:)
      type(assign_t), allocatable, intent(inout) :: a(:)
      character(len=msg_len), intent(inout) :: err
      character(len=:), allocatable :: grp
      integer :: k, e, ig
      character(len=32), allocatable :: seen(:)
      integer, allocatable :: nseen(:)
      integer :: ist
      character(len=200) :: emsg
      ! allow(multiple-allocations-with-stat): any of them refused is the same stop
      allocate (seen(0), nseen(0), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'seen, nseen in scan_text')
      k = 1
      groups: do
         ! outside a group everything up to the next & is ignored, as the reader does
         k = k + scan(s(k:), '&$') - 1
         if (scan(s(min(k, len(s)):), '&$') == 0) exit groups
         e = name_end(s, k + 1)
         grp = lower(s(k + 1:e - 1))
         k = e
         if (grp == 'end' .or. len(grp) == 0) cycle groups
         ig = findloc_str(seen, grp)
         if (ig == 0) then
            seen = [character(len=32) :: seen, grp]
            nseen = [nseen, 0]
            ig = size(seen)
         end if
         nseen(ig) = nseen(ig) + 1
         call scan_group(s, ln, k, grp, nseen(ig), a, err)
         if (len_trim(err) > 0) return
      end do groups
   end subroutine scan_text

   !> The assignments of one group, from k (after its name) to its closing /.
   subroutine scan_group(s, ln, k, grp, occ, a, err)
      character(len=*), intent(in) :: s, grp
      integer, intent(in) :: ln(:), occ
      integer, intent(inout) :: k
      type(assign_t), allocatable, intent(inout) :: a(:)
      character(len=msg_len), intent(inout) :: err
      character(len=64) :: var
      integer :: e, n
      type(assign_t) :: cur
      character(len=:), allocatable :: gn
      n = len(s)
      ! as the readers name a group that may come several times: 'box #2'
      gn = grp
      if (any(repeatable == grp)) gn = grp//' #'//str(occ)
      items: do
         call skip(s, k, .true.)
         if (k > n) then
            err = at(ln(n), gn)//'the group is not closed: a / is expected before the end of the file'
            return
         end if
         if (s(k:k) == '/') then
            k = k + 1
            return
         end if
         if (s(k:k) == '&' .or. s(k:k) == '$') then
            e = name_end(s, k + 1)
            if (lower(s(k + 1:e - 1)) /= 'end') err = at(ln(k), gn)// &
               'the group is not closed: a / is expected before &'//s(k + 1:e - 1)
            k = e
            return
         end if
         ! a variable: name, an optional index (...) and component %name
         e = var_end(s, k)
         if (e == k .or. .not. is_name(s(k:name_end(s, k) - 1))) then
            err = at(ln(k), gn)//'a variable name is expected, found '//quoted(word(s, k))
            return
         end if
         var = lower(s(k:e - 1))
         cur = assign_t(group=grp, occurrence=occ, var=var, line=ln(k))
         k = e
         call skip(s, k, .false.)
         if (k > n) then
            err = at(ln(n), gn, trim(var))//'= and a value are expected'
            return
         end if
         if (s(k:k) /= '=') then
            err = at(ln(k), gn, trim(var))//'= is expected after the name, found '//quoted(word(s, k))
            return
         end if
         k = k + 1
         call scan_values(s, ln, k, grp, gn, cur, err)
         if (len_trim(err) > 0) return
         a = [a, cur]
      end do items
   end subroutine scan_group

   !> The values of one assignment cur, from k (after its =) to the next name = or the end of the group.
   subroutine scan_values(s, ln, k, grp, gn, cur, err)
      character(len=*), intent(in) :: s, grp, gn
      integer, intent(in) :: ln(:)
      integer, intent(inout) :: k
      type(assign_t), intent(inout) :: cur
      character(len=msg_len), intent(inout) :: err
      character(len=64) :: var
      integer :: e, n
      logical :: next_name
      n = len(s)
      var = cur%var
      values: do
         call skip(s, k, .false.)
         if (k > n) exit values
         ! the value is s(k:e)
         select case (s(k:k))
         case ('=')
            err = at(ln(k), gn, trim(var))//'a value is expected after =, found ='
            return
         case ('/', '&', '$')
            exit values
         case (',')
            k = k + 1
            cycle values
         case ("'", '"')
            e = string_end(s, k)
            if (e > n) then
               err = at(ln(k), gn, trim(var))//'the string '//s(k:min(k + 30, line_end(s, k)))// &
                     ' is not closed (a quote is missing)'
               return
            end if
         case default
            e = k + scan(s(k:)//' ', ' ,/=&$'//achar(10)//achar(9)//achar(13)) - 2
            call check_bare(s, ln, k, gn, trim(var), s(k:e), cur%nvalues == 0, next_name, err)
            if (len_trim(err) > 0 .or. next_name) exit values
         end select
         cur%nvalues = cur%nvalues + 1
         if (cur%nvalues > 1) then
            cur%text = trim(cur%text)//', '//s(k:e)
         else
            cur%text = s(k:e)
         end if
         k = e + 1
      end do values
      if (len_trim(err) > 0) return
      if (cur%nvalues == 0) then
         err = at(cur%line, gn, trim(var))//'a value is expected after ='
      else if (cur%nvalues > 1 .and. .not. any(array_vars == grp//'%'//base_name(var))) then
         err = at(cur%line, gn, trim(var))//'takes one value, found '//str(cur%nvalues)//' ('//trim(cur%text)// &
               '); a comma separates assignments only after a whole value'
      end if
   end subroutine scan_values

   !> An unquoted token tok at k: the name of the next assignment (next_name),
   !> a value, or an error.
   subroutine check_bare(s, ln, k, grp, var, tok, first, next_name, err)
      character(len=*), intent(in) :: s, grp, var, tok
      integer, intent(in) :: ln(:), k
      logical, intent(in) :: first
      logical, intent(out) :: next_name
      character(len=msg_len), intent(inout) :: err
      integer :: e
      e = k + len(tok)
      call skip(s, e, .false.)
      next_name = .false.
      if (e <= len(s)) then
         ! a name followed by = starts the next assignment
         if (s(e:e) == '=' .and. is_name(tok(1:name_end(tok, 1) - 1))) then
            if (first) err = at(ln(k), grp, var)//'a value is expected after =, found '//quoted(tok)
            next_name = .true.
            return
         end if
      end if
      if (is_value(tok)) then
         ! NaN, Inf and numbers beyond the largest real: no length, time or
         ! coefficient of a case can take them (an object at x = NaN ran and
         ! wrote NaN lines)
         if (is_number(tok(index(tok, '*') + 1:)) .and. .not. is_finite(tok(index(tok, '*') + 1:))) then
            err = at(ln(k), grp, var)//'the value '//quoted(tok)//' is not a finite number'
         end if
         return
      end if
      ! a name followed by a value is a variable without its =
      if (is_name(tok) .and. e <= len(s)) then
         if (is_value(word(s, e)) .or. s(e:e) == "'" .or. s(e:e) == '"') then
            err = at(ln(k), grp, lower(tok))//'= is expected after the name, found '//quoted(word(s, e))
            return
         end if
      end if
      err = at(ln(k), grp, var)//'cannot read the value '//quoted(tok)// &
            ' (a number, a quoted string or .true./.false. is expected)'
   end subroutine check_bare

   !> Position of the quote that closes the string opened at k (a doubled
   !> quote stands for the quote itself); beyond len(s) when the line ends first.
   pure integer function string_end(s, k) result(e)
      character(len=*), intent(in) :: s
      integer, intent(in) :: k
      e = k + 1
      chars: do while (e <= len(s))
         if (s(e:e) == achar(10)) then
            e = len(s) + 1
         else if (s(e:e) /= s(k:k)) then
            e = e + 1
         else if (e < len(s) .and. s(min(e + 1, len(s)):min(e + 1, len(s))) == s(k:k)) then
            e = e + 2
         else
            exit chars
         end if
      end do chars
   end function string_end

   !> 'line N: &group: ' or 'line N: &group: var: ', the start of a message.
   function at(line, grp, var) result(m)
      integer, intent(in) :: line
      character(len=*), intent(in) :: grp
      character(len=*), intent(in), optional :: var
      character(len=:), allocatable :: m
      m = 'line '//str(line)//': &'//grp//': '
      if (present(var)) m = m//var//': '
   end function at

   !> The file as one string, comments (outside strings) blanked, lines
   !> joined by a newline; ln(k) is the line of character k. Two passes: the
   !> length, then the text, so that the string is allocated once.
   subroutine load(file, s, ln, err)
      character(len=*), intent(in) :: file
      character(len=:), allocatable, intent(out) :: s
      integer, allocatable, intent(out) :: ln(:)
      character(len=msg_len), intent(inout) :: err
      character(len=4096) :: buf
      character(len=msg_len) :: msg
      integer :: u, ios, line, i, m, pass, total, k
      logical :: in_str
      character :: q
      integer :: ist
      character(len=200) :: emsg
      open (newunit=u, file=file, status='old', action='read', iostat=ios, iomsg=msg)
      if (ios /= 0) then
         err = 'cannot open the case file: '//trim(msg)
         s = achar(10)      ! allocated on every path: the caller's scan needs no other case
         ln = [0]
         return
      end if
      total = 0
      do pass = 1, 2
         if (pass == 2) then
            allocate (character(len=max(total, 1)) :: s, stat=ist, errmsg=emsg)
            if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
               call alloc_check(ist, emsg, 's in load')
               error stop
            end if
            allocate (ln(max(total, 1)), stat=ist, errmsg=emsg)
            if (ist /= 0) then  ! error stop: the compiler cannot know alloc_check stops
               call alloc_check(ist, emsg, 'ln in load')
               error stop
            end if
            s(:) = achar(10)          ! s(:): an assignment to s would reallocate it
            ln = 1
            rewind (u)
         end if
         line = 0
         k = 0
         lines: do
            read (u, '(a)', iostat=ios, iomsg=msg) buf
            if (ios /= 0) exit lines
            line = line + 1
            in_str = .false.
            q = ' '
            m = len_trim(buf)
            chars: do i = 1, m
               if (in_str) then
                  if (buf(i:i) == q) in_str = .false.
               else if (buf(i:i) == '"' .or. buf(i:i) == "'") then
                  in_str = .true.
                  q = buf(i:i)
               else if (buf(i:i) == '!') then
                  m = i - 1
                  exit chars
               end if
            end do chars
            if (pass == 2) then
               s(k + 1:k + m + 1) = buf(1:m)//achar(10)
               ln(k + 1:k + m + 1) = line
            end if
            k = k + m + 1
         end do lines
         total = k
      end do
      close (u)
   end subroutine load

   !> Number, logical or repeat count r*value, as the namelist reader takes them.
   pure logical function is_value(t)
      character(len=*), intent(in) :: t
      integer :: k
      k = index(t, '*')
      if (k > 1) then
         is_value = verify(t(1:k - 1), '0123456789') == 0
         if (is_value .and. k < len(t)) is_value = is_value_one(t(k + 1:))
      else
         is_value = is_value_one(t)
      end if
   end function is_value

   pure logical function is_value_one(t)
      character(len=*), intent(in) :: t
      is_value_one = is_number(t) .or. is_logical(t)
   end function is_value_one

   !> [sign] digits [. digits] [e|d [sign] digits], at least one digit before
   !> the exponent; NaN and Inf are numbers to the reader (the range checks
   !> refuse them where they make no sense).
   pure logical function is_number(t)
      character(len=*), intent(in) :: t
      integer :: k, nd
      logical :: dot
      character(len=len(t)) :: l
      is_number = .false.
      k = 1
      if (len(t) == 0) return
      if (t(1:1) == '+' .or. t(1:1) == '-') k = 2
      l = lower(t)
      if (k <= len(t)) then
         if (l(k:) == 'nan' .or. l(k:) == 'inf' .or. l(k:) == 'infinity') then
            is_number = .true.
            return
         end if
      end if
      nd = 0
      dot = .false.
      do while (k <= len(t))
         if (index('0123456789', t(k:k)) > 0) then
            nd = nd + 1
         else if (t(k:k) == '.' .and. .not. dot) then
            dot = .true.
         else
            exit
         end if
         k = k + 1
      end do
      if (nd == 0) return
      if (k > len(t)) then
         is_number = .true.
         return
      end if
      if (index('eEdD', t(k:k)) == 0) return
      k = k + 1
      if (k <= len(t)) then
         if (t(k:k) == '+' .or. t(k:k) == '-') k = k + 1
      end if
      is_number = k <= len(t)
      if (is_number) is_number = verify(t(k:), '0123456789') == 0
   end function is_number

   !> A number token that reads as a finite real.
   logical function is_finite(t)
      character(len=*), intent(in) :: t
      real(rp) :: x
      integer :: ios
      character(len=msg_len) :: msg
      read (t, *, iostat=ios, iomsg=msg) x
      is_finite = ios == 0
      if (is_finite) is_finite = ieee_is_finite(x)
   end function is_finite

   !> .true., .false., T, F and their short forms.
   pure logical function is_logical(t)
      character(len=*), intent(in) :: t
      character(len=len(t)) :: l
      integer :: k
      l = lower(t)
      k = 1
      if (l(1:1) == '.') k = 2
      is_logical = .false.
      if (k > len(l)) return
      if (l(k:k) /= 't' .and. l(k:k) /= 'f') return
      is_logical = (l == 't' .or. l == 'f' .or. l == '.t.' .or. l == '.f.' .or. l == '.true.' .or. &
                    l == '.false.' .or. l == 'true' .or. l == 'false' .or. l == '.t' .or. l == '.f')
   end function is_logical

   !> Whitespace (and commas when commas is set) from k on.
   pure subroutine skip(s, k, commas)
      character(len=*), intent(in) :: s
      integer, intent(inout) :: k
      logical, intent(in) :: commas
      do while (k <= len(s))
         if (index(' '//achar(9)//achar(10)//achar(13), s(k:k)) > 0) then
            k = k + 1
         else if (commas .and. s(k:k) == ',') then
            k = k + 1
         else
            exit
         end if
      end do
   end subroutine skip

   !> One past the last name character from k.
   pure integer function name_end(s, k) result(e)
      character(len=*), intent(in) :: s
      integer, intent(in) :: k
      e = k
      do while (e <= len(s))
         if (verify(lower(s(e:e)), name_chars) /= 0) exit
         e = e + 1
      end do
   end function name_end

   !> One past a variable designator from k: name, (index), %name, repeated.
   pure integer function var_end(s, k) result(e)
      character(len=*), intent(in) :: s
      integer, intent(in) :: k
      integer :: c
      e = name_end(s, k)
      do while (e <= len(s))
         if (s(e:e) == '(') then
            c = index(s(e:), ')')
            if (c == 0) return
            e = e + c
         else if (s(e:e) == '%') then
            e = name_end(s, e + 1)
         else
            exit
         end if
      end do
   end function var_end

   pure integer function line_end(s, k) result(e)
      character(len=*), intent(in) :: s
      integer, intent(in) :: k
      e = k
      do while (e < len(s))
         if (s(e + 1:e + 1) == achar(10)) exit
         e = e + 1
      end do
   end function line_end

   !> The text from k to the next blank, comma or end of line (at most 40 characters).
   function word(s, k) result(w)
      character(len=*), intent(in) :: s
      integer, intent(in) :: k
      character(len=:), allocatable :: w
      integer :: e
      e = k
      do while (e < len(s) .and. e < k + 40)
         if (index(' ,'//achar(9)//achar(10), s(e + 1:e + 1)) > 0) exit
         e = e + 1
      end do
      w = s(k:min(e, len(s)))
      if (w == achar(10)) w = 'the end of the line'
   end function word

   !> The name of a variable without its index: 'x(3)' -> 'x'.
   pure function base_name(v) result(b)
      character(len=*), intent(in) :: v
      character(len=:), allocatable :: b
      integer :: k
      k = scan(v, '(%')
      if (k > 0) then
         b = trim(v(1:k - 1))
      else
         b = trim(v)
      end if
   end function base_name

   function quoted(t) result(q)
      character(len=*), intent(in) :: t
      character(len=:), allocatable :: q
      if (t == 'the end of the line') then
         q = t
      else
         q = "'"//t//"'"
      end if
   end function quoted

   pure integer function findloc_str(list, v) result(k)
      character(len=*), intent(in) :: list(:), v
      integer :: i
      k = 0
      do i = 1, size(list)
         if (list(i) == v) then
            k = i
            return
         end if
      end do
   end function findloc_str

   function str(i) result(s)
      integer, intent(in) :: i
      character(len=:), allocatable :: s
      character(len=16) :: b
      write (b, '(i0)') i
      s = trim(b)
   end function str

   !> Lower-case copy of a string (names and choices are case-insensitive).
   pure function lower(s) result(r)
      character(len=*), intent(in) :: s
      character(len=len(s)) :: r
      integer :: i, c
      r = s
      do i = 1, len(s)
         c = iachar(s(i:i))
         if (c >= iachar('A') .and. c <= iachar('Z')) r(i:i) = achar(c + 32)
      end do
   end function lower
end module input_syntax

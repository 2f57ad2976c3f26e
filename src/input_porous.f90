!> &porous, repeatable: a region of stones the water flows through (a
!> breakwater's core or underlayer, a porous dam), a polygon or a box with its
!> porosity, stone size and the resistance coefficients of the Forchheimer
!> law in Van Gent's form (doc/porous.md).
module input_porous
   use kinds, only: rp
   use constants, only: msg_len
   use input_check, only: open_case, read_failed_open, check_real, check_int, group_count, int_str, real_str, &
                          checked_outline
   use errors, only: input_error, alloc_check
   implicit none
   private
   public :: porous_cfg, read_porous, write_porous

   integer, parameter :: max_vert = 100

   type :: porous_cfg
      real(rp) :: porosity = -1.0_rp      !< n, pore volume over total volume; required
      real(rp) :: d50 = -1.0_rp           !< nominal stone diameter [m]; required
      real(rp) :: alpha = 1000.0_rp       !< linear (laminar) resistance coefficient [-]
      real(rp) :: beta = 1.1_rp           !< quadratic (turbulent) resistance coefficient [-]
      real(rp) :: gamma = 0.34_rp         !< added-mass coefficient [-]
      real(rp) :: nu = 1.0e-6_rp          !< kinematic viscosity of the pore water [m2/s]
      real(rp) :: width = -1.0_rp         !< width of the porosity's transition [m]; < 0: the kernel support 2h
      real(rp) :: box(4) = 0.0_rp         !< xmin, xmax, ymin, ymax when the region is a box
      integer :: nv = 0                   !< vertices of the outline
      logical :: is_box = .true.          !< given as a box (else as a polygon)
      logical :: generated = .false.      !< made by &breakwater (its core), not written back
      real(rp), allocatable :: v(:, :)    !< outline (2, nv), counter-clockwise
   end type porous_cfg

   real(rp) :: porosity, d50, alpha, beta, gamma, nu, width, xmin, xmax, ymin, ymax
   integer :: nvert
   real(rp) :: x(max_vert), y(max_vert)
   namelist /porous/ porosity, d50, alpha, beta, gamma, nu, width, xmin, xmax, ymin, ymax, nvert, x, y

contains

   subroutine defaults()
      type(porous_cfg) :: d
      porosity = d%porosity; d50 = d%d50; alpha = d%alpha; beta = d%beta; gamma = d%gamma; nu = d%nu; width = d%width
      xmin = 0.0_rp; xmax = 0.0_rp; ymin = 0.0_rp; ymax = 0.0_rp
      nvert = 0; x = 0.0_rp; y = 0.0_rp
   end subroutine defaults

   !> Every &porous group; h (the smoothing length) gives the default width.
   subroutine read_porous(file, h, regions)
      character(len=*), intent(in) :: file
      real(rp), intent(in) :: h
      type(porous_cfg), allocatable, intent(out) :: regions(:)
      integer :: n, k, u, ios, ist
      character(len=msg_len) :: msg
      character(len=200) :: emsg
      character(len=:), allocatable :: g
      n = group_count(file, 'porous')
      allocate (regions(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'regions in read_porous')
      if (n == 0) return
      u = open_case(file)
      do k = 1, n
         call defaults()
         read (u, nml=porous, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'porous', ios, msg)) return
         g = 'porous #'//int_str(k)
         if (porosity < 0.0_rp) call input_error(file, g, 'porosity', 'required: the pore volume over the '// &
                                                 'total volume, in (0, 1] (rock and concrete units: 0.35 to 0.55)')
         call check_real(file, g, 'porosity', porosity, 0.0_rp, 1.0_rp, lo_open=.true.)
         if (d50 < 0.0_rp) call input_error(file, g, 'd50', 'required: the nominal stone diameter in m, > 0')
         call check_real(file, g, 'd50', d50, 0.0_rp, 100.0_rp, lo_open=.true.)
         call check_real(file, g, 'alpha', alpha, 0.0_rp, 1.0e6_rp)
         call check_real(file, g, 'beta', beta, 0.0_rp, 1.0e3_rp)
         call check_real(file, g, 'gamma', gamma, 0.0_rp, 10.0_rp)
         call check_real(file, g, 'nu', nu, 0.0_rp, 1.0_rp, lo_open=.true.)
         if (width < 0.0_rp) width = 2.0_rp*h
         call check_real(file, g, 'width', width, 0.0_rp, 1.0e3_rp)
         regions(k)%porosity = porosity
         regions(k)%d50 = d50
         regions(k)%alpha = alpha
         regions(k)%beta = beta
         regions(k)%gamma = gamma
         regions(k)%nu = nu
         regions(k)%width = width
         if (nvert == 0) then
            if (.not. (xmax > xmin)) call input_error(file, g, 'xmax', 'must be greater than xmin = '// &
                                                      real_str(xmin)//' (got '//real_str(xmax)// &
                                                      '; or give the outline by nvert, x, y)')
            if (.not. (ymax > ymin)) call input_error(file, g, 'ymax', 'must be greater than ymin = '// &
                                                      real_str(ymin)//' (got '//real_str(ymax)//')')
            regions(k)%is_box = .true.
            regions(k)%box = [xmin, xmax, ymin, ymax]
            regions(k)%nv = 4
            regions(k)%v = reshape([xmin, ymin, xmax, ymin, xmax, ymax, xmin, ymax], [2, 4])
         else
            call check_int(file, g, 'nvert', nvert, 3, max_vert)
            regions(k)%is_box = .false.
            regions(k)%nv = nvert
            regions(k)%v = checked_outline(file, g, 'outline', nvert, x, y)
         end if
      end do
      close (u)
   end subroutine read_porous

   subroutine write_porous(u, regions)
      integer, intent(in) :: u
      type(porous_cfg), intent(in) :: regions(:)
      integer :: k
      do k = 1, size(regions)
         if (regions(k)%generated) cycle
         call defaults()
         porosity = regions(k)%porosity; d50 = regions(k)%d50
         alpha = regions(k)%alpha; beta = regions(k)%beta; gamma = regions(k)%gamma; nu = regions(k)%nu
         width = regions(k)%width
         if (regions(k)%is_box) then
            xmin = regions(k)%box(1); xmax = regions(k)%box(2); ymin = regions(k)%box(3); ymax = regions(k)%box(4)
         else
            nvert = regions(k)%nv
            x(1:nvert) = regions(k)%v(1, :)
            y(1:nvert) = regions(k)%v(2, :)
         end if
         write (u, nml=porous)
      end do
   end subroutine write_porous
end module input_porous

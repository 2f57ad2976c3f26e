!> &wavemaker (one paddle), &gauge (repeatable: elevation or pressure
!> probes) and &damping (one absorbing zone). The checks that need the
!> still-water depth and the domain are made in input (check_waves).
module input_wave
   use kinds, only: rp
   use constants, only: name_len, path_len, msg_len, ndim
   use input_check, only: open_case, read_failed, read_failed_open, check_real, check_int, &
                          group_count, int_str
   use errors, only: input_error, alloc_check
   use input_breakwater, only: breakwater_cfg
   use options, only: option_index, paddle_names, paddle_piston, wave_names, wave_regular, wave_irregular, wave_file, &
                      gauge_names, gauge_elevation
   implicit none
   private
   public :: z_left_out, wavemaker_cfg, gauge_cfg, damping_cfg, read_wavemaker, write_wavemaker, read_gauges, write_gauges, &
             read_damping, write_damping

   type :: wavemaker_cfg
      logical :: on = .false.                        !< a &wavemaker group is present
      character(len=name_len) :: paddle = 'piston'   !< 'piston' | 'flap'
      character(len=name_len) :: wave = 'regular'    !< 'regular' | 'irregular' | 'file'
      integer :: paddle_id = paddle_piston           !< paddle as its value in options (paddle_*)
      integer :: wave_id = wave_regular              !< wave as its value in options (wave_*)
      real(rp) :: x0 = 0.0_rp              !< rest position of the paddle face [m]
      real(rp) :: depth = 0.0_rp           !< still-water depth at the paddle [m]
      real(rp) :: height = 0.0_rp          !< regular: wave height H [m]
      real(rp) :: period = 0.0_rp          !< regular: period T [s]
      logical :: second_order = .false.    !< regular piston: Madsen's second-order paddle motion
      real(rp) :: hs = 0.0_rp              !< irregular: significant height Hm0 [m]
      real(rp) :: tp = 0.0_rp              !< irregular: peak period [s]
      real(rp) :: gamma = 3.3_rp           !< irregular: JONSWAP peak enhancement [-]
      integer :: seed = 1                  !< irregular: random phases
      real(rp) :: duration = 0.0_rp        !< the wave's length after t_start, ramped down at its end [s] (0: no end)
      real(rp) :: f_lo = 0.5_rp            !< irregular: lowest component / peak frequency [-]
      real(rp) :: f_hi = 3.0_rp            !< irregular: highest component / peak frequency [-]
      character(len=path_len) :: signal_file = ''  !< 'file': two columns, time [s] and displacement [m]
      real(rp) :: ramp_periods = 2.0_rp    !< smooth start over this many periods (T or Tp) [-]
      real(rp) :: ramp_time = 0.0_rp       !< or over this time [s] when > 0
      real(rp) :: t_start = 0.0_rp         !< the paddle rests until this time (a settling run first) [s]
      real(rp) :: max_stroke = 0.0_rp      !< largest paddle excursion allowed, peak to peak [m] (0: 0.8 depth)
      real(rp) :: top = 0.0_rp             !< top of the paddle [m] (0: 1.5 depth above the bed)
      integer :: layers = 0                !< paddle thickness in particle rows (0: enough for 2h)
      real(rp) :: y_bed = 0.0_rp           !< bed level at the paddle; the flap's hinge [m]
      logical :: absorb = .false.          !< active absorption of the waves that come back to the paddle
      real(rp) :: absorb_time = 0.0_rp     !< absorber's drift control and mean-level time [s] (0: 5 T or 5 Tp)
   end type wavemaker_cfg

   !> a gauge's z left out (3D: mid-width, set by input once the &domain is known)
   real(rp), parameter, public :: z_unset = -huge(1.0_rp)

   type :: gauge_cfg
      character(len=name_len) :: kind = 'elevation'  !< 'elevation' | 'pressure'
      integer :: kind_id = gauge_elevation           !< kind as its value in options (gauge_*)
      real(rp) :: x = 0.0_rp, y = 0.0_rp             !< position [m] (y: pressure gauges only)
      !> 3D: the position across the width [m]; z_unset (left out): mid-width
      real(rp) :: z = z_unset
   end type gauge_cfg

   type :: damping_cfg
      logical :: on = .false.
      real(rp) :: x0 = 0.0_rp             !< start of the zone [m]: no damping there
      real(rp) :: x1 = 0.0_rp             !< end of the zone [m]: full damping (x1 < x0 damps to the left)
      real(rp) :: strength = 10.0_rp      !< relaxation rate at x1 [1/s]
   end type damping_cfg

   ! &wavemaker
   character(len=name_len) :: paddle, wave
   real(rp) :: x0, depth, height, period, hs, tp, gamma, duration, f_lo, f_hi, ramp_periods, ramp_time, &
               max_stroke, top, y_bed, t_start, absorb_time
   logical :: second_order, absorb
   integer :: seed, layers
   character(len=path_len) :: signal_file
   namelist /wavemaker/ paddle, wave, x0, depth, height, period, second_order, hs, tp, gamma, seed, duration, &
      f_lo, f_hi, signal_file, ramp_periods, ramp_time, max_stroke, top, layers, y_bed, t_start, absorb, absorb_time
   ! &gauge
   character(len=name_len) :: kind
   real(rp) :: x, y, z
   namelist /gauge/ kind, x, y, z
   ! &damping
   real(rp) :: x1, strength
   namelist /damping/ x0, x1, strength

contains

   subroutine wm_to_vars(c)
      type(wavemaker_cfg), intent(in) :: c
      paddle = c%paddle; wave = c%wave; x0 = c%x0; depth = c%depth; height = c%height; period = c%period
      second_order = c%second_order; hs = c%hs; tp = c%tp; gamma = c%gamma; seed = c%seed
      duration = c%duration; f_lo = c%f_lo; f_hi = c%f_hi; signal_file = c%signal_file
      ramp_periods = c%ramp_periods; ramp_time = c%ramp_time; max_stroke = c%max_stroke; top = c%top
      layers = c%layers; y_bed = c%y_bed; t_start = c%t_start; absorb = c%absorb; absorb_time = c%absorb_time
   end subroutine wm_to_vars

   subroutine wm_from_vars(c)
      type(wavemaker_cfg), intent(inout) :: c
      c%paddle = paddle; c%wave = wave; c%x0 = x0; c%depth = depth; c%height = height; c%period = period
      c%second_order = second_order; c%hs = hs; c%tp = tp; c%gamma = gamma; c%seed = seed
      c%duration = duration; c%f_lo = f_lo; c%f_hi = f_hi; c%signal_file = signal_file
      c%ramp_periods = ramp_periods; c%ramp_time = ramp_time; c%max_stroke = max_stroke; c%top = top
      c%layers = layers; c%y_bed = y_bed; c%t_start = t_start; c%absorb = absorb; c%absorb_time = absorb_time
   end subroutine wm_from_vars

   !> The group alone: choices and ranges. Depth, steepness and stroke are
   !> checked in input once the geometry is known.
   subroutine read_wavemaker(file, c, bw)
      character(len=*), intent(in) :: file
      type(wavemaker_cfg), intent(out) :: c
      type(breakwater_cfg), intent(in) :: bw     !< in a breakwater flume the paddle stands at its start
      integer :: u, ios, n
      character(len=msg_len) :: msg
      character(len=*), parameter :: g = 'wavemaker'
      n = group_count(file, g)
      if (n > 1) call input_error(file, g, '', 'group appears more than once (one paddle per case)')
      if (n == 0) return
      if (bw%on) then
         c%x0 = bw%x_start
         c%depth = bw%depth
         c%y_bed = 0.0_rp
      end if
      call wm_to_vars(c)
      u = open_case(file)
      read (u, nml=wavemaker, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, g, ios, msg)) return
      call wm_from_vars(c)
      c%on = .true.
      c%paddle_id = option_index(file, g, 'paddle', c%paddle, paddle_names)
      c%paddle = paddle_names(c%paddle_id)
      c%wave_id = option_index(file, g, 'wave', c%wave, wave_names)
      c%wave = wave_names(c%wave_id)
      call check_real(file, g, 'depth', c%depth, 0.0_rp, 1.0e3_rp, lo_open=.true.)
      select case (c%wave_id)
      case (wave_regular)
         call check_real(file, g, 'height', c%height, 0.0_rp, c%depth, lo_open=.true.)
         call check_real(file, g, 'period', c%period, 0.0_rp, 1.0e3_rp, lo_open=.true.)
         call check_real(file, g, 'duration', c%duration, 0.0_rp, 1.0e6_rp)
      case (wave_irregular)
         call check_real(file, g, 'hs', c%hs, 0.0_rp, c%depth, lo_open=.true.)
         call check_real(file, g, 'tp', c%tp, 0.0_rp, 1.0e3_rp, lo_open=.true.)
         call check_real(file, g, 'gamma', c%gamma, 1.0_rp, 20.0_rp)
         call check_int(file, g, 'seed', c%seed, 0, huge(1))
         call check_real(file, g, 'duration', c%duration, 0.0_rp, 1.0e6_rp)
         call check_real(file, g, 'f_lo', c%f_lo, 0.05_rp, 1.0_rp, hi_open=.true.)
         call check_real(file, g, 'f_hi', c%f_hi, 1.0_rp, 10.0_rp, lo_open=.true.)
         if (c%second_order) call input_error(file, g, 'second_order', &
                                              "applies to regular waves only (wave = 'regular')")
      case (wave_file)
         if (len_trim(c%signal_file) == 0) call input_error(file, g, 'signal_file', &
                                                            "required with wave = 'file' (time [s], displacement [m])")
         if (c%absorb) call input_error(file, g, 'absorb', "needs the wave the paddle makes: wave = 'regular' "// &
                                        "or 'irregular' (the elevation of a signal file's wave is not known)")
         if (c%duration > 0.0_rp) call input_error(file, g, 'duration', &
                                                   "applies to wave = 'regular' or 'irregular' (a signal file ends itself)")
      case default
         call input_error(file, g, 'wave', 'no checks for wave '//trim(c%wave))
      end select
      if (c%second_order .and. c%paddle_id /= paddle_piston) call input_error(file, g, 'second_order', &
                                                                      'is implemented for the piston paddle only')
      ! the absorber's target is the first-order wave: it would take the bound second harmonic for a reflection
      if (c%second_order .and. c%absorb) call input_error(file, g, 'absorb', &
                                                          'is first-order: not with second_order = .true.')
      call check_real(file, g, 'ramp_periods', c%ramp_periods, 0.0_rp, 100.0_rp)
      call check_real(file, g, 'ramp_time', c%ramp_time, 0.0_rp, 1.0e4_rp)
      call check_real(file, g, 't_start', c%t_start, 0.0_rp, 1.0e6_rp)
      call check_real(file, g, 'max_stroke', c%max_stroke, 0.0_rp, 1.0e3_rp)
      if (c%max_stroke <= 0.0_rp) c%max_stroke = 0.8_rp*c%depth
      call check_real(file, g, 'top', c%top, 0.0_rp, 1.0e4_rp)
      call check_int(file, g, 'layers', c%layers, 0, 100)
      call check_real(file, g, 'absorb_time', c%absorb_time, 0.0_rp, 1.0e4_rp)
   end subroutine read_wavemaker

   subroutine write_wavemaker(u, c)
      integer, intent(in) :: u
      type(wavemaker_cfg), intent(in) :: c
      if (.not. c%on) return
      call wm_to_vars(c)
      write (u, nml=wavemaker)
   end subroutine write_wavemaker

   subroutine read_gauges(file, gs)
      character(len=*), intent(in) :: file
      type(gauge_cfg), allocatable, intent(out) :: gs(:)
      integer :: n, u, ios, k
      character(len=msg_len) :: msg
      type(gauge_cfg) :: d
      integer :: ist
      character(len=200) :: emsg
      n = group_count(file, 'gauge')
      allocate (gs(n), stat=ist, errmsg=emsg)
      call alloc_check(ist, emsg, 'gs in read_gauges')
      if (n == 0) return
      u = open_case(file)
      do k = 1, n
         kind = d%kind; x = d%x; y = d%y; z = d%z
         read (u, nml=gauge, iostat=ios, iomsg=msg)
         if (read_failed_open(u, file, 'gauge', ios, msg)) return
         gs(k)%kind = kind; gs(k)%x = x; gs(k)%y = y; gs(k)%z = z
         ! 2D: none, written as 0 in the run's case.nml
         if (ndim == 2 .and. .not. z_left_out(z) .and. abs(z) > 0.0_rp) then
            call input_error(file, 'gauge #'//int_str(k), 'z', &
                             'a position across the section is for the 3D build (build/mbsph3d); leave it out in 2D')
         end if
         if (ndim == 2) gs(k)%z = 0.0_rp
         gs(k)%kind_id = option_index(file, 'gauge #'//int_str(k), 'kind', gs(k)%kind, gauge_names)
         gs(k)%kind = gauge_names(gs(k)%kind_id)
      end do
      close (u)
   end subroutine read_gauges

   !> Whether a gauge's z is the z_unset of a group that left it out.
   elemental logical function z_left_out(z)
      real(rp), intent(in) :: z
      z_left_out = z < 0.5_rp*z_unset
   end function z_left_out

   subroutine write_gauges(u, gs)
      integer, intent(in) :: u
      type(gauge_cfg), intent(in) :: gs(:)
      integer :: k
      do k = 1, size(gs)
         kind = gs(k)%kind; x = gs(k)%x; y = gs(k)%y; z = gs(k)%z
         write (u, nml=gauge)
      end do
   end subroutine write_gauges

   subroutine read_damping(file, c)
      character(len=*), intent(in) :: file
      type(damping_cfg), intent(out) :: c
      integer :: u, ios, n
      character(len=msg_len) :: msg
      n = group_count(file, 'damping')
      if (n > 1) call input_error(file, 'damping', '', 'group appears more than once')
      if (n == 0) return
      x0 = c%x0; x1 = c%x1; strength = c%strength
      u = open_case(file)
      read (u, nml=damping, iostat=ios, iomsg=msg)
      close (u)
      if (read_failed(file, 'damping', ios, msg)) return
      c%on = .true.
      c%x0 = x0; c%x1 = x1; c%strength = strength
      if (abs(c%x1 - c%x0) <= 0.0_rp) call input_error(file, 'damping', 'x1', &
                                                       'must differ from x0 (the zone has a length)')
      call check_real(file, 'damping', 'strength', c%strength, 0.0_rp, 1.0e4_rp, lo_open=.true.)
   end subroutine read_damping

   subroutine write_damping(u, c)
      integer, intent(in) :: u
      type(damping_cfg), intent(in) :: c
      if (.not. c%on) return
      x0 = c%x0; x1 = c%x1; strength = c%strength
      write (u, nml=damping)
   end subroutine write_damping
end module input_wave

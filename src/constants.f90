!> Physical and bookkeeping constants shared by all subsystems.
module constants
   use kinds, only: rp
   implicit none
   private
   public :: pi, ndim, nsym, nsec, iup, kind_fluid, kind_fixed, kind_moving, kind_floating, kind_filter, kind_name, &
             name_len, path_len, msg_len

   real(rp), parameter :: pi = 3.14159265358979323846_rp
   integer, parameter :: ndim = 2            !< space dimensions; arrays are shaped (ndim, n)
   integer, parameter :: nsym = ndim*(ndim + 1)/2   !< components of a symmetric tensor (xx, xy, yy in 2D)
   !> the vertical section's dimensions (x along the flume, y up); outlines, slopes and porous
   !> regions are drawn in it, and a 3D scene extrudes them across its width (z)
   integer, parameter :: nsec = 2
   integer, parameter :: iup = 2             !< the vertical axis (y), gravity along -y in 2D and 3D

   ! particle kinds: the integer stored per particle and in the snapshots
   integer, parameter :: kind_fluid = 1
   integer, parameter :: kind_fixed = 2      !< fixed boundary (walls, floor, slopes)
   integer, parameter :: kind_moving = 3     !< boundary with prescribed motion
   integer, parameter :: kind_floating = 4   !< boundary of a free rigid body
   !> a permeable filter: fixed particles that stop bodies (contact) and are
   !> massless to the water, which flows through (the underlayer under armour)
   integer, parameter :: kind_filter = 5

   integer, parameter :: name_len = 32
   integer, parameter :: path_len = 512
   integer, parameter :: msg_len = 1024

contains

   !> Human-readable name of a particle kind.
   pure function kind_name(k) result(s)
      integer, intent(in) :: k
      character(len=:), allocatable :: s
      select case (k)
      case (kind_fluid); s = 'fluid'
      case (kind_fixed); s = 'fixed boundary'
      case (kind_moving); s = 'moving boundary'
      case (kind_floating); s = 'floating body'
      case (kind_filter); s = 'filter'
      case default; s = 'unknown'
      end select
   end function kind_name
end module constants

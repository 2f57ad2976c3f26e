!> Working precisions. Every real in MBSPH is real(rp); literals are written 1.0_rp.
module kinds
   use, intrinsic :: iso_fortran_env, only: real64, int32, int64
   use, intrinsic :: iso_c_binding, only: c_bool
   implicit none
   private
   public :: rp, ip, i8, lk

   integer, parameter :: rp = real64  !< reals: double precision everywhere
   integer, parameter :: ip = int32   !< particle and cell indices
   integer, parameter :: i8 = int64   !< counters that can pass 2**31 (particle-steps)
   integer, parameter :: lk = c_bool  !< per-particle flags: one byte each
end module kinds

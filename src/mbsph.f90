!> MBSPH: multi-body SPH for free-surface flow with rigid bodies.
!> Usage: mbsph CASE.nml
program mbsph
   use constants, only: path_len
   use comm, only: comm_init, comm_finalize
   use input, only: case_cfg, read_case
   use solver, only: run_t, solver_run
   use run_setup, only: setup_run
   use errors, only: fatal
   implicit none
   character(len=path_len) :: file
   type(case_cfg) :: c
   type(run_t) :: r
   call comm_init()
   if (command_argument_count() /= 1) call fatal('usage: mbsph CASE.nml', 2)
   call get_command_argument(1, file)
   call read_case(trim(file), c)
   call setup_run(r, c)
   call solver_run(r)
   call comm_finalize()
end program mbsph

#!/bin/bash
# SLURM batch template for an MBSPH run on several nodes (doc/cluster.md).
# Copy it next to your case file, edit the lines marked EDIT, submit with
#     sbatch slurm_mbsph.sh
#SBATCH --job-name=mbsph
#SBATCH --nodes=2                 # EDIT: nodes
#SBATCH --ntasks-per-node=32      # EDIT: MPI ranks per node (one per core)
#SBATCH --cpus-per-task=1
#SBATCH --time=24:00:00           # EDIT: wall-clock limit
#SBATCH --output=mbsph_%j.out

set -euo pipefail
CASE=case.nml                     # EDIT: the case file
MBSPH=$HOME/mbsph/build/mbsph     # EDIT: the binary built on this cluster

# EDIT: the modules that provide the compiler, MPI and parallel HDF5 used for the build
# module load gcc openmpi hdf5-mpi

# A case whose out_dir holds a checkpoint continues from it (&run restart = .true.
# in the case file, on any number of ranks); set checkpoint_every so that a job
# killed at its time limit loses little.
srun "$MBSPH" "$CASE"

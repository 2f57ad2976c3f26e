#!/bin/bash
# SLURM array of test series (doc/cluster.md, "Test series"): one array task per series
# file, each task runs its series' steps one after the other (restarts of one another).
# A task stopped at its time limit is submitted again the same way: finished steps are
# kept and the step it was in continues from its last checkpoint (set checkpoint_every
# in the series files). Edit the lines marked EDIT, then
#     sbatch --array=0-2 slurm_series.sh
#SBATCH --job-name=mbsph-series
#SBATCH --nodes=1                 # EDIT: nodes per series
#SBATCH --ntasks-per-node=32      # EDIT: MPI ranks per node (one per core)
#SBATCH --cpus-per-task=1
#SBATCH --time=48:00:00           # EDIT: wall-clock limit of one submission
#SBATCH --output=series_%A_%a.out

set -euo pipefail
MBSPH_DIR=$HOME/mbsph             # EDIT: the checkout, built on this cluster (make PORTABLE=1)
SERIES=(                          # EDIT: one series file per array task
  study/series/regular_1000.toml
  study/series/irregular_1000_s7.toml
  study/series/irregular_1000_s8.toml
)

# EDIT: the modules of the build, and Python 3 with the packages of tools/requirements.txt
# module load gcc openmpi hdf5-mpi fftw python

cd "$MBSPH_DIR"
.venv/bin/python -m post.series "${SERIES[$SLURM_ARRAY_TASK_ID]}" --launcher srun

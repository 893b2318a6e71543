#!/usr/bin/env bash
# A sweep on a Slurm cluster without MPI: one array task per shard, then one job that assembles
# the table (docs/sweep.md, "On a cluster"). Submit from the repository's root:
#   sbatch --array=0-7 examples/sweeps/slurm_array.sh examples/sweeps/table32.json out/table32
#   sbatch --dependency=afterany:JOBID examples/sweeps/slurm_array.sh --collect examples/sweeps/table32.json out/table32
# A task that is killed (time limit, node failure) loses only the point it was running: submit the
# same array again and the shards skip the points done and resume the rest from their checkpoints.
#SBATCH --job-name=mrjam-sweep
#SBATCH --cpus-per-task=2
#SBATCH --time=12:00:00
set -euo pipefail
if [ "${1:-}" = "--collect" ]; then
  exec mrjam sweep "$2" --out "$3" --collect
fi
shards="${SLURM_ARRAY_TASK_COUNT:?run as a job array: sbatch --array=0-N ...}"
exec mrjam sweep "$1" --out "$2" --shard "${SLURM_ARRAY_TASK_ID}/${shards}" --threads "${SLURM_CPUS_PER_TASK:-1}" --yes

#!/usr/bin/env bash
# A Slurm job array over a batch manifest: one array task per cache. Slurm sets
# SLURM_ARRAY_TASK_ID in each task, and `surftrack batch` runs that cache (0-based) into
# OUTROOT/NAME/. Set --array to 0-(caches - 1):
#
#   sbatch --array=0-9 docs/farm/slurm.sh /shows/caches.txt /shows/tracked
#   sbatch --dependency=afterany:JOBID --wrap 'surftrack batch /shows/caches.txt -o /shows/tracked --report'
#
# A requeued or resubmitted task resumes its cache from the last complete frame; a cache done
# before is skipped.
#SBATCH --job-name=surftrack
#SBATCH --cpus-per-task=2
#SBATCH --mem=8G
#SBATCH --requeue
#SBATCH --output=surftrack-%A_%a.log
set -euo pipefail
manifest="$1"
outroot="$2"
exec surftrack batch "$manifest" -o "$outroot" --backend auto

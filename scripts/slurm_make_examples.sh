#!/usr/bin/env bash
# Acquires a large example set as a Slurm job array: one shard per array task, then one merge.
#   sbatch --array=1-N scripts/slurm_make_examples.sh SCENE SET_DIR [de_make_examples options...]
#   sbatch --dependency=afterok:<array job id> --wrap "devel/lib/deformation_enrichment/de_merge_examples \
#          --output SET_DIR SET_DIR.shard-*"
# Every task runs `de_make_examples --shard TASK/N` into SET_DIR.shard-TASK (resumable: a requeued task
# keeps what it acquired). The package must be built on a path the nodes share (scripts/test or catkin_make).
#SBATCH --job-name=de_make_examples
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=02:00:00
#SBATCH --output=de_make_examples-%A_%a.log
set -eo pipefail
[ $# -ge 2 ] || { echo "usage: sbatch --array=1-N $0 SCENE SET_DIR [options]" >&2; exit 2; }
[ -n "${SLURM_ARRAY_TASK_ID:-}" ] && [ -n "${SLURM_ARRAY_TASK_COUNT:-}" ] ||
  { echo "$0: run as a Slurm job array (sbatch --array=1-N)" >&2; exit 2; }
scene="$1" set_dir="$2"
shift 2
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${DE_BIN:-$root/devel/lib/deformation_enrichment}"  # a catkin workspace: DE_BIN=~/catkin_ws/devel/lib/...
export OMP_NUM_THREADS="${SLURM_CPUS_PER_TASK:-1}"
exec "$bin/de_make_examples" --scene "$scene" \
  --shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT" --output "$set_dir.shard-$SLURM_ARRAY_TASK_ID" "$@"

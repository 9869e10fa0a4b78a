#!/usr/bin/env bash
# Two shards acquired at the same time, as two tasks of a Slurm job array would (scripts/slurm_make_examples.sh
# with the array variables Slurm sets), merged by de_merge_examples: the merged set must equal one run of the
# whole plan byte for byte (manifest and stamps). Usage: shards_in_parallel.sh SOURCE_DIR TOOL_DIR
set -eo pipefail
source_dir="$1" tools="$2"
work=$(mktemp -d /tmp/de_shards.XXXXXX)
trap 'rm -rf "$work"' EXIT
# A small slab (coarse 5 x 5 x 1, fine 10 x 10 x 2 cells) and a 4-line plan keep the test short.
sed -e 's/coarse_cells: \[10, 10, 2\]/coarse_cells: [5, 5, 1]/' -e 's/fine_cells: \[24, 24, 4\]/fine_cells: [10, 10, 2]/' \
  -e 's/fine_skin_layers: 2/fine_skin_layers: 1/' -e 's/plan: slab_plan.csv/plan: plan.csv/' \
  -e 's/resolution: 32/resolution: 16/' "$source_dir/config/scenes/slab.yaml" >"$work/small.yaml"
grep -q "coarse_cells: \[5, 5, 1\]" "$work/small.yaml" || { echo "FAIL: could not derive the small scene" >&2; exit 1; }
head -5 "$source_dir/config/scenes/slab_plan.csv" >"$work/plan.csv"
export OMP_NUM_THREADS=1
"$tools/de_make_examples" --scene "$work/small.yaml" --output "$work/one" 2>"$work/one.log"
pids=()
for task in 1 2; do
  DE_BIN="$tools" SLURM_ARRAY_TASK_ID=$task SLURM_ARRAY_TASK_COUNT=2 SLURM_CPUS_PER_TASK=1 \
    bash "$source_dir/scripts/slurm_make_examples.sh" "$work/small.yaml" "$work/set" 2>"$work/shard-$task.log" &
  pids+=($!)
done
for pid in "${pids[@]}"; do
  wait "$pid" || { cat "$work"/shard-*.log >&2; echo "FAIL: a shard failed" >&2; exit 1; }
done
"$tools/de_merge_examples" --output "$work/merged" "$work/set.shard-1" "$work/set.shard-2" 2>"$work/merge.log"
cmp "$work/one/stamps.bin" "$work/merged/stamps.bin" || { echo "FAIL: merged stamps differ from one run" >&2; exit 1; }
cmp "$work/one/manifest.json" "$work/merged/manifest.json" || { echo "FAIL: merged manifest differs from one run" >&2; exit 1; }
echo "two parallel shards merged into the single run's set: $(grep -c '"plan_line"' "$work/merged/manifest.json") examples, identical bytes"

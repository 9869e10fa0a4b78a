#!/usr/bin/env bash
# Acquisition speed-up from shards: the default slab plan (10 interactions) acquired by one de_make_examples
# run (OpenMP on every core) against N shards run at the same time, one core each, then merged; same
# process tree, back to back, wall clock (median of REPEATS). Usage: bench_shards.sh TOOL_DIR [SHARDS] [REPEATS]
set -eo pipefail
tools="$1" shards="${2:-$(nproc)}" repeats="${3:-3}"
work=$(mktemp -d /tmp/de_bench_shards.XXXXXX)
trap 'rm -rf "$work"' EXIT
seconds() { local s=$(date +%s%N); "$@"; awk -v a="$s" -v b="$(date +%s%N)" 'BEGIN {printf "%.2f\n", (b - a) / 1e9}'; }
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
one_run() { rm -rf "$work/one"; "$tools/de_make_examples" --scene slab --output "$work/one" 2>/dev/null; }
sharded_run() {
  rm -rf "$work"/shard-* "$work/merged"
  local pids=() i
  for i in $(seq "$shards"); do
    OMP_NUM_THREADS=1 "$tools/de_make_examples" --scene slab --shard "$i/$shards" --output "$work/shard-$i" 2>/dev/null &
    pids+=($!)
  done
  for i in "${pids[@]}"; do wait "$i"; done
  "$tools/de_merge_examples" --output "$work/merged" "$work"/shard-* 2>/dev/null
}
single=$(for _ in $(seq "$repeats"); do seconds one_run; done | median)
sharded=$(for _ in $(seq "$repeats"); do seconds sharded_run; done | median)
cmp -s "$work/one/stamps.bin" "$work/merged/stamps.bin" && same=identical || same=DIFFERENT
echo "acquisition of the default slab plan: one run ${single} s, ${shards} shards in parallel + merge ${sharded} s," \
     "speed-up $(awk -v a="$single" -v b="$sharded" 'BEGIN {printf "%.2f", a / b}')x (median of $repeats, $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)); stamps $same"

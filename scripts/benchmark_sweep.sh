#!/usr/bin/env bash
# Benchmarks of `fogpipe sweep` and of the job-array overhead (medians of REPS runs, wall time):
#  1. `fogpipe sweep` of 11 AR orders x 3 q scales x 3 R scales on a 1 h 100 Hz recording against
#     one `fogpipe run` of the same recording (target: sweep <= 2x run, since the EMD is reused);
#  2. job-array overhead per recording: `fogpipe plan` of a campaign, the start of every shard
#     (plan --shard + `fogpipe run` on finished results, i.e. process start, manifest and skip
#     checks) and `fogpipe merge` (target: < 1 s per recording). Slurm's own scheduling latency is
#     not included (it depends on the site's sched_interval).
#   scripts/benchmark_sweep.sh [FOGPIPE] [THREADS]   (REPS=3, WORK=/tmp/... in the environment)
set -euo pipefail
FOGPIPE="$(realpath "${1:-build/pipeline/fogpipe}")"
THREADS="${2:-2}"
REPS="${REPS:-3}"
work="${WORK:-$(mktemp -d /tmp/fogpipe-bench-sweep.XXXXXX)}"
mkdir -p "$work"
calc() { awk "BEGIN { printf \"%.4f\", $* }"; }
median() { sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }
seconds() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1 || { echo "failed: $*" >&2; return 1; }; t1=$(date +%s.%N); calc "$t1 - $t0"; }
# CPU seconds (user + sys) of a command: on a shared machine wall time also counts other processes.
cpu_seconds() { /usr/bin/time -f "%U %S" -o "$work/time.txt" "$@" >/dev/null 2>&1 || { echo "failed: $*" >&2; return 1; }; awk '{ printf "%.4f", $1 + $2 }' "$work/time.txt"; }

rec="$work/hour100hz.h5"
[ -f "$rec" ] || "$FOGPIPE" simulate -o "$rec" --profile paper --duration-s 3600 --sample-rate-hz 100 --seed 5 \
  --rate-profile "step:600:20,ramp:1200:1800:0.05,sine:0.005:10" >/dev/null 2>&1
run_times=(); sweep_times=(); run_cpu=(); sweep_cpu=()
sweep_args=(--ar-order 2:12 --q-scale 0.1,1,10 --r-scale 0.1,1,10)
for i in $(seq 1 "$REPS"); do
  rm -rf "$work/run"
  run_times+=("$(seconds "$FOGPIPE" run "$rec" -o "$work/run" --threads "$THREADS")")
  sweep_times+=("$(seconds "$FOGPIPE" sweep "$rec" -o "$work/sweep" --threads "$THREADS" "${sweep_args[@]}")")
  rm -rf "$work/run"
  run_cpu+=("$(cpu_seconds "$FOGPIPE" run "$rec" -o "$work/run" --threads "$THREADS")")
  sweep_cpu+=("$(cpu_seconds "$FOGPIPE" sweep "$rec" -o "$work/sweep" --threads "$THREADS" "${sweep_args[@]}")")
done
run_med=$(printf '%s\n' "${run_times[@]}" | median)
sweep_med=$(printf '%s\n' "${sweep_times[@]}" | median)
run_cpu_med=$(printf '%s\n' "${run_cpu[@]}" | median)
sweep_cpu_med=$(printf '%s\n' "${sweep_cpu[@]}" | median)
echo "run   1 h 100 Hz, $THREADS threads: median $run_med s wall, $run_cpu_med s CPU  (wall runs: ${run_times[*]})"
echo "sweep 110 settings, $THREADS threads: median $sweep_med s wall, $sweep_cpu_med s CPU  (wall runs: ${sweep_times[*]})"
echo "sweep / run = $(calc "$sweep_med / $run_med" | cut -c1-5) wall, $(calc "$sweep_cpu_med / $run_cpu_med" | cut -c1-5) CPU  (target <= 2)"

n=16
camp="$work/campaign"
[ -d "$camp/data" ] || "$FOGPIPE" simulate -o "$camp/data" --files "$n" --duration-s 600 \
  --sample-rate-hz 10 --seed 9 --profile paper >/dev/null 2>&1
"$FOGPIPE" plan "$camp/data" -o "$camp/manifest.txt" 2>/dev/null
"$FOGPIPE" run --manifest "$camp/manifest.txt" -o "$camp/out" --threads "$THREADS" >/dev/null 2>&1
plan_t=(); start_t=(); merge_t=()
for i in $(seq 1 "$REPS"); do
  plan_t+=("$(seconds "$FOGPIPE" plan "$camp/data" -o "$camp/manifest.txt")")
  t=0
  for shard in 0 1 2 3; do
    a=$(seconds "$FOGPIPE" plan --manifest "$camp/manifest.txt" --shard $shard --num-shards 4 \
      -o "$camp/shard.txt")
    b=$(seconds "$FOGPIPE" run --manifest "$camp/shard.txt" -o "$camp/out")
    t=$(calc "$t + $a + $b")
  done
  start_t+=("$t")
  merge_t+=("$(seconds "$FOGPIPE" merge "$camp/out" -o "$camp/campaign.h5" --manifest "$camp/manifest.txt")")
done
p=$(printf '%s\n' "${plan_t[@]}" | median)
s=$(printf '%s\n' "${start_t[@]}" | median)
m=$(printf '%s\n' "${merge_t[@]}" | median)
echo "job-array overhead, $n recordings, 4 shards: plan $p s, shard starts $s s, merge $m s"
echo "per recording: $(calc "($p + $s + $m) / $n" | cut -c1-6) s  (target < 1)"
echo "work files in $work"

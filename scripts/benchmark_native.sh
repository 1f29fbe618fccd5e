#!/usr/bin/env bash
# Native (-march=native) against portable (x86-64 baseline) builds: `fogpipe run` on one simulated
# 1 h recording at 100 Hz (3.6e5 samples, the paper profile's noise terms), REPS runs of each binary,
# alternated so that both see the same machine load; prints wall and user CPU seconds (medians) and
# the load average before each run (/usr/bin/time -v).
#   scripts/benchmark_native.sh NATIVE_BUILD_DIR PORTABLE_BUILD_DIR [WORK_DIR]
# Build the two trees with -DFOGPIPE_NATIVE=ON and -DFOGPIPE_NATIVE=OFF first.
set -euo pipefail
native="$1/pipeline/fogpipe"
portable="$2/pipeline/fogpipe"
WORK="${3:-$(mktemp -d /tmp/fogpipe_native.XXXXXX)}"
REPS="${REPS:-3}"
THREADS="${THREADS:-2}"
"$portable" simulate --profile paper --sample-rate-hz 100 --seed 7 -o "$WORK/hour.h5" >/dev/null

# run_timed BINARY LABEL: prints "wall_s user_s".
run_timed() {
  rm -rf "$WORK/out_$2"
  /usr/bin/time -v -o "$WORK/time_$2.txt" "$1" run "$WORK/hour.h5" -o "$WORK/out_$2" \
    --threads "$THREADS" >/dev/null 2>&1
  awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; w=s}
              /User time/ {u=$2} END {print w, u}' "$WORK/time_$2.txt"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
: >"$WORK/native.txt"
: >"$WORK/portable.txt"
for rep in $(seq "$REPS"); do
  echo "rep $rep: load $(cut -d' ' -f1-3 /proc/loadavg)"
  run_timed "$native" native >>"$WORK/native.txt"
  run_timed "$portable" portable >>"$WORK/portable.txt"
done
for build in native portable; do
  wall=$(awk '{print $1}' "$WORK/$build.txt" | median)
  user=$(awk '{print $2}' "$WORK/$build.txt" | median)
  echo "$build: wall ${wall} s, user CPU ${user} s (median of $REPS; runs: $(awk '{printf "%s/%s ", $1, $2}' "$WORK/$build.txt"))"
done

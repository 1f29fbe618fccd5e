#!/usr/bin/env bash
# Benchmarks of `fogpipe run` (medians of REPS runs; wall time and peak RSS from /usr/bin/time -v).
#   1. One 24-hour recording at 100 Hz (8.64e6 samples), full method, 2 threads (target <= 25 s).
#   2. A campaign of 16 one-hour recordings at 100 Hz: 1 thread vs 2 threads (target >= 1.8x).
#   3. Peak RSS of that campaign under --memory-budget smaller than the campaign (target: within).
# Usage: scripts/benchmark_pipeline.sh [BUILD_DIR] [WORK_DIR]   (env REPS, default 3)
# Heavy: about 10 minutes on 2 free cores; needs ~2 GB of disk in WORK_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
WORK="${2:-$(mktemp -d /tmp/fogpipe_bench.XXXXXX)}"
REPS="${REPS:-3}"
FOGPIPE="$BUILD/pipeline/fogpipe"
PY=/usr/bin/python3
mkdir -p "$WORK/one" "$WORK/campaign"

# Recordings: white noise (N = 0.005 deg/sqrt(h)) + rate random walk + bias, seeded, deg/h,
# chunked like a logger would write them.
"$PY" - "$WORK" <<'PYEOF'
import sys, os, numpy as np, h5py
work = sys.argv[1]
def write(path, n, seed, fs=100.0):
    if os.path.exists(path):
        return
    rng = np.random.default_rng(seed)
    x = 0.005 * 60.0 * np.sqrt(fs) * rng.standard_normal(n)
    x += np.cumsum(0.005 / 60.0 / np.sqrt(fs) * rng.standard_normal(n)) + 0.02
    with h5py.File(path, "w") as f:
        f.attrs["sample_rate_hz"] = fs
        d = f.create_dataset("rate", data=x, chunks=(65536,))
        d.attrs["units"] = "deg/h"
write(f"{work}/one/day.h5", 8640000, 1)
for k in range(16):
    write(f"{work}/campaign/hour{k:02d}.h5", 360000, 100 + k)
PYEOF

# run_timed LABEL ARGS...: prints "LABEL wall_s max_rss_kb" for one run (fresh output folder).
run_timed() {
  local label="$1"; shift
  local out="$WORK/out_$label"
  rm -rf "$out"
  /usr/bin/time -v -o "$WORK/time_$label.txt" "$FOGPIPE" run "$@" -o "$out" >/dev/null 2>&1 || true
  local wall rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; print s}' "$WORK/time_$label.txt")
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$WORK/time_$label.txt")
  echo "$label $wall $rss"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }

echo "fogpipe benchmark: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), reps $REPS, work $WORK"
day=(); one=(); two=(); rss=()
for r in $(seq "$REPS"); do
  read -r _ w m < <(run_timed day "$WORK/one/day.h5" --threads 2); day+=("$w"); echo "  24 h @ 100 Hz, 2 threads: ${w} s, peak RSS ${m} kB"
  read -r _ w m < <(run_timed c1 "$WORK/campaign" --threads 1); one+=("$w"); echo "  16 x 1 h, 1 thread: ${w} s"
  read -r _ w m < <(run_timed c2 "$WORK/campaign" --threads 2); two+=("$w"); echo "  16 x 1 h, 2 threads: ${w} s"
  read -r _ w m < <(run_timed budget "$WORK/campaign" --threads 2 --memory-budget 256M); rss+=("$m")
  echo "  16 x 1 h, 2 threads, --memory-budget 256M: ${w} s, peak RSS ${m} kB"
done
d=$(printf '%s\n' "${day[@]}" | median); a=$(printf '%s\n' "${one[@]}" | median)
b=$(printf '%s\n' "${two[@]}" | median); m=$(printf '%s\n' "${rss[@]}" | median)
echo "median: 24 h recording, 2 threads: $d s (target <= 25 s)"
echo "median: campaign 1 thread $a s, 2 threads $b s, speed-up $(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a/b}') (target >= 1.8)"
echo "median: peak RSS under --memory-budget 256M: $m kB = $(awk -v m="$m" 'BEGIN {printf "%.0f", m/1024}') MiB (target <= 256 MiB; campaign inputs total $(du -sm "$WORK/campaign" | cut -f1) MiB on disk)"

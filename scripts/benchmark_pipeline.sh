#!/usr/bin/env bash
# Benchmarks of `fogpipe run` against its performance targets (medians of REPS runs; wall
# time and peak RSS from /usr/bin/time -v):
#   1. one 24-hour recording at 100 Hz (8.64e6 samples), full method, 2 threads (target <= 25 s);
#   2. a campaign of 16 one-hour recordings at 100 Hz, 1 thread and 2 threads (target >= 1.8x);
#   3. memory budget: that campaign under --memory-budget 512M (9x smaller than the campaign's
#      estimated need; target: peak RSS within it), and the 24 h recording under a budget below
#      its own need (documented behaviour: refused with a message saying what it needs, exit 1).
# Usage: scripts/benchmark_pipeline.sh [BUILD_DIR] [WORK_DIR]
# Environment: REPS (default 3); METHOD_ARGS, extra `fogpipe run` options for every run, e.g.
#   METHOD_ARGS="--q 1e-12 --r 2e-10" to time the pipeline with explicit Kalman noise variances.
# The 24 h run gets --memory-budget 8G (its estimate is about 7.1 GiB, its peak RSS about 4 GiB;
# the default 2G refuses it).
# Heavy: about 10 minutes on 2 free cores; needs ~3 GB of disk in WORK_DIR and ~4 GB of RAM. Run
# it on a quiet machine: the load average is printed before each run.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
WORK="${2:-$(mktemp -d /tmp/fogpipe_bench.XXXXXX)}"
REPS="${REPS:-3}"
read -r -a EXTRA <<<"${METHOD_ARGS:-}"
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

load() { cut -d' ' -f1 /proc/loadavg; }
# run_timed LABEL ARGS...: one run into a fresh output folder; prints "wall_s max_rss_kib exit".
run_timed() {
  local label="$1"; shift
  local out="$WORK/out_$label"
  rm -rf "$out"
  local code=0
  /usr/bin/time -v -o "$WORK/time_$label.txt" "$FOGPIPE" run "$@" "${EXTRA[@]}" -o "$out" \
    >"$WORK/stdout_$label.txt" 2>"$WORK/stderr_$label.txt" || code=$?
  local wall rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; print s}' "$WORK/time_$label.txt")
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$WORK/time_$label.txt")
  echo "$wall $rss $code"
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
mib() { awk -v k="$1" 'BEGIN {printf "%.0f", k / 1024}'; }

echo "fogpipe benchmark: $(nproc) cores, reps $REPS, work $WORK, extra options '${METHOD_ARGS:-}'"
day=(); dayrss=(); one=(); two=(); budget=(); loads=()
for r in $(seq "$REPS"); do
  loads+=("$(load)")
  read -r w m c < <(run_timed day "$WORK/one/day.h5" --threads 2 --memory-budget 8G)
  day+=("$w"); dayrss+=("$m")
  echo "  [$r] 24 h @ 100 Hz, 2 threads: $w s, peak RSS $(mib "$m") MiB, exit $c (load $(load))"
  read -r w m c < <(run_timed c1 "$WORK/campaign" --threads 1); one+=("$w")
  echo "  [$r] 16 x 1 h, 1 thread: $w s, exit $c (load $(load))"
  read -r w m c < <(run_timed c2 "$WORK/campaign" --threads 2); two+=("$w")
  echo "  [$r] 16 x 1 h, 2 threads: $w s, exit $c (load $(load))"
  read -r w m c < <(run_timed budget "$WORK/campaign" --threads 2 --memory-budget 512M)
  budget+=("$m")
  echo "  [$r] 16 x 1 h, 2 threads, --memory-budget 512M: $w s, peak RSS $(mib "$m") MiB, exit $c"
done
# The 24 h recording under a budget below its need: refused, with the reason, before reading it.
read -r w m c < <(run_timed over "$WORK/one/day.h5" --threads 2 --memory-budget 1G)
over_msg=$(grep -o '"message":"[^"]*"' "$WORK/out_over/status.jsonl" | head -1)

d=$(printf '%s\n' "${day[@]}" | median); drss=$(printf '%s\n' "${dayrss[@]}" | median)
a=$(printf '%s\n' "${one[@]}" | median); b=$(printf '%s\n' "${two[@]}" | median)
brss=$(printf '%s\n' "${budget[@]}" | median)
stages=$("$PY" - "$WORK/out_day/day.fogpipe.h5" <<'PYEOF'
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    p = f["provenance"]
    names = [n.decode() if isinstance(n, bytes) else n for n in p["stage_names"][:]]
    print(", ".join(f"{n} {s:.1f} s" for n, s in zip(names, p["stage_seconds"][:])))
PYEOF
)
echo
echo "Medians of $REPS (load average before each repetition: ${loads[*]})"
printf '%-52s %12s %12s\n' "case" "value" "target"
printf '%-52s %10s s %12s\n' "24 h @ 100 Hz, 2 threads: wall" "$d" "<= 25 s"
printf '%-52s %8s MiB %12s\n' "24 h @ 100 Hz, 2 threads: peak RSS" "$(mib "$drss")" ""
printf '%-52s %10s s\n' "16 x 1 h @ 100 Hz, 1 thread: wall" "$a"
printf '%-52s %10s s\n' "16 x 1 h @ 100 Hz, 2 threads: wall" "$b"
printf '%-52s %10s x %12s\n' "16 x 1 h: speed-up 1 -> 2 threads" \
  "$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a/b}')" ">= 1.8 x"
printf '%-52s %8s MiB %12s\n' "16 x 1 h, --memory-budget 512M: peak RSS" "$(mib "$brss")" \
  "<= 512 MiB"
printf '%-52s %8s MiB %12s\n' "24 h, --memory-budget 1G: peak RSS (exit $c)" "$(mib "$m")" \
  "<= 1024 MiB"
echo "stage times of the last 24 h run (provenance): $stages"
echo "24 h under 1G: $over_msg"
echo "campaign inputs: $(du -sm "$WORK/campaign" | cut -f1) MiB on disk; 24 h results file:" \
  "$(du -sm "$WORK/out_day" | cut -f1) MiB"

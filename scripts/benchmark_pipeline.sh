#!/usr/bin/env bash
# Benchmarks of `fogpipe run` against its performance targets (medians of REPS runs; wall time
# and peak RSS from /usr/bin/time -v, bytes per sample = peak RSS / samples):
#   1. one 1 h recording at 100 Hz (3.6e5 samples) and one 24 h recording at 100 Hz (8.64e6),
#      full method, 2 threads (targets: 24 h <= 20 s wall, <= 100 bytes of peak RSS per sample,
#      and 24 h / 1 h wall <= 26);
#   2. a campaign of 16 one-hour recordings at 100 Hz, 1 thread and 2 threads (target >= 1.8x);
#   3. the memory budget: that campaign under --memory-budget 512M (target: peak RSS within it),
#      and the 24 h recording under a budget below its need (refused with a message saying what
#      it needs, exit 1);
#   4. with LONG=1 (heavy: ~20 GB of disk, ~15 GB of RAM, about 10 minutes each): 72 h at
#      100 Hz with three axes in one run under --memory-budget 20G (target: completes within the
#      budget), and 24 h at 1 kHz, one axis (8.64e7 samples; targets <= 180 s, <= 10 GB).
# Usage: scripts/benchmark_pipeline.sh [BUILD_DIR] [WORK_DIR]
# Environment: REPS (default 3); LONG=1 for case 4 (one run each); METHOD_ARGS, extra `fogpipe
#   run` options for every run, e.g. METHOD_ARGS="--q 1e-12 --r 2e-10".
# Run it on a quiet machine: the load average is printed before each run. The targets are quoted
# for a native build (-DFOGPIPE_NATIVE=ON, docs/performance.md): pass its folder as BUILD_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
WORK="${2:-$(mktemp -d /tmp/fogpipe_bench.XXXXXX)}"
REPS="${REPS:-3}"
LONG="${LONG:-0}"
read -r -a EXTRA <<<"${METHOD_ARGS:-}"
FOGPIPE="$BUILD/pipeline/fogpipe"
PY=/usr/bin/python3
mkdir -p "$WORK/one" "$WORK/campaign" "$WORK/long"

# Recordings: white noise (N = 0.005 deg/sqrt(h)) + rate random walk + bias, seeded, deg/h,
# chunked like a logger would write them.
"$PY" - "$WORK" "$LONG" <<'PYEOF'
import sys, os, numpy as np, h5py
work, long_cases = sys.argv[1], sys.argv[2] == "1"
def write(path, n, seed, fs=100.0, axes=1):
    if os.path.exists(path):
        return
    rng = np.random.default_rng(seed)
    cols = []
    for _ in range(axes):
        x = 0.005 * 60.0 * np.sqrt(fs) * rng.standard_normal(n)
        x += np.cumsum(0.005 / 60.0 / np.sqrt(fs) * rng.standard_normal(n)) + 0.02
        cols.append(x)
    with h5py.File(path, "w") as f:
        f.attrs["sample_rate_hz"] = fs
        data = cols[0] if axes == 1 else np.stack(cols, axis=1)
        d = f.create_dataset("rate", data=data, chunks=(65536,) if axes == 1 else (65536, 1))
        d.attrs["units"] = "deg/h"
        if axes > 1:
            d.attrs["axes"] = ["x", "y", "z"][:axes]
write(f"{work}/one/hour.h5", 360000, 2)
write(f"{work}/one/day.h5", 8640000, 1)
for k in range(16):
    write(f"{work}/campaign/hour{k:02d}.h5", 360000, 100 + k)
if long_cases:
    write(f"{work}/long/h72_3axes.h5", 72 * 360000, 8, axes=3)
    write(f"{work}/long/day_1khz.h5", 86400000, 7, fs=1000.0)
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
per_sample() { awk -v k="$1" -v n="$2" 'BEGIN {printf "%.0f", k * 1024 / n}'; }
stages() {
  "$PY" - "$1" <<'PYEOF'
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    p = f["provenance"]
    names = [n.decode() if isinstance(n, bytes) else n for n in p["stage_names"][:]]
    print(", ".join(f"{n} {s:.1f} s" for n, s in zip(names, p["stage_seconds"][:])))
PYEOF
}

echo "fogpipe benchmark: $(nproc) cores, reps $REPS, work $WORK, extra options '${METHOD_ARGS:-}'"
hour=(); day=(); dayrss=(); one=(); two=(); budget=(); loads=()
for r in $(seq "$REPS"); do
  loads+=("$(load)")
  read -r w m c < <(run_timed hour "$WORK/one/hour.h5" --threads 2); hour+=("$w")
  echo "  [$r] 1 h @ 100 Hz, 2 threads: $w s, peak RSS $(mib "$m") MiB, exit $c (load $(load))"
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
read -r ow om oc < <(run_timed over "$WORK/one/day.h5" --threads 2 --memory-budget 1G)
over_msg=$(grep -o '"message":"[^"]*"' "$WORK/out_over/status.jsonl" | head -1)

h=$(printf '%s\n' "${hour[@]}" | median)
d=$(printf '%s\n' "${day[@]}" | median); drss=$(printf '%s\n' "${dayrss[@]}" | median)
a=$(printf '%s\n' "${one[@]}" | median); b=$(printf '%s\n' "${two[@]}" | median)
brss=$(printf '%s\n' "${budget[@]}" | median)
echo
echo "Medians of $REPS (load average before each repetition: ${loads[*]})"
printf '%-56s %12s %12s\n' "case" "value" "target"
printf '%-56s %10s s\n' "1 h @ 100 Hz, 2 threads: wall" "$h"
printf '%-56s %10s s %12s\n' "24 h @ 100 Hz, 2 threads: wall" "$d" "<= 20 s"
printf '%-56s %10s x %12s\n' "24 h / 1 h wall" \
  "$(awk -v a="$d" -v b="$h" 'BEGIN {printf "%.1f", a/b}')" "<= 26 x"
printf '%-56s %8s MiB\n' "24 h @ 100 Hz, 2 threads: peak RSS" "$(mib "$drss")"
printf '%-56s %10s B %12s\n' "24 h @ 100 Hz: peak RSS per sample" "$(per_sample "$drss" 8640000)" \
  "<= 100 B"
printf '%-56s %10s s\n' "16 x 1 h @ 100 Hz, 1 thread: wall" "$a"
printf '%-56s %10s s\n' "16 x 1 h @ 100 Hz, 2 threads: wall" "$b"
printf '%-56s %10s x %12s\n' "16 x 1 h: speed-up 1 -> 2 threads" \
  "$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a/b}')" ">= 1.8 x"
printf '%-56s %8s MiB %12s\n' "16 x 1 h, --memory-budget 512M: peak RSS" "$(mib "$brss")" \
  "<= 512 MiB"
printf '%-56s %8s MiB %12s\n' "24 h, --memory-budget 1G: peak RSS (exit $oc)" "$(mib "$om")" \
  "<= 1024 MiB"
echo "stage times of the last 24 h run (provenance): $(stages "$WORK/out_day/day.fogpipe.h5")"
echo "24 h under 1G: $over_msg"

if [ "$LONG" = "1" ]; then
  echo
  echo "Long recordings, one run each (load $(load))"
  read -r w m c < <(run_timed h72 "$WORK/long/h72_3axes.h5" --threads 2 --memory-budget 20G)
  printf '%-56s %10s s, %s MiB peak RSS, exit %s (target: completes, <= 20480 MiB)\n' \
    "72 h @ 100 Hz, 3 axes, --memory-budget 20G" "$w" "$(mib "$m")" "$c"
  echo "  stages: $(stages "$WORK/out_h72/h72_3axes.fogpipe.h5")"
  read -r w m c < <(run_timed khz "$WORK/long/day_1khz.h5" --threads 2 --memory-budget 20G)
  printf '%-56s %10s s, %s MiB peak RSS, exit %s (targets <= 180 s, <= 10240 MiB)\n' \
    "24 h @ 1 kHz, 1 axis, --memory-budget 20G" "$w" "$(mib "$m")" "$c"
  echo "  stages: $(stages "$WORK/out_khz/day_1khz.fogpipe.h5")"
  echo "  results file: $(du -sm "$WORK/out_khz" | cut -f1) MiB"
fi

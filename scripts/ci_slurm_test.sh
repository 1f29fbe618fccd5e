#!/usr/bin/env bash
# The real single-node Slurm test (ctest label `slurm`): a simulated campaign as a job array.
#
#   scripts/ci_slurm_test.sh FOGPIPE_BINARY [WORKDIR]
#
# 1. installs slurm-wlm and munge from Debian when missing (the CI machine is fresh and root);
# 2. starts munged, slurmctld and slurmd privately on localhost (scripts/slurm/local_cluster.sh);
# 3. simulates NUM_RECORDINGS short recordings (10 min at 10 Hz), plans them, submits the array in
#    4 shards plus the afterany merge job (scripts/slurm/submit_campaign.sh), waits by polling
#    `scontrol show job` (no sacct without slurmdbd) and checks campaign.h5 with h5py;
# 4. the killed shard: a second campaign (1 h at 100 Hz recordings, so that a shard is still busy
#    when it is killed) where shard 1 gets SIGKILL (scancel -s KILL) after its first results
#    file; the merge then lists its unfinished files as missing; only index 1 is resubmitted,
#    and the merged table is complete with every recording exactly once, and every recording
#    analysed exactly once (status.jsonl);
# 5. stops every daemon it started, by PID, in an EXIT trap.
# Exit 77 (ctest: skipped) when Slurm is missing and cannot be installed (not root).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
FOGPIPE="$(realpath "${1:?usage: $0 FOGPIPE_BINARY [WORKDIR]}")"
NUM_RECORDINGS="${NUM_RECORDINGS:-16}"
NUM_SHARDS=4
PY=/usr/bin/python3

need_install=0
for exe in munged slurmctld slurmd sbatch scontrol; do command -v "$exe" >/dev/null || need_install=1; done
if [ "$need_install" = 1 ]; then
  if [ "$(id -u)" != 0 ]; then echo "ci_slurm_test: slurm-wlm/munge missing and not root: skipped"; exit 77; fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y --no-install-recommends slurm-wlm munge >/dev/null ||
    { apt-get update >/dev/null && apt-get install -y --no-install-recommends slurm-wlm munge >/dev/null; }
fi

work="${2:-$(mktemp -d /tmp/fogpipe-slurm.XXXXXX)}"
mkdir -p "$work"
work="$(cd "$work" && pwd)"
cluster="$work/cluster"
cleanup() {
  local rc=$?
  "$here/slurm/local_cluster.sh" stop "$cluster" >/dev/null 2>&1 || true
  if [ "$rc" = 0 ] && [ -z "${2:-}" ] && [ -z "${KEEP_WORK:-}" ]; then rm -rf "$work"; else echo "ci_slurm_test: files kept in $work"; fi
}
trap cleanup EXIT
trap 'exit 143' TERM INT
t0=$SECONDS
"$here/slurm/local_cluster.sh" start "$cluster"
export SLURM_CONF="$cluster/slurm.conf"

# Waits until none of the given jobs (array ids include all their tasks) is pending or running.
wait_jobs() {
  local deadline=$((SECONDS + ${WAIT_LIMIT_S:-240})) states
  while :; do
    states="$(for id in "$@"; do scontrol show job "$id" 2>/dev/null | grep -o 'JobState=[A-Z_]*' || true; done)"
    if [ -n "$states" ] && ! grep -qE 'PENDING|RUNNING|CONFIGURING|COMPLETING|SUSPENDED|REQUEUED' <<<"$states"; then
      return 0
    fi
    if [ "$SECONDS" -gt "$deadline" ]; then
      echo "ci_slurm_test: jobs $* did not finish: $states" >&2
      squeue >&2 || true
      return 1
    fi
    sleep 0.3
  done
}

data="$work/recordings"
"$FOGPIPE" simulate -o "$data" --files "$NUM_RECORDINGS" --profile paper --duration-s 600 \
  --sample-rate-hz 10 \
  --seed 11 --instrument "SIM-FOG" >/dev/null

# ---- 1. The campaign: 4 shards + afterany merge --------------------------------------------------
out_a="$work/campaign-a"
submitted="$(FOGPIPE="$FOGPIPE" "$here/slurm/submit_campaign.sh" -n "$NUM_SHARDS" -k "$NUM_SHARDS" \
  -c 1 -o "$out_a" "$data")"
echo "ci_slurm_test: $submitted"
array_a="$(sed -n 's/.*array_job=\([0-9]*\).*/\1/p' <<<"$submitted")"
merge_a="$(sed -n 's/.*merge_job=\([0-9]*\).*/\1/p' <<<"$submitted")"
wait_jobs "$array_a" "$merge_a"
$PY "$here/slurm/check_campaign.py" "$out_a/campaign.h5" "$out_a/manifest.txt" --expect-complete

# ---- 2. The killed shard -------------------------------------------------------------------------
out_b="$work/campaign-b"
victim=1
mkdir -p "$out_b/slurm-logs"
# Longer recordings (1 h at 100 Hz, about 1 s of analysis each on one CPU) than campaign a's: with
# 10-minute ones a shard finished its remaining files between the poll that saw its first results
# file and the scancel, and the kill scenario did not happen.
data_b="$work/recordings-b"
"$FOGPIPE" simulate -o "$data_b" --files "$NUM_RECORDINGS" --profile paper --duration-s 3600 \
  --sample-rate-hz 100 --seed 31 --instrument "SIM-FOG" >/dev/null
"$FOGPIPE" plan "$data_b" -o "$out_b/manifest.txt"
"$FOGPIPE" plan --manifest "$out_b/manifest.txt" --shard "$victim" --num-shards "$NUM_SHARDS" \
  -o "$work/victim.txt" 2>/dev/null
mapfile -t victim_files < <(grep -v '^#' "$work/victim.txt" | awk '{print $1}')
submit_array() {  # INDICES
  sbatch --parsable --array="$1" --cpus-per-task=1 --output="$out_b/slurm-logs/shard-%A_%a.log" \
    --export="ALL,FOGPIPE=$FOGPIPE,MANIFEST=$out_b/manifest.txt,NUM_SHARDS=$NUM_SHARDS,OUTDIR=$out_b,FOGPIPE_ARGS=--threads 1" \
    "$here/slurm/fogpipe_array.sbatch"
}
submit_merge() {  # DEPENDENCY
  sbatch --parsable --dependency="afterany:$1" --output="$out_b/slurm-logs/merge-%j.log" \
    --export="ALL,FOGPIPE=$FOGPIPE,OUTDIR=$out_b,MANIFEST=$out_b/manifest.txt" \
    "$here/slurm/fogpipe_merge.sbatch"
}
victim_done() {
  local n=0 f
  for f in "${victim_files[@]}"; do
    [ -f "$out_b/$(basename "${f%.h5}").fogpipe.h5" ] && n=$((n + 1))
  done
  echo "$n"
}
array_b="$(submit_array "0-$((NUM_SHARDS - 1))")"
merge_b="$(submit_merge "$array_b")"
deadline=$((SECONDS + 120))
until [ "$(victim_done)" -ge 1 ]; do
  [ "$SECONDS" -lt "$deadline" ] || { echo "ci_slurm_test: shard $victim never finished a file" >&2; exit 1; }
  sleep 0.05
done
# --batch: SIGKILL straight to the batch step (fogpipe, by exec); without it Slurm cancels the
# job with SIGTERM first and fogpipe would stop cleanly, which is not the scenario here.
scancel --batch -s KILL "${array_b}_${victim}"
wait_jobs "$array_b" "$merge_b"
done_at_kill="$(victim_done)"
echo "ci_slurm_test: shard $victim killed with $done_at_kill of ${#victim_files[@]} files done"
if [ "$done_at_kill" -ge "${#victim_files[@]}" ]; then
  echo "ci_slurm_test: the shard finished before SIGKILL arrived; the scenario did not happen" >&2
  exit 1
fi
scontrol show job "${array_b}_${victim}" | grep -o 'JobState=[A-Z_]*'
# The first merge (afterany) ran: the unfinished files of the killed shard are "missing".
$PY "$here/slurm/check_campaign.py" "$out_b/campaign.h5" "$out_b/manifest.txt" \
  --expect-missing "$(( ${#victim_files[@]} - done_at_kill ))"
# Resubmit only the killed index, then merge again.
resubmit="$(submit_array "$victim")"
merge_b2="$(submit_merge "$resubmit")"
wait_jobs "$resubmit" "$merge_b2"
$PY "$here/slurm/check_campaign.py" "$out_b/campaign.h5" "$out_b/manifest.txt" --expect-complete \
  --status-log "$out_b/status.jsonl"
echo "ci_slurm_test: all checks passed in $((SECONDS - t0)) s"

#!/usr/bin/env bash
# Plans a campaign, submits it as a Slurm job array of NUM_SHARDS shards (at most MAX_RUNNING at once)
# and a merge job that runs after all of them (afterany).
#   scripts/slurm/submit_campaign.sh -n NUM_SHARDS [-k MAX_RUNNING] [-c CPUS] -o OUTDIR INPUT...
# Prints the array job id and the merge job id.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
# The binary: $FOGPIPE, else the build tree's (run from a checkout), else fogpipe on PATH (installed).
if [ -z "${FOGPIPE:-}" ]; then
  FOGPIPE="$here/../../build/pipeline/fogpipe"
  [ -x "$FOGPIPE" ] || FOGPIPE="$(command -v fogpipe || true)"
  [ -n "$FOGPIPE" ] || { echo "$0: set FOGPIPE to the fogpipe binary" >&2; exit 2; }
fi
num_shards=4; max_running=4; cpus=2; outdir=""
while getopts "n:k:c:o:" opt; do
  case "$opt" in
    n) num_shards="$OPTARG" ;;
    k) max_running="$OPTARG" ;;
    c) cpus="$OPTARG" ;;
    o) outdir="$OPTARG" ;;
    *) echo "usage: $0 -n NUM_SHARDS [-k MAX_RUNNING] [-c CPUS] -o OUTDIR INPUT..." >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ -n "$outdir" ] && [ "$#" -gt 0 ] || { echo "usage: $0 -n NUM_SHARDS -o OUTDIR INPUT..." >&2; exit 2; }
mkdir -p "$outdir/slurm-logs"
outdir="$(cd "$outdir" && pwd)"
FOGPIPE="$(cd "$(dirname "$FOGPIPE")" && pwd)/$(basename "$FOGPIPE")"
manifest="$outdir/manifest.txt"
"$FOGPIPE" plan "$@" -o "$manifest"
array_id=$(sbatch --parsable --array="0-$((num_shards - 1))%${max_running}" --cpus-per-task="$cpus" \
  --output="$outdir/slurm-logs/shard-%A_%a.log" \
  --export="ALL,FOGPIPE=$FOGPIPE,MANIFEST=$manifest,NUM_SHARDS=$num_shards,OUTDIR=$outdir,SHARD_BY=${SHARD_BY:-stride}" \
  "$here/fogpipe_array.sbatch")
merge_id=$(sbatch --parsable --dependency="afterany:${array_id}" \
  --output="$outdir/slurm-logs/merge-%j.log" \
  --export="ALL,FOGPIPE=$FOGPIPE,OUTDIR=$outdir,MANIFEST=$manifest" "$here/fogpipe_merge.sbatch")
echo "array_job=$array_id merge_job=$merge_id manifest=$manifest"

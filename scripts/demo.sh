#!/usr/bin/env bash
# The README's demo command: installs dependencies, builds in Release, simulates a small campaign in the
# paper's setting (1 h at 1 Hz, navigation-grade FOG), runs the whole method on it and prints the
# paper's Tables 3 and 5 for the first recording.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
FOGPIPE="${BUILD_DIR:-build}/pipeline/fogpipe"
DEMO_DIR="${DEMO_DIR:-demo-campaign}"
rm -rf "$DEMO_DIR"
mkdir -p "$DEMO_DIR"
"$FOGPIPE" simulate --profile paper --files 4 --seed 1 -o "$DEMO_DIR/recordings"
"$FOGPIPE" run "$DEMO_DIR/recordings" -o "$DEMO_DIR/results" --threads "$(nproc)"
"$FOGPIPE" merge "$DEMO_DIR/results"
/usr/bin/python3 scripts/campaign_report.py "$DEMO_DIR/results" -o "$DEMO_DIR/report"
first="$(ls "$DEMO_DIR"/results/*.fogpipe.h5 | head -n 1)"
"$FOGPIPE" info "$first"
echo
echo "fogpipe demo: recordings in $DEMO_DIR/recordings, results in $DEMO_DIR/results"
echo "              per-file status in $DEMO_DIR/results/status.jsonl"
echo "              campaign table $DEMO_DIR/results/campaign.h5, report $DEMO_DIR/report/index.html"

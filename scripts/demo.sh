#!/usr/bin/env bash
# Quick start, command 1: install dependencies, build, and run the demo session on the simulated device
# in real time, then plot what happened.
# Usage: scripts/demo.sh [SESSION.yaml] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
session=${1:-config/sessions/demo.yaml}
seconds=${2:-5}
bash scripts/build.sh default
out=build/demo
mkdir -p "$out"
echo "== hapticd --config $session --duration $seconds"
build/default/bin/hapticd --config "$session" --duration "$seconds" \
  --record "$out/recording.csv" --stats-json "$out/stats.json"
/usr/bin/python3 scripts/plot_recording.py "$out/recording.csv" "$out/demo.png"
echo "== recording: $out/recording.csv, loop statistics: $out/stats.json, plot: $out/demo.png"

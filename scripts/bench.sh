#!/usr/bin/env bash
# Runs the benchmark programs with medians over repetitions; the model benchmark prints the KDL/ours ratios.
# Usage: scripts/bench.sh [REPETITIONS]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-10}
[ -x build/default/bin/model_benchmark ] || bash scripts/build.sh default > /dev/null
build/default/bin/model_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2

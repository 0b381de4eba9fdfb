#!/usr/bin/env bash
# Runs the benchmark programs with medians over repetitions: the model toolbox against KDL (with the ratios)
# the simulated devices (real_time_factor) and the control schemes (compute time per cycle, ratio to the
# per-cycle model terms), the redundancy resolutions on the ViSHaRD10 (ik_benchmark) and the group stage of the
# dual-arm sessions (group_benchmark).
# Usage: scripts/bench.sh [REPETITIONS]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-10}
[ -x build/default/bin/sim_benchmark ] || bash scripts/build.sh default > /dev/null
build/default/bin/model_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2
build/default/bin/sim_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true
build/default/bin/scheme_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2
build/default/bin/ik_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2
build/default/bin/group_benchmark --benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2

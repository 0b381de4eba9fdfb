#!/usr/bin/env bash
# Quick start, command 1: install dependencies, build, and run the demo: the server with the simulated
# ViSHaRD3 in admittance display, the example rendering engine (a wall, a cube, a sphere) coupled over DDS on
# the loopback interface, and the simulated operator pushing into the objects (driven with hapticctl).
# Then a dual-arm part: two simulated ViSHaRD3 facing each other in one device group, their operators moving the
# hands towards each other; the group's repulsion keeps the arms apart (felt on the handles), and a group E-stop
# stops both at once. Prints what happens; writes the engine's view, the server's recording and a plot to
# build/demo/ (or the folder --out names).
# Builds only what the demo runs (the CMake target `demo`: the server, the plugins, the scene engine, hapticctl,
# the plot), with the `default` preset; --no-build runs it from that build if there is one, else from the
# programs on PATH (an installation).
# Usage: scripts/demo.sh [--no-build] [--out DIR] [DOMAIN_ID]
set -euo pipefail
cd "$(dirname "$0")/.."
build=1
out=build/demo
domain=0
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) build=0 ;;
    --out)
      [ $# -ge 2 ] || { echo "demo: --out needs a folder" >&2; exit 2; }
      out=$2
      shift
      ;;
    -h | --help)
      sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    [0-9]*) domain=$1 ;;
    *) echo "demo: unknown argument '$1' (usage: scripts/demo.sh [--no-build] [--out DIR] [DOMAIN_ID])" >&2; exit 2 ;;
  esac
  shift
done

if [ "$build" = 1 ]; then
  bash scripts/install-deps.sh
  cmake --preset default > /dev/null
  cmake --build --preset default --target demo -j "$(nproc)"
  bin=build/default/bin
elif [ -x build/default/bin/hapticd ]; then
  bin=build/default/bin
elif command -v hapticd > /dev/null; then
  bin=$(dirname "$(command -v hapticd)")
else
  echo "demo: --no-build, but there is no build/default/bin/hapticd and no hapticd on PATH" >&2
  exit 2
fi
for program in hapticd hapticctl hapticd-scene-engine hapticd-plot-engine-run; do
  [ -x "$bin/$program" ] || { echo "demo: $bin/$program is missing (build it: scripts/demo.sh without --no-build)" >&2; exit 2; }
done
mkdir -p "$out" || { echo "demo: cannot create the output folder $out" >&2; exit 2; }
rm -f "$out"/engine.csv

live_view_port=${HAPTICD_LIVE_VIEW_PORT:-8765}
echo "== hapticd --config config/sessions/demo.yaml --dds-domain $domain (11 s, real time)"
echo "   live view: http://127.0.0.1:$live_view_port/ in a browser, or ws://127.0.0.1:$live_view_port in Foxglove or Lichtblick (docs/live-view.md)"
"$bin/hapticd" --config config/sessions/demo.yaml --dds-domain "$domain" --live-view "$live_view_port" \
  --record "$out/recording.h5" --stats-json "$out/stats.json" > "$out/server.log" 2>&1 &
server=$!
trap 'kill $server $engine 2>/dev/null || true' EXIT
engine=
"$bin/hapticd-scene-engine" --device vishard3 --domain "$domain" --csv "$out/engine.csv" --wait 10 &
engine=$!

ctl() { "$bin/hapticctl" --domain "$domain" --timeout 5 "$@"; }
ctl list
sleep 1
echo "== the operator pushes along +x (12 N): the wall is 30 mm ahead"
ctl operator vishard3 push 12 0 0 1.0
sleep 3
echo "== the operator pushes along -y (12 N): the cube is below"
ctl operator vishard3 push 0 -12 0 1.0
sleep 3
echo "== the operator pushes along -x (12 N): the sphere is that way"
ctl operator vishard3 push -12 0 0 1.0
sleep 2.5
ctl operator vishard3 release
wait "$engine" || true
wait "$server"
trap - EXIT
grep -E "round trip|engine commands|commands applied|cycles in|device |live view" "$out/server.log" | sed 's/^\[[^]]*\] \[[a-z]*\] /server: /'
"$bin/hapticd-plot-engine-run" "$out/engine.csv" "$out/demo.png"

echo "== dual arm: hapticd --config config/sessions/dual-arm/vishard3-pair.yaml (6 s, real time)"
"$bin/hapticd" --config config/sessions/dual-arm/vishard3-pair.yaml --dds-domain "$domain" \
  > "$out/dual-arm.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
ctl groups
echo "== the operators move their hands 15 cm towards each other (0.2 Hz); the arms meet in the repulsion"
sleep 4.5
echo "== group E-stop: both arms of the group 'table' at once"
ctl estop --group table
wait "$server" || true  # exit code 3: the devices were stopped
trap - EXIT
grep -E "group 'table'|device '(left|right)'" "$out/dual-arm.log" | sed 's/^\[[^]]*\] \[[a-z]*\] /server: /'
echo "== engine view: $out/engine.csv, server recording: $out/recording.h5 (hapticctl export ... --csv, hapticd-plot-recording), server log: $out/server.log, plot: $out/demo.png, dual-arm log: $out/dual-arm.log"

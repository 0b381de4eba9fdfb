#!/usr/bin/env bash
# A MuJoCo scene felt through the simulated device, in one command (docs/engines.md, "Physics engines"): the scene's
# session (config/scenes/SCENE.yaml) with its live view, hapticd-mujoco-engine on the scene, and the scene's
# operator script (config/scenes/SCENE.operator: timed `hapticctl operator` commands) played against the
# simulated operator; at the end, where the script's watched bodies are and what the goal was.
#   scripts/scene-demo.sh peg-in-hole|table-blocks|door-drawer|bimanual-box [--bin DIR] [--live-view PORT]
#                         [--domain D] [--hold S]
#     --live-view: the page http://127.0.0.1:PORT/ (default 8765; 0: a free port, named in the log);
#     --hold: seconds the session runs on after the script's last command (default 3)
set -uo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
scene=${1:-}
[ -n "$scene" ] && [ "${scene#-}" = "$scene" ] || { sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
shift
bin="" port=8765 domain=0 hold=3
while [ $# -gt 0 ]; do
  case $1 in
    --bin) bin=$2; shift 2 ;;
    --live-view) port=$2; shift 2 ;;
    --domain) domain=$2; shift 2 ;;
    --hold) hold=$2; shift 2 ;;
    *) echo "scene-demo: unknown option '$1'" >&2; exit 2 ;;
  esac
done
script="$src/config/scenes/$scene.operator"
[ -f "$script" ] || { echo "scene-demo: no operator script $script (scenes: $(cd "$src/config/scenes" && ls *.operator | sed 's/\.operator//' | tr '\n' ' '))" >&2; exit 2; }
if [ -z "$bin" ]; then
  for b in "$src/build/default/bin" "$src/build/ci/bin"; do [ -x "$b/hapticd-mujoco-engine" ] && { bin=$b; break; }; done
  [ -n "$bin" ] || bin=$(dirname "$(command -v hapticd-mujoco-engine || echo /nonexistent/x)")
fi
[ -x "$bin/hapticd-mujoco-engine" ] || { echo "scene-demo: no hapticd-mujoco-engine in $bin (--bin DIR)" >&2; exit 2; }
engine_args=$(sed -n 's/^# engine: //p' "$script")
watch=$(sed -n 's/^# watch: //p' "$script")
goal=$(sed -n "/^# goal: /,/^[^#]/p" "$script" | grep "^#" | sed "s/^# \(goal: \)\{0,1\} *//" | tr "\n" " ")
last=$(awk '!/^#/ && NF { t = $1 } END { print t + 0 }' "$script")
seconds=$(awk -v l="$last" -v h="$hold" 'BEGIN { printf "%d", l + h + 4 }')
out=$(mktemp -d "${TMPDIR:-/tmp}/hapticd-scene-demo.XXXXXX")
"$bin/hapticd" --config "$src/config/scenes/$scene.yaml" --dds-domain "$domain" --duration "$seconds" --busy-machine \
  --live-view "$port" > "$out/server.log" 2>&1 &
server=$!
trap 'kill $server $engine 2> /dev/null' EXIT
engine=""
"$bin/hapticd-mujoco-engine" "$src/config/scenes/$scene.xml" $engine_args --domain "$domain" --wait 10 \
  --duration $((seconds - 1)) $(for b in $watch; do echo --watch "$b"; done) > "$out/engine.log" 2>&1 &
engine=$!
for _ in $(seq 100); do grep -q "claimed" "$out/engine.log" && break; sleep 0.1; done
grep -q "claimed" "$out/engine.log" || { echo "scene-demo: the engine did not claim: $(tail -3 "$out/engine.log")"; exit 1; }
grep -o "live view on .*" "$out/server.log" | sed 's/^/scene-demo: /'
echo "scene-demo: playing $script"
start=$(date +%s.%N)
while read -r at device command args; do
  case $at in '#'* | '') continue ;; esac
  sleep "$(awk -v a="$at" -v s="$start" -v n="$(date +%s.%N)" 'BEGIN { d = a - (n - s); print (d > 0 ? d : 0) }')"
  echo "  t=$at s: $device $command $args"
  "$bin/hapticctl" --domain "$domain" --timeout 5 operator "$device" "$command" $args > /dev/null ||
    echo "scene-demo: hapticctl operator $device $command $args failed"
done < "$script"
wait "$engine"
wait "$server"
code=$?
trap - EXIT
grep "at the end" "$out/engine.log"
echo "scene-demo: the goal: $goal"
grep -E "device '.*': " "$out/server.log" | sed 's/^\[[^]]*\] \[[a-z]*\] /scene-demo: /' | tail -4
echo "scene-demo: logs in $out"
exit $code

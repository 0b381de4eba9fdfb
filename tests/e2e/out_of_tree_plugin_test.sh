#!/usr/bin/env bash
# The SDK as a plugin author gets it: install hapticd to a prefix, build examples/out_of_tree_plugin (one plugin
# of each kind but inverse kinematics, and their GoogleTest tests) against the installed package with
# find_package(hapticd), run those tests, then have the installed server list the plugins, load the controller and run
# a lockstep session with it; then build examples/session_api against the same package and step an installed
# session file in-process with the session API (the installed plugins found beside libhapticd_server.so); then
# build examples/client_engine against the installed client library (hapticd::client) and have it render its
# wall over DDS (loopback, domain 90) to the installed server; and examples/mujoco_world against the installed
# MuJoCo coupling (hapticd::mujoco_coupling), pressing a proxy into the installed table scene's fixed box.
# Usage: out_of_tree_plugin_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
build=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
prefix="$work/prefix"
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
cmake -S "$src/examples/out_of_tree_plugin" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/configure.log"
cmake --build "$work/build" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
plugin_dir="$work/build"
ls "$plugin_dir"/libexample_plugins.so > /dev/null
# The example plugins' own tests, built against the installed SDK's test helpers (hapticd::testing).
ctest --test-dir "$work/build" --output-on-failure > "$work/ctest.log" || { cat "$work/ctest.log"; exit 1; }
grep -q "100% tests passed" "$work/ctest.log" || { echo "FAIL: the example plugins' tests"; cat "$work/ctest.log"; exit 1; }

export HAPTICD_PLUGIN_PATH="$plugin_dir"
listed=$("$prefix/bin/hapticd" --list-plugins)
for p in "example_spring_wall .*controller" "example_wall .*virtual_model" "example_point_mass .*virtual_model" \
         "example_linear_axis .*device" "example_spring_link .*group_model"; do
  echo "$listed" | grep -q "$p" || { echo "FAIL: plugin not listed: $p"; echo "$listed"; exit 1; }
done
"$prefix/bin/hapticd" --check-config "$src/examples/out_of_tree_plugin/session.yaml"
"$prefix/bin/hapticd" --config "$src/examples/out_of_tree_plugin/session.yaml" --clock lockstep --duration 1 \
  --stats-json "$work/stats.json" --record "$work/run.h5" --log-level warn
"$prefix/bin/hapticctl" export "$work/run.h5" --csv > /dev/null || { echo "FAIL: the recording does not export"; exit 1; }
grep -q '"fault": "none"' "$work/stats.json" || { echo "FAIL: device faulted"; cat "$work/stats.json"; exit 1; }
# The wall at 0.02 m holds the test device that the example's setpoint pushes to 0.05 m.
max=$(awk -F, 'NR > 1 && $1 > 1000 { if ($3 > m) m = $3 } END { print m }' "$(ls "$work"/run.*.csv | head -n 1)")
awk -v m="$max" 'BEGIN { exit !(m > 0.015 && m < 0.03) }' || { echo "FAIL: wall did not hold, max position $max"; exit 1; }
echo "out-of-tree plugin built against the installed SDK and loaded; wall holds at $max m"

# The session API from the installed package, no HAPTICD_PLUGIN_PATH: the plugins beside the library.
unset HAPTICD_PLUGIN_PATH
cmake -S "$src/examples/session_api" -B "$work/session_api" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/session_api_configure.log"
cmake --build "$work/session_api" > "$work/session_api_build.log"
session="$prefix/share/hapticd/config/sessions/vishard3/admittance-resolved-acceleration.yaml"
out=$("$work/session_api/step_session" "$session" 1.5 server.seed=3)
echo "$out"
echo "$out" | grep -q "^vishard3: t 1.4995 s, scheme default, fault none" || { echo "FAIL: session API run"; exit 1; }
echo "$out" | grep -q "^cycles 3000," || { echo "FAIL: cycle count"; exit 1; }
# A bad override is a located error, and nothing runs.
if err=$("$work/session_api/step_session" "$session" 1 devices.vishard3.virtual_model.parameters.mass_kg=-1 2>&1); then
  echo "FAIL: a negative mass was accepted"; exit 1
fi
echo "$err" | grep -q "override 'devices.vishard3.virtual_model.parameters.mass_kg=-1'" || { echo "FAIL: $err"; exit 1; }

# The C API from the installed package through pkg-config: the plain-C engine compiles, links and runs (its version
# check and a client made and ended; no server needed for that).
cmake -S "$src/examples/mujoco_world" -B "$work/mujoco_world" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/mujoco_world_configure.log"
cmake --build "$work/mujoco_world" > "$work/mujoco_world_build.log" || { cat "$work/mujoco_world_build.log"; exit 1; }
out=$("$work/mujoco_world/press_world" "$prefix/share/hapticd/config/scenes/table-blocks.xml")
echo "$out"
echo "$out" | grep -q "^proxy at x = 4[0-9]\.[0-9]* mm, hand at 60.00 mm" || { echo "FAIL: the embedded MuJoCo world"; exit 1; }

PKG_CONFIG_PATH="$prefix/lib/pkgconfig:$prefix/lib/$(gcc -print-multiarch)/pkgconfig" \
  cc -std=c11 -Wall -Wextra -Werror "$src/examples/c_api/wall_engine.c" -o "$work/c_wall_engine" \
  $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig:$prefix/lib/$(gcc -print-multiarch)/pkgconfig" \
    pkg-config --cflags --libs hapticd-client) -Wl,-rpath,"$prefix/lib" || { echo "FAIL: the C API through pkg-config"; exit 1; }
code=0
out=$("$work/c_wall_engine" --domain 90 --device nobody --wait 0.2 --duration 0 2>&1 < /dev/null) || code=$?
[ "$code" -eq 1 ] && echo "$out" | grep -q "no device 'nobody' started" ||
  { echo "FAIL: the pkg-config-built C engine ($code): $out"; exit 1; }
echo "ok: the C API from the installed package (pkg-config hapticd-client)"

# The engine guides' code (docs/unreal.md: a link on the C++ client library; docs/godot.md: one on the C API),
# extracted as written and built against the installed package: each, asked for a device nobody serves, says so.
python3 "$src/tests/docs/guide_code.py" "$work/guides" "$src/docs/unreal.md" "$src/docs/godot.md"
cat > "$work/guides/unreal/main.cpp" << 'CPP'
#include <cstdio>
#include "HapticLink.h"
int main() {
  HapticLink link("nobody", 90);
  std::string error;
  const bool started = link.Start(0.2, error);
  std::printf("%s\n", error.c_str());
  return !started && error == "no state from nobody" ? 0 : 1;
}
CPP
cat > "$work/guides/unreal/CMakeLists.txt" << 'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(unreal_guide LANGUAGES CXX)
find_package(hapticd 0.1 REQUIRED)
add_executable(unreal_guide main.cpp)
target_link_libraries(unreal_guide PRIVATE hapticd::client)
target_compile_features(unreal_guide PRIVATE cxx_std_20)
target_compile_options(unreal_guide PRIVATE -Wall -Wextra -Werror)
CMAKE
cmake -S "$work/guides/unreal" -B "$work/guides/unreal/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/guides/unreal.log" && cmake --build "$work/guides/unreal/build" >> "$work/guides/unreal.log" ||
  { cat "$work/guides/unreal.log"; echo "FAIL: the Unreal guide's link does not build"; exit 1; }
"$work/guides/unreal/build/unreal_guide" || { echo "FAIL: the Unreal guide's link"; exit 1; }
cat > "$work/guides/godot/main.c" << 'C'
#include "haptic_link.h"
int main(void) { return haptic_link_start("nobody", 90, 0.2) == 0 ? 0 : 1; }
C
cc -std=c11 -Wall -Wextra -Werror -I"$work/guides/godot" "$work/guides/godot/haptic_link.c" "$work/guides/godot/main.c" \
  -o "$work/guides/godot_guide" $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs hapticd-client) \
  -Wl,-rpath,"$prefix/lib" || { echo "FAIL: the Godot guide's link does not build"; exit 1; }
"$work/guides/godot_guide" || { echo "FAIL: the Godot guide's link"; exit 1; }
echo "ok: the Unreal and Godot guides' code builds against the installed package and runs"

# A rendering engine on the installed client library, against the installed server over DDS (real time, 4 s).
cmake -S "$src/examples/client_engine" -B "$work/client_engine" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/client_engine_configure.log"
cmake --build "$work/client_engine" > "$work/client_engine_build.log"
dds_session="$prefix/share/hapticd/config/sessions/vishard3/dds-coupling.yaml"
"$prefix/bin/hapticd" --config "$dds_session" --dds-domain 90 --duration 5 --stats-json "$work/dds_stats.json" \
  --log-level warn --set server.realtime_priority=0 --set server.lock_memory=false $(loose_watchdogs vishard3) &
server=$!
engine_out=$(timeout 60 "$work/client_engine/wall_engine" --domain 90 --device vishard3 --duration 3 --push 15) || {
  kill "$server" 2>/dev/null; echo "FAIL: wall engine: $engine_out"; exit 1; }
wait "$server"
echo "$engine_out"
grep -q '"fault": "none"' "$work/dds_stats.json" || { echo "FAIL: device faulted"; cat "$work/dds_stats.json"; exit 1; }
# The 15 N push holds at the wall 2 cm ahead: through the 3000 N/m coupling the handle stops about 5 mm past it.
past=$(echo "$engine_out" | sed -n 's/.*handle \([-0-9.]*\) m past the start.*/\1/p')
awk -v x="$past" 'BEGIN { exit !(x > 0.015 && x < 0.03) }' || { echo "FAIL: the wall did not hold: $past m"; exit 1; }

# The installed Python package: importable from the prefix, its session finds the installed plugins.
if [ -d "$prefix"/lib/python3*/dist-packages/hapticd ]; then
  site=$(echo "$prefix"/lib/python3*/dist-packages)
  PYTHONPATH="$site" /usr/bin/python3 -c "
import hapticd
with hapticd.Session.from_file('$session', ['server.seed=3']) as s:
    s.step(100)
    v = s.device('vishard3')
    assert v.fault == '' and v.cycle == 99, v
print('installed python package:', hapticd.__file__)" || { echo "FAIL: the installed Python package"; exit 1; }
  echo "4 passed, 0 failed"
else
  echo "3 passed, 0 failed (no Python package in this build)"
fi

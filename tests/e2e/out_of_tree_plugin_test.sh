#!/usr/bin/env bash
# The SDK as a plugin author gets it: install hapticd to a prefix, build examples/out_of_tree_plugin against
# the installed package with find_package(hapticd), then have the installed server load the new plugin and run
# a lockstep session with it. Usage: out_of_tree_plugin_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
build=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
prefix="$work/prefix"

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
cmake -S "$src/examples/out_of_tree_plugin" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" > "$work/configure.log"
cmake --build "$work/build" > "$work/build.log"
plugin_dir="$work/build"
ls "$plugin_dir"/libexample_spring_wall.so > /dev/null

export HAPTICD_PLUGIN_PATH="$plugin_dir"
"$prefix/bin/hapticd" --list-plugins | grep -q "example_spring_wall .*controller" || { echo "FAIL: plugin not listed"; exit 1; }
"$prefix/bin/hapticd" --check-config "$src/examples/out_of_tree_plugin/session.yaml"
"$prefix/bin/hapticd" --config "$src/examples/out_of_tree_plugin/session.yaml" --clock lockstep --duration 1 \
  --stats-json "$work/stats.json" --record "$work/run.csv" --log-level warn
grep -q '"fault": "none"' "$work/stats.json" || { echo "FAIL: device faulted"; cat "$work/stats.json"; exit 1; }
# The wall at 0.02 m holds the test device that the example's setpoint pushes to 0.05 m.
max=$(awk -F, 'NR > 1 && $1 > 1000 { if ($5 > m) m = $5 } END { print m }' "$work/run.csv")
awk -v m="$max" 'BEGIN { exit !(m > 0.015 && m < 0.03) }' || { echo "FAIL: wall did not hold, max position $max"; exit 1; }
echo "out-of-tree plugin built against the installed SDK and loaded; wall holds at $max m"
echo "1 passed, 0 failed"

#!/usr/bin/env bash
# The quick start's demo builds only the CMake target `demo` (CMakeLists.txt): its plugin libraries must provide
# every plugin the demo's two sessions name, or a newcomer's first command fails after its build.
# Usage: demo_plugins_test.sh HAPTICD SOURCE_DIR LIBRARY...   (the file names of the demo's plugin libraries)
set -u
hapticd=$1; src=$2; shift 2
libraries=" $* "
listing=$(timeout 30 "$hapticd" --list-plugins 2> /dev/null)
failures=0
for session in "$src/config/sessions/demo.yaml" "$src/config/sessions/dual-arm/vishard3-pair.yaml"; do
  for plugin in $(grep -oE "plugin: *[a-z_0-9]+" "$session" | awk '{ print $2 }' | sort -u); do
    library=$(echo "$listing" | awk -v p="$plugin" '$1 == p { print $NF }' | tr -d '()' | xargs -r basename)
    if [ -z "$library" ]; then
      echo "FAIL: ${session#$src/}: plugin '$plugin' is not listed by hapticd --list-plugins"; failures=$((failures + 1))
    elif [[ "$libraries" != *" $library "* ]]; then
      echo "FAIL: ${session#$src/}: plugin '$plugin' is in $library, which the demo target does not build"
      failures=$((failures + 1))
    else
      echo "ok: ${session#$src/}: $plugin ($library)"
    fi
  done
done
[ "$failures" -eq 0 ]

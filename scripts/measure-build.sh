#!/usr/bin/env bash
# The quick start's and CI's times, as a newcomer meets them (docs/measurements.md, "Build times"): each command
# runs in a fresh clone of this repository's HEAD, first cold (an empty compiler cache of its own), then warm (a
# second fresh clone, the cache the cold run filled). Prints a table of wall times and CPU times (user + system
# of every process), and writes it to OUT/build-times.md with each run's log beside it.
#   demo: ./scripts/demo.sh (builds the CMake target `demo`, runs the ~30 s demo)
#   test: ./scripts/test.sh (builds everything, installs into OUT's own prefix, runs every test)
#   ci:   .ci/run's parts one by one - install-deps, check-format, test.sh (ci preset), sanitize.sh asan, tsan, fuzz
# The packages must be installed already (scripts/install-deps.sh). The user's ccache is not touched.
# Usage: scripts/measure-build.sh [--out DIR] [--cold-only] [demo] [test] [ci]   (default: demo test)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$root/build/measure-build
cold_only=0
commands=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$(realpath -m "$2"); shift ;;
    --cold-only) cold_only=1 ;;
    demo | test | ci) commands+=("$1") ;;
    *) echo "usage: scripts/measure-build.sh [--out DIR] [--cold-only] [demo] [test] [ci]" >&2; exit 2 ;;
  esac
  shift
done
[ ${#commands[@]} -gt 0 ] || commands=(demo test)
mkdir -p "$out"
table="$out/build-times.md"
{
  echo "| command | run | wall | CPU (user + sys) | exit |"
  echo "|---|---|---|---|---|"
} > "$table"
echo "measure-build: $(nproc) CPUs, HEAD $(git -C "$root" rev-parse --short HEAD), results in $out"

# run NAME RUN DIR COMMAND...: times COMMAND in DIR, its log in $out/NAME-RUN.log, a row in the table.
run() {
  local name=$1 kind=$2 dir=$3
  shift 3
  local log="$out/$name-$kind.log" times="$out/$name-$kind.time"
  local start=$SECONDS rc=0
  (cd "$dir" && /usr/bin/time -f "%e %U %S" -o "$times" "$@") > "$log" 2>&1 || rc=$?
  local wall=$((SECONDS - start))
  local cpu
  cpu=$(awk '{ printf "%.0f", $2 + $3 }' "$times" 2> /dev/null || echo "?")
  printf "| %s | %s | %d min %02d s | %s min | %d |\n" "$name" "$kind" $((wall / 60)) $((wall % 60)) \
    "$(awk -v c="$cpu" 'BEGIN { printf "%.1f", c / 60 }')" "$rc" >> "$table"
  echo "measure-build: $name ($kind): ${wall} s wall, ${cpu} s CPU, exit $rc ($log)"
}

fresh_clone() {
  local dir=$1
  rm -rf "$dir"
  git clone -q "$root" "$dir"
  git -C "$dir" checkout -q "$(git -C "$root" rev-parse HEAD)"
  # The live view test's npm packages come from the npm registry's lock file: as install-deps would fetch them.
}

cache="$out/ccache"
for kind in cold warm; do
  [ "$kind" = warm ] && [ "$cold_only" = 1 ] && break
  for c in "${commands[@]}"; do
    [ "$kind" = cold ] && rm -rf "$cache-$c"
    export CCACHE_DIR="$cache-$c"
    dir="$out/clone-$c-$kind"
    fresh_clone "$dir"
    case "$c" in
      demo) run demo "$kind" "$dir" ./scripts/demo.sh 91 ;;
      test) HAPTICD_PREFIX="$out/prefix-$kind" run test "$kind" "$dir" ./scripts/test.sh ;;
      ci)
        export CI=true
        run ci:install-deps "$kind" "$dir" bash scripts/install-deps.sh
        run ci:check-format "$kind" "$dir" bash scripts/check-format.sh
        HAPTICD_PREFIX="$out/prefix-ci-$kind" run ci:test "$kind" "$dir" bash scripts/test.sh
        run ci:asan "$kind" "$dir" bash scripts/sanitize.sh asan
        run ci:tsan "$kind" "$dir" bash scripts/sanitize.sh tsan
        run ci:fuzz "$kind" "$dir" bash scripts/sanitize.sh fuzz
        unset CI
        ;;
    esac
    du -sh "$dir/build" 2> /dev/null | awk -v c="$c" -v k="$kind" '{ print "measure-build: " c " (" k "): build folder " $1 }'
  done
done
unset CCACHE_DIR
echo
cat "$table"

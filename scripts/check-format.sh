#!/usr/bin/env bash
# Checks (never rewrites) that every C and C++ source of the project is formatted by .clang-format
# (clang-format-14). Lists the files that differ and exits 1 if any does. To fix them:
#   git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h' '*.c' | xargs clang-format-14 -i
# New files not yet added to git are checked too (not ignored ones), so a commit never brings an unformatted file.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format-14 >/dev/null || { echo "check-format: clang-format-14 is missing (scripts/install-deps.sh)" >&2; exit 1; }
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h' '*.c' | sort -u)
present=()
for f in "${files[@]}"; do [ -f "$f" ] && present+=("$f"); done  # not the deleted, not yet committed
# Batches of 40 files per clang-format, two at a time (one process per file took 51 s of a cold CI run); a file
# that differs is named in clang-format's own error lines. clang-format failing without naming a file (a broken
# .clang-format) fails the check too.
status=0
report=$(printf '%s\0' "${present[@]}" | xargs -0 -n 40 -P 2 clang-format-14 --dry-run --Werror 2>&1 >/dev/null) ||
  status=$?
mapfile -t differ < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: .*/\1/p' <<< "$report" | sort -u)
if [ "$status" -ne 0 ] && [ ${#differ[@]} -eq 0 ]; then
  echo "check-format: clang-format-14 failed: $(head -c 400 <<< "$report")" >&2
  exit 1
fi
if [ ${#differ[@]} -ne 0 ]; then
  echo "check-format: ${#differ[@]} of ${#files[@]} files are not formatted:" >&2
  printf '  %s\n' "${differ[@]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"

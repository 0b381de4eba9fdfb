#!/usr/bin/env bash
# Checks (never rewrites) that every C and C++ source of the project is formatted by .clang-format
# (clang-format-14). Lists the files that differ and exits 1 if any does. To fix them:
#   git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h' '*.c' | xargs clang-format-14 -i
# New files not yet added to git are checked too (not ignored ones), so a commit never brings an unformatted file.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format-14 >/dev/null || { echo "check-format: clang-format-14 is missing (scripts/install-deps.sh)" >&2; exit 1; }
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' '*.h' '*.c' | sort -u)
differ=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue  # deleted, not yet committed
  clang-format-14 --dry-run --Werror "$f" >/dev/null 2>&1 || differ+=("$f")
done
if [ ${#differ[@]} -ne 0 ]; then
  echo "check-format: ${#differ[@]} of ${#files[@]} files are not formatted:" >&2
  printf '  %s\n' "${differ[@]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"

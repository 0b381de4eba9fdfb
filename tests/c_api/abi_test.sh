#!/usr/bin/env bash
# The C API's ABI is what was committed: the library exports exactly the symbols of clients/c/abi/hapticd_c.symbols,
# each with its version node (HAPTICD_C_2), and the structs have the sizes and offsets of
# clients/c/abi/hapticd_c.layout. A change to either is an ABI change: update the file in the same commit, and
# raise the version node (and HAPTICD_C_API_VERSION's major) when an existing symbol or layout changes.
# Usage: abi_test.sh LIBRARY ABI_DIR LAYOUT_PROGRAM
set -u
library=$1 abi=$2 layout=$3
failures=0
exported=$(nm -D --defined-only "$library" | awk '{print $3}' | sort)
if ! diff <(echo "$exported") "$abi/hapticd_c.symbols" > /tmp/hapticd_c_abi_symbols.$$; then
  echo "FAIL: the exported symbols differ from $abi/hapticd_c.symbols (< the library, > committed):"
  cat /tmp/hapticd_c_abi_symbols.$$
  failures=$((failures + 1))
else
  echo "ok: $(echo "$exported" | wc -l) symbols, each versioned as committed"
fi
rm -f /tmp/hapticd_c_abi_symbols.$$
if ! diff <("$layout") "$abi/hapticd_c.layout"; then
  echo "FAIL: the struct layouts differ from $abi/hapticd_c.layout (< now, > committed)"
  failures=$((failures + 1))
else
  echo "ok: the struct layouts as committed"
fi
exit "$failures"

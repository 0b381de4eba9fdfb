# Sourced by the real-time end-to-end scripts. session_copy SESSION SOURCE_DIR OUT writes a copy of a shipped
# single-device session that runs from any folder (the robot model paths made absolute) with the loop watchdogs
# loosened for this virtual machine: it runs the loop late for several milliseconds now and then, which trips the
# default watchdogs (10 consecutive overruns, a 20 ms stall) in a few sessions in ten (docs/safety.md). These
# tests test the tools and the DDS path, not the machine; hardening_test.sh's stall is 0.3 s and still trips.
# loose_watchdogs DEVICE prints the same loosening as --set arguments, for a shipped session run where it lies.
session_copy() {
  sed -e "s|\.\./\.\./urdf/|$2/config/urdf/|" \
      -e 's|^  - name: \(.*\)$|  - name: \1\n    safety: {max_consecutive_overruns: 60, max_stall_s: 0.1}|' "$1" > "$3"
}
loose_watchdogs() {
  echo "--set devices.$1.safety.max_consecutive_overruns=60 --set devices.$1.safety.max_stall_s=0.1"
}

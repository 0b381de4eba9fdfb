#!/usr/bin/env bash
# The teleoperation sweep (docs/teleoperation.md, "The sweep"): `hapticd-eval teleoperation` with the time-domain
# passivity approach at every round trip from 0 to 800 ms in steps of 10 ms, 0, 5 and 20 % loss each way, the wall
# and free motion, for both architectures, without jitter and with it (packets overtaking each other) - then every
# row that is not passive and stable, listed, and the wall's felt stiffness at 500 ms against the no-delay row.
# About 0.25 s a run: 486 runs per architecture and jitter, some 8 minutes in all on a 2-core machine.
# Usage: scripts/teleop-sweep.sh [OUT_DIR] [JITTER_MS]    (defaults: build/teleop-sweep, 10)
#        BUILD=build/ci (default) or another build tree with bin/hapticd-eval
#        DOF=6: the ViSHaRD6 pair in six degrees of freedom (`--dof 6`: the rotation's felt stiffness too)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/teleop-sweep}
jitter=${2:-10}
build=${BUILD:-build/ci}
dof=${DOF:-3}
mkdir -p "$out"
round_trips=$(seq -s ' ' 0 10 800)
for architecture in position_force position_position; do
  for j in 0 "$jitter"; do
    name="$architecture-jitter-$j"
    echo "== $name (dof $dof)" >&2
    # shellcheck disable=SC2086  # the round trips are words
    "$build/bin/hapticd-eval" teleoperation --dof "$dof" --architecture "$architecture" --passivity tdpa \
      --round-trips $round_trips --losses 0 5 20 --jitter "$j" --no-figures --out "$out/$name" \
      --table "$out/$name.json" > "$out/$name.log"
  done
done
python3 - "$out" "$jitter" << 'PY'
import json, pathlib, sys
from collections import defaultdict
out, jitter = pathlib.Path(sys.argv[1]), sys.argv[2]
for architecture in ("position_force", "position_position"):
    for j in ("0", jitter):
        rows = json.loads((out / f"{architecture}-jitter-{j}.json").read_text())
        bad = defaultdict(list)
        for r in rows:
            if not (r["passive"] and r["stable"]):
                key = (r["task"], r["loss_percent"], "active" if not r["passive"] else "unstable")
                bad[key].append(f'{r["round_trip_ms"]:g}')
        lowest = min(r["min_energy_j"] for r in rows)
        print(f"{architecture}, jitter {j} ms: {len(rows)} rows, {len(rows) - sum(map(len, bad.values()))} passive "
              f"and stable; lowest energy {1e3 * lowest:.3f} mJ")
        for (task, loss, what), rtts in sorted(bad.items()):
            print(f"  {task}, {loss:g} % loss, {what} at: {' '.join(rtts)} ms")
        k = {(r["round_trip_ms"], r["loss_percent"]): r["felt_stiffness_n_per_m"] for r in rows if r["task"] == "wall"}
        for loss in (0, 5, 20):
            k0, k500 = k.get((0, loss)), k.get((500, loss))
            if k0 and k500 == k500 and k500 is not None:
                print(f"  the wall at 500 ms, {loss} % loss: {k500:.0f} N/m, {100 * k500 / k0:.0f} % of the no-delay row")
            else:
                print(f"  the wall at 500 ms, {loss} % loss: not stable")
        kr = {(r["round_trip_ms"], r["loss_percent"]): r.get("felt_rotational_stiffness_n_m_per_rad")
              for r in rows if r["task"] == "wall"}
        for loss in (0, 5, 20):
            k0, k500 = kr.get((0, loss)), kr.get((500, loss))
            if k0 is not None and k500 is not None and k500 == k500 and k0 > 0:
                print(f"  rotation at the wall at 500 ms, {loss} % loss: {k500:.2f} N m/rad, "
                      f"{100 * k500 / k0:.0f} % of the no-delay row")
PY

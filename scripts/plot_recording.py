#!/usr/bin/python3
"""Plot a hapticd --record CSV: joint positions, torque commands and sensor forces of every device."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path: str, png_path: str) -> None:
    series = defaultdict(lambda: {"t": [], "position": [], "torque_command": []})
    forces = defaultdict(lambda: {"t": [], "fx": [], "fy": [], "fz": []})
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            s = series[(row["device"], int(row["joint"]))]
            s["t"].append(float(row["time_s"]))
            s["position"].append(float(row["position"]))
            s["torque_command"].append(float(row["torque_command"]))
            if row["joint"] == "0" and "sensor_fx" in row:
                w = forces[row["device"]]
                w["t"].append(float(row["time_s"]))
                for axis in ("fx", "fy", "fz"):
                    w[axis].append(float(row["sensor_" + axis]))
    if not series:
        sys.exit(f"{csv_path}: no samples")
    fig, (ax_q, ax_tau, ax_f) = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
    for (device, joint), s in sorted(series.items()):
        label = f"{device} joint {joint}"
        ax_q.plot(s["t"], s["position"], label=label)
        ax_tau.plot(s["t"], s["torque_command"], label=label)
    for device, w in sorted(forces.items()):
        for axis in ("fx", "fy", "fz"):
            ax_f.plot(w["t"], w[axis], label=f"{device} {axis}")
    ax_q.set_ylabel("position [rad or m]")
    ax_tau.set_ylabel("torque command [N m or N]")
    ax_f.set_ylabel("sensor force [N]\n(sensor frame)")
    ax_f.set_xlabel("time [s]")
    for ax in (ax_q, ax_tau, ax_f):
        ax.grid(True)
        ax.legend(loc="upper right", fontsize="small")
    fig.suptitle(csv_path)
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_recording.py RECORDING.csv OUT.png")
    main(sys.argv[1], sys.argv[2])

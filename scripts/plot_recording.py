#!/usr/bin/python3
"""Plot a hapticd --record CSV: joint positions and torque commands of every device over time."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path: str, png_path: str) -> None:
    series = defaultdict(lambda: {"t": [], "position": [], "torque_command": []})
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            s = series[(row["device"], int(row["joint"]))]
            s["t"].append(float(row["time_s"]))
            s["position"].append(float(row["position"]))
            s["torque_command"].append(float(row["torque_command"]))
    if not series:
        sys.exit(f"{csv_path}: no samples")
    fig, (ax_q, ax_tau) = plt.subplots(2, 1, sharex=True, figsize=(9, 6))
    for (device, joint), s in sorted(series.items()):
        label = f"{device} joint {joint}"
        ax_q.plot(s["t"], s["position"], label=label)
        ax_tau.plot(s["t"], s["torque_command"], label=label)
    ax_q.set_ylabel("position [rad or m]")
    ax_tau.set_ylabel("torque command [N m or N]")
    ax_tau.set_xlabel("time [s]")
    for ax in (ax_q, ax_tau):
        ax.grid(True)
        ax.legend(loc="upper right", fontsize="small")
    fig.suptitle(csv_path)
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_recording.py RECORDING.csv OUT.png")
    main(sys.argv[1], sys.argv[2])

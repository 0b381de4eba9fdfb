#!/usr/bin/env python3
"""Plot a hapticd-scene-engine --csv file: handle position and proxy, and the rendered and operator forces.
Installed as hapticd-plot-engine-run."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path: str, png_path: str) -> None:
    rows = list(csv.DictReader(open(csv_path, newline="")))
    if not rows:
        sys.exit(f"{csv_path}: no samples")
    t = [float(r["time_s"]) for r in rows]
    col = lambda name, scale=1.0: [scale * float(r[name]) for r in rows]  # noqa: E731
    fig, (ax_x, ax_f) = plt.subplots(2, 1, sharex=True, figsize=(9, 7))
    for axis, colour in (("x", "tab:blue"), ("y", "tab:orange"), ("z", "tab:green")):
        ax_x.plot(t, col(axis, 1e3), color=colour, label=f"handle {axis}")
        ax_x.plot(t, col("proxy_" + axis, 1e3), color=colour, linestyle="--", label=f"proxy {axis}")
        ax_f.plot(t, col("env_f" + axis), color=colour, label=f"rendered F{axis}")
        ax_f.plot(t, col("op_f" + axis), color=colour, linestyle=":", label=f"operator F{axis}")
    # Shade contacts.
    start, current = None, ""
    for time, r in zip(t + [t[-1]], rows + [{"contact": ""}]):
        if r["contact"] != current:
            if current:
                for ax in (ax_x, ax_f):
                    ax.axvspan(start, time, alpha=0.08, color="grey")
                ax_x.text(start, 0, f" {current}", fontsize=8, va="bottom")
            start, current = time, r["contact"]
    ax_x.set_ylabel("position from start [mm]")
    ax_f.set_ylabel("force [N]")
    ax_f.set_xlabel("time [s]")
    ax_x.legend(fontsize=7, ncol=3)
    ax_f.legend(fontsize=7, ncol=3)
    ax_x.set_title("hapticd demo: simulated ViSHaRD3, admittance display, scene engine over DDS")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: hapticd-plot-engine-run ENGINE.csv OUT.png")
    main(sys.argv[1], sys.argv[2])

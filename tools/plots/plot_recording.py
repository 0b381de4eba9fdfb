#!/usr/bin/env python3
"""Plot a hapticd recording (hapticd --record FILE.h5): per device the joint positions, the torque commands,
the handle's position and the operator's force, over time. Needs python3-h5py and python3-matplotlib; reads
the file with the hapticd package's reader (hapticd.recording). Installed as hapticd-plot-recording."""
import os
import sys

from hapticd import recording

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402



def main(path: str, png_path: str) -> None:
    rec = recording.read(path)
    if not rec.devices:
        sys.exit(f"{path}: no devices")
    fig, axes = plt.subplots(4, 1, sharex=True, figsize=(9, 10))
    for name, dev in rec.devices.items():
        t = dev.time_s
        for j, joint in enumerate(dev.joint_names):
            axes[0].plot(t, dev["joints/position"][:, j], label=f"{name} {joint}")
            axes[1].plot(t, dev["joints/torque_command"][:, j], label=f"{name} {joint}")
        for a, axis in enumerate("xyz"):
            axes[2].plot(t, dev["handle/pose"][:, a], label=f"{name} {axis}")
            axes[3].plot(t, dev["wrench/operator"][:, a], label=f"{name} F{axis}")
    for ax, label in zip(axes, ["position [rad or m]", "torque command [N m]", "handle position [m]",
                                "operator force [N]"]):
        ax.set_ylabel(label)
        ax.grid(True)
        ax.legend(fontsize="small", ncol=3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"{os.path.basename(path)}: {', '.join(rec.devices)}")
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: hapticd-plot-recording RECORDING.h5 OUT.png")
    main(sys.argv[1], sys.argv[2])

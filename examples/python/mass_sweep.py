#!/usr/bin/python3
"""An experiment script on the in-process session API: the same push into the admittance display rendering
virtual masses from 0.5 to 8 kg, each a lockstep run (repeatable, faster than real time), plotted with
matplotlib: the handle's path and the operator's force per mass, and the peak force (the inertia felt while the hand
accelerates the handle) against the mass.

    hapticd-python examples/python/mass_sweep.py [--out build/mass_sweep.png]"""
import argparse
import os

import numpy as np

import hapticd

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SESSION = os.path.join(ROOT, "config", "sessions", "vishard3", "admittance-resolved-acceleration.yaml")


def pushed(mass_kg, seconds=1.5):
    """The handle's response to the operator's 8 N push (ramped in 0.1 s) with the given virtual mass."""
    overrides = ["server.seed=1", f"devices.vishard3.virtual_model.parameters.mass_kg=[{mass_kg}, {mass_kg}, {mass_kg}]",
                 "devices.vishard3.device.parameters.operator_force=constant",
                 "devices.vishard3.device.parameters.operator_force_n=[0.0, 0.0, 0.0]"]
    with hapticd.Session.from_file(SESSION, overrides) as s:
        s.step(100)
        s.operator("vishard3", "push", [8.0, 0.0, 0.0, 0.1])
        run = s.run(int(seconds / s.period_s), "vishard3", every=4)
    run["time_s"] -= run["time_s"][0]
    run["x_mm"] = 1e3 * (run["position"][:, 0] - run["position"][0, 0])
    return run


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="build/mass_sweep.png")
    parser.add_argument("--masses", type=float, nargs="+", default=[0.5, 1.0, 2.0, 4.0, 8.0])
    args = parser.parse_args()

    runs = {m: pushed(m) for m in args.masses}
    peaks = []
    for m, run in runs.items():
        peaks.append(run["operator_force"][:, 0].max())
        k = np.argmax(run["operator_force"][:, 0])
        print(f"mass {m:4.1f} kg: peak operator force {peaks[-1]:.2f} N at {run['time_s'][k]:.3f} s, "
              f"{run['x_mm'][-1]:5.1f} mm at the end, faulted {bool(run['faulted'].any())}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax_x, ax_f, ax_m) = plt.subplots(1, 3, figsize=(13, 4))
    for m, run in runs.items():
        ax_x.plot(run["time_s"], run["x_mm"], label=f"{m} kg")
        ax_f.plot(run["time_s"], run["operator_force"][:, 0], label=f"{m} kg")
    ax_x.set(xlabel="time [s]", ylabel="handle x [mm]", title="handle under an 8 N push")
    ax_f.set(xlabel="time [s]", ylabel="operator force x [N]", title="what the operator feels")
    ax_m.plot(list(runs), peaks, "o-")
    ax_m.set(xscale="log", xlabel="virtual mass [kg]", ylabel="peak operator force [N]", title="felt inertia")
    for ax in (ax_x, ax_f, ax_m):
        ax.grid(True, alpha=0.3)
    ax_x.legend()
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

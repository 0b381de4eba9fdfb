#!/usr/bin/env python3
"""ViSHaRD3's calibration rows against the thesis, for simulator settings given as hapticd-eval --sim sets.

For each setting (one argument: space-separated KEY=VALUE pairs, "" for the defaults) runs
`hapticd-eval minimum-inertia` on the 12 schemes of the thesis's table (RAC, IJC, TJC at kp 10000 and 1000, with
and without acceleration feedforward; pure masses) and `hapticd-eval force-gain`, and prints one markdown row:
the largest force gain, the minimum masses, how many of the 12 are within 30 % of the thesis's, and how many
of the three kp 1000 feedforward orderings are the thesis's. About 80 s per setting on a 2-core machine.

Usage: eval/calibration-sweep.py [--build build/default] [--out DIR] SETTING [SETTING ...]
  e.g. eval/calibration-sweep.py "" "structural_damping_ratio=0.15" \\
           "structural_damping_ratio=0.3 operator_grasp_damping=[2, 45]"
The tables of docs/evaluation.md ("Largest force gain") were made this way.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

# The thesis's minimum masses [kg] (issue 20's table), scheme id -> figure.
THESIS_KG = {
    "rac-kp10000-ff": 2.5, "rac-kp10000": 4.5, "ijc-kp10000-ff": 2.6, "ijc-kp10000": 4.3,
    "tjc-kp10000-ff": 2.5, "tjc-kp10000": 4.2, "rac-kp1000-ff": 2.0, "rac-kp1000": 2.3,
    "ijc-kp1000-ff": 3.4, "ijc-kp1000": 2.8, "tjc-kp1000-ff": 1.75, "tjc-kp1000": 2.0,
}
THESIS_FORCE_GAIN = 3.75
SCHEMES = [i.replace("-kp", ":").replace("-ff", ":ff") for i in THESIS_KG]


def sim_options(setting):
    """'a=1 b=[2, 3]' -> ['--sim', 'a=1', '--sim', 'b=[2, 3]'] (a value may hold spaces inside brackets)."""
    options, current, depth = [], "", 0
    for ch in setting.strip():
        if ch == " " and depth == 0:
            if current:
                options += ["--sim", current]
            current = ""
            continue
        depth += ch == "["
        depth -= ch == "]"
        current += ch
    if current:
        options += ["--sim", current]
    return options


def run(eval_bin, args, out):
    done = subprocess.run([eval_bin] + args + ["--no-figures", "--out", out], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"calibration-sweep: {' '.join(args[:1])} failed: {done.stderr.strip()[-500:]}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("settings", nargs="+")
    ap.add_argument("--build", default="build/default")
    ap.add_argument("--out", default=None, help="where the JSON results go (default: a temporary folder)")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    eval_bin = os.path.join(root, args.build, "bin", "hapticd-eval")
    if not os.access(eval_bin, os.X_OK):
        sys.exit(f"calibration-sweep: no {eval_bin} (build first: scripts/build.sh)")
    base = args.out or tempfile.mkdtemp(prefix="calibration-sweep.")
    print("| setting | largest Kp (thesis 3.75) | " + " | ".join(THESIS_KG) +
          " | within 30 % (of 12) | kp 1000 orderings (of 3) |")
    print("|---|---|" + "---|" * len(THESIS_KG) + "---|---|")
    for n, setting in enumerate(args.settings):
        out = os.path.join(base, f"setting-{n}")
        os.makedirs(out, exist_ok=True)
        sims = sim_options(setting)
        run(eval_bin, ["force-gain"] + sims, out)
        run(eval_bin, ["minimum-inertia", "--device", "vishard3", "--schemes"] + SCHEMES + sims, out)
        kp = json.load(open(os.path.join(out, "force-gain.json")))["worst_kp"]
        worst = {s["id"]: s["worst_kg"] for s in json.load(open(os.path.join(out, "minimum-inertia.json")))["schemes"]}
        within = sum(abs(worst[k] / v - 1.0) <= 0.3 for k, v in THESIS_KG.items())
        orderings = sum((worst[f"{l}-kp1000-ff"] < worst[f"{l}-kp1000"]) ==
                        (THESIS_KG[f"{l}-kp1000-ff"] < THESIS_KG[f"{l}-kp1000"]) for l in ("rac", "ijc", "tjc"))
        print(f"| {setting or 'defaults'} | {kp:.2f} | " + " | ".join(f"{worst[k]:.2f}" for k in THESIS_KG) +
              f" | {within} | {orderings} |", flush=True)
    print(f"\nresults: {base}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Draws the evaluation suite's figures and one self-contained HTML report.

usage: hapticd-eval-report RESULTS_DIR   (hapticd-eval runs it after each experiment)

Reads every <experiment>.json hapticd-eval wrote into RESULTS_DIR, draws <experiment>*.png beside it and writes
RESULTS_DIR/report.html with the figures embedded (base64), the tables of our figures beside the thesis's, the
command that reproduces each experiment and the session file of one of its runs (docs/evaluation.md).
"""
import base64
import html
import json
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fmt(value, unit=""):
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    return f"{value:.3g}{(' ' + unit) if unit else ''}"


def force_response(result, out_dir):
    """Bode plots (gain in dB, phase) and distortion per scheme."""
    fig, (ax_gain, ax_phase, ax_dist) = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for s in result["schemes"]:
        f = s["frequency_hz"]
        if not f:
            continue
        gain_db = [20.0 * math.log10(max(g, 1e-9)) for g in s["gain"]]
        ax_gain.plot(f, gain_db, marker=".", label=s["label"])
        ax_phase.plot(f, s["phase_deg"], marker=".")
        ax_dist.plot(f, s["distortion_percent"], marker=".")
    ax_gain.axhline(-3.0, color="grey", linestyle=":", linewidth=1)
    ax_gain.set_ylabel("gain [dB]")
    ax_gain.legend(fontsize=8)
    ax_phase.set_ylabel("phase [deg]")
    ax_dist.set_ylabel("D_rms [%]")
    ax_dist.set_xlabel("frequency [Hz]")
    for ax in (ax_gain, ax_phase, ax_dist):
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"Dynamic force precision, {result['device']}, {result['axis']} axis")
    fig.tight_layout()
    png = out_dir / "force-response.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = []
    for s in result["schemes"]:
        pub = s.get("published", {})
        bw = fmt(s["bandwidth_hz"], "Hz") if s["bandwidth_hz"] is not None else (
            "> range" if s.get("bandwidth_above_range") else "-")
        rows.append([s["label"], bw, fmt(pub.get("bandwidth_hz"), "Hz"), fmt(s["resonance_hz"], "Hz"),
                     fmt(pub.get("resonance_hz"), "Hz"), fmt(s["peak_gain"]),
                     "; ".join(f"{x['frequency_hz']:.1f} Hz: {x['fault']}" for x in s["faults"]) or "-"])
    table = (["scheme", "bandwidth", "thesis", "resonance", "thesis", "peak gain", "unstable"], rows)
    return [png], [table]


def backdrivability(result, out_dir):
    """Force error over time per scheme, with the path's acceleration."""
    fig, (ax_path, ax_err) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    first = True
    for s in result["schemes"]:
        t = s["time_s"]
        if first:
            ax_path.plot(t, s["acceleration_m_s2"], color="black", label="acceleration [m/s^2]")
            ax_path.plot(t, s["velocity_m_s"], color="grey", label="velocity [m/s]")
            first = False
        ax_err.plot(t, s["force_error_n"], label=s["label"], linewidth=1)
    if result.get("predicted"):
        p = result["predicted"]
        ax_err.plot(p["time_s"], p["force_error_n"], color="black", linestyle="--", linewidth=1,
                    label=p["label"])
    ax_path.legend(fontsize=8)
    ax_path.set_ylabel("guide path")
    ax_err.set_ylabel("force error [N]")
    ax_err.set_xlabel("time [s]")
    ax_err.legend(fontsize=8)
    for ax in (ax_path, ax_err):
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"Backdrivability, {result['device']}, x axis")
    fig.tight_layout()
    png = out_dir / "backdrivability.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = [[s["label"], fmt(s["rms_error_n"], "N"), fmt(s["peak_error_n"], "N"),
             fmt(s.get("fault") or "-")] for s in result["schemes"]]
    table = (["scheme", "RMS force error", "peak force error", "fault"], rows)
    tables = [table]
    if "ratios" in result:
        tables.append((["comparison", "ours", "thesis"],
                       [[r["what"], fmt(r["ours"]), fmt(r["published"])] for r in result["ratios"]]))
    return [png], tables


def minimum_inertia(result, out_dir):
    """Smallest stable virtual mass (and rotational inertia) per scheme and direction, beside the thesis's."""
    schemes = result["schemes"]
    present = [d for d in ["x", "y", "z", "rx", "ry", "rz"]
               if any(r["direction"] == d for s in schemes for r in s["directions"])]
    groups = [(ds, unit) for ds, unit in ((["x", "y", "z"], "kg"), (["rx", "ry", "rz"], "kg m^2"))
              if any(d in present for d in ds)]
    fig, axes = plt.subplots(1, len(groups), figsize=(max(6, 0.6 * len(schemes) + 2) * len(groups), 5),
                             squeeze=False)
    width = 0.2
    shape = result.get("shape", "per-direction")
    for ax, (ds, unit) in zip(axes[0], groups):
        for i, d in enumerate(ds):
            values, thesis = [], []
            for s in schemes:
                found = [r for r in s["directions"] if r["direction"] == d]
                values.append(found[0]["minimum"] if found and found[0]["minimum"] is not None else float("nan"))
                thesis.append(found[0]["published"] if found and found[0].get("published") is not None
                              else float("nan"))
            xs = [k + (i - 1) * width for k in range(len(schemes))]
            ax.bar(xs, values, width, label=f"ours, {'pushed along ' if shape == 'isotropic' else ''}{d}")
            if any(t == t for t in thesis):
                ax.plot(xs, thesis, "k_", markersize=10, markeredgewidth=2)
        if unit == "kg":
            published = [s["published_kg"] if s["published_kg"] is not None else float("nan") for s in schemes]
            ax.plot(range(len(schemes)), published, "k_", markersize=20, markeredgewidth=2,
                    label="thesis (worst; short marks: per axis)")
        else:
            ax.set_yscale("log")
        ax.set_xticks(range(len(schemes)))
        ax.set_xticklabels([s["label"] for s in schemes], rotation=45, ha="right", fontsize=8)
        ax.set_ylabel(f"smallest stable virtual {'mass' if unit == 'kg' else 'inertia'} [{unit}]")
        ax.legend(fontsize=8)
        ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"Minimum virtual inertia, {result['device']}\n"
                 f"({'m I: the same on every axis, pushed along each' if shape == 'isotropic' else 'per direction'})",
                 fontsize=10)
    fig.tight_layout()
    png = out_dir / "minimum-inertia.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = []
    for s in schemes:
        cells = {r["direction"]: r for r in s["directions"]}
        row = [s["label"]]
        for d in present:
            r = cells.get(d)
            if r is None:
                row.append("-")
                continue
            cell = ">range" if r["above_range"] else fmt(r["minimum"], r["unit"])
            if r.get("published") is not None:
                cell += f" (thesis {fmt(r['published'], r['unit'])})"
            row.append(cell)
        why = "; ".join(f"{r['direction']}: {r['unstable']['load']} "
                        f"({r['unstable']['fault'] or fmt(r['unstable']['oscillation_hz'], 'Hz')})"
                        for r in s["directions"] if r.get("unstable"))
        row += [fmt(s["worst_kg"], "kg"), fmt(s["published_kg"], "kg"), why or "-"]
        rows.append(row)
    c = result["criterion"]
    criterion = (["stability criterion", "value"],
                 [["inertia", "the same on every axis (m I), each direction's loads in turn" if shape == "isotropic"
                   else f"on the direction under test; the others {result.get('other_axes_kg')} kg, "
                        f"{result.get('other_axes_kg_m2')} kg m^2"],
                  ["run", f"{c['duration_s']} s per load"], ["window", f"last {c['window_s']} s"],
                  ["high-pass", f"{c['cutoff_hz']} Hz (2nd-order Butterworth)"],
                  ["threshold", f"{c['threshold_m_s']} m/s RMS of the handle velocity"
                                f"{', ' + str(c['rotational_threshold_rad_s']) + ' rad/s angular' if result.get('rotational_loads') else ''}"],
                  ["loads", ", ".join(x["label"] for x in result["loads"] + result.get("rotational_loads", []))]])
    return [png], [(["scheme"] + present + ["worst", "thesis", "unstable near the boundary"], rows), criterion]


def force_gain(result, out_dir):
    """Largest stable force-feedback gain per direction, beside the thesis's."""
    ds = result["directions"]
    fig, ax = plt.subplots(figsize=(5, 4))
    values = [d["largest_kp"] if d["largest_kp"] is not None else float("nan") for d in ds]
    ax.bar([d["direction"] for d in ds], values, label="ours (largest stable Kp)")
    ax.axhline(result["published_kp"], color="k", linestyle="--", label=f"thesis: up to {result['published_kp']:g}")
    ax.set_ylabel("force-feedback gain Kp")
    ax.legend(fontsize=8)
    ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"Largest stable force gain, {result['device']} (Kd {result['kd']:g} s)")
    fig.tight_layout()
    png = out_dir / "force-gain.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = []
    for d in ds:
        u = d.get("unstable")
        why = "-" if not u else f"{u['load']} ({u['fault'] or fmt(u['oscillation_hz'], 'Hz')})"
        rows.append([d["direction"], ">range" if d["above_range"] else fmt(d["largest_kp"]),
                     fmt(d["smallest_unstable_kp"]), why])
    return [png], [(["direction", "largest stable Kp", "unstable at", "unstable near the boundary"], rows)]


def z_width(result, out_dir):
    """The region of walls (K over B) per scheme; the mass-damping-stiffness space of admittance display."""
    fig, ax = plt.subplots(figsize=(7, 5))
    low, top = result["range_n_per_m"]
    for s in result["schemes"]:
        b = [p["wall_damping_n_s_per_m"] for p in s["region"]]
        # none rendered: drawn on the bottom line; above the range: on the top line
        k = [top if p["above_range"] else max(p["stiffness_n_per_m"], low / 2) for p in s["region"]]
        ax.plot(b, k, marker="o", label=s["label"])
    ax.set_yscale("log")
    ax.set_xlabel("wall damping B [N s/m]")
    ax.set_ylabel("largest wall stiffness K [N/m]")
    ax.axhline(top, color="grey", linestyle=":", linewidth=1)
    ax.axhline(low / 2, color="grey", linestyle=":", linewidth=1)
    ax.set_ylim(low / 3, top * 2)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.suptitle(f"Z-width, {result['device']}, walls across {result['direction']} "
                 "(below a line: rendered; bottom: none; top: range)")
    fig.tight_layout()
    png = out_dir / "z-width.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    head = ["scheme"] + [f"B = {p['wall_damping_n_s_per_m']:g}" for p in result["schemes"][0]["region"]]
    rows = []
    for s in result["schemes"]:
        rows.append([s["label"]] + [">range" if p["above_range"] else fmt(p["stiffness_n_per_m"], "N/m")
                                    for p in s["region"]])
    tables = [(head, rows)]
    mbk = []
    for s in result["schemes"]:
        for p in s.get("mass_damping_stiffness", []):
            mbk.append([s["label"], fmt(p["virtual_mass_kg"], "kg"), fmt(p["virtual_damping_n_s_per_m"], "N s/m"),
                        ">range" if p["above_range"] else fmt(p["stiffness_n_per_m"], "N/m"), p["limited_by"] or "-"])
    if mbk:
        tables.append((["admittance scheme", "virtual mass", "virtual damping", "largest wall K", "limited by"], mbk))
    return [png], tables


def tracking(result, out_dir):
    """Tracking error along the path and across it per inner loop."""
    fig, (ax_path, ax_x, ax_across) = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for i, s in enumerate(result["schemes"]):
        if i == 0:
            ax_path.plot(s["time_s"], s["path_m"], color="black")
        ax_x.plot(s["time_s"], s["error_x_mm"], label=s["label"], linewidth=1)
        ax_across.plot(s["time_s"], s["error_across_mm"], linewidth=1)
    ax_path.set_ylabel("desired x - start [m]")
    ax_x.set_ylabel("error along x [mm]")
    ax_across.set_ylabel("error across (y, z) [mm]")
    ax_across.set_xlabel("time [s]")
    ax_x.legend(fontsize=8)
    for ax in (ax_path, ax_x, ax_across):
        ax.grid(True, alpha=0.3)
    p = result["path"]
    fig.suptitle(f"Tracking, {result['device']}: +-{p['acceleration_m_s2']:g} m/s^2, {p['speed_m_s']:g} m/s, "
                 f"condition number up to {p['worst_condition']:.1f}")
    fig.tight_layout()
    png = out_dir / "tracking.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = [[s["label"], fmt(s["rms_error_mm"], "mm"), fmt(s["peak_error_mm"], "mm"), s["fault"] or "-"]
            for s in result["schemes"]]
    return [png], [(["inner loop", "RMS error", "peak error", "fault"], rows)]


def transparency(result, out_dir):
    """Maps of the apparent mass and the condition number over the workspace's middle height."""
    pts = result["points"]
    zs = sorted({round(p["position_m"][2], 6) for p in pts})
    mid = zs[len(zs) // 2]
    layer = [p for p in pts if abs(p["position_m"][2] - mid) < 1e-6]
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, (title, value) in zip(axes, [("apparent mass along x [kg]", lambda p: p["mass_kg"][0]),
                                         ("apparent mass along y [kg]", lambda p: p["mass_kg"][1]),
                                         ("condition number", lambda p: p["condition"])]):
        sc = ax.scatter([p["position_m"][0] for p in layer], [p["position_m"][1] for p in layer],
                        c=[value(p) for p in layer], s=80, cmap="viridis")
        fig.colorbar(sc, ax=ax)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    fig.suptitle(f"Transparency, {result['device']} open loop, z = {mid:.2f} m")
    fig.tight_layout()
    png = out_dir / "transparency.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    w = result["worst"]
    rows = [["apparent mass x / y / z (largest)", " / ".join(fmt(v, "kg") for v in w["mass_kg"])],
            ["apparent mass x / y / z (smallest)", " / ".join(fmt(v, "kg") for v in w["least_mass_kg"])],
            [f"friction felt at {result['probe_speed_m_s']:g} m/s, x / y / z (largest)",
             " / ".join(fmt(v, "N") for v in w["friction_n"])],
            ["condition number of the mass matrix (largest)", fmt(w["condition"])],
            ["angle between acceleration and inertial force (largest)", fmt(w["angle_deg"], "deg")]]
    return [png], [(["index (worst over the grid)", "value"], rows)]


def friction(result, out_dir):
    """Identified sliding friction against the simulator's truth, per joint."""
    joints = result["joints"]
    fig, axes = plt.subplots(1, max(1, len(joints)), figsize=(5 * max(1, len(joints)), 4), squeeze=False)
    for ax, j in zip(axes[0], joints):
        ax.plot(j["velocity_rad_s"], j["true_torque_nm"], "k.", markersize=4, label="simulator (truth)")
        ax.plot(j["velocity_rad_s"], j["identified_torque_nm"], "-", label="identified")
        ax.set_title(j["joint"])
        ax.set_xlabel("velocity [rad/s]")
        ax.set_ylabel("friction torque [N m]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Friction identification, {result['device']}")
    fig.tight_layout()
    png = out_dir / "friction.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    rows = [[j["joint"], fmt(j["coulomb_nm"], "N m"), fmt(j["breakaway_nm"], "N m"),
             fmt(j["rms_error_percent"], "%"), fmt(j["worst_error_percent"], "%")] for j in joints]
    return [png], [(["joint", "Coulomb", "break-away", "RMS error vs truth", "worst"], rows)]


def teleoperation(result, out_dir):
    """Each row's claims (passive, stable), the wall's felt stiffness and the drift; the wall over time."""
    pngs = []
    traces = result.get("traces", [])
    if traces:
        fig, (ax_x, ax_f) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        for tr in traces:
            label = f"{tr['passivity']}, {tr['round_trip_ms']:g} ms" + (
                f", {tr['loss_percent']:g} % loss" if tr.get("loss_percent") else "")
            line, = ax_x.plot(tr["time_s"], [1e3 * x for x in tr["master_x_m"]], label=f"master, {label}")
            ax_x.plot(tr["time_s"], [1e3 * x for x in tr["remote_x_m"]], linestyle="--", color=line.get_color(),
                      label=f"remote, {label}")
            ax_f.plot(tr["time_s"], [-f for f in tr["master_force_x_n"]], color=line.get_color(), label=label)
        ax_x.axhline(1e3 * result.get("wall_offset_m", 0.03), color="grey", linestyle=":", linewidth=1)
        ax_x.set_ylabel("handle along x [mm]")
        ax_f.set_ylabel("force felt at the master [N]")
        ax_f.set_xlabel("time [s]")
        ax_x.legend(fontsize=7)
        ax_f.legend(fontsize=7)
        for ax in (ax_x, ax_f):
            ax.grid(True, alpha=0.3)
        fig.suptitle(f"Teleoperation, {result['architecture']}: the remote's wall (dotted) through the link")
        fig.tight_layout()
        png = out_dir / "teleoperation.png"
        fig.savefig(png, dpi=100)
        plt.close(fig)
        pngs.append(png)
    head = ["task", "passivity", "round trip", "loss", "passive", "stable", "lowest energy", "felt stiffness",
            "drift"]
    rows = []
    for r in result["rows"]:
        rows.append([r["task"], r["passivity"], fmt(r["round_trip_ms"], "ms"), fmt(r["loss_percent"], "%"),
                     "yes" if r["passive"] else "no", "yes" if r["stable"] else ("fault" if r["fault"] else "no"),
                     fmt(1e3 * r["min_energy_j"], "mJ"),
                     fmt(r["felt_stiffness_n_per_m"], "N/m") if r["task"] == "wall" else "-",  # null: unstable
                     fmt(r["drift_mm"], "mm") if r["drift_mm"] is not None else "-"])
    return pngs, [(head, rows)]


DRAW = {"teleoperation": teleoperation, "force-response": force_response, "backdrivability": backdrivability, "minimum-inertia": minimum_inertia,
        "force-gain": force_gain,
        "tracking": tracking, "z-width": z_width, "transparency": transparency, "friction": friction}


def html_table(table):
    head, rows = table
    out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>"]
    for r in rows:
        out.append("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir = pathlib.Path(sys.argv[1])
    sections = []
    for path in sorted(out_dir.glob("*.json")):
        result = json.loads(path.read_text())
        draw = DRAW.get(result.get("experiment"))
        if draw is None:
            continue
        pngs, tables = draw(result, out_dir)
        parts = [f"<h2>{html.escape(result.get('title', result['experiment']))}</h2>"]
        parts.append(f"<p>Reproduce: <code>{html.escape(result.get('command', ''))}</code></p>")
        parts += [html_table(t) for t in tables]
        for png in pngs:
            data = base64.b64encode(png.read_bytes()).decode()
            parts.append(f'<p><img alt="{html.escape(png.name)}" src="data:image/png;base64,{data}"></p>')
        if result.get("example_session"):
            parts.append("<details><summary>session file of one run</summary><pre>"
                         f"{html.escape(result['example_session'])}</pre></details>")
        sections.append("\n".join(parts))
    page = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>hapticd evaluation</title>
<style>body{{font-family:sans-serif;max-width:960px;margin:auto}}table{{border-collapse:collapse}}
td,th{{border:1px solid #bbb;padding:2px 8px;text-align:left}}img{{max-width:100%}}</style></head>
<body><h1>hapticd evaluation report</h1>
<p>The thesis's chapter-5 experiments on the simulated device, in lockstep (docs/evaluation.md).</p>
{''.join(sections) or '<p>No results.</p>'}
</body></html>
"""
    (out_dir / "report.html").write_text(page)
    print(f"report: {out_dir / 'report.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

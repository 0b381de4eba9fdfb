#!/usr/bin/env python3
"""Draws the evaluation suite's figures and one self-contained HTML report.

usage: eval_report.py RESULTS_DIR

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


DRAW = {"force-response": force_response, "backdrivability": backdrivability}


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

"""The Python examples run: the experiment sweep (in-process) and the wall engine against a real server."""
import os
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = os.path.join(ROOT, "examples", "python")


def run_example(name, *args, timeout=120):
    done = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args], capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ))
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_the_mass_sweep_runs_and_plots(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "sweep.png"
    text = run_example("mass_sweep.py", "--masses", "0.5", "4", "--out", str(out))
    lines = [l for l in text.splitlines() if l.startswith("mass")]
    assert len(lines) == 2 and all("faulted False" in l for l in lines)
    peaks = [float(l.split("peak operator force ")[1].split(" N")[0]) for l in lines]
    assert peaks[1] > 1.5 * peaks[0]  # the heavier virtual mass is felt
    assert out.stat().st_size > 10000


@pytest.mark.domain(94)
def test_the_wall_engine_holds_the_pushing_operator(server):
    text = run_example("wall_engine.py", "--domain", "94", "--duration", "2", "--push", "15")
    answered = int(text.split("answered ")[1].split(" ")[0])
    deepest_mm = float(text.split("deepest ")[1].split(" mm")[0])
    assert answered > 1000 and 2.0 < deepest_mm < 10.0, text

"""A recording written by the server (hapticd --record, lockstep) read back with hapticd.recording; the CSV
export and the plot script on the same file."""
import os
import subprocess

import numpy as np
import pytest

import hapticd
from conftest import BIN, ROOT, session_path

h5py = pytest.importorskip("h5py")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    out = tmp_path_factory.mktemp("rec") / "demo.h5"
    subprocess.run([os.path.join(BIN, "hapticd"), "--config", session_path("demo.yaml"), "--clock", "lockstep",
                    "--duration", "1", "--set", "dds.enabled=false", "--record", str(out), "--log-level", "warn"],
                   check=True, timeout=60)
    return out


def test_every_quantity_of_every_cycle_is_recorded(recorded):
    rec = hapticd.recording.read(str(recorded))
    assert rec.attributes["rate_hz"] == 2000.0
    assert "devices:" in rec.session_text and rec.session_file.endswith("demo.yaml")
    dev = rec.devices["vishard3"]
    n = rec.statistics["cycles"]
    assert n == 2400  # 1 s and the 0.2 s shutdown ramp at 2 kHz
    for column in dev.columns:
        assert dev[column].shape[0] == n, column
    assert dev["joints/position"].shape == (n, 3) and dev.joint_names == ["joint1", "joint2", "joint3"]
    assert np.all(np.diff(dev["cycle"]) == 1) and dev.time_s[1] - dev.time_s[0] == pytest.approx(0.0005)
    # the handle settles in the operator's hand (it moves), its pose is a unit quaternion
    assert np.ptp(dev["handle/pose"][:, 0]) > 0.0
    assert np.allclose(np.linalg.norm(dev["handle/pose"][:, 3:], axis=1), 1.0)
    # the velocity column is the server's estimate, not zeros (the old CSV's was on simulated devices)
    assert np.abs(dev["joints/velocity"]).max() > 0.0
    assert dev.modes()[n // 2] == "running" and dev.modes()[-1] in ("stopping", "safe", "running")
    assert not dev.flag("fault").any()
    assert rec.events == []


def test_the_csv_export_has_every_cycle(recorded, tmp_path):
    out = subprocess.run([os.path.join(BIN, "hapticctl"), "export", str(recorded), "--csv", "--out", str(tmp_path)],
                         check=True, capture_output=True, text=True, timeout=60).stdout
    assert "2400 cycles of 'vishard3'" in out
    csv = (tmp_path / "demo.vishard3.csv").read_text().splitlines()
    assert len(csv) == 2401 and csv[0].startswith("cycle,time_s,joints.position.joint1")
    rec = hapticd.recording.read(str(recorded))
    header = csv[0].split(",")
    x = [float(line.split(",")[header.index("handle.pose.x")]) for line in csv[1:]]
    assert np.array_equal(np.array(x), rec.devices["vishard3"]["handle/pose"][:, 0])


def test_a_file_that_is_not_a_recording_is_refused(tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = [1, 2, 3]
    with pytest.raises(ValueError, match="not a hapticd recording"):
        hapticd.recording.read(str(other))


def test_the_plot_program_draws_the_recording_whatever_python3_the_path_finds(recorded, tmp_path):
    # hapticd-plot-recording names its interpreter and finds the package itself: no PYTHONPATH, and a PATH whose
    # first python3 cannot import anything of ours.
    pytest.importorskip("matplotlib")
    png = tmp_path / "rec.png"
    fake_bin = tmp_path / "fake-bin"
    fake_bin.mkdir()
    (fake_bin / "python3").write_text("#!/bin/sh\necho 'not this python3' >&2\nexit 1\n")
    (fake_bin / "python3").chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PATH"] = f"{fake_bin}:{env.get('PATH', '')}"
    subprocess.run([os.path.join(BIN, "hapticd-plot-recording"), str(recorded), str(png)],
                   check=True, timeout=120, env=env)
    assert png.stat().st_size > 10000


def test_attributes_read_as_text_not_bytes(recorded):
    rec = hapticd.recording.read(str(recorded))
    assert rec.attributes["format"] == "hapticd-recording"
    assert rec.attributes["clock"] in ("lockstep", "realtime")
    assert rec.attributes["devices"] == list(rec.devices)
    dev = next(iter(rec.devices.values()))
    assert dev.attributes["joint_names"] == dev.joint_names and all(isinstance(n, str) for n in dev.joint_names)
    assert isinstance(dev.attributes["model"], str)


def test_the_shipped_recording_reads():
    # config/recordings/vishard3-sine.h5, which config/sessions/playback.yaml replays as shipped.
    rec = hapticd.recording.read(os.path.join(ROOT, "config", "recordings", "vishard3-sine.h5"))
    pose = rec.devices["vishard3"]["handle/pose"]
    assert pose.shape[0] > 500 and np.ptp(pose[:, 0]) > 0.02  # the operator moved the handle

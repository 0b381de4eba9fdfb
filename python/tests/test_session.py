"""The in-process session API from Python: lockstep runs, NumPy views, engine input, requests, errors."""
import os

import numpy as np
import pytest

import hapticd
from conftest import session_path

RAC = session_path("vishard3", "admittance-resolved-acceleration.yaml")


def pushed_run(seed):
    with hapticd.Session.from_file(RAC, [f"server.seed={seed}"]) as s:
        s.step(200)
        s.operator("vishard3", "push", [8.0, 0.0, 0.0, 0.1])
        return s.run(2000, "vishard3", every=10)


def test_a_lockstep_run_is_repeatable_and_follows_the_push():
    a, b = pushed_run(3), pushed_run(3)
    assert set(a) >= {"time_s", "position", "orientation", "operator_force", "joint_position", "true_position"}
    assert a["position"].shape == (200, 3) and a["joint_position"].shape == (200, 3)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    # 8 N along +x into a 3 kg, 15 N s/m admittance: the handle moves along +x (the operator's arm holds it back
    # after a few centimetres), and the push is felt at the handle.
    moved = a["position"][-1] - a["position"][0]
    assert moved[0] > 0.01 and abs(moved[1]) < 0.5 * moved[0]
    assert a["operator_force"][:, 0].max() > 3.0
    np.testing.assert_allclose(np.diff(a["time_s"]), 10 * 0.0005)
    assert not a["faulted"].any()


def test_the_device_view_has_numpy_fields_and_the_ground_truth():
    with hapticd.Session.from_file(RAC, ["server.seed=1"]) as s:
        assert s.device_names == ["vishard3"]
        assert s.period_s == pytest.approx(0.0005)
        s.step(50)
        v = s.device("vishard3")
        assert v.cycle == 49 and v.scheme == "default" and v.fault == ""
        assert isinstance(v.joint_position, np.ndarray) and v.joint_position.shape == (3,)
        assert v.handle_pose.position.shape == (3,) and v.handle_pose.orientation.shape == (4,)
        assert v.truth is not None
        np.testing.assert_allclose(v.truth.handle_pose.position, v.handle_pose.position, atol=1e-3)
        d = s.description("vishard3")
        assert d.model == "vishard3" and d.dof == 3 and d.simulated
        assert s.statistics().cycles == 50


def test_engine_input_couples_the_handle_to_a_proxy():
    with hapticd.Session.from_file(session_path("vishard3", "dds-coupling.yaml"), ["server.seed=2"]) as s:
        s.step(20)
        start = s.device("vishard3").handle_pose
        proxy = hapticd.Pose(start.position + [0.02, 0.0, 0.0], start.orientation)
        for k in range(1, 2001):  # 1 s of engine input, a new command every cycle as an engine would send
            command = hapticd.EngineInput.coupling(proxy)
            command.sequence = k
            s.set_engine_input("vishard3", command)
            s.step(1)
        v = s.device("vishard3")
        assert v.engine_weight == pytest.approx(1.0)
        # The coupling spring pulls the virtual body (and the handle, held loosely) towards the proxy 2 cm ahead.
        assert v.handle_pose.position[0] - start.position[0] > 0.01


def test_requests_answer_or_raise_with_the_servers_message():
    with hapticd.Session.from_file(RAC, ["server.seed=1"]) as s:
        s.step(10)
        assert s.get_parameter("vishard3", "virtual_model.mass_kg") == [3.0, 3.0, 3.0]
        s.set_parameter("vishard3", "virtual_model.mass_kg", [2.0, 2.0, 2.0])
        assert s.get_parameter("vishard3", "virtual_model.mass_kg") == [2.0, 2.0, 2.0]
        described = {p["name"]: p for p in s.parameters("vishard3")}
        mass = described["virtual_model.mass_kg"]
        assert mass["value"] == [2.0, 2.0, 2.0] and mass["unit"] == "kg" and mass["tunable"]
        assert (mass["minimum"], mass["maximum"]) == (0.1, 1000.0)
        assert described["device.urdf"]["type"] == "string" and not described["device.urdf"]["tunable"]
        assert described["safety.passivity_control"]["value"] == [0.0]
        with pytest.raises(hapticd.RequestRefused, match="mass_kg"):
            s.set_parameter("vishard3", "virtual_model.mass_kg", -1.0)
        with pytest.raises(hapticd.RequestRefused, match="no-such-scheme"):
            s.switch_scheme("vishard3", "no-such-scheme")
        s.estop("vishard3")
        s.step(2)
        assert s.device("vishard3").fault.startswith("emergency")
        with pytest.raises(KeyError, match="nope"):
            s.device("nope")


def test_a_configuration_error_names_file_line_and_key(tmp_path):
    bad = tmp_path / "bad.yaml"
    text = open(RAC).read().replace("mass_kg: [3.0, 3.0, 3.0]", "mass_kg: [3.0, -3.0, 3.0]")
    assert text != open(RAC).read()
    bad.write_text(text.replace("../../urdf/", session_path("..", "urdf") + "/"))
    line = next(i + 1 for i, l in enumerate(text.splitlines()) if "mass_kg" in l)
    with pytest.raises(hapticd.SessionError) as error:
        hapticd.Session.from_file(bad)
    message = str(error.value)
    assert str(bad) in message and f":{line}" in message and "mass_kg" in message
    with pytest.raises(hapticd.SessionError, match="override 'server.rate_hz=fast'"):
        hapticd.Session.from_file(RAC, ["server.rate_hz=fast"])
    with pytest.raises(hapticd.SessionError):
        hapticd.Session.from_yaml("devices: [", name="inline")
    with pytest.raises(hapticd.SessionError):
        hapticd.Session.from_file(tmp_path / "missing.yaml")


def test_bad_values_raise_value_errors_and_a_stopped_session_cannot_step():
    with pytest.raises(ValueError, match="3 numbers"):
        hapticd.Pose([1.0, 2.0])
    with pytest.raises(ValueError, match="zero quaternion"):
        hapticd.Pose([0, 0, 0], [0, 0, 0, 0])
    with pytest.raises(ValueError, match="not finite"):
        hapticd.Wrench([float("nan"), 0, 0])
    s = hapticd.Session.from_file(RAC)
    s.step(5)
    with pytest.raises(ValueError):
        s.run(10, "vishard3", every=0)
    s.stop()
    with pytest.raises(hapticd.SessionError):
        s.step(1)


@pytest.mark.skipif("HAPTICD_STANDIN_DIR" not in os.environ, reason="the vendors' SDK stand-ins are not built")
def test_a_handle_device_reports_its_buttons_and_gripper(monkeypatch):
    # A Force Dimension omega.7 on the project's stand-in of the vendor's SDK (docs/devices.md), found through the
    # vendor's own variable; its buttons held (mask 5), its gripper at the stand-in's 0.3 rad.
    monkeypatch.setenv("FORCEDIM_SDK", os.path.join(os.environ["HAPTICD_STANDIN_DIR"], "forcedimension"))
    monkeypatch.setenv("HAPTICD_DHD_STANDIN", "omega.7:10002")
    monkeypatch.setenv("HAPTICD_DHD_STANDIN_BUTTONS", "5")
    monkeypatch.setenv("HAPTICD_DHD_STANDIN_STEP", "0.0005")
    with hapticd.Session.from_file(session_path("forcedimension", "omega-wall.yaml")) as s:
        s.step(100)
        v = s.device("omega")
        assert v.fault == ""
        assert v.buttons == 5
        assert v.gripper == pytest.approx(0.3)
        assert v.joint_position.shape == (4,)  # x, y, z and the gripper: a handle device's axes


def test_an_interpreter_without_numpy_is_told_to_use_hapticd_python():
    # A pyenv or conda python3 without NumPy importing the package: before, "No module named 'numpy'" from deep in
    # hapticd/recording.py; now a message that names the way out. (NumPy hidden in a child interpreter.)
    import subprocess
    import sys

    code = "import sys; sys.modules['numpy'] = None\ntry:\n    import hapticd\nexcept ImportError as e:\n    print(e)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60).stdout
    assert "needs NumPy" in out and "hapticd-python" in out, out

"""The Python client against a real server on loopback (each test on a DDS domain of its own)."""
import threading
import time

import pytest

import hapticd
from wall_engine import Wall  # examples/python (conftest puts it on the path)


@pytest.mark.domain(91)
def test_devices_states_and_requests(server):
    with hapticd.Client("py-tool", domain=91) as c:
        info = c.wait_for_device("vishard3", timeout=20.0, started=True)
        assert info.dof == 3 and info.simulated and info.device_plugin == "sim"
        assert [s.name for s in info.schemes] == ["default"]
        assert info.start_pose is not None and info.start_pose.position.shape == (3,)
        assert [d.device for d in c.devices()] == ["vishard3"]
        first = c.wait_for_state("vishard3", timeout=5.0)
        later = c.wait_for_state("vishard3", timeout=5.0, after=first.serial)
        assert later.serial > first.serial and later.mode == hapticd.Mode.RUNNING
        assert later.position.shape == (3,) and later.owner == ""
        seen = [s.serial for s in hapticd.states(c, "vishard3", duration=0.2)]
        assert len(seen) > 10 and seen == sorted(seen)
        assert c.get_parameter("vishard3", "virtual_model.coupling_stiffness_n_per_m") == [3000.0]
        described = {p["name"]: p for p in c.parameters("vishard3")}
        stiffness = described["virtual_model.coupling_stiffness_n_per_m"]
        assert (stiffness["value"], stiffness["unit"], stiffness["tunable"]) == ([3000.0], "N/m", True)
        with pytest.raises(hapticd.RequestRefused, match="no-such-scheme"):
            c.switch_scheme("vishard3", "no-such-scheme")
        with pytest.raises(hapticd.RequestRefused):
            c.set_parameter("vishard3", "virtual_model.mass_kg", [-1.0, 1.0, 1.0])
        with pytest.raises(hapticd.Timeout):
            c.wait_for_device("no-such-device", timeout=0.3)
        with pytest.raises(hapticd.Timeout):
            c.claim("no-such-device", timeout=0.5)
    with pytest.raises(ValueError):
        hapticd.Client("")  # a client id of 1..31 characters


@pytest.mark.domain(92)
def test_a_python_engine_renders_a_wall_the_operator_pushes_against(server):
    with hapticd.Client("py-engine", domain=92) as c:
        start = c.wait_for_state("vishard3", timeout=20.0).pose.position
        wall_x = start[0] + 0.02
        pusher = hapticd.Client("py-operator", domain=92)
        timer = threading.Timer(0.3, lambda: pusher.operator("vishard3", "push", [15.0, 0.0, 0.0, 0.2]))
        timer.start()
        wall = Wall(wall_x)
        stats = hapticd.run_engine(c, "vishard3", wall, duration=2.5)
        timer.join()
        pusher.close()
        assert stats.ended_by == "duration" and stats.send_failures == 0
        assert stats.answered > 1000  # most of 2.5 s at 2 kHz
        # The release reaches the server a little after the last command: wait (bounded) for a state that shows it.
        last = c.wait_for_state("vishard3", timeout=5.0)
        give_up = time.monotonic() + 5.0
        while last.owner != "" and time.monotonic() < give_up:
            time.sleep(0.01)
            last = c.wait_for_state("vishard3", timeout=5.0)
        # Held at the wall while claimed: 15 N through the 3000 N/m coupling is 5 mm into it; released at the end.
        assert 0.002 < wall.deepest < 0.01
        assert last.owner == ""
        assert 0.015 < last.pose.position[0] - start[0] < 0.03


@pytest.mark.domain(95)
def test_a_wrench_with_a_local_model_is_a_wall_at_the_loops_rate(server):
    # Issue 63: Python could send no wrench with a local model. A spring of 2000 N/m along x anchored on a wall 2 cm
    # ahead, sent while the handle is past it (nothing in front): the server applies it every cycle until the next
    # command; the operator's 15 N push rests 7.5 mm into it.
    with hapticd.Client("py-local-model", domain=95) as c:
        start = c.wait_for_state("vishard3", timeout=20.0).pose.position
        wall_x = start[0] + 0.02
        deepest = [0.0]

        def wall(state):
            depth = state.pose.position[0] - wall_x
            deepest[0] = max(deepest[0], depth)
            anchor = hapticd.Pose([wall_x, state.pose.position[1], state.pose.position[2]])
            k, b = ([2000.0, 0.0, 0.0], [10.0, 0.0, 0.0]) if depth > 0 else ([0.0] * 3, [0.0] * 3)
            return hapticd.EngineCommand.force(hapticd.Wrench(), local_model=hapticd.LocalModel.spring(anchor, k, b))

        pusher = hapticd.Client("py-pusher", domain=95)
        timer = threading.Timer(0.3, lambda: pusher.operator("vishard3", "push", [15.0, 0.0, 0.0, 0.2]))
        timer.start()
        stats = hapticd.run_engine(c, "vishard3", wall, duration=2.5)
        timer.join()
        pusher.close()
        assert stats.ended_by == "duration" and stats.send_failures == 0 and stats.answered > 1000
        assert 0.006 < deepest[0] < 0.010, deepest[0]
    model = hapticd.LocalModel(hapticd.Pose(), [1, 2, 3, 4, 5, 6], [6, 5, 4, 3, 2, 1])
    assert list(model.stiffness) == [1, 2, 3, 4, 5, 6] and list(model.damping) == [6, 5, 4, 3, 2, 1]
    with pytest.raises(TypeError):
        hapticd.LocalModel.spring(hapticd.Pose(), [1.0, 2.0])  # three values, one per axis


@pytest.mark.domain(96)
def test_run_engine_raises_what_the_function_raised_releases_and_ends_when_told(server):
    # run_engine is the client library's engine helper (issue 63): the function runs on the receive thread, an
    # exception it raises ends the run, is raised in the caller and the device is released; False ends the run.
    with hapticd.Client("py-raiser", domain=96) as c:
        calls, threads = [0], set()

        def broken(state):
            calls[0] += 1
            threads.add(threading.get_ident())
            if calls[0] > 100:
                raise ZeroDivisionError("the physics blew up")
            return hapticd.EngineCommand.force(hapticd.Wrench())

        with pytest.raises(ZeroDivisionError, match="blew up"):
            hapticd.run_engine(c, "vishard3", broken, duration=10.0)
        assert calls[0] == 101  # never called again once it raised
        assert threading.get_ident() not in threads
        with hapticd.Client("py-next", domain=96) as other:
            other.claim("vishard3")  # released by the helper
            other.release("vishard3")
        seen = [0]

        def few(state):
            seen[0] += 1
            return False if seen[0] == 50 else None

        stats = hapticd.run_engine(c, "vishard3", few, duration=10.0)
        assert (stats.ended_by, stats.unanswered, stats.answered) == ("function", 49, 0)
        with pytest.raises(TypeError, match="not an EngineCommand"):
            hapticd.run_engine(c, "vishard3", lambda state: 42, duration=10.0)
        with pytest.raises(hapticd.Timeout):
            hapticd.run_engine(c, "no-such-device", few, wait=0.3)


@pytest.mark.domain(93)
def test_an_emergency_stop_is_an_event_and_a_fault_report_and_recovery_works(server):
    with hapticd.Client("py-safety", domain=93) as c:
        state = c.wait_for_state("vishard3", timeout=20.0)
        while state.time_s < 0.2:
            state = c.wait_for_state("vishard3", timeout=5.0, after=state.serial)
        c.claim("vishard3")
        with pytest.raises(hapticd.RequestRefused):  # one engine at a time
            with hapticd.Client("py-other", domain=93) as other:
                other.claim("vishard3")
        c.estop("vishard3")
        report = None
        for _ in range(100):  # at most 5 s
            report = c.latest_fault_report("vishard3")
            if report is not None:
                break
            time.sleep(0.05)
        assert report is not None and report.fault == "emergency_stop" and len(report.records) == 50
        assert report.records[-1].handle_position.shape == (3,)
        safe = c.wait_for_state("vishard3", timeout=5.0)
        while safe.mode != hapticd.Mode.SAFE:
            safe = c.wait_for_state("vishard3", timeout=5.0, after=safe.serial)
        assert "estop" in safe.flag_names
        kinds = [(e.kind, e.code) for e in c.take_events()]
        assert (hapticd.EventKind.ESTOP, "emergency_stop") in kinds
        # Recovered once the safe mode has reached zero torque (it may refuse until then).
        for _ in range(40):
            try:
                c.recover("vishard3")
                break
            except hapticd.RequestRefused:
                time.sleep(0.1)
        running = c.wait_for_state("vishard3", timeout=5.0)
        while running.mode != hapticd.Mode.RUNNING:
            running = c.wait_for_state("vishard3", timeout=5.0, after=running.serial)
        assert running.fault == ""
        telemetry = c.latest_telemetry("vishard3")
        assert telemetry is not None and telemetry.faults >= 1
        c.release("vishard3")


def test_flag_names_decode_every_bit():
    assert hapticd.flag_names(0) == []
    assert hapticd.flag_names(1 | 8 | 1024) == ["torque_saturated", "estop", "passivity_control"]
    assert hapticd.flag_names(1 << 20) == ["bit20"]

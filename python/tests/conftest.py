"""Fixtures of the Python package's tests: the repository's paths and a real hapticd server on loopback.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH at the build tree's package and HAPTICD_BIN_DIR at its
programs. Every server runs on a DDS domain of its own (91..99), loopback only, for a bounded time."""
import os
import subprocess
import sys
import time

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SESSIONS = os.path.join(ROOT, "config", "sessions")
sys.path.insert(0, os.path.join(ROOT, "examples", "python"))  # the tests use the examples' engines
BIN = os.environ.get("HAPTICD_BIN_DIR", os.path.join(ROOT, "build", "default", "bin"))

# The loop watchdogs loosened as in tests/e2e/session_copy.sh (why: there): these tests test the package and the
# DDS path, not the machine, and a shared CI machine runs the loop late now and then.
LOOSE_WATCHDOGS = ("--set", "devices.vishard3.safety.max_consecutive_overruns=2000",
                   "--set", "devices.vishard3.safety.max_stall_s=1.0")


def session_path(*parts):
    return os.path.join(SESSIONS, *parts)


class Server:
    """hapticd with the simulated ViSHaRD3 (real time, no RT priority): by default in admittance display coupled over
    DDS (vishard3/dds-coupling.yaml), else the session file named."""

    def __init__(self, domain, duration_s, tmp_path, extra=(), session="dds-coupling.yaml"):
        self.domain = domain
        self.stats = os.path.join(tmp_path, f"stats-{domain}.json")
        self.log = open(os.path.join(tmp_path, f"server-{domain}.log"), "w")
        self.process = subprocess.Popen(
            [os.path.join(BIN, "hapticd"), "--config", session_path("vishard3", session),
             "--dds-domain", str(domain), "--duration", str(duration_s), "--stats-json", self.stats,
             "--log-level", "warn", "--set", "server.realtime_priority=0", "--set", "server.lock_memory=false",
             *LOOSE_WATCHDOGS, *extra],
            stdout=self.log, stderr=subprocess.STDOUT)

    def stop(self):
        if self.process.poll() is None:
            self.process.terminate()
        try:
            self.process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.log.close()


@pytest.fixture
def server(request, tmp_path):
    """A server for one test: the domain from the test's marker (pytest.mark.domain(N), or (N, SESSION): a session
    file of config/sessions/vishard3), at most 40 s."""
    marker = request.node.get_closest_marker("domain")
    assert marker is not None, "a test with a server names its DDS domain: @pytest.mark.domain(N)"
    session = marker.args[1] if len(marker.args) > 1 else "dds-coupling.yaml"
    s = Server(marker.args[0], 40, str(tmp_path), session=session)
    time.sleep(0.2)
    yield s
    s.stop()


def pytest_configure(config):
    config.addinivalue_line("markers", "domain(id[, session]): the DDS domain of the test's server (one per test)")

"""hapticd: the Python package of the hapticd haptic control server (docs/python.md).

- ``Client``: hapticd's DDS interface - devices, states (NumPy arrays), claims, every request, events, fault
  reports, engine commands, the session's haptic scene (``Client.scene()``, a ``Scene``). Loopback only by default.
- ``run_engine``: a Python function answers each state of a device with an engine command at the loop rate.
- ``Session``: a session in this process, stepped in lockstep (for experiments and notebooks).
- ``recording.read``: a recording (``hapticd --record FILE.h5``) as NumPy arrays.
- Errors: ``Error``, ``SessionError``, ``RequestRefused``, ``Timeout`` (``hapticd.errors``).
"""
try:
    import numpy as _numpy  # noqa: F401  (the states, the recordings: every part of the package uses it)
except ImportError as _missing:  # a python3 other than the one the package was built for (pyenv, conda, a venv)
    import sys as _sys

    raise ImportError(
        f"the hapticd package needs NumPy, which this interpreter ({_sys.executable}) lacks: run your script with "
        "hapticd-python (the interpreter the package was built for, with NumPy, h5py and Matplotlib), or install "
        "NumPy here (python3 -m pip install numpy) - docs/python.md, 'Which Python'") from _missing
from ._hapticd import (  # noqa: F401
    Client,
    CycleRecord,
    DeviceDescription,
    DeviceInfo,
    DeviceState,
    DeviceView,
    EngineCommand,
    EngineInput,
    Event,
    EventKind,
    FaultReport,
    GroupInfo,
    GroupState,
    JointDescription,
    LocalModel,
    LoopSummary,
    Mode,
    Pose,
    Scene,
    SceneContact,
    SceneObject,
    SchemeInfo,
    Session,
    SessionStatistics,
    SimulatedTruth,
    Telemetry,
    Twist,
    Wrench,
    flag_names,
)
from .engine import EngineStats, run_engine, states  # noqa: F401
from . import recording  # noqa: F401
from .errors import ClaimLost, Error, RequestRefused, SessionError, Timeout  # noqa: F401

__all__ = [
    "ClaimLost", "Client", "CycleRecord", "DeviceDescription", "DeviceInfo", "DeviceState", "DeviceView", "EngineCommand",
    "EngineInput", "EngineStats", "Error", "Event", "EventKind", "FaultReport", "GroupInfo", "GroupState",
    "JointDescription", "LocalModel", "LoopSummary", "Mode", "Pose", "RequestRefused", "Scene", "SceneContact",
    "SceneObject", "SchemeInfo", "Session", "SessionError", "SessionStatistics", "SimulatedTruth", "Telemetry", "Timeout",
    "Twist", "Wrench", "flag_names", "run_engine", "states",
]

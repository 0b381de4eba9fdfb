"""Reading hapticd recordings (``hapticd --record FILE.h5``; the schema: docs/recording.md) with h5py.

    rec = hapticd.recording.read("run.h5")
    dev = rec.devices["vishard3"]
    plt.plot(dev.time_s, dev["handle/pose"][:, 0])     # handle x over time
    dev.flag("limit_engaged")                            # one bool per cycle
    rec.statistics["cycles"], rec.events                  # the session's summary

MATLAB reads the same file with ``h5read('run.h5', '/devices/vishard3/handle/pose')`` (rows and columns swapped).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any, Dict, List

import numpy as np

FORMAT = "hapticd-recording"


def _text(value: Any) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    return str(value)


def _texts(value: Any) -> List[str]:
    return [_text(v) for v in np.atleast_1d(value)]


def _attribute(value: Any) -> Any:
    """An HDF5 attribute as Python reads it best: text as str (h5py gives bytes), lists of text as lists of str,
    single numbers as numbers, other arrays unchanged."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray):
        if value.dtype.kind in ("S", "O", "U"):
            return _texts(value) if value.shape != () else _text(value)
        if value.shape == ():
            return value[()].item()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _attributes(attrs: Any) -> Dict[str, Any]:
    return {k: _attribute(v) for k, v in attrs.items()}


@dataclass
class DeviceRecording:
    """One device's cycles: ``dev["joints/position"]`` is an array with a row per cycle; ``attributes``: the
    device's description (text as str, lists of text as lists of str)."""

    name: str
    attributes: Dict[str, Any]
    columns: List[str]
    data: Dict[str, np.ndarray]

    def __getitem__(self, path: str) -> np.ndarray:
        return self.data[path]

    @property
    def time_s(self) -> np.ndarray:
        return self.data["time_s"]

    @property
    def joint_names(self) -> List[str]:
        return _texts(self.attributes["joint_names"])

    @property
    def flag_names(self) -> List[str]:
        return _texts(self.attributes["flag_names"])

    @property
    def mode_names(self) -> List[str]:
        return _texts(self.attributes["mode_names"])

    @property
    def schemes(self) -> List[str]:
        return _texts(self.attributes["schemes"])

    def flag(self, name: str) -> np.ndarray:
        """Whether the state flag ``name`` (e.g. "engine_active") was set, per cycle.

        Recordings before plugin API 10 spell the names in capitals: either spelling finds the flag."""
        names = [n.lower() for n in self.flag_names]
        if name.lower() not in names:
            raise KeyError(f"no state flag {name!r} (the recording has {', '.join(names)})")
        bit = names.index(name.lower())
        return (self.data["flags"] & (1 << bit)) != 0

    def modes(self) -> List[str]:
        """The device's mode per cycle, by name."""
        names = self.mode_names
        return [names[m] for m in self.data["mode"]]


@dataclass
class Recording:
    path: str
    attributes: Dict[str, Any]
    session_file: str
    session_text: str
    devices: Dict[str, DeviceRecording]
    statistics: Dict[str, Any] = field(default_factory=dict)  # as hapticd --stats-json writes it ({} if cut short)
    events: List[Dict[str, Any]] = field(default_factory=list)  # faults and recoveries: device, kind, code, cycle, time_s


def read(path: str) -> Recording:
    """Reads a whole recording into memory (NumPy arrays). Raises ValueError for a file that is not one."""
    import h5py  # Debian's python3-h5py

    with h5py.File(path, "r") as f:
        if _text(f.attrs.get("format", b"")) != FORMAT:
            raise ValueError(f"{path}: not a hapticd recording (format attribute is not '{FORMAT}')")
        devices: Dict[str, DeviceRecording] = {}
        for name in _texts(f.attrs["devices"]):
            g = f["devices"][name]
            columns = _texts(g.attrs["columns"])
            data = {c: g[c][()] for c in columns}
            devices[name] = DeviceRecording(name, _attributes(g.attrs), columns, data)
        statistics: Dict[str, Any] = {}
        if "statistics" in f:
            statistics = json.loads(_text(f["statistics"][()]))
        events: List[Dict[str, Any]] = []
        if "events" in f:
            e = f["events"]
            for k in range(e["cycle"].shape[0]):
                events.append({"device": _text(e["device"][k]), "kind": _text(e["kind"][k]),
                               "code": _text(e["code"][k]), "cycle": int(e["cycle"][k]),
                               "time_s": float(e["time_s"][k])})
        return Recording(path, _attributes(f.attrs), _text(f["session"].attrs["path"]),
                         _text(f["session/file"][()]), devices, statistics, events)

"""Rendering engines in Python: iterate over a device's states, or answer each one with a command."""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable, Iterator, Optional

from ._hapticd import Client, DeviceState, Mode, _run_engine
from .errors import ClaimLost, Error, RequestRefused, Timeout


def states(client: Client, device: str, timeout: float = 1.0,
           duration: Optional[float] = None) -> Iterator[DeviceState]:
    """Yield the device's states as they arrive, newest first when several arrived at once (a slow reader skips
    states, it never queues them). Stops after ``duration`` seconds (None: never) or when the device stops;
    raises ``Timeout`` when no state comes within ``timeout`` seconds. The GIL is released while waiting."""
    serial = 0
    end = None if duration is None else time.monotonic() + duration
    while end is None or time.monotonic() < end:
        state = client.wait_for_state(device, timeout, serial)
        serial = state.serial
        yield state
        if state.mode in (Mode.STOPPING, Mode.OFF):
            return


@dataclass
class EngineStats:
    """What ``run_engine`` did."""
    answered: int = 0          # states answered with a command
    skipped: int = 0           # states that arrived while the function ran (not answered)
    unanswered: int = 0        # states the function answered with None
    send_failures: int = 0     # commands that could not be written
    ended_by: str = ""         # "duration", "device stopped" (the session ended) or "function" (it returned False)


def run_engine(client: Client, device: str, answer: Callable[[DeviceState], object], duration: Optional[float] = None,
               timeout: float = 3.0, wait: float = 20.0) -> EngineStats:
    """Answer each state of ``device`` with ``answer(state)``: an ``EngineCommand`` (``EngineCommand.coupling``,
    ``.force`` or ``.motion``; its state_serial is set to the state's), None (no command for this state) or False
    (stop). The client library's engine helper (docs/engines.md, "The engine helper") waits up to ``wait`` seconds
    for the device to start, claims it, calls ``answer`` on the client's receive thread for each state (holding the
    GIL for the call only: other Python threads run meanwhile), claims again when the server ended the claim (the
    engine was gone - frozen, or its process stalled - for longer than the server's claim hold), and releases the
    device at the end. Runs for ``duration`` seconds (None: until the session ends, no state comes for ``timeout``
    seconds, or the function returns False). Raises what ``answer`` raised, ``Timeout`` when the device did not start
    or its states stopped coming, ``RequestRefused`` when the claim was refused, ``ClaimLost`` when another client
    took the device after the server ended this engine's claim."""
    result = _run_engine(client, device, answer, duration_s=duration or 0.0, timeout_s=timeout, wait_s=wait)
    reason, message = result["reason"], result["message"]
    if reason == _NO_DEVICE:
        raise Timeout(f"no device '{device}' started within {wait} s")
    if reason == _CLAIM_REFUSED:
        raise RequestRefused(f"cannot claim '{device}': {message}")
    if reason == _CLAIM_LOST:
        raise ClaimLost(f"the claim of '{device}' ended without its release and another client took it: the server "
                        "found this engine gone for longer than its claim hold")
    if reason == _SESSION_ENDED and message.startswith("no state"):
        raise Timeout(f"'{device}': {message}")
    if reason == _FAILED:
        raise Error(message)
    ended_by = "function" if result["stopped_by_function"] else \
        "duration" if reason == _FINISHED else "device stopped" if reason == _SESSION_ENDED else "stopped"
    return EngineStats(answered=result["answered"], skipped=result["skipped"], unanswered=result["unanswered"],
                       send_failures=result["send_failures"], ended_by=ended_by)


# hapticd::client::EngineEndReason
_FINISHED, _STOPPED, _SESSION_ENDED, _NO_DEVICE, _CLAIM_REFUSED, _CLAIM_LOST, _FAILED = range(7)

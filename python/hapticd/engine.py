"""Rendering engines in Python: iterate over a device's states, or answer each one with a command."""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable, Iterator, Optional

from ._hapticd import Client, DeviceState, EngineCommand, Mode
from .errors import ClaimLost


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
    ended_by: str = ""         # "duration", "device stopped" or "function" (it returned False)


def run_engine(client: Client, device: str, answer: Callable[[DeviceState], object], duration: Optional[float] = None,
               claim: bool = True, timeout: float = 1.0) -> EngineStats:
    """Answer each state of ``device`` with ``answer(state)``: an ``EngineCommand`` (``EngineCommand.coupling``,
    ``.force`` or ``.motion``; its state_serial is set to the state's), None (no command for this state) or False
    (stop). Claims the device first and releases it at the end when ``claim`` is true. The GIL is released while
    waiting for the next state, so other Python threads run meanwhile. Runs for ``duration`` seconds (None: until
    the device stops or the function returns False). Raises ``ClaimLost`` when the server ends the claim (the
    engine was gone - frozen, or its process stalled - for longer than the server's claim hold)."""
    stats = EngineStats()
    if claim:
        client.claim(device)
    end = None if duration is None else time.monotonic() + duration
    try:
        serial = 0
        while not stats.ended_by:
            if end is not None and time.monotonic() >= end:
                stats.ended_by = "duration"
                break
            state = client.wait_for_state(device, timeout, serial)
            if serial and state.serial > serial + 1:
                stats.skipped += state.serial - serial - 1
            serial = state.serial
            if state.mode in (Mode.STOPPING, Mode.OFF):
                stats.ended_by = "device stopped"
                break
            if claim and client.claim_lost(device):
                raise ClaimLost(f"the claim of '{device}' ended without its release (owner now "
                                f"'{state.owner}'): the server found this engine gone for longer than its claim hold")
            command = answer(state)
            if command is False:
                stats.ended_by = "function"
            elif command is None:
                stats.unanswered += 1
            elif not isinstance(command, EngineCommand):
                raise TypeError(f"the engine function returned {type(command).__name__}, not an EngineCommand")
            else:
                command.state_serial = state.serial
                if client.send(device, command):
                    stats.answered += 1
                else:
                    stats.send_failures += 1
    finally:
        if claim:
            try:
                client.release(device)
            except Exception:  # the server may be gone: there is nothing to release then
                pass
    return stats

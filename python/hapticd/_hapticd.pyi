"""Type stubs of the extension module (hapticd re-exports everything here). Units SI, world frame;
quaternions [w, x, y, z]; NumPy arrays are copies."""
from __future__ import annotations

import enum
import os
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

Vector = npt.NDArray[np.float64]
Values = Union[None, float, Sequence[float]]

# ---- spatial value types ----
class Pose:
    position: Vector      # [x, y, z] m
    orientation: Vector   # [w, x, y, z]
    def __init__(self, position: Sequence[float] = ..., orientation: Sequence[float] = ...) -> None: ...
    def rotation_matrix(self) -> Vector: ...

class Twist:
    linear: Vector        # m/s
    angular: Vector       # rad/s
    def __init__(self, linear: Sequence[float] = ..., angular: Sequence[float] = ...) -> None: ...

class Wrench:
    force: Vector         # N
    torque: Vector        # N m
    def __init__(self, force: Sequence[float] = ..., torque: Sequence[float] = ...) -> None: ...

# ---- the DDS client ----
class Mode(enum.Enum):
    STARTING = ...
    RUNNING = ...
    STOPPING = ...
    SAFE = ...
    OFF = ...

class EventKind(enum.Enum):
    FAULT = ...
    ESTOP = ...
    MODE = ...
    SCHEME = ...
    OWNER = ...
    ENGINE_STALE = ...
    ENGINE_REJECTED = ...
    RECOVERED = ...
    RECORDING = ...
    PARAMETER = ...

def flag_names(flags: int) -> list[str]: ...
# run_engine's engine helper (hapticd.engine.run_engine wraps it)
def _run_engine(client: Client, device: str, answer: Callable[[DeviceState], object], duration_s: float,
                timeout_s: float, wait_s: float) -> dict[str, Any]: ...

class LoopSummary:
    rate_hz: float
    cycles: int
    overruns: int
    latency_max_us: float
    compute_max_us: float

class SchemeInfo:
    name: str
    virtual_model: str

class DeviceInfo:
    device: str
    version: int
    device_plugin: str
    simulated: bool
    rate_hz: float
    dof: int
    joint_names: list[str]
    position_min: Vector
    position_max: Vector
    velocity_max: Vector
    torque_peak: Vector
    torque_continuous: Vector
    base_frame: str
    base_pose: Pose
    handle_frame: str
    start_pose: Optional[Pose]
    workspace_radius: float
    workspace_min: Vector
    workspace_max: Vector
    schemes: list[SchemeInfo]
    command_deadline_s: float
    command_fade_s: float

class DeviceState:
    device: str
    serial: int
    cycle: int
    loop_time_ns: int
    time_s: float
    pose: Pose
    twist: Twist
    operator_wrench: Wrench
    environment_wrench: Wrench
    target_pose: Pose
    dof: int
    position: Vector
    velocity: Vector
    torque: Vector
    mode: Mode
    flags: int
    flag_names: list[str]
    fault: str
    scheme: str
    owner: str
    engine_serial: int
    loop: LoopSummary

class GroupInfo:
    group: str
    version: int
    devices: list[str]
    min_distance_m: float
    repulsion_distance_m: float
    own_loop: bool

class GroupState:
    group: str
    serial: int
    cycle: int
    loop_time_ns: int
    clearance_m: float
    states: list[DeviceState]

class Event:
    device: str
    serial: int
    loop_time_ns: int
    kind: EventKind
    code: str
    message: str

class Telemetry:
    device: str
    wall_time_ns: int
    loop: LoopSummary
    states_published: int
    commands_received: int
    commands_accepted: int
    rejected: list[int]
    requests: int
    deadline_misses: int
    scheme_switches: int
    saturated_cycles: int
    limited_cycles: int
    render_limited_cycles: int
    faults: int
    recoveries: int
    thermal_load: float
    dissipated_j: float

class CycleRecord:
    cycle: int
    loop_time_ns: int
    position: Vector
    velocity: Vector
    torque: Vector
    handle_position: Vector
    handle_velocity: Vector
    operator_force: Vector
    environment_force: Vector
    flags: int

class FaultReport:
    device: str
    serial: int
    fault: str
    message: str
    cycle: int
    loop_time_ns: int
    dof: int
    records: list[CycleRecord]

class LocalModel:
    anchor: Pose
    stiffness: Vector     # 6: N/m (3), N m/rad (3)
    damping: Vector       # 6: N s/m (3), N m s/rad (3)
    def __init__(self, anchor: Pose, stiffness: Sequence[float], damping: Sequence[float] = ...) -> None: ...
    @staticmethod
    def spring(anchor: Pose, stiffness: Sequence[float], damping: Sequence[float] = ...) -> LocalModel: ...

class EngineCommand:
    state_serial: int
    @staticmethod
    def coupling(proxy: Pose, proxy_twist: Twist = ..., state_serial: int = 0) -> EngineCommand: ...
    @staticmethod
    def force(wrench: Wrench, state_serial: int = 0, local_model: Optional[LocalModel] = None) -> EngineCommand: ...
    @staticmethod
    def motion(pose: Pose, twist: Twist = ..., state_serial: int = 0) -> EngineCommand: ...

class Client:
    id: str
    def __init__(self, client_id: str, domain: int = 0, cyclone_config: str = "", network: str = "",
                 command_deadline_s: float = 0.05) -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> Client: ...
    def __exit__(self, *args: object) -> None: ...
    def devices(self) -> list[DeviceInfo]: ...
    def wait_for_device(self, device: str, timeout: float = 5.0, started: bool = False) -> DeviceInfo: ...
    def latest_state(self, device: str) -> Optional[DeviceState]: ...
    def wait_for_state(self, device: str, timeout: float = 1.0, after: int = 0) -> DeviceState: ...
    def groups(self) -> list[GroupInfo]: ...
    def wait_for_group(self, group: str, timeout: float = 5.0) -> GroupInfo: ...
    def wait_for_group_state(self, group: str, timeout: float = 1.0, after: int = 0) -> GroupState: ...
    def latest_group_state(self, group: str) -> Optional[GroupState]: ...
    def take_events(self) -> list[Event]: ...
    def latest_telemetry(self, device: str) -> Optional[Telemetry]: ...
    def latest_fault_report(self, device: str) -> Optional[FaultReport]: ...
    def claim(self, device: str, timeout: float = 2.0) -> str: ...
    def claim_lost(self, device: str) -> bool: ...
    def release(self, device: str, timeout: float = 2.0) -> str: ...
    def switch_scheme(self, device: str, scheme: str, timeout: float = 2.0) -> str: ...
    def set_parameter(self, device: str, parameter: str, values: Values, timeout: float = 2.0) -> str: ...
    def get_parameter(self, device: str, parameter: str, timeout: float = 2.0) -> list[float]: ...
    def parameters(self, device: str, timeout: float = 2.0) -> list[dict[str, Any]]: ...
    def estop(self, device: str, timeout: float = 2.0) -> str: ...
    def recover(self, device: str, timeout: float = 2.0) -> str: ...
    def operator(self, device: str, command: str, values: Values = None, timeout: float = 2.0) -> str: ...
    def claim_group(self, group: str, timeout: float = 2.0) -> str: ...
    def release_group(self, group: str, timeout: float = 2.0) -> str: ...
    def estop_group(self, group: str, timeout: float = 2.0) -> str: ...
    def recover_group(self, group: str, timeout: float = 2.0) -> str: ...
    def send(self, device: str, command: EngineCommand) -> bool: ...
    def send_coupling(self, device: str, proxy: Pose, proxy_twist: Twist = ..., state_serial: int = 0) -> bool: ...
    def send_wrench(self, device: str, wrench: Wrench, state_serial: int = 0) -> bool: ...
    def send_motion(self, device: str, pose: Pose, twist: Twist = ..., state_serial: int = 0) -> bool: ...
    def send_group(self, group: str, commands: Sequence[tuple[str, EngineCommand]]) -> bool: ...

# ---- the in-process session ----
class SimulatedTruth:
    time_s: float
    link_position: Vector
    link_velocity: Vector
    motor_position: Vector
    motor_velocity: Vector
    friction_torque: Vector
    motor_torque: Vector
    handle_pose: Pose
    handle_twist: Twist
    handle_wrench: Wrench

class DeviceView:
    name: str
    cycle: int
    time_s: float
    joint_position: Vector
    joint_velocity: Vector
    joint_effort: Vector
    joint_torque: Vector
    handle_pose: Pose
    handle_twist: Twist
    operator_wrench: Wrench
    target_pose: Pose
    target_twist: Twist
    target_wrench: Wrench
    scheme: str
    fault: str
    at_rest: bool
    engine_weight: float
    faults: int
    recoveries: int
    scheme_switches: int
    refused_switches: int
    saturated_cycles: int
    limited_cycles: int
    render_limited_cycles: int
    thermal_load: float
    dissipated_j: float
    truth: Optional[SimulatedTruth]

class JointDescription:
    name: str
    position_min: float
    position_max: float
    velocity_max: float
    torque_peak_nm: float
    torque_continuous_nm: float

class DeviceDescription:
    model: str
    joints: list[JointDescription]
    dof: int
    handle_frame: str
    robot_model_file: str
    simulated: bool
    base_pose: Pose

class SessionStatistics:
    cycles: int
    time_s: float
    compute_p50_us: float
    compute_p99_us: float
    compute_max_us: float

class EngineInput:
    sequence: int
    @staticmethod
    def coupling(proxy: Pose, proxy_twist: Twist = ...) -> EngineInput: ...
    @staticmethod
    def force(wrench: Wrench) -> EngineInput: ...
    @staticmethod
    def motion(pose: Pose, twist: Twist = ...) -> EngineInput: ...

class Session:
    device_names: list[str]
    period_s: float
    cycles_run: int
    @staticmethod
    def from_file(file: Union[str, os.PathLike[str]], overrides: Sequence[str] = ...,
                  plugin_paths: Sequence[Union[str, os.PathLike[str]]] = ...) -> Session: ...
    @staticmethod
    def from_yaml(yaml: str, overrides: Sequence[str] = ..., plugin_paths: Sequence[Union[str, os.PathLike[str]]] = ...,
                  name: str = "<session>") -> Session: ...
    def __enter__(self) -> Session: ...
    def __exit__(self, *args: object) -> None: ...
    def step(self, cycles: int = 1) -> None: ...
    def run(self, cycles: int, device: str, every: int = 1) -> dict[str, Vector]: ...
    def device(self, name: str) -> DeviceView: ...
    def description(self, name: str) -> DeviceDescription: ...
    def set_engine_input(self, device: str, input: EngineInput) -> None: ...
    def switch_scheme(self, device: str, scheme: str) -> str: ...
    def set_parameter(self, device: str, parameter: str, values: Values) -> str: ...
    def get_parameter(self, device: str, parameter: str) -> list[float]: ...
    def parameters(self, device: str) -> list[dict[str, Any]]: ...
    def operator(self, device: str, command: str, values: Values = None) -> str: ...
    def estop(self, device: str) -> str: ...
    def recover(self, device: str) -> str: ...
    def statistics(self) -> SessionStatistics: ...
    def stop(self) -> None: ...

"""Type stubs of softfinger (the Rust extension softfinger._native)."""

from types import TracebackType
from typing import Any, Dict, Optional, Sequence, Tuple, Type

import numpy as np
import numpy.typing as npt

class Error(Exception):
    """Base of the softfinger errors."""

class LinkError(Error):
    """The link failed: cannot open, no answer in time, closed, unexpected answer, homing failed."""

class DeviceRefused(Error):
    """The device refused a request."""

    code: str
    """The device's error code, e.g. "WrongMode", "InvalidValue", "StaleSequence"."""

class Device:
    """A connection to a softfinger device or the virtual device (a context manager).

    target: "tcp:HOST:PORT", "usb" or "usb:/dev/ttyACM0"; timeout_s: how long a request waits
    for its answer. ValueError for a bad target or timeout, LinkError if it cannot connect.
    """

    def __init__(self, target: str, timeout_s: float = 1.0) -> None: ...
    def __enter__(self) -> "Device": ...
    def __exit__(
        self,
        exc_type: Optional[Type[BaseException]],
        exc: Optional[BaseException],
        tb: Optional[TracebackType],
    ) -> None: ...
    def close(self) -> None:
        """Close the connection (idempotent)."""
    def info(self) -> Dict[str, Any]:
        """name, firmware_version, protocol_version, rate_hz, max_force_n, max_stream_hz,
        virtual_device, watchdog_ms, surfaces, fingertip_radius_m."""
    def home(self, wait: bool = True, timeout_s: float = 10.0) -> None:
        """Home; with wait, return once homed (LinkError if it failed or timed out)."""
    def arm(self) -> None:
        """Render force (ramped in over 0.5 s); DeviceRefused("WrongMode") before homing."""
    def disarm(self) -> None:
        """No force."""
    def clear(self) -> None:
        """Clear latched faults (then disarmed)."""
    def set_local_model(
        self,
        shape: str,
        position_m: Tuple[float, float, float],
        orientation: Tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0),
        radius_m: float = 0.05,
        stiffness_n_per_m: float = 2000.0,
        damping_n_s_per_m: float = 2.0,
        mu_s: float = 0.8,
        mu_k: float = 0.6,
        spin_stiffness_nm_per_rad: float = 0.01,
        max_age_ms: int = 0,
    ) -> int:
        """Send a local model ("plane", "sphere", "bowl", "cylinder"); returns its sequence number."""
    def stream(self, seconds: float, rate_hz: float = 1000.0) -> Dict[str, npt.NDArray[Any]]:
        """seconds of device time at rate_hz: t_s, tick, position_m (N x 3), velocity_m_s (N x 3),
        force_n (N x 3), spin_torque_nm, contact, mode, flags, model_seq."""
    def state(self) -> Optional[Dict[str, Any]]:
        """The newest sample (None before the first); never waits."""

def replay(
    t_s: Sequence[float],
    quats: Sequence[Sequence[float]],
    method: str = "exact",
    surface: str = "plane",
    radius_m: float = 0.01,
    object_radius_m: float = 0.05,
    normal_force_n: float = 1.0,
) -> Dict[str, npt.NDArray[Any]]:
    """Recorded orientations through the core's rolling model, as `host-sim replay`: its CSV
    columns (t_s, plane_x_m, plane_y_m, sphere_*_m, spin_rad, tau_n_nm, state, object_*_m,
    finger_*_m) as numpy arrays."""

"""softfinger.Device against the virtual device: home, arm, a model, 1 s of states, the normal
force against the model's spring; bad arguments and refusals."""

import math
import socket
import time

import numpy as np
import pytest

import softfinger

# The bound of capi/examples/press.c (derived there from f32 rounding; measured 1.6e-6 N).
BOUND_N = 5e-6


def test_press_renders_the_models_spring(server):
    with softfinger.Device(server) as dev:
        info = dev.info()
        assert info["virtual_device"] is True
        assert info["rate_hz"] == 10_000
        r = info["fingertip_radius_m"]
        with pytest.raises(softfinger.DeviceRefused) as e:
            dev.arm()
        assert e.value.code == "WrongMode"
        dev.home(timeout_s=30.0)
        s = dev.state()
        assert s is not None and s["mode"] == "disarmed"
        # A soft plane, first 10 mm below the fingertip (the device refuses Arm with the fingertip
        # inside the surface), armed once that model is in force, then raised to 2 mm into the
        # fingertip where the hand holds it (as press.c).
        k, c = 200.0, 2.0
        x, y, z_tip = s["position_m"]
        below = dev.set_local_model("plane", (x, y, z_tip - r - 0.010),
                                    stiffness_n_per_m=k, damping_n_s_per_m=c)
        assert below == s["model_seq"] + 1
        t_end = time.monotonic() + 10.0
        while dev.state()["model_seq"] != below:
            assert time.monotonic() < t_end, "the model comes into force"
            dev.stream(0.02)
        dev.arm()
        z_plane = z_tip - r + 0.002
        seq = dev.set_local_model("plane", (x, y, z_plane), stiffness_n_per_m=k,
                                  damping_n_s_per_m=c)
        assert seq == below + 1
        dev.stream(0.6)  # the arming ramp
        st = dev.stream(1.0, rate_hz=1000.0)
        n = len(st["t_s"])
        assert n == 1000
        assert st["position_m"].shape == (n, 3) and st["force_n"].shape == (n, 3)
        assert np.all(np.diff(st["tick"]) == 10)
        assert np.all(st["mode"] == 3) and np.all(st["model_seq"] == seq)
        touching = st["contact"] != 0
        fmag = np.linalg.norm(st["force_n"], axis=1)
        checked = touching & (fmag < info["max_force_n"] * 0.999)
        assert checked.sum() >= 900
        pen = r - (st["position_m"][:, 2] - np.float64(np.float32(z_plane)))
        spring = np.maximum(0.0, k * pen - c * st["velocity_m_s"][:, 2])
        worst = np.abs(st["force_n"][checked, 2] - spring[checked]).max()
        print(f"python: {checked.sum()} samples in contact, worst |f_n - spring| {worst:.3g} N")
        assert worst <= BOUND_N
        # A newer model on top: the sequence goes on.
        assert dev.set_local_model("plane", (0.0, 0.0, z_plane - 0.05)) == seq + 1
        dev.disarm()
        assert dev.state()["tick"] >= st["tick"][-1]


def test_bad_arguments_and_a_closed_port(server):
    for bad in ("serial:x", "tcp:127.0.0.1", "usb:", ""):
        with pytest.raises(ValueError):
            softfinger.Device(bad)
    with pytest.raises(ValueError):
        softfinger.Device(server, timeout_s=0.0)
    # A port nobody listens on: the link fails.
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(softfinger.LinkError):
        softfinger.Device(f"tcp:127.0.0.1:{port}")
    with softfinger.Device(server) as dev:
        with pytest.raises(ValueError, match="shape"):
            dev.set_local_model("cube", (0.0, 0.0, 0.0))
        with pytest.raises(ValueError, match="max_age_ms"):
            dev.set_local_model("plane", (0.0, 0.0, 0.0), max_age_ms=65_536)
        with pytest.raises(ValueError, match="position_m"):
            dev.set_local_model("plane", (0.0, math.nan, 0.0))
        with pytest.raises(ValueError, match="radius_m"):
            dev.set_local_model("sphere", (0.0, 0.0, 0.0), radius_m=math.inf)
        # The device checks the ranges: a negative radius is refused with its code.
        with pytest.raises(softfinger.DeviceRefused) as e:
            dev.set_local_model("sphere", (0.0, 0.0, 0.0), radius_m=-0.01)
        assert e.value.code == "InvalidValue"
        with pytest.raises(ValueError):
            dev.stream(1.0, rate_hz=0.0)
        with pytest.raises(ValueError):
            dev.stream(1.0, rate_hz=10_000.1)  # just above the control rate
        assert len(dev.stream(0.01, rate_hz=10_000.0)["t_s"]) == 100  # the control rate itself
        with pytest.raises(ValueError):
            dev.stream(math.nan)
        with pytest.raises(ValueError):
            dev.home(timeout_s=-1.0)
    # Closed: calls fail as a link error, closing again is harmless.
    dev.close()
    with pytest.raises(softfinger.LinkError):
        dev.arm()

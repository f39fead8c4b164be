"""softfinger: drive a softfinger haptic device, or its virtual device, from Python.

    import softfinger
    with softfinger.Device("tcp:127.0.0.1:7700") as dev:   # host-sim serve
        dev.home()                       # waits until homed
        dev.arm()
        dev.set_local_model("sphere", (0.0, 0.0, 0.02), radius_m=0.05)
        s = dev.stream(1.0)              # 1 s at 1 kHz: dict of numpy arrays
        print(s["force_n"].max(axis=0))

Errors: softfinger.DeviceRefused (the device said no; .code names its error code),
softfinger.LinkError (the connection), ValueError (bad arguments); both softfinger errors
derive from softfinger.Error.

softfinger.replay(t_s, quats, ...) runs recorded orientations through the core's rolling model
offline, as `host-sim replay` does.

Units are SI (m, m/s, N, N*m, s), vectors in the device base frame, quaternions (w, x, y, z).
"""

from ._native import Device, DeviceRefused, Error, LinkError, replay

__all__ = ["Device", "DeviceRefused", "Error", "LinkError", "replay"]

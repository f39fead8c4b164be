//! `softfinger.Device`: one connection to a device, a context manager.
//!
//! Every call releases the GIL while it waits for the device, so other Python threads run.
//! Units are SI; vectors in the device base frame; quaternions `(w, x, y, z)`.

use crate::arrays::Columns;
use crate::errors::to_py;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use softfinger_host::protocol::{LocalModel, StateSample, SurfaceShape};
use softfinger_host::{Device as HostDevice, LatestState, Target};
use std::sync::Arc;
use std::sync::Mutex;
use std::time::Duration;

/// The longest wait any call accepts, s (a day).
const MAX_WAIT_S: f64 = 86_400.0;

/// A connection to a softfinger device or the virtual device.
///
/// `Device(target, timeout_s=1.0)`: `target` is `"tcp:HOST:PORT"` (the virtual device of
/// `host-sim serve`), `"usb"` (the first softfinger USB device) or `"usb:/dev/ttyACM0"`;
/// `timeout_s` is how long a request waits for its answer. Use it as a context manager (`with
/// softfinger.Device(...) as dev:`) or call `close()`. While it is open a library thread pings
/// the device so its communication watchdog stays fed.
#[pyclass(module = "softfinger")]
pub struct Device {
    dev: Mutex<Option<HostDevice>>,
    latest: Arc<LatestState>,
    rate_hz: u32,
    seq: Mutex<u32>,
}

/// A wait in seconds: finite and within 0 ..= a day, else `ValueError` naming `what`.
fn seconds(what: &str, s: f64, allow_zero: bool) -> PyResult<Duration> {
    if s.is_finite() && s <= MAX_WAIT_S && (s > 0.0 || (allow_zero && s == 0.0)) {
        Ok(Duration::from_secs_f64(s))
    } else {
        let range = if allow_zero { "0" } else { "above 0" };
        Err(PyValueError::new_err(format!(
            "{what} must be a number of seconds from {range} to {MAX_WAIT_S}, got {s}"
        )))
    }
}

/// A finite value as the wire's f32, else `ValueError` naming `what`.
fn finite(what: &str, x: f64) -> PyResult<f32> {
    let y = x as f32;
    if y.is_finite() {
        Ok(y)
    } else {
        Err(PyValueError::new_err(format!(
            "{what} must be a finite number, got {x}"
        )))
    }
}

fn state_dict<'py>(py: Python<'py>, s: &StateSample, rate_hz: u32) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let v = |a: [f32; 3]| a.map(f64::from);
    d.set_item("t_s", s.tick as f64 / f64::from(rate_hz.max(1)))?;
    d.set_item("tick", s.tick)?;
    d.set_item("position_m", v(s.probe_m))?;
    d.set_item("velocity_m_s", v(s.probe_vel_m_s))?;
    d.set_item("force_n", v(s.force_n))?;
    d.set_item("spin_torque_nm", f64::from(s.spin_torque_nm))?;
    d.set_item("contact_point_m", v(s.contact_point_m))?;
    d.set_item("contact", s.contact.name())?;
    d.set_item("mode", format!("{:?}", s.mode).to_lowercase())?;
    d.set_item("flags", s.flags)?;
    d.set_item("model_seq", s.model_seq)?;
    Ok(d)
}

impl Device {
    /// Run `f` on the open device without the GIL.
    fn with<T: Send>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut HostDevice) -> Result<T, softfinger_host::LinkError> + Send,
    ) -> PyResult<T> {
        py.detach(|| {
            let mut g = self
                .dev
                .lock()
                .map_err(|_| softfinger_host::LinkError::Disconnected)?;
            let d = g.as_mut().ok_or(softfinger_host::LinkError::Disconnected)?;
            f(d)
        })
        .map_err(to_py)
    }
}

#[pymethods]
impl Device {
    #[new]
    #[pyo3(signature = (target, timeout_s = 1.0))]
    fn new(py: Python<'_>, target: &str, timeout_s: f64) -> PyResult<Self> {
        let timeout = seconds("timeout_s", timeout_s, false)?;
        let target: Target = target.parse().map_err(to_py)?;
        let (dev, rate_hz) = py
            .detach(|| {
                let mut d = HostDevice::connect(&target)?;
                d.set_timeout(timeout);
                let rate = d.info()?.control_rate_hz;
                Ok((d, rate))
            })
            .map_err(to_py)?;
        Ok(Device {
            latest: dev.latest(),
            dev: Mutex::new(Some(dev)),
            rate_hz,
            seq: Mutex::new(0),
        })
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&self, py: Python<'_>, _args: &Bound<'_, pyo3::types::PyTuple>) {
        self.close(py);
    }

    /// Close the connection (stops the stream and the library's threads). Idempotent.
    fn close(&self, py: Python<'_>) {
        py.detach(|| {
            if let Ok(mut g) = self.dev.lock() {
                if let Some(mut d) = g.take() {
                    let _ = d.set_stream(0);
                }
            }
        });
    }

    /// What the device says about itself: `name`, `firmware_version`, `rate_hz`,
    /// `max_force_n`, `max_stream_hz`, `virtual_device`, `watchdog_ms`, `surfaces`,
    /// `fingertip_radius_m`.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (i, p) = self.with(py, |d| Ok((d.info()?, d.contact_params()?)))?;
        let out = PyDict::new(py);
        out.set_item("name", i.name.as_str())?;
        out.set_item("firmware_version", i.firmware_version.as_str())?;
        out.set_item("protocol_version", i.protocol_version)?;
        out.set_item("rate_hz", i.control_rate_hz)?;
        out.set_item("max_force_n", f64::from(i.max_force_n))?;
        out.set_item(
            "max_stream_hz",
            f64::from(i.control_rate_hz) / f64::from(i.min_stream_divisor.max(1)),
        )?;
        out.set_item("virtual_device", i.virtual_device)?;
        out.set_item("watchdog_ms", i.watchdog_ms)?;
        let surfaces: Vec<String> = i
            .surfaces
            .iter()
            .map(|s| format!("{s:?}").to_lowercase())
            .collect();
        out.set_item("surfaces", surfaces)?;
        out.set_item("fingertip_radius_m", f64::from(p.fingertip_radius_m))?;
        Ok(out)
    }

    /// Home the device. With `wait` (the default) return once it is homed; raise `LinkError`
    /// when homing failed or took longer than `timeout_s`.
    #[pyo3(signature = (wait = true, timeout_s = 10.0))]
    fn home(&self, py: Python<'_>, wait: bool, timeout_s: f64) -> PyResult<()> {
        let t = seconds("timeout_s", timeout_s, false)?;
        if wait {
            self.with(py, |d| d.home_and_wait(t))
        } else {
            self.with(py, |d| d.home())
        }
    }

    /// Arm: the device renders force (ramped in over 0.5 s). Needs homing
    /// (`DeviceRefused`, code `"WrongMode"`).
    fn arm(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |d| d.arm())
    }

    /// Disarm: no force.
    fn disarm(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |d| d.disarm())
    }

    /// Clear latched faults (the device is then disarmed).
    fn clear(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |d| d.clear_faults())
    }

    /// Send a local model and return its sequence number (one after the newest this
    /// connection sent or the device reported). `shape` is `"plane"` (z = 0 of the object frame,
    /// normal +z), `"sphere"`, `"bowl"` (the inside of a sphere) or `"cylinder"` (axis along
    /// object x); `position_m` is the object frame's origin in the base frame, `orientation` its
    /// unit quaternion `(w, x, y, z)`; `radius_m` is used by the curved shapes; `max_age_ms` > 0
    /// fades the force if no newer model arrives in that time. The device blends it in.
    #[pyo3(signature = (
        shape, position_m, orientation = (1.0, 0.0, 0.0, 0.0), radius_m = 0.05,
        stiffness_n_per_m = 2000.0, damping_n_s_per_m = 2.0, mu_s = 0.8, mu_k = 0.6,
        spin_stiffness_nm_per_rad = 0.01, max_age_ms = 0
    ))]
    #[allow(clippy::too_many_arguments)]
    fn set_local_model(
        &self,
        py: Python<'_>,
        shape: &str,
        position_m: (f64, f64, f64),
        orientation: (f64, f64, f64, f64),
        radius_m: f64,
        stiffness_n_per_m: f64,
        damping_n_s_per_m: f64,
        mu_s: f64,
        mu_k: f64,
        spin_stiffness_nm_per_rad: f64,
        max_age_ms: i64,
    ) -> PyResult<u32> {
        let r = || finite("radius_m", radius_m);
        let shape = match shape {
            "plane" => SurfaceShape::Plane,
            "sphere" => SurfaceShape::Sphere { radius_m: r()? },
            "bowl" => SurfaceShape::Bowl { radius_m: r()? },
            "cylinder" => SurfaceShape::Cylinder { radius_m: r()? },
            other => {
                return Err(PyValueError::new_err(format!(
                    "shape must be plane, sphere, bowl or cylinder, got '{other}'"
                )))
            }
        };
        let max_age_ms = u16::try_from(max_age_ms).map_err(|_| {
            PyValueError::new_err(format!(
                "max_age_ms must be within 0..65535, got {max_age_ms}"
            ))
        })?;
        let (px, py_, pz) = position_m;
        let (qw, qx, qy, qz) = orientation;
        let mut model = LocalModel {
            seq: 0,
            shape,
            position_m: [
                finite("position_m", px)?,
                finite("position_m", py_)?,
                finite("position_m", pz)?,
            ],
            orientation: [
                finite("orientation", qw)?,
                finite("orientation", qx)?,
                finite("orientation", qy)?,
                finite("orientation", qz)?,
            ],
            stiffness_n_per_m: finite("stiffness_n_per_m", stiffness_n_per_m)?,
            damping_n_s_per_m: finite("damping_n_s_per_m", damping_n_s_per_m)?,
            mu_s: finite("mu_s", mu_s)?,
            mu_k: finite("mu_k", mu_k)?,
            spin_stiffness_nm_per_rad: finite(
                "spin_stiffness_nm_per_rad",
                spin_stiffness_nm_per_rad,
            )?,
            max_age_ms,
        };
        self.with(py, |d| {
            let mut seq = self
                .seq
                .lock()
                .map_err(|_| softfinger_host::LinkError::Disconnected)?;
            let reported = d.latest_state().map_or(0, |s| s.model_seq);
            // Wrapping comparison, as the device's.
            let base = if (reported.wrapping_sub(*seq) as i32) > 0 {
                reported
            } else {
                *seq
            };
            model.seq = base.wrapping_add(1);
            d.set_local_model(model)?;
            *seq = model.seq;
            Ok(model.seq)
        })
    }

    /// Stream `seconds` of device time at `rate_hz` (the nearest rate the device makes:
    /// control rate / an integer) and return it as numpy arrays: `t_s` (N), `tick`,
    /// `position_m` (N x 3), `velocity_m_s` (N x 3), `force_n` (N x 3), `spin_torque_nm`,
    /// `contact` (0 broken, 1 rolling, 2 sliding), `mode` (0 unhomed ... 4 faulted), `flags`,
    /// `model_seq`. The stream is off again afterwards. Raises `LinkError` if the samples stop
    /// coming for `timeout_s` (the constructor's) plus one period.
    #[pyo3(signature = (seconds, rate_hz = 1000.0))]
    fn stream<'py>(
        &self,
        py: Python<'py>,
        seconds: f64,
        rate_hz: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let span = crate::device::seconds("seconds", seconds, false)?;
        let rate = f64::from(self.rate_hz);
        if !(rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= rate) {
            return Err(PyValueError::new_err(format!(
                "rate_hz must be above 0 and at most the control rate {rate}, got {rate_hz}"
            )));
        }
        let divisor = (rate / rate_hz).round();
        if divisor > f64::from(u16::MAX) {
            return Err(PyValueError::new_err(format!(
                "rate_hz must be at least {} (control rate / 65535), got {rate_hz}",
                rate / f64::from(u16::MAX)
            )));
        }
        let ticks = (span.as_secs_f64() * rate).round() as u64;
        let samples = self.with(py, |d| {
            let q = d.state_queue();
            while let Ok(Some(_)) = q.next(Duration::ZERO) {}
            d.set_stream(divisor as u16)?;
            let mut out: Vec<StateSample> = Vec::new();
            let wait = Duration::from_secs_f64(1.0 + divisor / rate);
            let result = loop {
                match q.next(wait) {
                    Ok(Some(s)) => {
                        let first = out.first().map_or(s.tick, |f| f.tick);
                        if s.tick >= first + ticks {
                            break Ok(());
                        }
                        out.push(s);
                    }
                    Ok(None) => break Err(softfinger_host::LinkError::Timeout),
                    Err(e) => break Err(e),
                }
            };
            let off = d.set_stream(0);
            result.and(off).map(|()| out)
        })?;
        let c = Columns::new(py)?;
        let r = f64::from(self.rate_hz.max(1));
        let v = |a: [f32; 3]| a.map(f64::from);
        c.f64("t_s", samples.iter().map(|s| s.tick as f64 / r).collect())?;
        c.int("tick", samples.iter().map(|s| s.tick).collect(), "uint64")?;
        c.vec3("position_m", samples.iter().map(|s| v(s.probe_m)).collect())?;
        c.vec3(
            "velocity_m_s",
            samples.iter().map(|s| v(s.probe_vel_m_s)).collect(),
        )?;
        c.vec3("force_n", samples.iter().map(|s| v(s.force_n)).collect())?;
        c.f64(
            "spin_torque_nm",
            samples
                .iter()
                .map(|s| f64::from(s.spin_torque_nm))
                .collect(),
        )?;
        c.int(
            "contact",
            samples.iter().map(|s| s.contact as i32).collect(),
            "int8",
        )?;
        c.int(
            "mode",
            samples.iter().map(|s| i32::from(s.mode.code())).collect(),
            "int8",
        )?;
        c.int("flags", samples.iter().map(|s| s.flags).collect(), "uint32")?;
        c.int(
            "model_seq",
            samples.iter().map(|s| s.model_seq).collect(),
            "uint32",
        )?;
        Ok(c.into_dict())
    }

    /// The newest state sample as a dict (`t_s`, `tick`, `position_m`, `velocity_m_s`,
    /// `force_n`, `spin_torque_nm`, `contact_point_m`, `contact` and `mode` by name, `flags`,
    /// `model_seq`), or `None` if none has arrived (the stream is off unless `stream` runs or
    /// `home` waits). Never waits.
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.latest
            .get()
            .map(|l| state_dict(py, &l.sample, self.rate_hz))
            .transpose()
    }
}

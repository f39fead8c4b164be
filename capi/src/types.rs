//! The C API's structs and their constants, and their conversions from and to the protocol's
//! messages. SI units, device base frame; quaternions `[w, x, y, z]` mapping object-frame vectors
//! to the base frame.

#![allow(non_camel_case_types)]

use crate::error::SF_ERR_BAD_VALUE;
use softfinger_host::protocol::{
    ContactState, DeviceInfo, LocalModel, Mode, StateSample, SurfaceShape,
};
use std::ffi::c_char;

/// Mode: powered up, encoder zero unknown, no torque.
pub const SF_MODE_UNHOMED: i32 = 0;
/// Mode: homing (the arms seek their stops).
pub const SF_MODE_HOMING: i32 = 1;
/// Mode: homed, no force.
pub const SF_MODE_DISARMED: i32 = 2;
/// Mode: rendering force (ramped in after `sf_arm`).
pub const SF_MODE_ARMED: i32 = 3;
/// Mode: a fault latched, no torque until `sf_clear`.
pub const SF_MODE_FAULTED: i32 = 4;

/// Contact: none. The device has one no-contact state, broken (see `SF_CONTACT_BROKEN`); this
/// is the same value under the name an application looks for.
pub const SF_CONTACT_NONE: i32 = 0;
/// Contact: broken, i.e. no contact: no friction, no rolling, no spin torque (a probe pressed
/// beyond the make force while the re-contact dwell holds still gets the normal spring).
pub const SF_CONTACT_BROKEN: i32 = 0;
/// Contact: rolling without slip.
pub const SF_CONTACT_ROLLING: i32 = 1;
/// Contact: sliding, kinetic friction opposes the motion.
pub const SF_CONTACT_SLIDING: i32 = 2;

/// Shape: the plane z = 0 of the object frame, outward normal +z (`radius_m` unused).
pub const SF_SHAPE_PLANE: i32 = 0;
/// Shape: a sphere of radius `radius_m` centred at the object origin.
pub const SF_SHAPE_SPHERE: i32 = 1;
/// Shape: the inside of a sphere of radius `radius_m` (larger than the fingertip's) centred at
/// the object origin; its bottom at (0, 0, -radius_m).
pub const SF_SHAPE_BOWL: i32 = 2;
/// Shape: a cylinder of radius `radius_m` whose axis is the object x axis (turn it with
/// `orientation`).
pub const SF_SHAPE_CYLINDER: i32 = 3;

/// One state sample of the device. Base frame, SI units.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct sf_state {
    /// Device time of the sample, s (`tick` / control rate).
    pub t_s: f64,
    /// Control tick of the sample since the device started.
    pub tick: u64,
    /// Fingertip (probe) centre, m.
    pub position_m: [f64; 3],
    /// Fingertip velocity, m/s.
    pub velocity_m_s: [f64; 3],
    /// Force rendered on the user, N.
    pub force_n: [f64; 3],
    /// Spin torque about the contact normal, N*m.
    pub spin_torque_nm: f64,
    /// Contact point on the object, m.
    pub contact_point_m: [f64; 3],
    /// `SF_CONTACT_*`.
    pub contact: i32,
    /// `SF_MODE_*`.
    pub mode: i32,
    /// Flag bits raised this tick (latched ones included); names in `softfinger flags`.
    pub flags: u32,
    /// Sequence number of the local model in force.
    pub model_seq: u32,
    /// Samples the device could not send this connection (its queue was full), since it started.
    pub dropped: u32,
}

/// The surface the device renders locally until the next model: the protocol's local model.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct sf_local_model {
    /// Chosen by the application; a model whose `seq` is not newer than the one in force is
    /// refused (`SF_ERR_REFUSED_STALE_SEQUENCE`, wrapping comparison).
    pub seq: u32,
    /// `SF_SHAPE_*`.
    pub shape: i32,
    /// Radius of a sphere, bowl or cylinder, m (unused for the plane).
    pub radius_m: f64,
    /// Origin of the object frame in the base frame, m.
    pub position_m: [f64; 3],
    /// Orientation of the object frame: unit quaternion `[w, x, y, z]`.
    pub orientation: [f64; 4],
    /// Normal stiffness, N/m.
    pub stiffness_n_per_m: f64,
    /// Normal damping, N*s/m.
    pub damping_n_s_per_m: f64,
    /// Static friction coefficient.
    pub mu_s: f64,
    /// Kinetic friction coefficient (at most `mu_s`).
    pub mu_k: f64,
    /// Spin stiffness, N*m/rad.
    pub spin_stiffness_nm_per_rad: f64,
    /// The model goes stale this long after it arrived unless a newer one came (its force then
    /// fades to zero), ms, 0..65535; 0: never (a static scene).
    pub max_age_ms: u32,
}

/// What the device says about itself.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct sf_info_t {
    /// Device name, NUL-terminated.
    pub name: [c_char; 32],
    /// Firmware (or simulator) version, NUL-terminated.
    pub firmware_version: [c_char; 32],
    /// Control rate, Hz.
    pub rate_hz: u32,
    /// Largest force the device renders, N.
    pub max_force_n: f64,
    /// Fastest state stream, Hz (`rate_hz` / the smallest divisor).
    pub max_stream_hz: f64,
    /// Protocol version spoken.
    pub protocol_version: u32,
    /// 1 for the virtual device (host-sim), 0 for hardware.
    pub virtual_device: i32,
    /// Communication watchdog timeout in force, ms (0: off).
    pub watchdog_ms: u32,
    /// Fingertip sphere radius in force, m (a contact parameter): the probe position is its
    /// centre, so a surface is touched at this distance.
    pub fingertip_radius_m: f64,
}

fn c_text<const N: usize>(s: &str) -> [c_char; N] {
    let mut out = [0 as c_char; N];
    for (o, b) in out.iter_mut().zip(s.bytes().take(N - 1)) {
        *o = b as c_char;
    }
    out
}

impl sf_info_t {
    /// The C view of `i`, with the fingertip radius in force, m.
    pub fn of(i: &DeviceInfo, fingertip_radius_m: f32) -> sf_info_t {
        sf_info_t {
            name: c_text(&i.name),
            firmware_version: c_text(&i.firmware_version),
            rate_hz: i.control_rate_hz,
            max_force_n: f64::from(i.max_force_n),
            max_stream_hz: f64::from(i.control_rate_hz) / f64::from(i.min_stream_divisor.max(1)),
            protocol_version: u32::from(i.protocol_version),
            virtual_device: i32::from(i.virtual_device),
            watchdog_ms: u32::from(i.watchdog_ms),
            fingertip_radius_m: f64::from(fingertip_radius_m),
        }
    }
}

fn v3(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

impl sf_state {
    /// The C view of `s`, timed by a control rate of `rate_hz`.
    pub fn of(s: &StateSample, rate_hz: u32) -> sf_state {
        sf_state {
            t_s: s.tick as f64 / f64::from(rate_hz.max(1)),
            tick: s.tick,
            position_m: v3(s.probe_m),
            velocity_m_s: v3(s.probe_vel_m_s),
            force_n: v3(s.force_n),
            spin_torque_nm: f64::from(s.spin_torque_nm),
            contact_point_m: v3(s.contact_point_m),
            contact: match s.contact {
                ContactState::Broken => SF_CONTACT_BROKEN,
                ContactState::Rolling => SF_CONTACT_ROLLING,
                ContactState::Sliding => SF_CONTACT_SLIDING,
            },
            mode: match s.mode {
                Mode::Unhomed => SF_MODE_UNHOMED,
                Mode::Homing => SF_MODE_HOMING,
                Mode::Disarmed => SF_MODE_DISARMED,
                Mode::Armed => SF_MODE_ARMED,
                Mode::Faulted => SF_MODE_FAULTED,
            },
            flags: s.flags,
            model_seq: s.model_seq,
            dropped: s.dropped,
        }
    }
}

/// `x` as the wire's f32, if it is finite there.
fn f32_of(x: f64) -> Result<f32, i32> {
    let y = x as f32;
    if y.is_finite() {
        Ok(y)
    } else {
        Err(SF_ERR_BAD_VALUE)
    }
}

impl sf_local_model {
    /// The protocol's message, or `SF_ERR_BAD_VALUE` for a shape outside `SF_SHAPE_*`, a value
    /// that is not finite as an f32, or `max_age_ms` beyond 65535. Ranges (a positive radius, a
    /// unit quaternion, `mu_k <= mu_s`, ...) are the device's to check: it refuses with
    /// `SF_ERR_REFUSED_INVALID_VALUE`.
    pub fn to_wire(&self) -> Result<LocalModel, i32> {
        let radius_m = || f32_of(self.radius_m);
        let shape = match self.shape {
            SF_SHAPE_PLANE => SurfaceShape::Plane,
            SF_SHAPE_SPHERE => SurfaceShape::Sphere {
                radius_m: radius_m()?,
            },
            SF_SHAPE_BOWL => SurfaceShape::Bowl {
                radius_m: radius_m()?,
            },
            SF_SHAPE_CYLINDER => SurfaceShape::Cylinder {
                radius_m: radius_m()?,
            },
            _ => return Err(SF_ERR_BAD_VALUE),
        };
        let p = self.position_m;
        let q = self.orientation;
        Ok(LocalModel {
            seq: self.seq,
            shape,
            position_m: [f32_of(p[0])?, f32_of(p[1])?, f32_of(p[2])?],
            orientation: [f32_of(q[0])?, f32_of(q[1])?, f32_of(q[2])?, f32_of(q[3])?],
            stiffness_n_per_m: f32_of(self.stiffness_n_per_m)?,
            damping_n_s_per_m: f32_of(self.damping_n_s_per_m)?,
            mu_s: f32_of(self.mu_s)?,
            mu_k: f32_of(self.mu_k)?,
            spin_stiffness_nm_per_rad: f32_of(self.spin_stiffness_nm_per_rad)?,
            max_age_ms: u16::try_from(self.max_age_ms).map_err(|_| SF_ERR_BAD_VALUE)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere() -> sf_local_model {
        sf_local_model {
            seq: 3,
            shape: SF_SHAPE_SPHERE,
            radius_m: 0.05,
            position_m: [0.0, 0.0, 0.02],
            orientation: [1.0, 0.0, 0.0, 0.0],
            stiffness_n_per_m: 2000.0,
            damping_n_s_per_m: 2.0,
            mu_s: 0.8,
            mu_k: 0.6,
            spin_stiffness_nm_per_rad: 0.01,
            max_age_ms: 0,
        }
    }

    /// Each field lands in its wire field; what the wire cannot carry is refused here.
    #[test]
    fn local_models_convert_or_are_refused() {
        let m = sphere().to_wire().unwrap();
        assert_eq!(m.shape, SurfaceShape::Sphere { radius_m: 0.05 });
        assert_eq!((m.seq, m.position_m[2], m.mu_k), (3, 0.02, 0.6));
        for shape in [-1, 4] {
            assert_eq!(
                sf_local_model { shape, ..sphere() }.to_wire(),
                Err(SF_ERR_BAD_VALUE)
            );
        }
        // The plane ignores its radius, the curved shapes need a finite one.
        let plane = sf_local_model {
            shape: SF_SHAPE_PLANE,
            radius_m: f64::NAN,
            ..sphere()
        };
        assert_eq!(plane.to_wire().unwrap().shape, SurfaceShape::Plane);
        assert!(sf_local_model {
            radius_m: f64::NAN,
            ..sphere()
        }
        .to_wire()
        .is_err());
        // Just inside and just outside the f32 range and the 16-bit age.
        let big = f64::from(f32::MAX);
        assert!(sf_local_model {
            stiffness_n_per_m: big,
            ..sphere()
        }
        .to_wire()
        .is_ok());
        assert!(sf_local_model {
            stiffness_n_per_m: big * 1.001,
            ..sphere()
        }
        .to_wire()
        .is_err());
        assert!(sf_local_model {
            max_age_ms: 65_535,
            ..sphere()
        }
        .to_wire()
        .is_ok());
        assert!(sf_local_model {
            max_age_ms: 65_536,
            ..sphere()
        }
        .to_wire()
        .is_err());
        assert!(sf_local_model {
            orientation: [f64::INFINITY, 0.0, 0.0, 0.0],
            ..sphere()
        }
        .to_wire()
        .is_err());
    }

    /// Names are cut to fit and NUL-terminated.
    #[test]
    fn text_fits_with_its_nul() {
        let t: [c_char; 4] = c_text("abcdef");
        assert_eq!(t.map(|c| c as u8), *b"abc\0");
        let t: [c_char; 4] = c_text("");
        assert_eq!(t, [0; 4]);
    }
}

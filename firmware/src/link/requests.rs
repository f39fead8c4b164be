//! What each request becomes: a pipeline command for the tick, an answer the link gives itself,
//! or a typed refusal.

use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::local_model::{LocalModelSpec, ModelKind, ModelPose};
use softfinger_core::control::pipeline::Command;
use softfinger_core::{Quat, Vec3};
use softfinger_protocol::{ContactParamsWire, ErrorCode, LocalModel, Request, SurfaceShape};

/// Where a request goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Route {
    /// To the tick, through the command queue; acknowledged with the tick's outcome.
    Pipeline(Command),
    /// Answered at once with the device description.
    Info,
    /// Answered at once with the contact parameters in force.
    ContactParams,
    /// Answered at once with `Ok` (round-trip measurement, keep-alive).
    Ping,
    /// Refused at once, nothing changed.
    Refuse(ErrorCode),
}

/// The route of `req`. `contact`: the contact parameters in force (the wire carries only some
/// fields; the others are kept). Link-level requests (`GetCounters`, `SetStream`) never get here:
/// the protocol endpoint answers them.
pub fn route(req: &Request, contact: &ContactParams) -> Route {
    match req {
        Request::GetInfo => Route::Info,
        Request::GetContactParams => Route::ContactParams,
        Request::Ping => Route::Ping,
        Request::Home => Route::Pipeline(Command::Home),
        Request::Arm => Route::Pipeline(Command::Arm),
        Request::Disarm => Route::Pipeline(Command::Disarm),
        Request::ClearFaults => Route::Pipeline(Command::ClearFaults),
        Request::SetContactParams(w) => {
            Route::Pipeline(Command::SetContactParams(contact_params(w, contact)))
        }
        Request::SetLocalModel(m) => Route::Pipeline(Command::SetLocalModel(model_spec(m))),
        Request::SetWatchdog { timeout_ms } => Route::Pipeline(Command::SetWatchdog {
            timeout_s: watchdog_s(*timeout_ms),
        }),
        // The simulated hand exists on the virtual device only.
        Request::DriveHand(_) | Request::ReleaseHand => Route::Refuse(ErrorCode::Unsupported),
        // Answered by the endpoint before routing; refused if one ever gets here.
        Request::GetCounters | Request::SetStream { .. } => Route::Refuse(ErrorCode::Unsupported),
    }
}

/// A wire model as the core's spec, field for field (validated by the pipeline's renderer when
/// the tick applies it: a bad pose, size, age or material is refused there, with its error code).
/// Poses are in the base frame (the firmware's `object_origin_m` is zero); the quaternion is
/// `[w, x, y, z]`; the maximum age goes from ms to s.
pub fn model_spec(m: &LocalModel) -> LocalModelSpec {
    let kind = match m.shape {
        SurfaceShape::Plane => ModelKind::Plane,
        SurfaceShape::Sphere { radius_m } => ModelKind::Sphere { radius_m },
        SurfaceShape::Bowl { radius_m } => ModelKind::Bowl { radius_m },
        SurfaceShape::Cylinder { radius_m } => ModelKind::Cylinder { radius_m },
    };
    let [w, x, y, z] = m.orientation;
    LocalModelSpec {
        seq: m.seq,
        kind,
        pose: ModelPose {
            position_m: Vec3::from_array(m.position_m),
            orientation: Quat::new(w, x, y, z),
        },
        stiffness_n_per_m: m.stiffness_n_per_m,
        damping_n_s_per_m: m.damping_n_s_per_m,
        mu_s: m.mu_s,
        mu_k: m.mu_k,
        spin_stiffness_nm_per_rad: m.spin_stiffness_nm_per_rad,
        max_age_s: f32::from(m.max_age_ms) * 1e-3,
    }
}

/// A wire watchdog timeout (ms; 0: off) in seconds. The pipeline checks the range.
pub fn watchdog_s(timeout_ms: u16) -> f32 {
    f32::from(timeout_ms) * 1e-3
}

/// The wire contact parameters over `base` (fields the wire does not carry are kept). Validation
/// is the pipeline's: invalid values are refused by `Pipeline::command`.
pub fn contact_params(w: &ContactParamsWire, base: &ContactParams) -> ContactParams {
    ContactParams {
        fingertip_radius_m: w.fingertip_radius_m,
        normal_stiffness: w.normal_stiffness,
        normal_damping: w.normal_damping,
        tangential_stiffness: w.tangential_stiffness,
        tangential_damping: w.tangential_damping,
        mu_s: w.mu_s,
        mu_k: w.mu_k,
        spin_stiffness: w.spin_stiffness,
        max_force_n: w.max_force_n,
        ..*base
    }
}

/// The wire view of contact parameters.
pub fn contact_params_wire(p: &ContactParams) -> ContactParamsWire {
    ContactParamsWire {
        fingertip_radius_m: p.fingertip_radius_m,
        normal_stiffness: p.normal_stiffness,
        normal_damping: p.normal_damping,
        tangential_stiffness: p.tangential_stiffness,
        tangential_damping: p.tangential_damping,
        mu_s: p.mu_s,
        mu_k: p.mu_k,
        spin_stiffness: p.spin_stiffness,
        max_force_n: p.max_force_n,
    }
}

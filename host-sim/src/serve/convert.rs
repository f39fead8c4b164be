//! Conversions between the wire types of `softfinger-protocol` and the core's types.

use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::control::local_model::{LocalModelSpec, ModelKind, ModelPose};
use softfinger_core::control::pipeline::{Command, CommandError};
use softfinger_core::{Quat, Vec3};
use softfinger_protocol::{
    ContactParamsWire, ContactStateWire, ErrorCode, LocalModel, Mode, Request, SurfaceKind,
    SurfaceShape,
};

/// A wire model as the core's spec (validated later by the renderer).
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
        max_age_s: m.max_age_ms as f32 * 1e-3,
    }
}

/// The wire contact parameters over `base` (fields the wire does not carry are kept).
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

/// The wire contact state.
pub fn contact_state(s: ContactState) -> ContactStateWire {
    match s {
        ContactState::Broken => ContactStateWire::Broken,
        ContactState::Rolling => ContactStateWire::Rolling,
        ContactState::Sliding => ContactStateWire::Sliding,
    }
}

/// The surfaces the virtual device renders.
pub const SURFACES: [SurfaceKind; 4] = [
    SurfaceKind::Plane,
    SurfaceKind::Sphere,
    SurfaceKind::Bowl,
    SurfaceKind::Cylinder,
];

/// The pipeline command of a request, if it is one (`base`: the contact parameters in force).
pub fn core_request(req: &Request, base: &ContactParams) -> Option<Command> {
    Some(match req {
        Request::Home => Command::Home,
        Request::Arm => Command::Arm,
        Request::Disarm => Command::Disarm,
        Request::ClearFaults => Command::ClearFaults,
        Request::SetContactParams(w) => Command::SetContactParams(contact_params(w, base)),
        Request::SetLocalModel(m) => Command::SetLocalModel(model_spec(m)),
        Request::SetWatchdog { timeout_ms } => Command::SetWatchdog {
            timeout_s: *timeout_ms as f32 * 1e-3,
        },
        _ => return None,
    })
}

/// The protocol's mode of the pipeline's: the one place the two meet (same five modes, same
/// order; `mode_codes_agree` checks every one).
pub fn mode(m: softfinger_core::control::pipeline::Mode) -> Mode {
    use softfinger_core::control::pipeline::Mode as P;
    match m {
        P::Unhomed => Mode::Unhomed,
        P::Homing => Mode::Homing,
        P::Disarmed => Mode::Disarmed,
        P::Armed => Mode::Armed,
        P::Faulted => Mode::Faulted,
    }
}

/// The wire code of a refused pipeline command.
pub fn error_code(e: CommandError) -> ErrorCode {
    use softfinger_core::control::local_model::ModelError;
    match e {
        CommandError::NotHomed | CommandError::Armed | CommandError::Homing => ErrorCode::WrongMode,
        CommandError::Faulted => ErrorCode::Faulted,
        CommandError::InvalidParams(_) => ErrorCode::InvalidValue,
        CommandError::InvalidModel(ModelError::StaleSequence) => ErrorCode::StaleSequence,
        CommandError::InvalidModel(_) => ErrorCode::InvalidValue,
        CommandError::Unsupported => ErrorCode::Unsupported,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_codes_agree() {
        use softfinger_core::control::pipeline::Mode as P;
        for m in [P::Unhomed, P::Homing, P::Disarmed, P::Armed, P::Faulted] {
            assert_eq!(mode(m).name(), m.name());
        }
    }

    #[test]
    fn contact_params_round_trip_through_the_wire() {
        let p = ContactParams {
            normal_stiffness: 1234.0,
            mu_k: 0.5,
            ..ContactParams::DEFAULT
        };
        assert_eq!(
            contact_params(&contact_params_wire(&p), &ContactParams::DEFAULT),
            p
        );
    }

    #[test]
    fn a_sphere_model_keeps_its_fields() {
        let m = LocalModel {
            seq: 9,
            shape: SurfaceShape::Sphere { radius_m: 0.03 },
            position_m: [0.0, 0.01, 0.1],
            orientation: [0.0, 1.0, 0.0, 0.0],
            stiffness_n_per_m: 900.0,
            damping_n_s_per_m: 1.5,
            mu_s: 0.7,
            mu_k: 0.4,
            spin_stiffness_nm_per_rad: 0.02,
            max_age_ms: 250,
        };
        let s = model_spec(&m);
        assert_eq!(s.kind, ModelKind::Sphere { radius_m: 0.03 });
        assert_eq!(s.pose.orientation, Quat::new(0.0, 1.0, 0.0, 0.0));
        assert_eq!(s.pose.position_m, Vec3::new(0.0, 0.01, 0.1));
        assert!((s.max_age_s - 0.25).abs() < 1e-7);
        assert_eq!((s.seq, s.mu_k), (9, 0.4));
    }
}

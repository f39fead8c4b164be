//! What each request becomes: a pipeline command for the tick, an answer the link gives itself,
//! or a typed refusal.

use softfinger_core::params::ContactParams;
use softfinger_core::pipeline::Command;
use softfinger_protocol::{ContactParamsWire, ErrorCode, Request};

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
        Request::SetLocalModel(_) | Request::SetWatchdog { .. } => awaiting_core_commands(req),
        // The simulated hand exists on the virtual device only.
        Request::DriveHand(_) | Request::ReleaseHand => Route::Refuse(ErrorCode::Unsupported),
        // Answered by the endpoint before routing; refused if one ever gets here.
        Request::GetCounters | Request::SetStream { .. } => Route::Refuse(ErrorCode::Unsupported),
    }
}

/// The route of `SetLocalModel` and `SetWatchdog`. The core pipeline has no such commands yet, so
/// both are refused with [`ErrorCode::Unsupported`] (nothing changes on the device). When the
/// pipeline gains `Command::SetLocalModel` and `Command::SetWatchdog`, this is the one function to
/// change: return `Route::Pipeline` with the converted command (as host-sim's
/// `serve::convert::core_request` converts them).
pub fn awaiting_core_commands(req: &Request) -> Route {
    match req {
        Request::SetLocalModel(_model) => Route::Refuse(ErrorCode::Unsupported),
        Request::SetWatchdog { timeout_ms: _ } => Route::Refuse(ErrorCode::Unsupported),
        // Only the two requests above are routed here.
        _ => Route::Refuse(ErrorCode::Unsupported),
    }
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

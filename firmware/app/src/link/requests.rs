//! What each request becomes: a pipeline command for the tick, an answer the link gives itself,
//! or a typed refusal. The wire-to-core conversions are the protocol's
//! (`softfinger_protocol::convert`), shared with the virtual device.

use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::pipeline::Command;
use softfinger_protocol::{ErrorCode, Request};

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
    if let Some(command) = req.command(contact) {
        return Route::Pipeline(command);
    }
    match req {
        Request::GetInfo => Route::Info,
        Request::GetContactParams => Route::ContactParams,
        Request::Ping => Route::Ping,
        // The simulated hand exists on the virtual device only; `GetCounters` and `SetStream` are
        // answered by the endpoint before routing (refused if one ever gets here); the others
        // are pipeline commands, routed above.
        _ => Route::Refuse(ErrorCode::Unsupported),
    }
}

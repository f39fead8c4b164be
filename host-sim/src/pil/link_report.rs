//! What `host-sim pil --link-check` saw: each check with its verdict, the state frames decoded and
//! the device's link counters; filled by [`super::link_check`] and [`super::link_model`].

use softfinger_protocol::LinkCounters;

/// What the check saw.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct LinkReport {
    /// Each check, in order: (what, passed, detail).
    pub checks: Vec<(String, bool, String)>,
    /// State frames decoded.
    pub states: u32,
    /// Frames from the device this side could not decode.
    pub rx_errors_here: u32,
    /// The device's counters at the end.
    pub counters: Option<LinkCounters>,
}

impl LinkReport {
    pub(super) fn check(&mut self, what: &str, ok: bool, detail: String) {
        self.checks.push((what.to_string(), ok, detail));
    }

    /// Every check passed (and there were some).
    pub fn passed(&self) -> bool {
        !self.checks.is_empty() && self.checks.iter().all(|(_, ok, _)| *ok)
    }
}

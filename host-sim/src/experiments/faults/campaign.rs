//! The campaign's table: every scenario of [`super::classic`], [`super::pipeline_cases`] and
//! [`super::safety_cases`] in order, each run by [`super::scenarios::run_scenario`].

use super::scenarios::{run_scenario, Ctx, Outcome, Scenario};
use super::{classic, pipeline_cases, safety_cases, FaultsError};

/// Every scenario of the campaign, in order.
pub fn table() -> Vec<&'static Scenario> {
    classic::SCENARIOS
        .iter()
        .chain(pipeline_cases::SCENARIOS.iter())
        .chain(safety_cases::SCENARIOS.iter())
        .collect()
}

/// Run every scenario: (outcome, injected). `Err` only if a scenario could not be set up.
pub fn campaign() -> Result<Vec<(Outcome, bool)>, FaultsError> {
    let ctx = Ctx::new();
    table()
        .into_iter()
        .map(|s| run_scenario(s, &ctx).map(|o| (o, s.injected)))
        .collect()
}

//! `host-sim faults`: the fault-injection campaign, closed loop with the plant (see
//! [`scenarios`] for the scenarios and what "survived" means for each), and `host-sim soak`,
//! the long repeated-script run ([`soak`]).

pub mod campaign;
pub mod classic;
pub mod closed_loop;
pub mod pipeline_cases;
pub mod safety_cases;
pub mod scenarios;
pub mod soak;

use crate::error::JsonError;
use serde::Serialize;
use std::fmt::Write;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print the campaign as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The campaign's figures, as printed with `--json`.
#[derive(Clone, Debug, Serialize)]
pub struct CampaignReport {
    /// Scenarios with a fault or disturbance injected.
    pub injected: usize,
    /// Of those, how many survived.
    pub survived: usize,
    /// NaN outputs over every scenario (nominal included).
    pub nan_outputs: usize,
    /// Largest rendered force over every scenario, N.
    pub max_force_n: f64,
    /// Largest force the motors exerted (plant currents), N.
    pub max_plant_force_n: f64,
    /// The rendered-force limit (`max_force_n` of the contact parameters), N.
    pub force_limit_n: f64,
    /// The motors' limit: force_limit_n × the plant margin, N.
    pub plant_force_limit_n: f64,
    pub scenarios: Vec<scenarios::Outcome>,
}

/// Run the campaign and summarise it.
pub fn campaign_report() -> Result<CampaignReport, FaultsError> {
    let results = campaign::campaign()?;
    let limit = softfinger_core::contact::params::ContactParams::DEFAULT.max_force_n as f64;
    let injected = results.iter().filter(|(_, i)| *i).count();
    let survived = results.iter().filter(|(o, i)| *i && o.survived).count();
    let all = || results.iter().map(|(o, _)| o);
    Ok(CampaignReport {
        injected,
        survived,
        nan_outputs: all().map(|o| o.nan_outputs).sum(),
        max_force_n: all().map(|o| o.max_rendered_force_n).fold(0.0, f64::max),
        max_plant_force_n: all().map(|o| o.max_plant_force_n).fold(0.0, f64::max),
        force_limit_n: limit,
        plant_force_limit_n: limit * scenarios::PLANT_FORCE_MARGIN,
        scenarios: results.into_iter().map(|(o, _)| o).collect(),
    })
}

fn opt(v: Option<u64>) -> String {
    v.map_or("-".into(), |k| k.to_string())
}

/// `host-sim faults`.
pub fn main(args: &Args) -> Result<(), FaultsError> {
    let r = campaign_report()?;
    if args.json {
        return emit_json(&r);
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{:<26} {:>8} {:>7} {:>7} {:>7} {:>9} {:>9} {:>4}  states / detail",
        "scenario", "result", "inject", "detect", "safe", "render N", "motors N", "NaN"
    );
    for o in &r.scenarios {
        let _ = writeln!(
            text,
            "{:<26} {:>8} {:>7} {:>7} {:>7} {:>9.3} {:>9.3} {:>4}  {} {}",
            o.name,
            if o.survived { "survived" } else { "FAILED" },
            opt(o.inject_tick),
            opt(o.detect_tick),
            opt(o.safe_tick),
            o.max_rendered_force_n,
            o.max_plant_force_n,
            o.nan_outputs,
            o.states.join(">"),
            o.detail
        );
    }
    let _ = writeln!(
            text,

        "injected {}, survived {}, NaN outputs {}, max force rendered {:.3} N / motors {:.3} N (limits {:.1} N / {:.1} N)",
        r.injected,
        r.survived,
        r.nan_outputs,
        r.max_force_n,
        r.max_plant_force_n,
        r.force_limit_n,
        r.plant_force_limit_n
    );
    emit(&text);
    Ok(())
}

/// Write to stdout; a closed pipe (`| head`) is not an error worth a panic.
/// Print `value` as pretty JSON and a newline on stdout.
pub(crate) fn emit_json(value: &impl Serialize) -> Result<(), FaultsError> {
    let text = serde_json::to_string_pretty(value).map_err(JsonError)?;
    emit(&format!("{text}\n"));
    Ok(())
}

/// Why a fault campaign or soak could not run.
#[derive(Debug, thiserror::Error)]
pub enum FaultsError {
    /// A scenario's closed loop could not be set up.
    #[error("{scenario}: {source}")]
    Setup {
        /// Scenario name.
        scenario: &'static str,
        /// The setup's reason.
        source: crate::sim::closed_loop::SetupError,
    },
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
}

pub(crate) fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().write_all(text.as_bytes());
}

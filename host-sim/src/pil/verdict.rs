//! Whether a processor-in-the-loop run passed: an injected fault handled as the firmware must,
//! and `--check`'s failures (overruns, differences from the in-process run, output timing, ticks
//! over the period or over the budget file's baselines).

use super::faults::Fault;
use super::report::Summary;
use super::session;
use super::PilError;
use crate::error::FileError;
use std::path::Path;

/// Whether the fault was handled as the firmware must: outputs off at once (a hung tick: within
/// the watchdog's reset) and kept off; a stalled log reader only drops frames.
pub(super) fn judge(summary: &Summary, s: &session::Settings) -> bool {
    let f = &summary.fault;
    let off_and_kept = |within: u64| {
        f.outputs_off_after_ticks.is_some_and(|t| t <= within) && f.periods_driven_after_off == 0
    };
    let all_identical = summary.identical_ticks == summary.compared_ticks;
    match s.fault {
        Fault::None => true,
        Fault::LogStall => summary.defmt_drops > 0 && summary.overruns == 0 && all_identical,
        Fault::EncoderGlitch | Fault::DriverFault => off_and_kept(0) && all_identical,
        Fault::Panic => off_and_kept(0),
        // 5 ms watchdog timeout (the firmware's configuration), then the NMI.
        Fault::Hang => {
            summary.watchdog_resets > 0 && off_and_kept(u64::from(s.rate_hz()) / 200 + 1)
        }
    }
}

/// `--check`: every failure in one error.
pub(super) fn check(summary: &Summary, budget: Option<&Path>) -> Result<(), PilError> {
    let mut failures = Vec::new();
    if summary.overruns > 0 {
        failures.push(format!("{} overruns", summary.overruns));
    }
    if summary.identical_ticks != summary.compared_ticks || summary.compared_ticks == 0 {
        failures.push(format!(
            "{} of {} ticks differ from the in-process run (max duty diff {:e})",
            summary.compared_ticks - summary.identical_ticks,
            summary.compared_ticks,
            summary.max_duty_diff
        ));
    }
    failures.extend(summary.output.failure());
    if !summary.fault.handled {
        failures.push(format!("fault {:?} not handled", summary.fault.name));
    }
    if summary.max_tick_instructions as u64 > summary.period_instructions {
        failures.push(format!(
            "tick of {} instructions exceeds the period ({})",
            summary.max_tick_instructions, summary.period_instructions
        ));
    }
    if let Some(path) = budget {
        failures.extend(over_budget(summary, path)?);
    }
    if failures.is_empty() {
        Ok(())
    } else {
        Err(PilError::Check(failures))
    }
}

/// Figures over the budget file's baselines by more than its tolerance.
fn over_budget(summary: &Summary, path: &Path) -> Result<Vec<String>, PilError> {
    let text = std::fs::read_to_string(path).map_err(FileError::on(path, "cannot read"))?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|source| PilError::Budget {
        path: path.to_path_buf(),
        source,
    })?;
    let tol = v["tolerance_percent"].as_f64().unwrap_or(10.0);
    let mut out = Vec::new();
    for (name, value) in [
        ("max_tick_instructions", summary.max_tick_instructions),
        (
            "max_start_latency_instructions",
            summary.max_start_latency_instructions,
        ),
    ] {
        let rate = summary.rate_hz.to_string();
        let Some(base) = v["baseline"][&rate][name].as_f64() else {
            return Err(PilError::NoBaseline {
                path: path.to_path_buf(),
                figure: name,
                rate_hz: summary.rate_hz,
            });
        };
        if f64::from(value) > base * (1.0 + tol / 100.0) {
            out.push(format!(
                "{name} {value} over its budget {base} (+{tol} % allowed)"
            ));
        }
    }
    Ok(out)
}

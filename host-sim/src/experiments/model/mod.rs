//! `host-sim model --scene NAME|FILE [--json] [--svg FILE]`: which contact model a scene needs.
//!
//! The scene runs in closed loop once per model choice ([`softfinger_core::contact::parts`]); each
//! run is compared with the full model's run ([`ablation`]) and held against the perceptual
//! [`yardstick`] ([`chart`]: cost against difference, `--svg`). The answer is the least choice whose differences stay below it. Each row also
//! gives the choice's cost: instructions per contact step on the emulated Cortex-M4F (the
//! `contact_step_<surface>_<model>` rows of `mcu-bench/budget.json`, written by
//! `scripts/mcu-bench --update-budget`) and ns per step on this host.

pub mod ablation;
pub mod chart;
pub mod grasp;
pub mod yardstick;

use crate::error::{ChartError, JsonError};
use crate::sim::closed_loop::SetupError;
use crate::sim::scene::{Scene, SceneError};
use ablation::{difference, transitions, Difference, Run};
use softfinger_core::contact::ModelChoice;
use std::path::PathBuf;

/// Why the model command failed.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A run of the named scene failed.
    #[error("scene '{scene}': {source}")]
    InScene {
        /// Scene name.
        scene: String,
        /// The stage and its reason.
        source: SetupError,
    },
    /// The grasp scene could not be run.
    #[error("scene 'grasp': {0}")]
    Grasp(String),
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
    /// The chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// `--check`: the model the scene names would be felt against the full model.
    #[error(
        "scene '{scene}' names model '{model}', which exceeds the yardstick on it: force {force_ratio:.2}, \
         path {path_ratio:.2} times the just-noticeable difference (torque {torque_ratio:.2}, counted \
         only on a device that displays it); `host-sim model --scene {scene}` names the least model"
    )]
    Exceeds {
        /// Scene name.
        scene: String,
        /// The named model.
        model: &'static str,
        /// Force difference over its yardstick.
        force_ratio: f64,
        /// Torque difference over its yardstick.
        torque_ratio: f64,
        /// Path difference over its yardstick.
        path_ratio: f64,
    },
}

#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// A built-in scene name (finger-on-plane, finger-on-sphere, finger-in-bowl,
    /// finger-on-cylinder, finger-slide-twist), `grasp` (two fingertips holding an object,
    /// [`grasp`]) or a scene TOML file.
    #[arg(long, default_value = "finger-on-plane")]
    pub scene: String,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also draw cost against difference for each choice into this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Only check the model the scene names against the full model (two closed-loop runs, not
    /// one per choice): exit 2 with the ratios when it exceeds the yardstick.
    #[arg(long, conflicts_with_all = ["json", "svg"])]
    pub check: bool,
}

/// One row of the table: a choice, its cost and its difference from the full model.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Row {
    /// The choice's name.
    pub model: &'static str,
    /// Instructions per contact step on the emulated Cortex-M4F (fast backend), from the budget
    /// file; `None` when the budget has no row for it.
    pub instructions: Option<u32>,
    /// Host time per contact step, ns (on the full run's inputs; least of several passes; NaN,
    /// null in JSON, when not timed).
    pub host_ns_per_step: f64,
    /// The differences from the full model.
    #[serde(flatten)]
    pub diff: Difference,
    /// Not felt on this device (the torque not counted: it is not displayed;
    /// [`yardstick::DEVICE_DISPLAYS_TORQUE`]).
    pub within_yardstick: bool,
    /// Not felt on a device that also displayed the spin torque (every ratio at most 1).
    pub within_yardstick_torque_displayed: bool,
}

/// The whole answer for a scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Report {
    /// The scene's name.
    pub scene: String,
    /// The surface kind.
    pub surface: &'static str,
    /// The least choice within the yardstick on this device: of the choices within it, the one
    /// with the fewest instructions per contact step on the M4F (ties: fewer parts).
    pub least_model: &'static str,
    /// The least choice within the yardstick on a device that also displayed the spin torque.
    pub least_model_torque_displayed: &'static str,
    /// Whether this device displays the spin torque ([`yardstick::DEVICE_DISPLAYS_TORQUE`]).
    pub device_displays_torque: bool,
    /// The choice the scene file names.
    pub named_model: &'static str,
    /// The named choice is within the yardstick.
    pub named_within_yardstick: bool,
    /// Transitions of the full model's run.
    pub full_transitions: usize,
    /// The yardstick and its sources.
    pub yardstick: &'static str,
    /// One row per choice, least first.
    pub rows: Vec<Row>,
}

/// The mcu-bench budget the instruction counts come from.
const BUDGET_JSON: &str = include_str!("../../../../mcu-bench/budget.json");

/// Instructions per contact step of `model` on `surface` (fast backend), from the budget.
pub fn instructions(surface: &str, model: ModelChoice) -> Option<u32> {
    budget_instructions(&format!("contact_step_{surface}_{}", model.name()))
}

/// Instructions of the budget's row `name` (fast backend).
pub fn budget_instructions(name: &str) -> Option<u32> {
    let v: serde_json::Value = serde_json::from_str(BUDGET_JSON).ok()?;
    v.get("baseline")?
        .as_array()?
        .iter()
        .find(|r| r["name"] == name && r["backend"] == "fast")?
        .get("instructions")?
        .as_u64()
        .map(|n| n as u32)
}

/// The report of `scene` from its runs (`full` and one per choice, least first).
pub fn report(scene: &Scene, full: &Run, runs: &[Run]) -> Result<Report, ModelError> {
    let named = scene.model().map_err(|problem| SceneError::Invalid {
        origin: scene.name.clone(),
        problem,
    })?;
    let rows: Vec<Row> = runs
        .iter()
        .map(|r| {
            let diff = difference(r, full, scene.rate_hz);
            Row {
                model: r.choice.name(),
                instructions: instructions(scene.surface.kind(), r.choice),
                host_ns_per_step: r.host_ns_per_step,
                diff,
                within_yardstick: diff.within_yardstick(),
                within_yardstick_torque_displayed: diff.within(true),
            }
        })
        .collect();
    let least = least_of(&rows, |r| r.within_yardstick);
    let least_torque = least_of(&rows, |r| r.within_yardstick_torque_displayed);
    let named_within = rows
        .iter()
        .find(|r| r.model == named.name())
        .is_some_and(|r| r.within_yardstick);
    Ok(Report {
        scene: scene.name.clone(),
        surface: scene.surface.kind(),
        least_model: least,
        least_model_torque_displayed: least_torque,
        device_displays_torque: yardstick::DEVICE_DISPLAYS_TORQUE,
        named_model: named.name(),
        named_within_yardstick: named_within,
        full_transitions: transitions(&full.ticks),
        yardstick: yardstick::STATEMENT,
        rows,
    })
}

/// The cheapest row (M4F instructions; a row without a count last; ties: the earlier row, fewer
/// parts) that `ok` accepts; `full` when none does.
pub fn least_of(rows: &[Row], ok: impl Fn(&Row) -> bool) -> &'static str {
    rows.iter()
        .enumerate()
        .filter(|(_, r)| ok(r))
        .min_by_key(|(k, r)| (r.instructions.unwrap_or(u32::MAX), *k))
        .map(|(_, r)| r.model)
        .unwrap_or(ModelChoice::Full.name())
}

/// Run every choice on the scene named `name_or_path` and report; each choice is timed on the
/// host when `timed`.
pub fn ablate(name_or_path: &str, timed: bool) -> Result<Report, ModelError> {
    let scene = Scene::load(name_or_path)?;
    let (full, runs) =
        ablation::runs(&scene, &ModelChoice::ALL, timed).map_err(|source| ModelError::InScene {
            scene: scene.name.clone(),
            source,
        })?;
    report(&scene, &full, &runs)
}

/// The table and the answer, as text.
pub fn table(r: &Report) -> String {
    let mut t = format!(
        "scene {} ({}): least model {} (on a device that displayed the spin torque: {}); the scene names {} ({})\n",
        r.scene,
        r.surface,
        r.least_model,
        r.least_model_torque_displayed,
        r.named_model,
        if r.named_within_yardstick {
            "within the yardstick"
        } else {
            "EXCEEDS the yardstick"
        }
    );
    t += &format!(
        "{:<15} {:>7} {:>8} {:>9} {:>9} {:>10} {:>10} {:>9} {:>8} {:>6} {:>7} {:>7} {:>7} {:>6} {:>8}\n",
        "model",
        "instr",
        "host ns",
        "max dF N",
        "rms dF N",
        "max dT mNm",
        "rms dT mNm",
        "path mm",
        "state %",
        "trans",
        "F/JND",
        "T/JND",
        "P/JND",
        "felt",
        "felt(+T)"
    );
    for row in &r.rows {
        let d = &row.diff;
        t += &format!(
            "{:<15} {:>7} {:>8.1} {:>9.4} {:>9.4} {:>10.4} {:>10.4} {:>9.4} {:>8.2} {:>6} {:>7.2} {:>7.2} {:>7.2} {:>6} {:>8}\n",
            row.model,
            row.instructions.map_or("-".to_string(), |n| n.to_string()),
            row.host_ns_per_step,
            d.max_force_diff_n,
            d.rms_force_diff_n,
            d.max_torque_diff_mnm,
            d.rms_torque_diff_mnm,
            d.max_path_diff_mm,
            d.state_diff_percent,
            d.transitions,
            d.force_ratio,
            d.torque_ratio,
            d.path_ratio,
            if row.within_yardstick { "no" } else { "yes" },
            if row.within_yardstick_torque_displayed {
                "no"
            } else {
                "yes"
            }
        );
    }
    t += &format!(
        "(full model: {} transitions) {}\n",
        r.full_transitions, r.yardstick
    );
    t
}

/// The named model's difference from the full model on the scene `name_or_path` (two runs).
pub fn check(name_or_path: &str) -> Result<Difference, ModelError> {
    let scene = Scene::load(name_or_path)?;
    let named = scene.model().map_err(|problem| SceneError::Invalid {
        origin: scene.name.clone(),
        problem,
    })?;
    let (full, runs) =
        ablation::runs(&scene, &[named], false).map_err(|source| ModelError::InScene {
            scene: scene.name.clone(),
            source,
        })?;
    let d = difference(&runs[0], &full, scene.rate_hz);
    if d.within_yardstick() {
        Ok(d)
    } else {
        Err(ModelError::Exceeds {
            scene: scene.name.clone(),
            model: named.name(),
            force_ratio: d.force_ratio,
            torque_ratio: d.torque_ratio,
            path_ratio: d.path_ratio,
        })
    }
}

/// `host-sim model`.
pub fn main(args: &Args) -> Result<(), ModelError> {
    if args.scene == grasp::SCENE {
        return grasp::main(args);
    }
    if args.check {
        let d = check(&args.scene)?;
        println!(
            "{}: the named model is within the yardstick (force {:.3}, path {:.3} of the \
             just-noticeable difference; torque {:.3}, {})",
            args.scene,
            d.force_ratio,
            d.path_ratio,
            d.torque_ratio,
            if yardstick::DEVICE_DISPLAYS_TORQUE {
                "counted"
            } else {
                "not displayed by this device"
            }
        );
        return Ok(());
    }
    let r = ablate(&args.scene, true)?;
    if let Some(path) = &args.svg {
        crate::experiments::model::chart::write(path, &r)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r).map_err(JsonError)?);
    } else {
        print!("{}", table(&r));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(model: &'static str, instructions: Option<u32>, ok: bool) -> Row {
        let d = Difference {
            max_force_diff_n: 0.0,
            rms_force_diff_n: 0.0,
            max_torque_diff_mnm: 0.0,
            rms_torque_diff_mnm: 0.0,
            max_path_diff_mm: 0.0,
            state_diff_ticks: 0,
            state_diff_percent: 0.0,
            transitions: 0,
            same_state_sequence: true,
            force_ratio: if ok { 1.0 } else { 1.01 },
            torque_ratio: 0.0,
            path_ratio: 0.0,
        };
        Row {
            model,
            instructions,
            host_ns_per_step: f64::NAN,
            diff: d,
            within_yardstick: d.within_yardstick(),
            within_yardstick_torque_displayed: d.within(true),
        }
    }

    /// The least model is the cheapest on the M4F among those within the yardstick (a ratio of
    /// exactly 1 is within, 1.01 is not), not the first in order; with none within, the full model.
    #[test]
    fn the_least_model_is_the_cheapest_within_the_yardstick() {
        let rows = [
            row("point-friction", Some(256), false),
            row("rolling", Some(372), true),
            row("spin", Some(383), false),
            row("spin-rolling", Some(434), true),
            row("full", Some(440), true),
        ];
        assert_eq!(least_of(&rows, |r| r.within_yardstick), "rolling");
        let sphere = [
            row("rolling", Some(741), true),
            row("spin", Some(556), true),
            row("full", Some(803), true),
        ];
        assert_eq!(least_of(&sphere, |r| r.within_yardstick), "spin");
        // A row without a count goes last; none within: full.
        let unknown = [row("rolling", None, true), row("full", Some(440), true)];
        assert_eq!(least_of(&unknown, |r| r.within_yardstick), "full");
        assert_eq!(least_of(&rows[..1], |r| r.within_yardstick), "full");
    }
}

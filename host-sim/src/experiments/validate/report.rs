//! `validate`'s output: an aligned table for people, JSON for scripts.
//!
//! JSON layout: `{"methods": [{"method", "plane_max_error_mm": [x, y, z], "sphere_max_error_mm": [x, y, z],
//! "ns_per_step", "error_against", "rtol"?, "atol"?}, ...], "best", "speedup", "speedup_spread"
//! ({"median", "q1", "q3", "min", "max", "rounds"} of the per-round ratio, or null), "reference", "paper"}`.
//! Our rows are named `method/backend` (e.g. `exact/libm`) and measured against the RK45 reference; the
//! classical rows' names start with `rk45` and are measured against the closed form.

use crate::error::JsonError;
use serde::Serialize;
use std::fmt::Write;

use super::classical::{Rk45Run, REFERENCE_TOLERANCES};
use super::errors::PathErrors;
use super::{Validation, TARGET_MM};
use crate::sim::reference::scene::{PAPER_DT_S, PAPER_DURATION_S, PAPER_INCREMENTS_ZYX};

/// The paper's §3.1 figures: largest difference along x, y, z (mm).
pub const PAPER_MAX_ERROR_MM: [f64; 3] = [0.004, 0.004, 0.001];
/// The paper's time for the whole 1 s scene with the classical equations (Matlab `ode45`), s.
pub const PAPER_CLASSICAL_S: f64 = 0.35;
/// The paper's time for the whole scene with its algorithm, s.
pub const PAPER_PROPOSED_S: f64 = 0.01;

/// One row of the JSON `methods` array.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// `method/backend` for ours; `rk45-…` for the classical runs.
    pub method: String,
    /// Largest |Δx|, |Δy|, |Δz| of the plane contact path, mm.
    pub plane_max_error_mm: [f64; 3],
    /// Largest |Δx|, |Δy|, |Δz| of the sphere contact path (fingertip frame), mm.
    pub sphere_max_error_mm: [f64; 3],
    /// Median wall-clock time per step, ns.
    pub ns_per_step: f64,
    /// What the errors are measured against: `rk45-reference` (the `rk45-reference/restart` run) or
    /// `closed-form`.
    pub error_against: &'static str,
    /// Relative tolerance (classical rows).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    /// Absolute tolerance (classical rows).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub atol: Option<f64>,
}

/// One row of the JSON `models` array: the whole contact step with one model choice.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelRow {
    /// The choice's name (`point-friction`, `rolling`, ...).
    pub model: &'static str,
    /// Instructions per contact step on the emulated M4F (plane, fast backend), from the budget.
    pub instructions: Option<u32>,
    /// Largest |Δx|, |Δy|, |Δz| of the plane contact path against the RK45 reference, mm.
    pub plane_max_error_mm: [f64; 3],
    /// The same on the sphere (fingertip frame), mm.
    pub sphere_max_error_mm: [f64; 3],
    /// Steps not in the rolling state.
    pub not_rolling_steps: usize,
    /// Median time per contact step, ns.
    pub ns_per_step: f64,
    /// Cheapest matched RK45 over this choice, ratio of the medians (None: no match, or this
    /// choice misses the accuracy target).
    pub speedup: Option<f64>,
    /// The same per timing round.
    pub speedup_spread: Option<super::timing::Spread>,
}

/// The least model for the paper's scene: the choice with the fewest M4F instructions whose paths
/// are within [`TARGET_MM`].
pub fn least_model(v: &Validation) -> Option<&super::models::ModelRun> {
    v.models
        .iter()
        .filter(|m| m.errors.max_mm() <= TARGET_MM)
        .min_by_key(|m| {
            crate::experiments::model::instructions("plane", m.choice).unwrap_or(u32::MAX)
        })
}

/// The `models` rows.
pub fn model_rows(v: &Validation) -> Vec<ModelRow> {
    let rk = v.cheapest_matched().and_then(|m| m.ns_per_step);
    v.models
        .iter()
        .map(|m| ModelRow {
            model: m.choice.name(),
            instructions: crate::experiments::model::instructions("plane", m.choice),
            plane_max_error_mm: m.errors.plane_mm,
            sphere_max_error_mm: m.errors.sphere_mm,
            not_rolling_steps: m.not_rolling_steps,
            ns_per_step: m.ns_per_step,
            speedup: rk
                .filter(|_| m.errors.max_mm() <= TARGET_MM)
                .map(|rk| rk / m.ns_per_step),
            speedup_spread: m.speedup_spread,
        })
        .collect()
}

#[derive(Serialize)]
struct Json<'a> {
    methods: &'a [Row],
    best: String,
    speedup: Option<f64>,
    speedup_spread: Option<super::timing::Spread>,
    models: Vec<ModelRow>,
    least_model: Option<&'static str>,
    reference: JsonReference,
    paper: JsonPaper,
}

#[derive(Serialize)]
struct JsonReference {
    method: &'static str,
    rtol: f64,
    atol: f64,
    plane_vs_closed_form_mm: [f64; 3],
    sphere_vs_closed_form_mm: [f64; 3],
}

#[derive(Serialize)]
struct JsonPaper {
    max_error_mm: [f64; 3],
    classical_s: f64,
    proposed_s: f64,
    speedup: f64,
}

/// Name of a classical row: `rk45-<kind>/<call>`.
fn rk45_name(kind: &str, r: &Rk45Run) -> String {
    format!("rk45-{kind}/{}", r.call.name())
}

fn rk45_row(kind: &str, r: &Rk45Run) -> Row {
    Row {
        method: rk45_name(kind, r),
        plane_max_error_mm: r.errors.plane_mm,
        sphere_max_error_mm: r.errors.sphere_mm,
        ns_per_step: r.ns_per_step.unwrap_or(f64::NAN),
        error_against: "closed-form",
        rtol: Some(r.rtol),
        atol: Some(r.atol),
    }
}

/// All rows: ours, then the reference, the `ode45`-default runs and the matched runs.
pub fn rows(v: &Validation) -> Vec<Row> {
    let mut rows: Vec<Row> = v
        .ours
        .iter()
        .map(|o| Row {
            method: o.variant.name(),
            plane_max_error_mm: o.errors.plane_mm,
            sphere_max_error_mm: o.errors.sphere_mm,
            ns_per_step: o.ns_per_step,
            error_against: "rk45-reference",
            rtol: None,
            atol: None,
        })
        .collect();
    rows.push(rk45_row("reference", &v.reference_run));
    rows.extend(
        v.ode45_defaults
            .iter()
            .map(|r| rk45_row("ode45-defaults", r)),
    );
    rows.extend(v.matched.iter().map(|r| rk45_row("matched", r)));
    rows
}

/// The JSON document.
pub fn json(v: &Validation) -> Result<String, JsonError> {
    let rows = rows(v);
    let doc = Json {
        methods: &rows,
        best: v.best().variant.name(),
        speedup: v.speedup(),
        speedup_spread: v.speedup_spread,
        models: model_rows(v),
        least_model: least_model(v).map(|m| m.choice.name()),
        reference: JsonReference {
            method: "rk45-reference/restart",
            rtol: REFERENCE_TOLERANCES.0,
            atol: REFERENCE_TOLERANCES.1,
            plane_vs_closed_form_mm: v.reference.errors.plane_mm,
            sphere_vs_closed_form_mm: v.reference.errors.sphere_mm,
        },
        paper: JsonPaper {
            max_error_mm: PAPER_MAX_ERROR_MM,
            classical_s: PAPER_CLASSICAL_S,
            proposed_s: PAPER_PROPOSED_S,
            speedup: PAPER_CLASSICAL_S / PAPER_PROPOSED_S,
        },
    };
    serde_json::to_string_pretty(&doc).map_err(JsonError)
}

fn e3(v: [f64; 3]) -> String {
    v.map(|x| format!("{x:>9.2e}")).join(" ")
}

/// Width of the name column.
const NAME_WIDTH: usize = 36;

/// A table line: name, plane errors, sphere errors, ns per step, then free text.
fn line(out: &mut String, name: &str, e: &PathErrors, ns: Option<f64>, tail: &str) {
    let ns = ns.map_or("-".to_string(), |n| format!("{n:.0}"));
    let _ = writeln!(
        out,
        "  {name:<NAME_WIDTH$} {}   {}  {ns:>8}  {tail}",
        e3(e.plane_mm),
        e3(e.sphere_mm)
    );
}

fn header(out: &mut String, first: &str, tail: &str) {
    let _ = writeln!(
        out,
        "  {first:<NAME_WIDTH$} {:<29}   {:<29}  {:>8}  {tail}",
        "plane max |Δ| x, y, z (mm)", "sphere max |Δ| x, y, z (mm)", "ns/step"
    );
}

/// The human-readable report.
pub fn table(v: &Validation) -> String {
    let mut out = String::new();
    let steps = v.scene.samples.len().saturating_sub(1);
    scene_and_reference(&mut out, v, steps);
    ours_rows(&mut out, v);
    classical_rows(&mut out, v, steps);
    paper_comparison(&mut out, v, steps);
    model_table(&mut out, v);
    out
}

/// The whole contact step per model choice, and its speed-up against the cheapest matched RK45.
fn model_table(out: &mut String, v: &Validation) {
    let _ = writeln!(
        out,
        "\n\nThe whole contact step (ContactModel<Fast, Plane, P>, pressed 1 mm, centre over the closed-form \
         contact point) per model choice, timed in the same rounds; errors against the reference:"
    );
    header(
        out,
        "model",
        " M4F instr  rolling  speed-up vs matched RK45 (median per round, quartiles)",
    );
    for r in model_rows(v) {
        let e = PathErrors {
            plane_mm: r.plane_max_error_mm,
            sphere_mm: r.sphere_max_error_mm,
        };
        let sp = match (r.speedup, r.speedup_spread) {
            (Some(x), Some(s)) => format!("{x:.1}x ({:.1}x, {:.1}x-{:.1}x)", s.median, s.q1, s.q3),
            (Some(x), None) => format!("{x:.1}x"),
            _ => format!("- (misses {TARGET_MM} mm)"),
        };
        let tail = format!(
            "{:>10}  {:>7}  {sp}",
            r.instructions.map_or("-".into(), |n| n.to_string()),
            if r.not_rolling_steps == 0 {
                "all"
            } else {
                "no"
            },
        );
        line(out, r.model, &e, Some(r.ns_per_step), &tail);
    }
    if let Some(m) = least_model(v) {
        let _ = write!(
            out,
            "Least model for this scene (fewest M4F instructions within {TARGET_MM} mm): {}",
            m.choice.name()
        );
    }
}

/// The scene and the reference run with its check against the closed form.
fn scene_and_reference(out: &mut String, v: &Validation, steps: usize) {
    let [phi, theta, psi] = PAPER_INCREMENTS_ZYX;
    let _ = writeln!(
        out,
        "Paper §3.1 scene: sphere of radius {} mm on a plane; per sample body-fixed δφ = {phi}, δθ = {theta}, \
         δψ = {psi} rad about z, y, x; sampling {} ms, {} s ({steps} steps).",
        v.scene.radius * 1e3,
        PAPER_DT_S * 1e3,
        PAPER_DURATION_S
    );
    let r = &v.reference;
    let _ = writeln!(
        out,
        "\nReference: Montana's rolling equations in f64, adaptive Dormand–Prince RK45 restarted at every \
         sample, rtol {:e}, atol {:e} ({} steps, {} rejected, {} f-evals).",
        REFERENCE_TOLERANCES.0,
        REFERENCE_TOLERANCES.1,
        r.paths.stats.steps,
        r.paths.stats.rejected,
        r.paths.stats.f_evals
    );
    let _ = writeln!(
        out,
        "Check against the closed form: plane max |Δ| x, y, z = {} mm; sphere {} mm; largest distance {:.2e} / {:.2e} mm.",
        e3(r.errors.plane_mm),
        e3(r.errors.sphere_mm),
        r.max_distance_mm.0,
        r.max_distance_mm.1
    );
}

/// One row per method x backend of ours, errors against the reference.
fn ours_rows(out: &mut String, v: &Validation) {
    let _ = writeln!(
        out,
        "\nOurs: softfinger-core Rolling<Plane> in f32, method/backend; errors against the reference:"
    );
    header(out, "method", "");
    for (i, o) in v.ours.iter().enumerate() {
        let note = if i == v.best { "<- best" } else { "" };
        line(out, &o.variant.name(), &o.errors, Some(o.ns_per_step), note);
    }
}

/// One row per classical run (the reference, ode45 defaults, matched accuracy).
fn classical_rows(out: &mut String, v: &Validation, steps: usize) {
    let _ = writeln!(
        out,
        "\nClassical: Montana + RK45 in f64; errors against the closed form; ns/step = one whole integration \
         over the scene / {steps} samples:"
    );
    header(out, "run", "   rtol     atol   steps  f-evals  call");
    let classical = |out: &mut String, kind: &str, r: &Rk45Run| {
        let tail = format!(
            "{:>7.1e}  {:>7.1e}  {:>6}  {:>7}  {}",
            r.rtol,
            r.atol,
            r.stats.steps,
            r.stats.f_evals,
            r.call.describe()
        );
        line(out, &rk45_name(kind, r), &r.errors, r.ns_per_step, &tail);
    };
    classical(out, "reference", &v.reference_run);
    for r in &v.ode45_defaults {
        classical(out, "ode45-defaults", r);
    }
    for r in &v.matched {
        classical(out, "matched", r);
    }
}

/// The paper's figures beside ours: best variant, matched-accuracy speed-up, speed-up against
/// ode45's defaults.
fn paper_comparison(out: &mut String, v: &Validation, steps: usize) {
    let best = v.best();
    let paper_speedup = PAPER_CLASSICAL_S / PAPER_PROPOSED_S;
    let _ = writeln!(
        out,
        "\nPaper (Matlab R2009a ode45 vs its algorithm, 2.4 GHz Core 2 Duo): max difference {} / {} / {} mm \
         along x, y, z; {} s vs {} s for the {steps}-step scene ({:.1} ms vs {:.1} ms per step): {paper_speedup:.0}x.",
        PAPER_MAX_ERROR_MM[0],
        PAPER_MAX_ERROR_MM[1],
        PAPER_MAX_ERROR_MM[2],
        PAPER_CLASSICAL_S,
        PAPER_PROPOSED_S,
        PAPER_CLASSICAL_S / steps.max(1) as f64 * 1e3,
        PAPER_PROPOSED_S / steps.max(1) as f64 * 1e3,
    );
    let _ = writeln!(
        out,
        "Ours: best = {} (fastest variant within {TARGET_MM} mm, else the most accurate): max error {:.2e} mm, \
         {:.0} ns per step, {:.1} µs for the scene.",
        best.variant.name(),
        best.errors.max_mm(),
        best.ns_per_step,
        best.ns_per_step * steps as f64 * 1e-3
    );
    match v.cheapest_matched() {
        Some(m) => {
            let ns = m.ns_per_step.unwrap_or(f64::NAN);
            let _ = writeln!(
                out,
                "Classical at matched accuracy (loosest rtol with error ≤ {:.2e} mm): {} at rtol {:.1e}, {ns:.0} ns per step.",
                best.errors.max_mm(),
                rk45_name("matched", m),
                m.rtol
            );
            let _ = writeln!(
                out,
                "Speed-up (RK45 at matched accuracy / our best, both computing both contact paths): \
                 {:.1}x   (paper: {paper_speedup:.0}x)",
                ns / best.ns_per_step
            );
            if let Some(s) = v.speedup_spread {
                let _ = writeln!(
                    out,
                    "  per timing round: median {:.1}x, quartiles {:.1}x-{:.1}x, range {:.1}x-{:.1}x over {} rounds",
                    s.median, s.q1, s.q3, s.min, s.max, s.rounds
                );
            }
        }
        None => {
            let _ = writeln!(
                out,
                "Classical: no tolerance down to rtol 1e-12 reached our best error; no matched speed-up."
            );
        }
    }
    let vs: Vec<String> = v
        .ode45_defaults
        .iter()
        .filter_map(|r| {
            r.ns_per_step
                .map(|ns| format!("{} {:.1}x", r.call.name(), ns / best.ns_per_step))
        })
        .collect();
    let _ = write!(
        out,
        "Speed-up against ode45 defaults (rtol 1e-3, atol 1e-6): {}",
        vs.join(", ")
    );
}

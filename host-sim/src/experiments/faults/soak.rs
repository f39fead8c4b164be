//! `host-sim soak`: a long closed-loop run that repeats the touch script, to show the forces stay
//! bounded, nothing turns NaN and the contact state does not drift over hours of use.
//!
//! The script is the default touch script followed by a 0.5 s return to its start (4.8 s, 48 000
//! ticks at 10 kHz); the plant restarts the script each time it ends, keeping its mechanical
//! state, and the pipeline (homed and armed once at the start) runs on without any reset. Per repetition the run records the
//! contact-state timeline (each transition and its tick within the repetition) and the contact
//! point on the plane at the end of the roll phase (t = 1.8 s into the repetition). Drift is
//! measured against the second repetition (the first starts from rest, the others from where the
//! return left the handle).
//!
//! Release build only. Through the pipeline and the bridge-driven plant, 2·10⁵ ticks took 0.93 s
//! of CPU here (2.5 s wall on a loaded machine), so 10⁸ ticks take about 8 min of CPU:
//! `cargo run --release -p host-sim -- soak --ticks 100000000 --json`.

use super::closed_loop::{scene_config, ClosedLoop};
use super::FaultsError;
use crate::sim::plant::{Phase, PlantParams, TouchScript, Waypoint};
use serde::Serialize;
use softfinger_core::contact::state::ContactState;
use std::fmt::Write;
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Controller ticks to run (10 kHz: 10⁸ ticks is 2.8 h of simulated use).
    #[arg(long, default_value_t = 100_000_000)]
    pub ticks: u64,
    /// Print the figures as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The figures of a soak run.
#[derive(Clone, Debug, Serialize)]
pub struct SoakReport {
    pub ticks: u64,
    pub repetitions: u64,
    pub ticks_per_repetition: u64,
    pub wall_s: f64,
    pub ticks_per_s: f64,
    pub max_rendered_force_n: f64,
    pub max_plant_force_n: f64,
    pub force_limit_n: f64,
    pub nan_outputs: u64,
    pub latched_ticks: u64,
    /// Complete repetitions whose state sequence differs from the reference repetition's.
    pub timeline_mismatches: u64,
    /// Largest shift of a transition's tick against the reference repetition, ticks.
    pub max_transition_shift_ticks: u64,
    /// Largest distance of the end-of-roll contact point from the reference repetition's, m.
    pub max_contact_point_drift_m: f64,
    /// The reference repetition's end-of-roll contact point on the plane, object frame, m.
    pub reference_roll_end_point_m: Option<[f64; 3]>,
    /// The reference repetition's timeline: (tick within the repetition, state entered).
    pub reference_timeline: Vec<(u64, &'static str)>,
}

#[derive(Clone, Debug, Default, PartialEq)]
struct Repetition {
    timeline: Vec<(u64, ContactState)>,
    roll_end_point: Option<[f64; 3]>,
}

/// How later repetitions differ from the reference one.
#[derive(Clone, Copy, Debug, Default)]
struct Drift {
    /// Repetitions whose sequence of states differs from the reference's.
    mismatches: u64,
    /// Largest shift of a transition, ticks, among repetitions with the same sequence.
    max_shift: u64,
    /// Largest distance between the rolled contact points at the roll's end, m.
    max_drift_m: f64,
}

impl Drift {
    fn compare(&mut self, r: &Repetition, done: &Repetition) {
        let same_states = r.timeline.len() == done.timeline.len()
            && r.timeline
                .iter()
                .zip(&done.timeline)
                .all(|(a, b)| a.1 == b.1);
        if same_states {
            for (a, b) in r.timeline.iter().zip(&done.timeline) {
                self.max_shift = self.max_shift.max(a.0.abs_diff(b.0));
            }
        } else {
            self.mismatches += 1;
        }
        if let (Some(a), Some(b)) = (r.roll_end_point, done.roll_end_point) {
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            self.max_drift_m = self.max_drift_m.max(d);
        }
    }
}

/// Run the soak for `ticks` controller ticks.
pub fn soak(ticks: u64) -> Result<SoakReport, FaultsError> {
    let touch = TouchScript::default();
    let script = touch.script();
    let start = script.sample(0.0);
    let period_s = script.duration_s() + 0.5;
    let script = script.then(
        Phase::Approach,
        0.5,
        Waypoint {
            position_m: start.position_m,
            wrist_rad: start.wrist_rad,
        },
    );
    let config = scene_config(&touch);
    let limit = config.contact.max_force_n as f64;
    let mut lp = ClosedLoop::new(config, PlantParams::OMEGA_LIKE, script).map_err(|source| {
        FaultsError::Setup {
            scenario: "soak",
            source,
        }
    })?;
    let per_rep = (period_s / lp.dt_s).round() as u64;
    let roll_end = (1.8 / lp.dt_s).round() as u64;

    let mut reference: Option<Repetition> = None;
    let mut rep = Repetition::default();
    let mut prev_state = None;
    let (mut max_r, mut max_p, mut nan, mut latched) = (0.0f64, 0.0f64, 0u64, 0u64);
    let mut drift = Drift::default();
    let mut reps = 0u64;
    let mut no_act = |_: u64, _: &mut _, _: &mut _| {};
    let mut no_inject = |_: u64, _: &mut _| {};
    let t0 = Instant::now();
    for k in 0..ticks {
        let within = k % per_rep;
        if within == 0 && k > 0 {
            // Close the repetition and compare it with the reference.
            reps += 1;
            let done = std::mem::take(&mut rep);
            match &reference {
                None if reps >= 2 => reference = Some(done),
                None => {}
                Some(r) => drift.compare(r, &done),
            }
            lp.plant.restart_script();
            prev_state = None;
        }
        let r = lp.tick(&mut no_act, &mut no_inject);
        max_r = max_r.max(r.rendered_n);
        max_p = max_p.max(r.plant_n);
        nan += r.nan as u64;
        latched += !r.out.latched.is_empty() as u64;
        if prev_state != Some(r.out.control.state) {
            rep.timeline.push((within, r.out.control.state));
            prev_state = Some(r.out.control.state);
        }
        if within == roll_end {
            let p = crate::experiments::creep::anchor_point(&lp.pipe);
            rep.roll_end_point = Some([p.x as f64, p.y as f64, p.z as f64]);
        }
    }
    let wall_s = t0.elapsed().as_secs_f64();
    Ok(SoakReport {
        ticks,
        repetitions: reps,
        ticks_per_repetition: per_rep,
        wall_s,
        ticks_per_s: ticks as f64 / wall_s,
        max_rendered_force_n: max_r,
        max_plant_force_n: max_p,
        force_limit_n: limit,
        nan_outputs: nan,
        latched_ticks: latched,
        timeline_mismatches: drift.mismatches,
        max_transition_shift_ticks: drift.max_shift,
        max_contact_point_drift_m: drift.max_drift_m,
        reference_roll_end_point_m: reference.as_ref().and_then(|r| r.roll_end_point),
        reference_timeline: reference
            .map(|r| r.timeline.iter().map(|(k, s)| (*k, s.name())).collect())
            .unwrap_or_default(),
    })
}

/// `host-sim soak`.
pub fn main(args: &Args) -> Result<(), FaultsError> {
    let r = soak(args.ticks)?;
    if args.json {
        return super::emit_json(&r);
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "soak: {} ticks ({} repetitions of {} ticks) in {:.1} s = {:.0} ticks/s",
        r.ticks, r.repetitions, r.ticks_per_repetition, r.wall_s, r.ticks_per_s
    );
    let _ = writeln!(
        text,

        "max force: rendered {:.3} N, motors {:.3} N (limit {} N); NaN outputs {}; faulted ticks {}",
        r.max_rendered_force_n, r.max_plant_force_n, r.force_limit_n, r.nan_outputs, r.latched_ticks
    );
    let _ = writeln!(
        text,

        "drift vs repetition 2: {} timeline mismatches, max transition shift {} ticks, max end-of-roll contact point drift {:.3e} m",
        r.timeline_mismatches, r.max_transition_shift_ticks, r.max_contact_point_drift_m
    );
    let _ = writeln!(text, "reference timeline: {:?}", r.reference_timeline);
    super::emit(&text);
    Ok(())
}

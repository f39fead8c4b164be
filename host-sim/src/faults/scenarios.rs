//! The fault campaign's scenarios: each is a closed-loop run of the plant and the controller
//! with one fault or disturbance injected, and a judge that says whether the safe state (or, for
//! disturbances that are not faults, bounded and sane behaviour) was reached in time.
//!
//! Common scene: the default touch script (approach 0.5 s, press 0.3 s, roll 1 s, twist 1 s,
//! slide 1 s, lift-off 0.5 s) on the plane z = −0.175 m, the default controller limits, 10 kHz,
//! the `Fast` math backend. Faults are injected at t = 1.2 s (tick 12 000), in the middle of the
//! roll, with the fingertip pressed on the surface.
//!
//! "In time", per scenario:
//! - a latching fault (glitch, driver fault, overrun streak) must be flagged on the tick its
//!   condition first holds (the documented thresholds: one count-jump over `max_counts_per_tick`,
//!   the fault input itself, `overrun_streak` overruns in a row), and that same tick's output must
//!   be zero duties with the drive disabled, to the end of the run;
//! - a stuck encoder must latch within `stuck_ticks` + 1 ticks of the first tick its motor is
//!   driven at `stuck_duty` or more while its count is frozen;
//! - rejected parameters must be flagged on the next tick, with the old ones kept;
//! - in every scenario the rendered force stays within `max_force_n`, the force the motors
//!   actually exert (from the plant's currents) within `max_force_n` × [`PLANT_FORCE_MARGIN`],
//!   and no output is NaN.

use super::closed_loop::{scene_config, ClosedLoop, Ctrl, Trace};
use crate::plant::{HandScript, Phase, Plant, PlantParams, TouchScript, Waypoint};
use serde::Serialize;
use softfinger_core::contact_state::ContactState;
use softfinger_core::controller::{ControllerConfig, Limits, TickInput, LATCHING};
use softfinger_core::params::ContactParams;
use softfinger_core::surface::Plane;
use softfinger_core::Flags;

/// Control rate of the campaign, Hz (the default configuration's).
pub const RATE_HZ: f64 = 10_000.0;
/// Tick of the injection: t = 1.2 s, mid-roll.
pub const K_INJECT: u64 = 12_000;
/// The motors' force may exceed the rendered limit by this factor: the duty is computed from the
/// counts of tick k and acts during tick k+1 through the winding's L/R = 0.11 ms lag and a
/// filtered back-EMF estimate, so the current follows the command with a transient error.
pub const PLANT_FORCE_MARGIN: f64 = 1.1;

/// One scenario's result.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    pub name: &'static str,
    /// What was done to the loop.
    pub injection: &'static str,
    /// What "survived" means for this scenario.
    pub criterion: &'static str,
    pub survived: bool,
    /// Why it failed (empty when survived), or notes.
    pub detail: String,
    pub ticks: u64,
    pub inject_tick: Option<u64>,
    /// First tick the fault's flag was raised.
    pub detect_tick: Option<u64>,
    /// First tick of zero torque held to the end.
    pub safe_tick: Option<u64>,
    pub max_rendered_force_n: f64,
    pub max_plant_force_n: f64,
    pub nan_outputs: usize,
    /// Contact states visited (in order of first visit).
    pub states: Vec<&'static str>,
}

type Act = Box<dyn FnMut(u64, &mut Ctrl, &mut Plant)>;
type Inject = Box<dyn FnMut(u64, &mut TickInput)>;

fn no_act() -> Act {
    Box::new(|_, _, _| {})
}

fn no_inject() -> Inject {
    Box::new(|_, _| {})
}

/// The scene's touch script with its roll and twist durations as parameters.
fn touch_script(t: &TouchScript, roll_s: f64, twist_s: f64) -> HandScript {
    t.script_with_durations(roll_s, twist_s)
}

/// Approach, press, roll until the injection time, then the hand jerks up 30 mm in 5 ms.
fn break_script(t: &TouchScript) -> HandScript {
    let touch_z = t.surface_z_m + t.fingertip_radius_m;
    let pressed = touch_z - t.press_depth_m;
    let w = |x: f64, z: f64, wy: f64| Waypoint {
        position_m: [x, 0.0, z],
        wrist_rad: [0.0, wy, 0.0],
    };
    let roll_s = K_INJECT as f64 / RATE_HZ - 0.8;
    let x1 = t.fingertip_radius_m * 0.1;
    HandScript::new(w(0.0, touch_z + t.clearance_m, 0.0))
        .then(Phase::Approach, 0.5, w(0.0, touch_z, 0.0))
        .then(Phase::Press, 0.3, w(0.0, pressed, 0.0))
        .then(Phase::Roll, roll_s, w(x1, pressed, 0.1))
        .then(Phase::LiftOff, 0.005, w(x1, touch_z + 0.03, 0.1))
}

/// A small deterministic generator (xorshift32) for the sensor noise.
#[derive(Clone, Copy, Debug)]
struct XorShift(u32);

impl XorShift {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }
    /// Uniform integer in [-k, k].
    fn symmetric(&mut self, k: i32) -> i32 {
        (self.next() % (2 * k as u32 + 1)) as i32 - k
    }
}

struct Setup {
    name: &'static str,
    injection: &'static str,
    criterion: &'static str,
    injected: bool,
    config: ControllerConfig<Plane>,
    plant: PlantParams,
    script: HandScript,
    ticks: u64,
    act: Act,
    inject: Inject,
}

fn run(s: Setup) -> Result<(Trace, ClosedLoop), String> {
    let mut lp = ClosedLoop::new(s.config, s.plant, s.script)?;
    let (mut act, mut inject) = (s.act, s.inject);
    let mut trace = Trace::default();
    trace.records.reserve(s.ticks as usize);
    for _ in 0..s.ticks {
        let r = lp.tick(&mut *act, &mut *inject);
        trace.records.push(r);
    }
    Ok((trace, lp))
}

fn state_names(trace: &Trace) -> Vec<&'static str> {
    let mut v: Vec<&'static str> = Vec::new();
    for s in trace.states() {
        if !v.contains(&s.name()) {
            v.push(s.name());
        }
    }
    v
}

/// The checks every scenario shares: bounded forces and no NaN. Returns failure reasons.
fn common_failures(trace: &Trace, limit: f64) -> Vec<String> {
    let mut f = Vec::new();
    // The rescale to max_force_n rounds in f32: a few ulps above is the limit itself.
    if trace.max_rendered_n() > limit * (1.0 + 1e-6) {
        f.push(format!(
            "rendered {:.3} N > {limit} N",
            trace.max_rendered_n()
        ));
    }
    if trace.max_plant_n() > limit * PLANT_FORCE_MARGIN {
        f.push(format!(
            "motors exert {:.3} N > {:.1} N",
            trace.max_plant_n(),
            limit * PLANT_FORCE_MARGIN
        ));
    }
    if trace.nan_outputs() > 0 {
        f.push(format!("{} NaN outputs", trace.nan_outputs()));
    }
    f
}

/// A latching fault whose condition first holds at `expect_detect`: flagged then, safe then.
fn latch_failures(trace: &Trace, flag: Flags, expect_detect: u64) -> Vec<String> {
    let mut f = Vec::new();
    let before = trace
        .records
        .iter()
        .find(|r| r.k < expect_detect && r.out.flags.intersects(LATCHING));
    if let Some(r) = before {
        f.push(format!("latched {:?} early at tick {}", r.out.flags, r.k));
    }
    match trace.first_flag(flag, 0) {
        Some(k) if k == expect_detect => {}
        other => f.push(format!("{flag:?} at {other:?}, expected {expect_detect}")),
    }
    match trace.safe_from() {
        Some(k) if k <= expect_detect => {}
        other => f.push(format!("safe from {other:?}, expected {expect_detect}")),
    }
    f
}

fn no_latch(trace: &Trace) -> Vec<String> {
    match trace.records.iter().find(|r| !r.out.enable) {
        Some(r) => vec![format!("spurious fault {:?} at tick {}", r.out.flags, r.k)],
        None => Vec::new(),
    }
}

struct Judged {
    survived: bool,
    detail: String,
    inject_tick: Option<u64>,
    detect_tick: Option<u64>,
}

fn judged(fails: Vec<String>, inject: Option<u64>, detect: Option<u64>, note: String) -> Judged {
    Judged {
        survived: fails.is_empty(),
        detail: if fails.is_empty() {
            note
        } else {
            fails.join("; ")
        },
        inject_tick: inject,
        detect_tick: detect,
    }
}

fn stuck_judge(t: &Trace, lim: &Limits) -> Judged {
    let driven = t
        .records
        .iter()
        .find(|r| r.k > K_INJECT && r.out.duties[0].abs() >= lim.stuck_duty)
        .map(|r| r.k);
    let detect = t.first_flag(Flags::ENCODER_STUCK, 0);
    let max_duty0 = t
        .records
        .iter()
        .filter(|r| r.k >= K_INJECT)
        .map(|r| r.out.duties[0].abs())
        .fold(0.0f32, f32::max);
    let mut f = Vec::new();
    match (driven, detect) {
        (Some(d), Some(k)) if k <= d + lim.per_tick(10_000.0).stuck_ticks as u64 + 1 => {
            if t.safe_from().is_none_or(|s| s > k) {
                f.push(format!("not safe from detection {k}"));
            }
        }
        (None, _) => f.push(format!(
            "not detected: the frozen motor's |duty| peaked at {max_duty0:.3}, below stuck_duty {}",
            lim.stuck_duty
        )),
        (Some(d), k) => f.push(format!("driven from {d}, detected at {k:?}")),
    }
    judged(
        f,
        Some(K_INJECT),
        detect,
        format!("max |duty0| while frozen {max_duty0:.3}"),
    )
}

/// Run every scenario. `Err` only if a scenario could not be set up.
pub fn campaign() -> Result<Vec<(Outcome, bool)>, String> {
    let touch = TouchScript::default();
    let base = scene_config(&touch);
    let limit = base.contact.max_force_n as f64;
    let plant = PlantParams::OMEGA_LIKE;
    let nominal_script = touch.script();
    let full = ((nominal_script.duration_s() + 0.2) * RATE_HZ) as u64;
    let short = K_INJECT + 5_000;
    let mut out = Vec::new();

    let mut push =
        |s: Setup, judge: &dyn Fn(&Trace, &ClosedLoop) -> Judged| -> Result<(), String> {
            let (name, injection, criterion, injected, ticks) =
                (s.name, s.injection, s.criterion, s.injected, s.ticks);
            let (trace, lp) = run(s)?;
            let mut j = judge(&trace, &lp);
            let common = common_failures(&trace, limit);
            if !common.is_empty() {
                j.detail = if j.survived {
                    common.join("; ")
                } else {
                    format!("{}; {}", j.detail, common.join("; "))
                };
                j.survived = false;
            }
            out.push((
                Outcome {
                    name,
                    injection,
                    criterion,
                    survived: j.survived,
                    detail: j.detail,
                    ticks,
                    inject_tick: j.inject_tick,
                    detect_tick: j.detect_tick,
                    safe_tick: trace.safe_from(),
                    max_rendered_force_n: trace.max_rendered_n(),
                    max_plant_force_n: trace.max_plant_n(),
                    nan_outputs: trace.nan_outputs(),
                    states: state_names(&trace),
                },
                injected,
            ));
            Ok(())
        };

    // 0. Nominal: the reference run.
    push(
        Setup {
            name: "nominal",
            injection: "none (reference run of the touch script)",
            criterion: "no fault latched; rolls, slides and breaks contact at lift-off",
            injected: false,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: full,
            act: no_act(),
            inject: no_inject(),
        },
        &|t, _| {
            let mut f = no_latch(t);
            let end = t.records.last().map(|r| r.out.state);
            if end != Some(ContactState::Broken) {
                f.push(format!("ends in {end:?}"));
            }
            if !t.states().any(|s| s == ContactState::Rolling) {
                f.push("never rolled".into());
            }
            judged(f, None, None, String::new())
        },
    )?;

    // 1. Encoder glitch: motor 1's count jumps by 5000 (and stays offset).
    push(
        Setup {
            name: "encoder_glitch",
            injection: "motor-1 count jumps +5000 at 1.2 s and stays offset",
            criterion: "ENCODER_GLITCH on the jump's tick; zero torque from that tick's output",
            injected: true,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: short,
            act: no_act(),
            inject: Box::new(|k, i| {
                if k >= K_INJECT {
                    i.counts[1] = i.counts[1].wrapping_add(5000);
                }
            }),
        },
        &|t, _| {
            let f = latch_failures(t, Flags::ENCODER_GLITCH, K_INJECT);
            judged(
                f,
                Some(K_INJECT),
                t.first_flag(Flags::ENCODER_GLITCH, 0),
                String::new(),
            )
        },
    )?;

    // 2. Encoder stuck under drive: pressing hard, motor 0's count freezes.
    let hard = TouchScript {
        press_depth_m: 0.05,
        ..touch
    };
    {
        let (name, config) = ("encoder_stuck", base);
        let lim = config.limits;
        push(
            Setup {
                name,
                injection: "pressing hard (hand reference 50 mm deep); motor-0 count frozen from 1.2 s",
                criterion: "ENCODER_STUCK within stuck_ticks+1 of the first tick the frozen motor is driven at >= stuck_duty",
                injected: true,
                config,
                plant,
                script: hard.script(),
                ticks: K_INJECT + 2 * lim.per_tick(10_000.0).stuck_ticks as u64 + 3_000,
                act: no_act(),
                inject: {
                    let mut frozen = None;
                    Box::new(move |k, i| {
                        if k >= K_INJECT {
                            let v = *frozen.get_or_insert(i.counts[0]);
                            i.counts[0] = v;
                        }
                    })
                },
            },
            &|t, _| stuck_judge(t, &lim),
        )?;
    }

    // 2b. The same hard press with no fault at all: a static press must not trip ENCODER_STUCK.
    push(
        Setup {
            name: "hard_press",
            injection: "none: pressing hard and still (hand reference 50 mm deep)",
            criterion: "no fault latched (a static press is not a stuck encoder)",
            injected: false,
            config: base,
            plant,
            script: hard.script(),
            ticks: K_INJECT + 2 * base.limits.per_tick(base.rate_hz).stuck_ticks as u64 + 3_000,
            act: no_act(),
            inject: no_inject(),
        },
        &|t, _| {
            judged(
                no_latch(t),
                None,
                t.first_flag(Flags::ENCODER_STUCK, 0),
                String::new(),
            )
        },
    )?;

    // 3. Driver fault mid-contact, asserted for 1 ms then gone.
    push(
        Setup {
            name: "driver_fault",
            injection: "driver fault input asserted 1.2 s .. 1.201 s, mid-roll",
            criterion: "DRIVER_FAULT on the first asserted tick; zero torque from it, latched after the input clears",
            injected: true,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: short,
            act: no_act(),
            inject: Box::new(|k, i| {
                i.driver_fault = (K_INJECT..K_INJECT + 10).contains(&k);
            }),
        },
        &|t, _| {
            let f = latch_failures(t, Flags::DRIVER_FAULT, K_INJECT);
            judged(f, Some(K_INJECT), t.first_flag(Flags::DRIVER_FAULT, 0), String::new())
        },
    )?;

    // 4. Overrun streak: pairs of overruns (tolerated), then a streak.
    let streak = base.limits.per_tick(base.rate_hz).overrun_streak as u64;
    push(
        Setup {
            name: "overrun_streak",
            injection: "overrun pairs every 10 ms from 1.1 s (tolerated), then overruns from 1.2 s on",
            criterion: "no latch on pairs; OVERRUN on the overrun_streak-th overrun in a row, zero torque from it",
            injected: true,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: short,
            act: no_act(),
            inject: Box::new(move |k, i| {
                let pair = (K_INJECT - 1000..K_INJECT).contains(&k) && k % 100 < streak - 1;
                i.overrun = pair || k >= K_INJECT;
            }),
        },
        &|t, _| {
            let expect = K_INJECT + streak - 1;
            let f = latch_failures(t, Flags::OVERRUN, expect);
            judged(f, Some(K_INJECT), t.first_flag(Flags::OVERRUN, 0), String::new())
        },
    )?;

    // 5. Invalid parameter changes mid-contact.
    push(
        Setup {
            name: "invalid_params",
            injection: "set_contact_params with NaN stiffness, mu_k > mu_s, 1e30 N/m and a negative force limit, mid-roll",
            criterion: "each rejected, PARAM_REJECTED on the next tick, old parameters kept, no fault, contact continues",
            injected: true,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: short,
            inject: no_inject(),
            act: Box::new(|k, c, _| {
                let d = c.config().contact;
                let bad = match k.checked_sub(K_INJECT) {
                    Some(0) => Some(ContactParams { normal_stiffness: f32::NAN, ..d }),
                    Some(10) => Some(ContactParams { mu_k: d.mu_s * 2.0, ..d }),
                    Some(20) => Some(ContactParams { normal_stiffness: 1e30, ..d }),
                    Some(30) => Some(ContactParams { max_force_n: -1.0, ..d }),
                    _ => None,
                };
                if let Some(p) = bad {
                    // Applied before this tick: the flag shows on this tick's output.
                    let _ = c.set_contact_params(p);
                }
            }),
        },
        &|t, lp| {
            let mut f = no_latch(t);
            for off in [0u64, 10, 20, 30] {
                let k = K_INJECT + off;
                let r = &t.records[k as usize];
                if !r.out.flags.contains(Flags::PARAM_REJECTED) {
                    f.push(format!("no PARAM_REJECTED at {k}"));
                }
                let next = &t.records[k as usize + 1];
                if next.out.flags.contains(Flags::PARAM_REJECTED) {
                    f.push(format!("PARAM_REJECTED repeated at {}", k + 1));
                }
            }
            if lp.ctrl.config().contact != scene_config(&TouchScript::default()).contact {
                f.push("parameters changed".into());
            }
            let in_contact = t.records[K_INJECT as usize..K_INJECT as usize + 100]
                .iter()
                .all(|r| r.out.state != ContactState::Broken);
            if !in_contact {
                f.push("contact lost".into());
            }
            judged(f, Some(K_INJECT), t.first_flag(Flags::PARAM_REJECTED, 0), String::new())
        },
    )?;

    // 6. Letting go of the handle while pressing on a stiff wall.
    let stiff = ControllerConfig {
        contact: ContactParams {
            normal_stiffness: 20_000.0,
            ..base.contact
        },
        ..base
    };
    let release_k = K_INJECT;
    push(
        Setup {
            name: "let_go_stiff_wall",
            injection: "20 N/mm wall; the hand lets go of the handle at 1.2 s, mid-roll",
            criterion: "no fault, forces bounded, no NaN; the handle comes to rest (speed < 5 mm/s over the last 0.1 s)",
            injected: true,
            config: stiff,
            plant,
            script: nominal_script.clone(),
            ticks: K_INJECT + 10_000,
            inject: no_inject(),
            act: Box::new(move |k, _, p| {
                if k == release_k {
                    p.release_hand();
                }
            }),
        },
        &|t, lp| {
            let mut f = no_latch(t);
            let v = lp.plant.effector_velocity_m_s();
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if speed > 0.005 {
                f.push(format!("still moving at {speed:.4} m/s"));
            }
            let end = t.records.last().map(|r| r.out.state.name()).unwrap_or("");
            judged(
                f,
                Some(release_k),
                None,
                format!("final speed {speed:.5} m/s, final state {end}"),
            )
        },
    )?;

    // 7. Sudden contact break: the hand jerks the handle 30 mm up in 5 ms.
    let gap_eps = base.contact.gap_eps_m;
    push(
        Setup {
            name: "contact_break",
            injection: "mid-roll the hand jerks up 30 mm in 5 ms",
            criterion: "contact state broken and zero force on the first tick the measured gap exceeds 2 gap_eps",
            injected: true,
            config: base,
            plant,
            script: break_script(&touch),
            ticks: K_INJECT + 3_000,
            act: no_act(),
            inject: no_inject(),
        },
        &move |t, _| {
            let mut f = no_latch(t);
            let r_tip = TouchScript::default().fingertip_radius_m;
            let surface = TouchScript::default().surface_z_m;
            let apart = t.records.iter().find(|r| {
                r.k > K_INJECT
                    && (r.out.probe_m.z as f64 - surface - r_tip) > 2.0 * gap_eps as f64
            });
            let detect = match apart {
                Some(r) if r.out.state == ContactState::Broken && r.rendered_n == 0.0 => Some(r.k),
                Some(r) => {
                    f.push(format!("apart at {} but {:?}, {:.3} N", r.k, r.out.state, r.rendered_n));
                    None
                }
                None => {
                    f.push("never apart".into());
                    None
                }
            };
            judged(f, Some(K_INJECT), detect, String::new())
        },
    )?;

    // 8. Sensor noise: ±3 counts on every encoder, every tick, over the whole script.
    push(
        Setup {
            name: "sensor_noise",
            injection: "uniform ±3 counts on all six encoders every tick",
            criterion: "no spurious fault, forces bounded, contact made and broken",
            injected: true,
            config: base,
            plant,
            script: nominal_script.clone(),
            ticks: full,
            act: no_act(),
            inject: {
                let mut rng = XorShift(0x2545_f491);
                Box::new(move |_, i| {
                    for c in i.counts.iter_mut() {
                        *c = c.wrapping_add(rng.symmetric(3));
                    }
                })
            },
        },
        &|t, _| {
            let mut f = no_latch(t);
            if t.records.last().map(|r| r.out.state) != Some(ContactState::Broken) {
                f.push("contact not broken at the end".into());
            }
            judged(f, None, None, String::new())
        },
    )?;

    // 9. Overspeed twist: the twist phase 10x faster (0.5 rad in 0.1 s).
    push(
        Setup {
            name: "overspeed_twist",
            injection: "twist phase 10x faster: 0.5 rad in 0.1 s",
            criterion: "no fault, forces bounded, no NaN",
            injected: true,
            config: base,
            plant,
            script: touch_script(&touch, 1.0, 0.1),
            ticks: ((touch_script(&touch, 1.0, 0.1).duration_s() + 0.2) * RATE_HZ) as u64,
            act: no_act(),
            inject: no_inject(),
        },
        &|t, _| {
            let twist_slid = t.states().any(|s| s == ContactState::Sliding);
            judged(no_latch(t), None, None, format!("slid: {twist_slid}"))
        },
    )?;

    // 10. A jump just under the glitch threshold: not a detectable fault by design.
    let sub = i32::from(base.limits.per_tick(base.rate_hz).max_counts_per_tick) - 100;
    push(
        Setup {
            name: "sub_threshold_jump",
            injection: "motor-1 count jumps by max_counts_per_tick - 100 at 1.2 s and stays offset",
            criterion: "not a fault by definition: forces bounded, no NaN",
            injected: true,
            config: base,
            plant,
            script: nominal_script,
            ticks: short,
            act: no_act(),
            inject: Box::new(move |k, i| {
                if k >= K_INJECT {
                    i.counts[1] = i.counts[1].wrapping_add(sub);
                }
            }),
        },
        &|t, _| {
            let latched = t
                .records
                .iter()
                .find(|r| r.out.flags.intersects(LATCHING))
                .map(|r| r.k);
            judged(
                Vec::new(),
                Some(K_INJECT),
                latched,
                format!("latched: {latched:?}"),
            )
        },
    )?;

    Ok(out)
}

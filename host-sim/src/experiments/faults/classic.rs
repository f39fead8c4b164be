//! The campaign's original scenarios (faults and disturbances while armed and touching), now in
//! the closed loop of the pipeline: injections edit the raw 16-bit counts, the nFAULT line and
//! the tick timing the pipeline reads; operator actions go through `Pipeline::command`.
//!
//! "In time", per scenario:
//! - a latching fault (glitch, driver fault, overrun streak) must be flagged on the tick its
//!   condition first holds (the documented thresholds: one count step over
//!   `max_counts_per_tick`, the nFAULT line itself, `overrun_streak` overruns in a row), and that
//!   same tick's bridges must be disabled with compare 0, to the end of the run;
//! - a stuck encoder must latch within `stuck_ticks` + 1 ticks of the first tick its motor is
//!   driven at `stuck_duty` or more while its count is frozen;
//! - rejected parameters must be flagged on the same tick, with the old ones kept.

use super::closed_loop::{ClosedLoop, Trace};
use super::scenarios::{
    judged, latch_failures, no_inject, no_latch, Ctx, Judged, Scenario, Setup, K_INJECT, RATE_HZ,
};
use crate::sim::plant::{HandScript, Phase, TouchScript, Waypoint};
use crate::sim::rng::SplitMix64;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::control::output_guard::LATCHING;
use softfinger_core::control::pipeline::Command;
use softfinger_core::Flags;

/// The table rows (in campaign order).
pub static SCENARIOS: [Scenario; 12] = [
    Scenario {
        name: "nominal",
        injection: "none (reference run of the touch script)",
        criterion: "no fault latched; rolls, slides and breaks contact at lift-off",
        injected: false,
        setup: |c| c.plain(c.touch.script(), c.full()),
        judge: nominal_judge,
    },
    Scenario {
        name: "encoder_glitch",
        injection: "motor-1 counter jumps +5000 at 1.2 s and stays offset",
        criterion: "ENCODER_GLITCH on the jump's tick; zero torque from that tick's output",
        injected: true,
        setup: glitch_setup,
        judge: |t, _, _| latch_judge(t, Flags::ENCODER_GLITCH, K_INJECT),
    },
    Scenario {
        name: "encoder_stuck",
        injection: "pressing hard (hand reference 50 mm deep); motor-0 counter frozen from 1.2 s",
        criterion: "ENCODER_STUCK within stuck_ticks+1 of the first tick the frozen motor is driven at >= stuck_duty",
        injected: true,
        setup: stuck_setup,
        judge: stuck_judge,
    },
    Scenario {
        name: "hard_press",
        injection: "none: pressing hard and still (hand reference 50 mm deep)",
        criterion: "no fault latched (a static press is not a stuck encoder)",
        injected: false,
        setup: |c| c.plain(hard(c).script(), stuck_ticks(c)),
        judge: |t, _, _| judged(no_latch(t), None, t.first_flag(Flags::ENCODER_STUCK, 0), String::new()),
    },
    Scenario {
        name: "driver_fault",
        injection: "nFAULT asserted 1.2 s .. 1.201 s, mid-roll",
        criterion: "DRIVER_FAULT on the first asserted tick; zero torque from it, latched after the line clears",
        injected: true,
        setup: |c| Setup {
            inject: Box::new(|k, r| r.driver_fault = (K_INJECT..K_INJECT + 10).contains(&k)),
            ..c.plain(c.touch.script(), K_INJECT + 5_000)
        },
        judge: |t, _, _| latch_judge(t, Flags::DRIVER_FAULT, K_INJECT),
    },
    Scenario {
        name: "overrun_streak",
        injection: "overrun runs one short of the streak every 10 ms from 1.1 s (tolerated), then overruns from 1.2 s on",
        criterion: "no latch on the short runs; OVERRUN on the overrun_streak-th overrun in a row, zero torque from it",
        injected: true,
        setup: overrun_setup,
        judge: |t, _, c| latch_judge(t, Flags::OVERRUN, K_INJECT + u64::from(c.per_tick.overrun_streak) - 1),
    },
    Scenario {
        name: "invalid_params",
        injection: "SetContactParams with NaN stiffness, mu_k > mu_s, 1e30 N/m and a negative force limit, mid-roll",
        criterion: "each refused, PARAM_REJECTED on that tick only, old parameters kept, no fault, contact continues",
        injected: true,
        setup: params_setup,
        judge: params_judge,
    },
    Scenario {
        name: "let_go_stiff_wall",
        injection: "20 N/mm wall; the hand lets go of the handle at 1.2 s, mid-roll",
        criterion: "no fault, forces bounded, no NaN; the handle comes to rest (speed < 5 mm/s over the last 0.1 s)",
        injected: true,
        setup: let_go_setup,
        judge: let_go_judge,
    },
    Scenario {
        name: "contact_break",
        injection: "mid-roll the hand jerks up 30 mm in 5 ms",
        criterion: "contact state broken and zero force on the first tick the measured gap exceeds 2 gap_eps",
        injected: true,
        setup: |c| c.plain(break_script(&c.touch), K_INJECT + 3_000),
        judge: break_judge,
    },
    Scenario {
        name: "sensor_noise",
        injection: "uniform ±3 counts on all six counters every tick",
        criterion: "no spurious fault, forces bounded, contact made and broken",
        injected: true,
        setup: noise_setup,
        judge: |t, _, _| {
            let mut f = no_latch(t);
            if t.records.last().map(|r| r.out.control.state) != Some(ContactState::Broken) {
                f.push("contact not broken at the end".into());
            }
            judged(f, None, None, String::new())
        },
    },
    Scenario {
        name: "overspeed_twist",
        injection: "twist phase 10x faster: 0.5 rad in 0.1 s",
        criterion: "no fault, forces bounded, no NaN",
        injected: true,
        setup: |c| {
            let s = c.touch.script_with_durations(1.0, 0.1);
            let n = ((s.duration_s() + 0.2) * RATE_HZ) as u64;
            c.plain(s, n)
        },
        judge: |t, _, _| {
            let slid = t.states().any(|s| s == ContactState::Sliding);
            judged(no_latch(t), None, None, format!("slid: {slid}"))
        },
    },
    Scenario {
    name: "sub_threshold_jump",
    injection: "motor-1 counter jumps by max_counts_per_tick - 100 at 1.2 s and stays offset",
    criterion: "not a fault by definition: forces bounded, no NaN",
    injected: true,
    setup: sub_threshold_setup,
    judge: |t, _, _| {
        let latched = t
            .records
            .iter()
            .find(|r| r.out.flags.intersects(LATCHING))
            .map(|r| r.k);
        judged(Vec::new(), Some(K_INJECT), latched, format!("latched: {latched:?}"))
    },
    },
];

fn latch_judge(t: &Trace, flag: Flags, expect: u64) -> Judged {
    judged(
        latch_failures(t, flag, expect),
        Some(K_INJECT),
        t.first_flag(flag, 0),
        String::new(),
    )
}

fn nominal_judge(t: &Trace, _: &ClosedLoop, _: &Ctx) -> Judged {
    let mut f = no_latch(t);
    let end = t.records.last().map(|r| r.out.control.state);
    if end != Some(ContactState::Broken) {
        f.push(format!("ends in {end:?}"));
    }
    if !t.states().any(|s| s == ContactState::Rolling) {
        f.push("never rolled".into());
    }
    judged(f, None, None, String::new())
}

fn glitch_setup(c: &Ctx) -> Setup {
    Setup {
        inject: Box::new(|k, r| {
            if k >= K_INJECT {
                r.counts[1] = r.counts[1].wrapping_add(5000);
            }
        }),
        ..c.plain(c.touch.script(), K_INJECT + 5_000)
    }
}

fn hard(c: &Ctx) -> TouchScript {
    TouchScript {
        press_depth_m: 0.05,
        ..c.touch
    }
}

fn stuck_ticks(c: &Ctx) -> u64 {
    K_INJECT + 2 * u64::from(c.per_tick.stuck_ticks) + 3_000
}

fn stuck_setup(c: &Ctx) -> Setup {
    let mut frozen = None;
    Setup {
        inject: Box::new(move |k, r| {
            if k >= K_INJECT {
                r.counts[0] = *frozen.get_or_insert(r.counts[0]);
            }
        }),
        ..c.plain(hard(c).script(), stuck_ticks(c))
    }
}

fn stuck_judge(t: &Trace, _: &ClosedLoop, c: &Ctx) -> Judged {
    let stuck_duty = c.base.device.limits.stuck_duty;
    let duty0 = |r: &&super::closed_loop::TickRecord| r.out.control.duties[0].abs();
    let driven = t
        .records
        .iter()
        .find(|r| r.k > K_INJECT && duty0(r) >= stuck_duty)
        .map(|r| r.k);
    let detect = t.first_flag(Flags::ENCODER_STUCK, 0);
    let max_duty0 = t
        .records
        .iter()
        .filter(|r| r.k >= K_INJECT)
        .map(|r| duty0(&r))
        .fold(0.0f32, f32::max);
    let mut f = Vec::new();
    match (driven, detect) {
        (Some(d), Some(k)) if k <= d + u64::from(c.per_tick.stuck_ticks) + 1 => {
            if t.safe_from().is_none_or(|s| s > k) {
                f.push(format!("not safe from detection {k}"));
            }
        }
        (None, _) => f.push(format!(
            "not detected: the frozen motor's |duty| peaked at {max_duty0:.3}, below stuck_duty {stuck_duty}"
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

fn overrun_setup(c: &Ctx) -> Setup {
    let streak = u64::from(c.per_tick.overrun_streak);
    let overrun_counts = c.base.timing.tick_period_counts();
    Setup {
        inject: Box::new(move |k, r| {
            let short_run = (K_INJECT - 1000..K_INJECT).contains(&k) && k % 100 < streak - 1;
            if short_run || k >= K_INJECT {
                r.prev_write_done_counts = overrun_counts;
            }
        }),
        ..c.plain(c.touch.script(), K_INJECT + 5_000)
    }
}

const PARAM_OFFSETS: [u64; 4] = [0, 10, 20, 30];

fn params_setup(c: &Ctx) -> Setup {
    Setup {
        act: Box::new(|k, p, _| {
            let d = p.controller().config().contact;
            let bad = match k.checked_sub(K_INJECT) {
                Some(0) => Some(ContactParams {
                    normal_stiffness: f32::NAN,
                    ..d
                }),
                Some(10) => Some(ContactParams {
                    mu_k: d.mu_s * 2.0,
                    ..d
                }),
                Some(20) => Some(ContactParams {
                    normal_stiffness: 1e30,
                    ..d
                }),
                Some(30) => Some(ContactParams {
                    max_force_n: -1.0,
                    ..d
                }),
                _ => None,
            };
            if let Some(bad) = bad {
                // Applied before this tick: the flag shows on this tick's output.
                let _ = p.command(Command::SetContactParams(bad));
            }
        }),
        inject: no_inject(),
        ..c.plain(c.touch.script(), K_INJECT + 5_000)
    }
}

fn params_judge(t: &Trace, lp: &ClosedLoop, c: &Ctx) -> Judged {
    let mut f = no_latch(t);
    for off in PARAM_OFFSETS {
        let k = (K_INJECT + off) as usize;
        if !t.records[k].out.flags.contains(Flags::PARAM_REJECTED) {
            f.push(format!("no PARAM_REJECTED at {k}"));
        }
        if t.records[k + 1].out.flags.contains(Flags::PARAM_REJECTED) {
            f.push(format!("PARAM_REJECTED repeated at {}", k + 1));
        }
    }
    if lp.pipe.controller().config().contact != c.base.contact {
        f.push("parameters changed".into());
    }
    let from = K_INJECT as usize;
    let in_contact = t.records[from..from + 100]
        .iter()
        .all(|r| r.out.control.state != ContactState::Broken);
    if !in_contact {
        f.push("contact lost".into());
    }
    judged(
        f,
        Some(K_INJECT),
        t.first_flag(Flags::PARAM_REJECTED, 0),
        String::new(),
    )
}

fn let_go_setup(c: &Ctx) -> Setup {
    let mut config = c.base;
    config.contact.normal_stiffness = 20_000.0;
    Setup {
        config,
        act: Box::new(|k, _, plant| {
            if k == K_INJECT {
                plant.release_hand();
            }
        }),
        ..c.plain(c.touch.script(), K_INJECT + 10_000)
    }
}

fn let_go_judge(t: &Trace, lp: &ClosedLoop, _: &Ctx) -> Judged {
    let mut f = no_latch(t);
    let v = lp.plant.effector_velocity_m_s();
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if speed > 0.005 {
        f.push(format!("still moving at {speed:.4} m/s"));
    }
    let end = t.records.last().map_or("", |r| r.out.control.state.name());
    judged(
        f,
        Some(K_INJECT),
        None,
        format!("final speed {speed:.5} m/s, final state {end}"),
    )
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

fn break_judge(t: &Trace, _: &ClosedLoop, c: &Ctx) -> Judged {
    let mut f = no_latch(t);
    let gap_eps = f64::from(c.base.contact.tolerances.gap_eps_m);
    let (r_tip, surface) = (c.touch.fingertip_radius_m, c.touch.surface_z_m);
    let apart = t.records.iter().find(|r| {
        r.k > K_INJECT && (f64::from(r.out.control.probe_m.z) - surface - r_tip) > 2.0 * gap_eps
    });
    let detect = match apart {
        Some(r) if r.out.control.state == ContactState::Broken && r.rendered_n == 0.0 => Some(r.k),
        Some(r) => {
            f.push(format!(
                "apart at {} but {:?}, {:.3} N",
                r.k, r.out.control.state, r.rendered_n
            ));
            None
        }
        None => {
            f.push("never apart".into());
            None
        }
    };
    judged(f, Some(K_INJECT), detect, String::new())
}

fn noise_setup(c: &Ctx) -> Setup {
    let mut rng = SplitMix64::new(0x2545_f491);
    Setup {
        inject: Box::new(move |_, r| {
            for x in r.counts.iter_mut() {
                *x = x.wrapping_add_signed(rng.symmetric(3) as i16);
            }
        }),
        ..c.plain(c.touch.script(), c.full())
    }
}

fn sub_threshold_setup(c: &Ctx) -> Setup {
    let jump = c.per_tick.max_counts_per_tick - 100;
    Setup {
        inject: Box::new(move |k, r| {
            if k >= K_INJECT {
                r.counts[1] = r.counts[1].wrapping_add(jump);
            }
        }),
        ..c.plain(c.touch.script(), K_INJECT + 5_000)
    }
}

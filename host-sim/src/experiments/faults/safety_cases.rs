//! The campaign's scenarios of the operator-safety rules (`softfinger_core::control::operator`,
//! `Pipeline::link_command` / `link_lost`, `Arm` refused inside the surface, the nFAULT latch),
//! in the closed loop of the pipeline from the armed start, the fingertip pressed mid-roll at
//! the injection (t = 1.2 s).

use super::closed_loop::{ClosedLoop, Pipe, Trace};
use super::scenarios::{
    judged, latch_failures, no_latch, Ctx, Judged, Scenario, Setup, Start, K_INJECT,
};
use softfinger_core::control::operator::{ButtonRules, ButtonTiming};
use softfinger_core::control::pipeline::liveness::{ThreadWatch, THREAD_STALE_S};
use softfinger_core::control::pipeline::{Command, Mode, LINK_FADE_S};
use softfinger_core::Flags;

/// The table rows (in campaign order).
pub static SCENARIOS: [Scenario; 6] = [
    Scenario {
        name: "button_press_while_armed",
        injection: "B1 pressed at 1.2 s and held 4 s (past the long and very long press times) while armed and pressing; the button rules sampled every tick",
        criterion: "Disarm on the debounced press (20 ms): zero torque from that tick to the end; no Home and no preset change while held; Disarmed at the end",
        injected: true,
        setup: button_setup,
        judge: button_judge,
    },
    Scenario {
        name: "link_lost_while_armed",
        injection: "a host armed the device over its link (link_command Arm at tick 0); the link is lost at 1.2 s (USB reset, suspend, DTR drop or writes not taken)",
        criterion: "COMM_TIMEOUT on the loss's tick; rendered force 0 within 20 ms (200 ticks) and to the end (latched); no guard fault",
        injected: true,
        setup: link_setup,
        judge: link_judge,
    },
    Scenario {
        name: "arm_inside_surface",
        injection: "Disarm at 1.2 s with the fingertip pressed into the surface, Arm 0.1 s later (button and link) while still inside",
        criterion: "both Arms refused (InsideSurface); no force from the Disarm to the end; Disarmed at the end",
        injected: true,
        setup: arm_inside_setup,
        judge: arm_inside_judge,
    },
    Scenario {
        name: "motor_supply_lost",
        injection: "the motor supply switched off at 1.2 s (the E-stop): the drivers' undervoltage lockout holds nFAULT asserted to the end; ClearFaults at 1.7 s with the supply still off",
        criterion: "DRIVER_FAULT on the first tick, zero torque from it to the end; after ClearFaults it latches again and the device never arms",
        injected: true,
        setup: supply_setup,
        judge: supply_judge,
    },
    Scenario {
        name: "homing_stall_midway",
        injection: "power-up; Home at 0.8 s while the operator holds the handle at the script's start (what the old instructions asked): the arms stall against the hand, short of their stops",
        criterion: "HOMING_FAILED: no zero taken (never Disarmed, not homed), zero torque from the failure to the end; homing torque within its limit",
        injected: true,
        setup: stall_midway_setup,
        judge: stall_midway_judge,
    },
    Scenario {
        name: "thread_mode_hang",
        injection: "the thread-mode heartbeat (every 1 ms) stops at 1.2 s (a hung task or executor) while armed and pressing; the tick keeps running; the IWDG (5 ms) resets the MCU when no longer fed",
        criterion: "THREAD_STALLED after 50 ms without a heartbeat, zero torque from that tick on (outputs off first), the IWDG reset 5 ms later (Unhomed, drivers asleep) and no force to the end",
        injected: true,
        setup: hang_setup,
        judge: hang_judge,
    },
];

/// Ticks the button is held: 4 s.
const HOLD_TICKS: u64 = 40_000;

fn button_setup(c: &Ctx) -> Setup {
    let rate = f64::from(c.base.timing.control_hz);
    let mut rules = ButtonRules::new(ButtonTiming::DEFAULT, (1.0 / rate) as f32);
    let mut s = c.plain(c.touch.script(), K_INJECT + HOLD_TICKS + 5_000);
    s.act = Box::new(move |k, p, _| {
        let pressed = (K_INJECT..K_INJECT + HOLD_TICKS).contains(&k);
        if let Some(cmd) = rules.sample(pressed, p.mode()) {
            // Anything but the one Disarm shows in the judge as a mode change.
            let _ = p.command(cmd);
        }
    });
    s
}

/// Debounce time in ticks at the campaign's rate.
fn debounce_ticks(c: &Ctx) -> u64 {
    (f64::from(ButtonTiming::DEFAULT.debounce_s) * f64::from(c.base.timing.control_hz)).round()
        as u64
}

fn button_judge(t: &Trace, _: &ClosedLoop, c: &Ctx) -> Judged {
    let mut f = no_latch(t);
    // The rules see the press on the tick's act, before the tick: the 20th pressed sample is
    // tick K_INJECT + 19, whose output is already disarmed.
    let expect = K_INJECT + debounce_ticks(c) - 1;
    let disarmed = t
        .records
        .iter()
        .find(|r| r.k >= K_INJECT && r.out.mode != Mode::Armed)
        .map(|r| r.k);
    if disarmed != Some(expect) {
        f.push(format!("left Armed at {disarmed:?}, expected {expect}"));
    }
    match t.safe_from() {
        Some(k) if k <= expect => {}
        other => f.push(format!("safe from {other:?}, expected {expect}")),
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k > expect && r.out.mode != Mode::Disarmed)
    {
        f.push(format!("{} at {} while held", r.out.mode.name(), r.k));
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k > expect && r.rendered_n != 0.0)
    {
        f.push(format!("force {:.3} N at {}", r.rendered_n, r.k));
    }
    judged(
        f,
        Some(K_INJECT),
        disarmed,
        format!(
            "disarmed {} ticks after the press (debounce {} ticks)",
            disarmed.map_or(0, |d| d - K_INJECT + 1),
            debounce_ticks(c)
        ),
    )
}

fn link_setup(c: &Ctx) -> Setup {
    let mut s = c.plain(c.touch.script(), c.full());
    s.act = Box::new(|k, p, _| {
        if k == 0 {
            // The host takes the arming over (Arm while armed keeps the force; the link holds it).
            let _ = p.link_command(Command::Arm);
        }
        if k == K_INJECT {
            p.link_lost();
        }
    });
    s
}

fn link_judge(t: &Trace, _: &ClosedLoop, c: &Ctx) -> Judged {
    let mut f = no_latch(t);
    let fade = (f64::from(LINK_FADE_S) * f64::from(c.base.timing.control_hz)).round() as u64;
    let detect = t.first_flag(Flags::COMM_TIMEOUT, 0);
    if detect != Some(K_INJECT) {
        f.push(format!("COMM_TIMEOUT at {detect:?}, expected {K_INJECT}"));
    }
    let pressing = t.records[K_INJECT as usize - 1].rendered_n;
    if pressing < 0.5 {
        f.push(format!(
            "only {pressing:.3} N before the loss: not pressing"
        ));
    }
    let zero_from = t
        .records
        .iter()
        .filter(|r| r.k >= K_INJECT)
        .rev()
        .take_while(|r| r.rendered_n == 0.0)
        .last()
        .map(|r| r.k);
    match zero_from {
        Some(k) if k < K_INJECT + fade => {}
        other => f.push(format!(
            "force zero from {other:?}, expected before {}",
            K_INJECT + fade
        )),
    }
    judged(
        f,
        Some(K_INJECT),
        detect,
        format!(
            "{pressing:.2} N before the loss, zero {} ticks after it (bound {fade})",
            zero_from.map_or(0, |z| z - K_INJECT + 1)
        ),
    )
}

const ARM_INSIDE_AT: u64 = K_INJECT + 1_000;

fn arm_inside_setup(c: &Ctx) -> Setup {
    let mut s = c.plain(c.touch.script(), K_INJECT + 5_000);
    s.act = Box::new(|k, p, _| {
        if k == K_INJECT {
            let _ = p.command(Command::Disarm);
        }
        if k == ARM_INSIDE_AT {
            // Refused (the judge sees the mode stay Disarmed; the error, InsideSurface, is
            // checked by the core's unit tests).
            let _ = p.command(Command::Arm);
            let _ = p.link_command(Command::Arm);
        }
    });
    s
}

fn arm_inside_judge(t: &Trace, _: &ClosedLoop, _: &Ctx) -> Judged {
    let mut f = no_latch(t);
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k >= K_INJECT && r.out.mode != Mode::Disarmed)
    {
        f.push(format!(
            "{} at {} (Arm not refused?)",
            r.out.mode.name(),
            r.k
        ));
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k >= K_INJECT && r.rendered_n != 0.0)
    {
        f.push(format!("force {:.3} N at {}", r.rendered_n, r.k));
    }
    let state = t.records[ARM_INSIDE_AT as usize].out.control.state;
    if state.name() == "broken" {
        f.push("not in contact at the Arm: the scenario does not exercise the rule".into());
    }
    judged(
        f,
        Some(ARM_INSIDE_AT),
        None,
        format!("Arm refused while {} on the surface", state.name()),
    )
}

const CLEAR_AT: u64 = K_INJECT + 5_000;

fn supply_setup(c: &Ctx) -> Setup {
    let mut s = c.plain(c.touch.script(), K_INJECT + 10_000);
    s.inject = Box::new(|k, r| r.driver_fault = k >= K_INJECT);
    s.act = Box::new(|k, p, _| {
        if k == CLEAR_AT {
            let _ = p.command(Command::ClearFaults);
        }
        if k > CLEAR_AT {
            let _ = p.command(Command::Arm);
        }
    });
    s
}

fn supply_judge(t: &Trace, _: &ClosedLoop, _: &Ctx) -> Judged {
    let mut f = latch_failures(t, Flags::DRIVER_FAULT, K_INJECT);
    let relatched = t
        .records
        .iter()
        .find(|r| r.k > CLEAR_AT && r.out.mode == Mode::Faulted)
        .map(|r| r.k);
    if relatched.is_none() {
        f.push("not latched again after ClearFaults".into());
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k >= K_INJECT && r.out.mode == Mode::Armed)
    {
        f.push(format!("armed at {} without motor supply", r.k));
    }
    judged(
        f,
        Some(K_INJECT),
        t.first_flag(Flags::DRIVER_FAULT, 0),
        format!(
            "latched again {} ticks after ClearFaults (the wake time from the nSLEEP edge)",
            relatched.map_or(0, |r| r - CLEAR_AT)
        ),
    )
}

const STALL_HOME_AT: u64 = 8_000;

fn stall_midway_setup(c: &Ctx) -> Setup {
    let mut s = c.plain(c.touch.script(), 100_000);
    s.start = Start::PowerUp;
    s.act = Box::new(|k, p, plant| {
        if k == STALL_HOME_AT {
            let _ = p.command(Command::Home);
        }
        // The hand holds the handle at the script's start from power-up on.
        plant.restart_script();
    });
    s
}

fn stall_midway_judge(t: &Trace, lp: &ClosedLoop, _: &Ctx) -> Judged {
    let mut f = Vec::new();
    let detect = t.first_flag(Flags::HOMING_FAILED, 0);
    let Some(d) = detect else {
        f.push("homing did not fail".into());
        return judged(f, Some(STALL_HOME_AT), None, String::new());
    };
    if let Some(r) = t.records.iter().find(|r| r.out.mode == Mode::Disarmed) {
        f.push(format!("homed (Disarmed) at {}: a wrong zero taken", r.k));
    }
    if lp.pipe.homed() {
        f.push("homed at the end".into());
    }
    match t.safe_from() {
        Some(k) if k <= d => {}
        other => f.push(format!("safe from {other:?}, expected {d}")),
    }
    if let Some(r) = t.records.iter().find(|r| r.rendered_n != 0.0) {
        f.push(format!("force {:.3} N at {}", r.rendered_n, r.k));
    }
    judged(
        f,
        Some(STALL_HOME_AT),
        detect,
        format!(
            "homing failed {:.2} s after Home",
            (d - STALL_HOME_AT) as f64 / super::scenarios::RATE_HZ
        ),
    )
}

/// The IWDG's timeout in ticks at 10 kHz (the firmware's `WATCHDOG_TIMEOUT_US`, 5 ms).
const IWDG_TICKS: u64 = 50;

fn hang_setup(c: &Ctx) -> Setup {
    let config = c.base;
    let mut watch = ThreadWatch::new(THREAD_STALE_S, config.timing.control_hz as f32);
    let mut last_feed = 0u64;
    let mut reset = false;
    let mut s = c.plain(c.touch.script(), K_INJECT + 5_000);
    s.act = Box::new(move |k, p, _| {
        if reset {
            return;
        }
        // The heartbeat task bumps its counter every 1 ms until it hangs.
        let beat = (k.min(K_INJECT) / 10) as u32 + 1;
        if watch.tick(beat) {
            last_feed = k;
        } else {
            // The tick stops the outputs first, then stops feeding the IWDG.
            p.thread_stalled();
        }
        if k - last_feed >= IWDG_TICKS {
            // The reset: the MCU starts again at power-up.
            if let Ok(fresh) = Pipe::new(config) {
                *p = fresh;
            }
            reset = true;
        }
    });
    s
}

fn hang_judge(t: &Trace, _: &ClosedLoop, c: &Ctx) -> Judged {
    let stale = (f64::from(THREAD_STALE_S) * f64::from(c.base.timing.control_hz)).round() as u64;
    let expect = K_INJECT + stale;
    let mut f = latch_failures(t, Flags::THREAD_STALLED, expect);
    let reset_at = t
        .records
        .iter()
        .find(|r| r.k > expect && r.out.mode == Mode::Unhomed)
        .map(|r| r.k);
    let want_reset = expect - 1 + IWDG_TICKS;
    if reset_at != Some(want_reset) {
        f.push(format!("reset at {reset_at:?}, expected {want_reset}"));
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k >= expect && r.rendered_n != 0.0)
    {
        f.push(format!("force {:.3} N at {}", r.rendered_n, r.k));
    }
    if let Some(r) = t
        .records
        .iter()
        .find(|r| r.k >= want_reset && (r.out.bridges.driver_awake || r.out.mode != Mode::Unhomed))
    {
        f.push(format!("after the reset: {} at {}", r.out.mode.name(), r.k));
    }
    judged(
        f,
        Some(K_INJECT),
        t.first_flag(Flags::THREAD_STALLED, 0),
        format!("outputs off {stale} ticks after the last heartbeat, IWDG reset {IWDG_TICKS} ticks later"),
    )
}

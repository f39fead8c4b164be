//! The operator's session before a scene, tick by tick, shared by the processor-in-the-loop host
//! and the in-process reference so both play it identically: the same steps as host-sim's
//! `closed_loop::prepare` (power-up with the handle let go, `Home`, the hand takes the handle when
//! homing is done, `Arm` after it settles; the script held at its start until armed), decided
//! from the mode the pipeline reported after the previous tick.
//!
//! A command returned for tick k is given after tick k (in effect from tick k+1): in-process by
//! `Pipeline::command` between the ticks, on the board through the link's reply to tick k's
//! sample, which the board queues for the end of tick k.

use crate::sim::closed_loop::{POWER_UP_S, SETTLE_S};
use crate::sim::plant::Plant;
use softfinger_app::scripted_app::ScriptedApp;
use softfinger_core::control::pipeline::{Command, Mode};

/// Longest homing the session waits for, s (as `closed_loop::prepare`).
pub const HOMING_WAIT_S: f64 = 10.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    PowerUp,
    Homing {
        since: u64,
    },
    Settle {
        arm_at: u64,
    },
    /// Armed after tick `armed_after`; the scene starts with the next tick.
    Scene {
        start: u64,
    },
}

/// The operator, tick by tick.
#[derive(Clone, Debug)]
pub struct Operator {
    /// With the scripted application session: ticks between its updates once armed.
    app_period: Option<u64>,
    power_up_ticks: u64,
    settle_ticks: u64,
    homing_limit: u64,
    phase: Phase,
}

impl Operator {
    /// The session at `rate_hz`.
    pub fn new(rate_hz: u32) -> Operator {
        let ticks = |s: f64| ((s * f64::from(rate_hz)).round() as u64).max(1);
        Operator {
            app_period: None,
            power_up_ticks: ticks(POWER_UP_S),
            settle_ticks: ticks(SETTLE_S),
            homing_limit: ticks(HOMING_WAIT_S),
            phase: Phase::PowerUp,
        }
    }

    /// The operator of the run `s` (with the scripted application session if it has one).
    pub fn for_settings(s: &super::session::Settings) -> Operator {
        let rate = s.rate_hz();
        Operator {
            app_period: s
                .app_session
                .then(|| u64::from(ScriptedApp::update_period_ticks(rate))),
            ..Operator::new(rate)
        }
    }

    /// The scripted application gives its next update after tick `k` (from the scene's first
    /// tick, every update period). Ask after [`Self::before_sample`] for the same `k`.
    pub fn app_step(&self, k: u64) -> bool {
        match (self.app_period, self.phase) {
            (Some(p), Phase::Scene { start }) => k >= start && (k - start).is_multiple_of(p),
            _ => false,
        }
    }

    /// The tick the scene starts at, once armed.
    pub fn scene_start(&self) -> Option<u64> {
        match self.phase {
            Phase::Scene { start } => Some(start),
            _ => None,
        }
    }

    /// Homing has taken longer than [`HOMING_WAIT_S`] by tick `k`.
    pub fn homing_timed_out(&self, k: u64) -> bool {
        matches!(self.phase, Phase::Homing { since } if k > since + self.homing_limit)
    }

    /// The operator's actions before tick `k` samples (`prev_mode`: the mode after tick k−1);
    /// returns the command to give after tick `k`.
    pub fn before_sample(&mut self, k: u64, prev_mode: Mode, plant: &mut Plant) -> Option<Command> {
        match self.phase {
            Phase::PowerUp => {
                if k == 0 {
                    plant.release_hand();
                }
                plant.restart_script();
                if k + 1 == self.power_up_ticks {
                    self.phase = Phase::Homing { since: k + 1 };
                    return Some(Command::Home);
                }
                None
            }
            Phase::Homing { since } => {
                if k > since && prev_mode == Mode::Disarmed {
                    plant.grasp_hand();
                    self.phase = Phase::Settle {
                        arm_at: k + self.settle_ticks - 1,
                    };
                    return self.before_sample(k, prev_mode, plant);
                }
                plant.restart_script();
                None
            }
            Phase::Settle { arm_at } => {
                plant.restart_script();
                if k == arm_at {
                    self.phase = Phase::Scene { start: k + 1 };
                    return Some(Command::Arm);
                }
                None
            }
            Phase::Scene { start } => {
                if k == start {
                    // `prepare` restarts the script once more after `Arm`.
                    plant.restart_script();
                }
                None
            }
        }
    }
}

/// The link's code of a command (0: none).
pub fn command_code(c: Option<Command>) -> u8 {
    match c {
        Some(Command::Home) => 1,
        Some(Command::Arm) => 2,
        Some(Command::Disarm) => 3,
        Some(Command::ClearFaults) => 4,
        _ => 0,
    }
}

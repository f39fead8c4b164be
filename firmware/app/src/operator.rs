//! The operator's button, by how long it is held:
//!
//! | press | held | command |
//! | --- | --- | --- |
//! | short | < 1 s | by mode: Disarmed → `Arm`; Armed or Homing → `Disarm`; Faulted → `ClearFaults`; Unhomed → none (logged: hold to home) |
//! | long | 1 s ..< 3 s | `Home` (hold the handle in the wrist calibration pose) |
//! | very long | ≥ 3 s | next surface stiffness preset (`SetContactParams`) |
//!
//! Commands reach the tick through a lock-free SPSC queue; the supervisor logs their outcomes.
//! A full queue drops the command (logged).

use defmt::{info, warn};
use embassy_time::{Duration, Timer};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::pipeline::{Command, Mode};

use crate::board::OperatorButton;
use crate::config;
use crate::link::session::CommandSink;
use crate::tick::published_mode;

/// Surface stiffness presets (N/m) cycled by a very long press: soft, the default, stiff.
const STIFFNESS_PRESETS: [f32; 3] = [500.0, 2000.0, 5000.0];

/// A debounced press, classified by how long it was held.
#[derive(Clone, Copy, PartialEq, Eq, defmt::Format)]
enum Press {
    Short,
    Long,
    VeryLong,
}

/// Wait for the next debounced press and classify it when it is released (or, for a very long
/// press, as soon as it has been held long enough).
async fn next_press(button: &mut impl OperatorButton) -> Press {
    loop {
        button.wait_released().await;
        button.wait_pressed().await;
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
        if !button.is_pressed() {
            continue;
        }
        if released_within(button, config::LONG_PRESS_MS - config::BUTTON_DEBOUNCE_MS).await {
            return Press::Short;
        }
        return if released_within(button, config::VERY_LONG_PRESS_MS - config::LONG_PRESS_MS).await
        {
            Press::Long
        } else {
            Press::VeryLong
        };
    }
}

/// The button was released within `ms`.
async fn released_within(button: &mut impl OperatorButton, ms: u64) -> bool {
    embassy_time::with_timeout(Duration::from_millis(ms), button.wait_released())
        .await
        .is_ok()
}

/// The command a short press gives in `mode`.
fn short_press_command(mode: Mode) -> Option<Command> {
    match mode {
        Mode::Unhomed => None,
        Mode::Homing | Mode::Armed => Some(Command::Disarm),
        Mode::Disarmed => Some(Command::Arm),
        Mode::Faulted => Some(Command::ClearFaults),
    }
}

/// Serve the button forever (the board binary spawns this as a task).
pub async fn run(mut button: impl OperatorButton, mut commands: impl CommandSink) {
    let mut preset = 1; // the default stiffness
    loop {
        let press = next_press(&mut button).await;
        let mode = published_mode();
        let command = match press {
            Press::Short => short_press_command(mode),
            Press::Long => Some(Command::Home),
            Press::VeryLong => {
                preset = (preset + 1) % STIFFNESS_PRESETS.len();
                Some(Command::SetContactParams(ContactParams {
                    normal_stiffness: STIFFNESS_PRESETS[preset],
                    ..ContactParams::DEFAULT
                }))
            }
        };
        match command {
            None => info!("button: {} press while {}; hold 1 s to home", press, mode),
            Some(c) => {
                info!("button: {} press while {}: {}", press, mode, c);
                if !commands.try_submit(c) {
                    warn!("operator command dropped: queue full (tick not running?)");
                }
            }
        }
    }
}

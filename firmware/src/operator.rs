//! The operator's button: the core's rules (`softfinger_core::control::operator`, the same the
//! emulated board and host-sim's fault campaign run), sampled every
//! [`config::BUTTON_SAMPLE_MS`]:
//!
//! | press | in `Armed` or `Homing` | otherwise, on release |
//! | --- | --- | --- |
//! | any, once debounced (20 ms) | `Disarm` at once | - |
//! | short (< 1 s) | - | Disarmed → `Arm`; Faulted → `ClearFaults`; Unhomed → none (logged: hold to home) |
//! | long (1 s ..< 3 s) | - | `Home` (hands off the handle: the arms move) |
//! | very long (≥ 3 s) | - | next surface stiffness preset, only Unhomed or Disarmed |
//!
//! Commands reach the tick through a lock-free SPSC queue; the supervisor logs their outcomes.
//! A full queue drops the command (logged).

use defmt::{info, warn};
use embassy_time::Timer;
use softfinger_core::control::operator::{ButtonRules, ButtonTiming};

use crate::board::OperatorButton;
use crate::config;
use crate::tick::published_mode;

/// Serve the button forever (the board binary spawns this as a task).
pub async fn run(mut button: impl OperatorButton, mut commands: crate::CommandTx) {
    let mut rules = ButtonRules::new(
        ButtonTiming::DEFAULT,
        config::BUTTON_SAMPLE_MS as f32 * 1e-3,
    );
    loop {
        if rules.idle() {
            button.wait_pressed().await;
        } else {
            Timer::after_millis(config::BUTTON_SAMPLE_MS).await;
        }
        let mode = published_mode();
        if let Some(c) = rules.sample(button.is_pressed(), mode) {
            info!("button while {}: {}", mode, c);
            if commands.enqueue(c).is_err() {
                warn!("operator command dropped: queue full (tick not running?)");
            }
        }
    }
}

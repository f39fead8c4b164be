//! The operator's button (B1), running softfinger-core's [`ButtonRules`] (the rules host-sim's
//! fault campaign runs in its closed loop), event-driven:
//!
//! | press | in `Armed` or `Homing` | otherwise, on release |
//! | --- | --- | --- |
//! | any, once debounced | `Disarm` at once (the stop) | - |
//! | short (< 1 s) | (already stopped) | Disarmed → `Arm`; Faulted → `ClearFaults`; Unhomed → nothing (logged: hold to home) |
//! | long (1 s ..< 3 s) | (already stopped) | Unhomed or Disarmed → `Home` |
//! | very long (≥ 3 s) | (already stopped) | Unhomed or Disarmed: the next stiffness preset |
//!
//! A short press never arms a device whose settings store could not be read (`persist`).
//!
//! So a press while the device renders force stops it within the debounce time
//! ([`config::BUTTON_TIMING`]), and the preset never changes while armed.
//!
//! Cost: while no press is in progress ([`ButtonRules::idle`]) the task waits for the button's
//! edge (EXTI) and never runs; only during a press (and its release's debounce) does it sample
//! every [`config::BUTTON_SAMPLE_MS`]. (A task that sampled every 1 ms all the time made 45
//! compare loads late at 20 kHz in the processor-in-the-loop run; this one costs nothing at rest.)
//!
//! Commands, checked here (`Command::check`), reach the tick through a lock-free SPSC queue; the
//! supervisor logs their outcomes.
//! A full queue drops the command (logged).

use defmt::{info, warn};
use embassy_time::Timer;
use heapless::spsc::Producer;
use softfinger_core::control::operator::ButtonRules;
use softfinger_core::control::pipeline::{CheckedCommand, Command};

use crate::board::OperatorButton;
use crate::config;
use crate::tick::published_mode;

/// Serve the button forever (the board binary spawns this as a task).
pub async fn run(mut button: impl OperatorButton, mut commands: Producer<'static, CheckedCommand>) {
    let mut rules = ButtonRules::new(
        config::BUTTON_TIMING,
        config::BUTTON_SAMPLE_MS as f32 * 1e-3,
    );
    loop {
        if rules.idle() {
            button.wait_pressed().await;
        } else {
            Timer::after_millis(config::BUTTON_SAMPLE_MS).await;
        }
        let mode = published_mode();
        let pressed = button.is_pressed();
        let Some(command) = rules.sample(pressed, mode) else {
            continue;
        };
        // Never arm on settings the device could not read (`persist::DeviceStore::arm_refusal`).
        if matches!(command, Command::Arm)
            && crate::persist::ARM_REFUSED.load(core::sync::atomic::Ordering::Relaxed)
        {
            warn!("button: Arm refused: the settings store could not be read (config reset or save first)");
            continue;
        }
        info!("button: while {}: {}", mode, command);
        // Checked here, so the tick only applies it (a preset's parameters are constants that
        // pass; a refusal is logged and nothing is sent).
        let command = match command.check() {
            Ok(c) => c,
            Err(e) => {
                warn!("button: {} refused: {}", command, e);
                continue;
            }
        };
        if commands.enqueue(command).is_err() {
            warn!("operator command dropped: queue full (tick not running?)");
        }
    }
}

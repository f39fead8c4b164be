//! The operator's button: a short press asks the tick to clear latched faults; a long press
//! (≥ `config::LONG_PRESS_MS`) cycles the surface stiffness through [`STIFFNESS_PRESETS`].
//! Commands reach the tick through a lock-free SPSC queue; a full queue drops the command (logged).

use defmt::{info, warn};
use embassy_time::{Duration, Timer};
use heapless::spsc::Producer;
use softfinger_core::params::ContactParams;

use crate::board::OperatorButton;
use crate::config;
use crate::tick::OperatorCommand;

/// Surface stiffness presets (N/m) cycled by a long press: soft, the default, stiff.
const STIFFNESS_PRESETS: [f32; 3] = [500.0, 2000.0, 5000.0];

/// A debounced press, classified by how long it was held.
enum Press {
    Short,
    Long,
}

/// Wait for the next debounced press and classify it; returns once the button is released or
/// held long enough.
async fn next_press(button: &mut impl OperatorButton) -> Press {
    loop {
        button.wait_released().await;
        button.wait_pressed().await;
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
        if !button.is_pressed() {
            continue;
        }
        let held = embassy_time::with_timeout(
            Duration::from_millis(config::LONG_PRESS_MS),
            button.wait_released(),
        )
        .await
        .is_err();
        return if held { Press::Long } else { Press::Short };
    }
}

/// Serve the button forever (the board binary spawns this as a task).
pub async fn run(
    mut button: impl OperatorButton,
    mut commands: Producer<'static, OperatorCommand>,
) {
    let mut preset = 1; // the default stiffness
    loop {
        let cmd = match next_press(&mut button).await {
            Press::Long => {
                preset = (preset + 1) % STIFFNESS_PRESETS.len();
                let stiffness = STIFFNESS_PRESETS[preset];
                info!("button held: surface stiffness {=f32} N/m", stiffness);
                OperatorCommand::SetContactParams(ContactParams {
                    normal_stiffness: stiffness,
                    ..ContactParams::DEFAULT
                })
            }
            Press::Short => {
                info!("button pressed: clear latched faults");
                OperatorCommand::ClearFaults
            }
        };
        if commands.enqueue(cmd).is_err() {
            warn!("operator command dropped: queue full (tick not running?)");
        }
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
    }
}

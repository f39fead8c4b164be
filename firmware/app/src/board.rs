//! The hardware interface the app is written against: what the control interrupt reads and
//! writes ([`ControlHw`]), the status LED ([`Indicator`]) and the operator's button
//! ([`OperatorButton`]). Board-independent: no HAL type appears here.

/// Raw inputs of one tick, as read from the hardware.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RawSample {
    /// Raw wrapping 16-bit counter values: `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`.
    pub counts: [u16; 6],
    /// The drivers' fault line is asserted (nFAULT low), or the hardware break tripped since the
    /// previous read. Reported as read: masking during sleep and wake is the pipeline's job.
    pub driver_fault: bool,
}

pub use softfinger_core::control::pipeline::BridgeCommands;
use softfinger_core::control::pipeline::CheckedCommand;

/// Who gave a command the tick applies, from a queue or with a board's sample
/// ([`ControlHw::sampled_command`]): the tick applies it by that source's rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandSource {
    /// The operator (`Pipeline::apply`), as from the operator's queue.
    Operator,
    /// A host application (`Pipeline::link_apply`), as from the host link's queue.
    Host,
}

/// The hardware the control interrupt owns.
///
/// Write order ([`ControlHw::write_bridges`]): the pipeline's contract
/// (`softfinger_core::control::pipeline::bridge`): outputs that switch off first (PWM enable, then nSLEEP),
/// then the phase pins, then the compares (preloaded: in effect from the next PWM period), then
/// outputs that switch on (PWM enable, then nSLEEP). The tick timer's event must coincide with a
/// PWM period boundary.
pub trait ControlHw {
    /// Tick-timer counts per control period (the timer counts up from 0 after each tick event).
    fn tick_period_counts(&self) -> u32;
    /// Tick-timer counts since the current period's tick event.
    fn tick_timer_count(&self) -> u32;
    /// Acknowledge this period's tick event.
    fn ack_tick(&mut self);
    /// A new tick event arrived since [`ControlHw::ack_tick`]: this tick ran into the next period.
    fn tick_event_pending(&self) -> bool;
    /// Read the six encoder counters and the drivers' fault line.
    fn read_inputs(&mut self) -> RawSample;
    /// Write the bridge commands in the documented order.
    fn write_bridges(&mut self, cmd: &BridgeCommands);
    /// Proof of life for the independent watchdog.
    fn pet_watchdog(&mut self);
    /// This tick's write time as the next tick's pipeline gets it
    /// (`RawInput::prev_write_done_counts`: tick-timer counts, `u32::MAX` when the writes ran into
    /// the next period), told after the writes. Nothing by default; the emulated board sends it
    /// to its plant with the next sample request, so that the in-process reference it is compared
    /// with gets the same timing input (a late write holds a direction reversal one more tick, see
    /// `softfinger_core::control::pipeline::bridge`).
    #[inline(always)]
    fn prev_write_done(&mut self, _counts: u32) {}
    /// A command that came with this tick's sample, applied where it lies at the end of this
    /// tick, then let go with [`ControlHw::sampled_command_done`]. None by default: the STM32
    /// board's commands come from thread mode, through the tick's queues. The emulated board's
    /// plant plays the operator and the scripted application in lock step with the samples, so
    /// their commands arrive inside the tick; lent by reference, they cost the tick what a
    /// queued command costs it (a 92-byte copy into a queue costs about 110 instructions, and on
    /// the STM32 that copy is the thread-mode sender's).
    #[inline(always)]
    fn sampled_command(&self) -> Option<(CommandSource, &CheckedCommand)> {
        None
    }
    /// The tick applied [`ControlHw::sampled_command`]'s command: the board lets it go.
    #[inline(always)]
    fn sampled_command_done(&mut self) {}
}

/// A status LED.
pub trait Indicator {
    /// Light (true) or extinguish the LED.
    fn set(&mut self, on: bool);
}

/// The operator's push button (debounced by the caller).
#[allow(async_fn_in_trait)] // used with concrete types only, never as `dyn` or across threads
pub trait OperatorButton {
    /// Wait until the button is pressed (returns at once if it already is).
    async fn wait_pressed(&mut self);
    /// Wait until the button is released (returns at once if it already is).
    async fn wait_released(&mut self);
    /// The button is pressed now.
    fn is_pressed(&mut self) -> bool;
}

//! The operator's button: what a press means in each mode. The firmware's button task samples
//! the button every [`ButtonRules::new`]'s period and sends what [`ButtonRules::sample`] returns
//! to [`crate::control::pipeline::Pipeline::command`]; host-sim's fault campaign runs the same
//! rules in its closed loop.
//!
//! | press (held, from the first pressed sample) | in `Armed` or `Homing` | otherwise, on release |
//! | --- | --- | --- |
//! | any, once debounced (`debounce_s`) | `Disarm` at once (the stop) | - |
//! | short (< `long_s`) | (already stopped) | Disarmed → `Arm`; Faulted → `ClearFaults`; Unhomed → nothing |
//! | long (`long_s` ..< `very_long_s`) | (already stopped) | Unhomed or Disarmed → `Home` |
//! | very long (≥ `very_long_s`) | (already stopped) | Unhomed or Disarmed: the next stiffness preset, as soon as held that long |
//!
//! So a press while the device renders force always stops it within the debounce time, and the
//! force never changes preset while armed. A press is released once the button has read
//! released for the debounce time (a bounce does not end it). Times are counted in samples.

use crate::contact::params::ContactParams;
use crate::control::command::Command;
use crate::control::pipeline::homing::ticks_for;
use crate::control::pipeline::Mode;

/// Surface stiffness presets cycled by a very long press, N/m: soft, the default, stiff.
pub const STIFFNESS_PRESETS_N_PER_M: [f32; 3] = [500.0, 2000.0, 5000.0];

/// The button's timing, s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ButtonTiming {
    /// A press (or a release) counts once the button has read so for this long.
    pub debounce_s: f32,
    /// Shortest long press (`Home`).
    pub long_s: f32,
    /// Shortest very long press (next preset).
    pub very_long_s: f32,
}

impl ButtonTiming {
    /// 20 ms debounce, 1 s long, 3 s very long.
    pub const DEFAULT: ButtonTiming = ButtonTiming {
        debounce_s: 0.020,
        long_s: 1.0,
        very_long_s: 3.0,
    };
}

/// The rules' state: sample counts of the press in progress and the preset in force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ButtonRules {
    debounce: u32,
    long: u32,
    very_long: u32,
    /// Consecutive samples read pressed.
    pressed_for: u32,
    /// Consecutive samples read released.
    released_for: u32,
    /// A debounced press is in progress.
    down: bool,
    /// This press already gave its command.
    consumed: bool,
    /// Samples since the press began (its first pressed sample).
    held: u32,
    preset: usize,
}

impl ButtonRules {
    /// Rules sampled every `sample_period_s` with `timing`; the preset starts at the default
    /// stiffness (index 1).
    pub fn new(timing: ButtonTiming, sample_period_s: f32) -> ButtonRules {
        let rate = 1.0 / sample_period_s;
        ButtonRules {
            debounce: ticks_for(timing.debounce_s, rate),
            long: ticks_for(timing.long_s, rate),
            very_long: ticks_for(timing.very_long_s, rate),
            pressed_for: 0,
            released_for: 0,
            down: false,
            consumed: false,
            held: 0,
            preset: 1,
        }
    }

    /// No press in progress and the last sample read released: the caller may wait for the
    /// next press edge instead of sampling.
    pub fn idle(&self) -> bool {
        !self.down && self.pressed_for == 0
    }

    /// The stiffness preset in force, N/m.
    pub fn preset_stiffness(&self) -> f32 {
        STIFFNESS_PRESETS_N_PER_M[self.preset]
    }

    /// One sample of the button (`pressed`: the contact is closed) in `mode`, the pipeline's
    /// mode now. Returns the command to send, if any.
    pub fn sample(&mut self, pressed: bool, mode: Mode) -> Option<Command> {
        if pressed {
            self.pressed_for = self.pressed_for.saturating_add(1);
            self.released_for = 0;
        } else {
            self.released_for = self.released_for.saturating_add(1);
            self.pressed_for = 0;
        }
        if !self.down {
            if self.pressed_for < self.debounce {
                return None;
            }
            self.down = true;
            self.consumed = false;
            self.held = self.pressed_for;
            if matches!(mode, Mode::Armed | Mode::Homing) {
                self.consumed = true;
                return Some(Command::Disarm);
            }
            return None;
        }
        if self.released_for >= self.debounce {
            self.down = false;
            if self.consumed {
                return None;
            }
            return self.on_release(mode);
        }
        if pressed {
            self.held = self.held.saturating_add(1);
        }
        if !self.consumed && matches!(mode, Mode::Armed | Mode::Homing) {
            // The device was armed while the button was held (from the link): stop it.
            self.consumed = true;
            return Some(Command::Disarm);
        }
        if !self.consumed && self.held >= self.very_long {
            self.consumed = true;
            if matches!(mode, Mode::Unhomed | Mode::Disarmed) {
                self.preset = (self.preset + 1) % STIFFNESS_PRESETS_N_PER_M.len();
                return Some(Command::SetContactParams(ContactParams {
                    normal_stiffness: self.preset_stiffness(),
                    ..ContactParams::DEFAULT
                }));
            }
        }
        None
    }

    /// A press that gave no command yet was released (held `self.held` samples, the release's
    /// debounce not counted).
    fn on_release(&mut self, mode: Mode) -> Option<Command> {
        if self.held < self.long {
            match mode {
                Mode::Disarmed => Some(Command::Arm),
                Mode::Faulted => Some(Command::ClearFaults),
                Mode::Armed | Mode::Homing => Some(Command::Disarm),
                Mode::Unhomed => None,
            }
        } else if matches!(mode, Mode::Unhomed | Mode::Disarmed) {
            Some(Command::Home)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// Sampled at 1 kHz: 20 samples debounce, 1 000 long, 3 000 very long.
    fn rules() -> ButtonRules {
        ButtonRules::new(ButtonTiming::DEFAULT, 1e-3)
    }

    /// Press for `n` samples then release for 50, in a fixed `mode`: every command with the
    /// sample it came on (counted from the first pressed sample).
    fn press(r: &mut ButtonRules, n: u32, mode: Mode) -> Vec<(u32, Command)> {
        let mut out = Vec::new();
        for k in 0..n + 50 {
            if let Some(c) = r.sample(k < n, mode) {
                out.push((k, c));
            }
        }
        out
    }

    #[test]
    fn derived_sample_counts() {
        let r = rules();
        assert_eq!((r.debounce, r.long, r.very_long), (20, 1_000, 3_000));
    }

    /// While armed the press disarms on its 20th pressed sample (the debounce), not the 19th, and
    /// a 19-sample press (a bounce) gives nothing.
    #[test]
    fn a_press_while_armed_disarms_on_the_debounced_press() {
        let mut r = rules();
        assert_eq!(press(&mut r, 19, Mode::Armed), []);
        let mut r = rules();
        assert_eq!(press(&mut r, 20, Mode::Armed), [(19, Command::Disarm)]);
        // Held on for 5 s while armed: the one Disarm, no Home, no preset.
        let mut r = rules();
        assert_eq!(press(&mut r, 5_000, Mode::Armed), [(19, Command::Disarm)]);
        assert_eq!(r.preset_stiffness(), 2000.0);
        // The same while homing.
        let mut r = rules();
        assert_eq!(press(&mut r, 1_500, Mode::Homing), [(19, Command::Disarm)]);
    }

    /// Short below 1 000 samples, long from 1 000, very long from 3 000.
    #[test]
    fn press_lengths_are_bracketed() {
        let released = |n: u32| n + 19; // the release's debounce
        let mut r = rules();
        assert_eq!(
            press(&mut r, 999, Mode::Disarmed),
            [(released(999), Command::Arm)]
        );
        let mut r = rules();
        assert_eq!(
            press(&mut r, 1_000, Mode::Disarmed),
            [(released(1_000), Command::Home)]
        );
        let mut r = rules();
        assert_eq!(
            press(&mut r, 2_999, Mode::Unhomed),
            [(released(2_999), Command::Home)]
        );
        let mut r = rules();
        let c = press(&mut r, 3_000, Mode::Disarmed);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].0, 2_999, "as soon as held 3 000 samples");
        assert!(
            matches!(c[0].1, Command::SetContactParams(p) if p.normal_stiffness == 5000.0),
            "{c:?}"
        );
        // Short presses by mode.
        let mut r = rules();
        assert_eq!(
            press(&mut r, 100, Mode::Faulted),
            [(released(100), Command::ClearFaults)]
        );
        assert_eq!(press(&mut r, 100, Mode::Unhomed), []);
    }

    /// No preset changes unless unhomed or disarmed; a long press in `Faulted` homes nothing.
    #[test]
    fn no_preset_change_while_armed_or_faulted() {
        for mode in [Mode::Armed, Mode::Faulted, Mode::Homing] {
            let mut r = rules();
            let c = press(&mut r, 4_000, mode);
            assert!(
                !c.iter()
                    .any(|(_, c)| matches!(c, Command::SetContactParams(_) | Command::Home)),
                "{mode:?}: {c:?}"
            );
            assert_eq!(r.preset_stiffness(), 2000.0);
        }
    }

    /// A release bounce shorter than the debounce does not end the press.
    #[test]
    fn a_release_bounce_does_not_end_the_press() {
        let mut r = rules();
        let mut out = Vec::new();
        for k in 0..1_200u32 {
            let pressed = !(500..519).contains(&k) && k < 1_100;
            if let Some(c) = r.sample(pressed, Mode::Disarmed) {
                out.push(c);
            }
        }
        assert_eq!(out, [Command::Home]);
    }

    /// Armed from the link while the button is held: the held press stops it.
    #[test]
    fn armed_while_held_disarms() {
        let mut r = rules();
        for _ in 0..100 {
            assert_eq!(r.sample(true, Mode::Disarmed), None);
        }
        assert_eq!(r.sample(true, Mode::Armed), Some(Command::Disarm));
        assert_eq!(r.sample(true, Mode::Armed), None);
    }
}

//! The perceptual yardstick: which difference between a reduced contact model and the full one a
//! user would feel.
//!
//! - **Force**: the just-noticeable difference of a force pressed with the fingertip is about 7 %
//!   of the force (Jones, "Matching forces: constant errors and differential thresholds",
//!   Perception 18, 1989; Pang, Tan and Durlach, "Manual discrimination of force using active
//!   finger motion", Perception & Psychophysics 49, 1991, report 5-10 %). We take 7 %, the lower
//!   end. Below [`FORCE_FLOOR_N`] a Weber fraction has no footing; that floor is our assumption,
//!   not a measured threshold.
//! - **Spin torque**: the JND of a torque about the finger's axis is about 12.7 % (Jandura and
//!   Srinivasan, "Experiments on human performance in torque discrimination and control", ASME
//!   DSC 55-1, 1994), floor [`TORQUE_FLOOR_NM`] (our assumption).
//! - **Contact path**: a touch is localised on the fingertip to about 1-2 mm (Weinstein, "Intensive
//!   and extensive aspects of tactile sensitivity", 1968: point localisation at the fingertip
//!   ~1.5 mm); we take the conservative [`PATH_THRESHOLD_MM`] = 1 mm.
//!
//! **What the device displays.** A difference a device does not put on the finger cannot be felt.
//! The device here is a 3-DoF delta: it renders the force, not the spin torque about the normal
//! (`softfinger_core::control::controller::TickOutput::tau_n_nm` is reported, not displayed),
//! so [`DEVICE_DISPLAYS_TORQUE`] is false and the torque criterion does not decide the least model
//! for it. The spin part still reaches the finger through the force where the limit surface
//! couples twist and slide; that shows in the force and path criteria. The table keeps the torque
//! ratio, and `host-sim model` also names the least model for a device that displayed the
//! torque.
//!
//! Forces and torques are compared tick by tick: the difference at a tick must stay below the
//! threshold of the full model's force (torque) at that tick. A user cannot tell a force from one
//! 10 µs later; both series are first averaged over [`PERCEPTION_WINDOW_S`], shorter than the
//! ~30 ms the skin needs to tell two taps apart (temporal resolution of touch, e.g. Gescheider,
//! "Resolving of successive clicks by the finger pad", JASA 1966: about 5-30 ms).
//!
//! **Timing.** For the same reason an event that one model renders up to [`TIME_SHIFT_S`] earlier
//! or later than the other (a stick after a slide 0.9 ms apart, measured on finger-slide-twist) is
//! the same event to the finger: a tick's difference is the least difference to the other run
//! within ±[`TIME_SHIFT_S`] (both ways, the larger kept). 5 ms is the lower end of the skin's
//! temporal resolution above; temporal-order thresholds of touch are larger still (about 20 ms,
//! Hirsh and Sherrick, "Perceived order in different sense modalities", J. Exp. Psychol. 62,
//! 1961). The table's max and RMS differences are the raw tick-by-tick ones.

/// Force JND, fraction of the force (Jones 1989).
pub const FORCE_WEBER: f64 = 0.07;
/// Force below which the Weber fraction is not applied, N (our assumption).
pub const FORCE_FLOOR_N: f64 = 0.05;
/// Torque JND, fraction of the torque (Jandura and Srinivasan 1994).
pub const TORQUE_WEBER: f64 = 0.127;
/// Torque below which the Weber fraction is not applied, N·m (our assumption: 0.1 mN·m).
pub const TORQUE_FLOOR_NM: f64 = 1.0e-4;
/// Contact-path difference a user would feel, mm (Weinstein 1968, conservative end).
pub const PATH_THRESHOLD_MM: f64 = 1.0;
/// Whether the device puts the spin torque on the finger: the 3-DoF delta does not.
pub const DEVICE_DISPLAYS_TORQUE: bool = false;
/// Averaging window before forces and torques are compared, s.
pub const PERCEPTION_WINDOW_S: f64 = 0.005;
/// Time shift within which the two runs are matched before a difference counts, s.
pub const TIME_SHIFT_S: f64 = 0.005;

/// The largest force difference allowed at a tick whose full-model force is `f_n` (N).
pub fn force_threshold_n(f_n: f64) -> f64 {
    (FORCE_WEBER * f_n).max(FORCE_WEBER * FORCE_FLOOR_N)
}

/// The largest torque difference allowed at a tick whose full-model torque is `tau` (N·m).
pub fn torque_threshold_nm(tau_nm: f64) -> f64 {
    (TORQUE_WEBER * tau_nm.abs()).max(TORQUE_WEBER * TORQUE_FLOOR_NM)
}

/// One paragraph for the table and the README: the yardstick and its sources.
pub const STATEMENT: &str = "Yardstick: force difference <= 7 % of the full model's force \
(Jones 1989; Pang, Tan & Durlach 1991: 5-10 %; floor 7 % of 0.05 N, our assumption), \
spin-torque difference <= 12.7 % of its torque (Jandura & Srinivasan 1994; floor 12.7 % of \
0.1 mN·m, our assumption), contact-path difference <= 1 mm (fingertip point localisation \
1-2 mm, Weinstein 1968); forces and torques averaged over 5 ms first and every difference \
taken to the nearest tick of the other run within ±5 ms (the skin's temporal resolution is \
5-30 ms, Gescheider 1966; temporal order about 20 ms, Hirsh & Sherrick 1961). The torque counts only on a device that displays it (this 3-DoF \
device does not; the torque-displayed column says what such a device would need).";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_scale_with_the_force_above_their_floor() {
        assert_eq!(force_threshold_n(2.0), 0.14);
        assert_eq!(force_threshold_n(0.0), FORCE_WEBER * FORCE_FLOOR_N);
        // Just below and just above the floor.
        assert_eq!(force_threshold_n(0.049), FORCE_WEBER * FORCE_FLOOR_N);
        assert!(force_threshold_n(0.051) > FORCE_WEBER * FORCE_FLOOR_N);
        assert_eq!(torque_threshold_nm(-0.01), TORQUE_WEBER * 0.01);
        assert_eq!(torque_threshold_nm(0.0), TORQUE_WEBER * TORQUE_FLOOR_NM);
    }
}

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
//! Forces and torques are compared tick by tick: the difference at a tick must stay below the
//! threshold of the full model's force (torque) at that tick. A user cannot tell a force from one
//! 10 µs later; both series are first averaged over [`PERCEPTION_WINDOW_S`], shorter than the
//! ~30 ms the skin needs to tell two taps apart (temporal resolution of touch, e.g. Gescheider,
//! "Resolving of successive clicks by the finger pad", JASA 1966: about 5-30 ms).

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
/// Averaging window before forces and torques are compared, s.
pub const PERCEPTION_WINDOW_S: f64 = 0.005;

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
1-2 mm, Weinstein 1968); forces and torques averaged over 5 ms first (the skin's temporal \
resolution is 5-30 ms).";

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

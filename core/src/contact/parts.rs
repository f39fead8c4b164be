//! The parts of the contact model as compile-time choices: a scene runs no more of the model than
//! it needs, and a part it leaves out costs no instruction on the MCU (the branches on the
//! associated constants below are resolved when [`crate::contact::ContactModel`] is compiled for a
//! choice).
//!
//! The choices add parts as MuJoCo's `condim` does (1 frictionless, 3 sliding friction, 4 adds
//! torsion, 6 adds rolling), each adding one part to one before it; rolling can be had without the
//! spin (a device that displays no torque about the normal feels the spin part only through the
//! limit surface, which needs it):
//!
//! | choice | name | what it adds |
//! | --- | --- | --- |
//! | [`PointFriction`] | `point-friction` | a point contact with Coulomb friction (the friction proxy, the normal spring, the state machine); the contact point stays where the touch put it until a slide moves it; no spin torque |
//! | [`RollingOnly`] | `rolling` | to [`PointFriction`]: the contact point rolls on both surfaces as the fingertip turns (eqs. 2-3), and the twist threshold on the tilt rate; no spin torque |
//! | [`WithSpin`] | `spin` | to [`PointFriction`]: the spin torque τn = k_z·φ_el about the normal, with its own torsional limit (3π/16)·μ·f_N·a |
//! | [`WithRolling`] | `spin-rolling` | to [`WithSpin`] (or to [`RollingOnly`]): rolling (or the spin) |
//! | [`Full`] | `full` | the limit surface: twist and slide share one friction budget ([`crate::contact::limit_surface`]) |
//!
//! Without the limit surface the friction cone |f_T| ≤ μ·f_N and the torsional limit act each on
//! their own (the box the ellipse is inscribed in).

use core::fmt::Debug;

/// One choice of the contact model's parts (a type with no data; see the module table).
pub trait Parts: Copy + Debug + Default + PartialEq + Send + Sync + 'static {
    /// The choice's name in scene files and tables.
    const NAME: &'static str;
    /// The spin torque about the normal, with its torsional limit.
    const SPIN: bool;
    /// Rolling of the contact point (and the twist threshold on the tilt rate).
    const ROLLING: bool;
    /// The limit surface coupling twist and slide (needs [`Parts::SPIN`]).
    const LIMIT_SURFACE: bool;
}

/// A point contact with friction: no spin torque, no rolling.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PointFriction;
/// [`PointFriction`] plus rolling of the contact point, without the spin torque.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RollingOnly;
/// [`PointFriction`] plus the spin torque with its torsional limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WithSpin;
/// [`WithSpin`] plus rolling of the contact point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WithRolling;
/// The whole model: [`WithRolling`] plus the limit surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Full;

impl Parts for PointFriction {
    const NAME: &'static str = "point-friction";
    const SPIN: bool = false;
    const ROLLING: bool = false;
    const LIMIT_SURFACE: bool = false;
}
impl Parts for RollingOnly {
    const NAME: &'static str = "rolling";
    const SPIN: bool = false;
    const ROLLING: bool = true;
    const LIMIT_SURFACE: bool = false;
}
impl Parts for WithSpin {
    const NAME: &'static str = "spin";
    const SPIN: bool = true;
    const ROLLING: bool = false;
    const LIMIT_SURFACE: bool = false;
}
impl Parts for WithRolling {
    const NAME: &'static str = "spin-rolling";
    const SPIN: bool = true;
    const ROLLING: bool = true;
    const LIMIT_SURFACE: bool = false;
}
impl Parts for Full {
    const NAME: &'static str = "full";
    const SPIN: bool = true;
    const ROLLING: bool = true;
    const LIMIT_SURFACE: bool = true;
}

/// A choice named at run time (a scene file's `model`), to pick the compiled [`Parts`] type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ModelChoice {
    /// [`PointFriction`].
    PointFriction,
    /// [`RollingOnly`].
    Rolling,
    /// [`WithSpin`].
    Spin,
    /// [`WithRolling`].
    SpinRolling,
    /// [`Full`].
    Full,
}

impl ModelChoice {
    /// Every choice, fewest parts first (`rolling` and `spin` have one each; which costs less
    /// depends on the surface, `mcu-bench/budget.json`).
    pub const ALL: [ModelChoice; 5] = [
        ModelChoice::PointFriction,
        ModelChoice::Rolling,
        ModelChoice::Spin,
        ModelChoice::SpinRolling,
        ModelChoice::Full,
    ];

    /// The name used in scene files ([`Parts::NAME`]).
    pub const fn name(self) -> &'static str {
        match self {
            ModelChoice::PointFriction => PointFriction::NAME,
            ModelChoice::Rolling => RollingOnly::NAME,
            ModelChoice::Spin => WithSpin::NAME,
            ModelChoice::SpinRolling => WithRolling::NAME,
            ModelChoice::Full => Full::NAME,
        }
    }

    /// The choice of that name, if any.
    pub fn from_name(name: &str) -> Option<ModelChoice> {
        ModelChoice::ALL.into_iter().find(|c| c.name() == name)
    }

    /// Whether every part of `self` is in `other` (`other` is `self` or more).
    pub const fn within(self, other: ModelChoice) -> bool {
        let (a, b) = (self.parts(), other.parts());
        (!a.0 || b.0) && (!a.1 || b.1) && (!a.2 || b.2)
    }

    /// The parts as ([`Parts::SPIN`], [`Parts::ROLLING`], [`Parts::LIMIT_SURFACE`]).
    pub const fn parts(self) -> (bool, bool, bool) {
        match self {
            ModelChoice::PointFriction => (
                PointFriction::SPIN,
                PointFriction::ROLLING,
                PointFriction::LIMIT_SURFACE,
            ),
            ModelChoice::Rolling => (
                RollingOnly::SPIN,
                RollingOnly::ROLLING,
                RollingOnly::LIMIT_SURFACE,
            ),
            ModelChoice::Spin => (WithSpin::SPIN, WithSpin::ROLLING, WithSpin::LIMIT_SURFACE),
            ModelChoice::SpinRolling => (
                WithRolling::SPIN,
                WithRolling::ROLLING,
                WithRolling::LIMIT_SURFACE,
            ),
            ModelChoice::Full => (Full::SPIN, Full::ROLLING, Full::LIMIT_SURFACE),
        }
    }
}

/// Evaluate `$body` with the type alias `$p` bound to the compiled
/// [`Parts`](crate::contact::Parts) type of the [`ModelChoice`](crate::contact::ModelChoice)
/// `$choice` (one monomorphised copy of `$body` per choice):
/// `with_parts!(choice, P => run::<P>())`.
#[macro_export]
macro_rules! with_parts {
    ($choice:expr, $p:ident => $body:expr) => {
        match $choice {
            $crate::contact::ModelChoice::PointFriction => {
                type $p = $crate::contact::PointFriction;
                $body
            }
            $crate::contact::ModelChoice::Rolling => {
                type $p = $crate::contact::RollingOnly;
                $body
            }
            $crate::contact::ModelChoice::Spin => {
                type $p = $crate::contact::WithSpin;
                $body
            }
            $crate::contact::ModelChoice::SpinRolling => {
                type $p = $crate::contact::WithRolling;
                $body
            }
            $crate::contact::ModelChoice::Full => {
                type $p = $crate::contact::Full;
                $body
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::state::ContactState;
    use crate::contact::surface::{Plane, Surface};
    use crate::contact::{ContactInput, ContactModel, ContactParams};
    use crate::math::{quat::Quat, vec3::Vec3, Libm};

    /// Press 1 mm into the plane, then turn the fingertip about x (rolling) and about the normal
    /// (twist) by `n` steps of 1 mrad each; returns the last output and the contact point.
    fn press_roll_twist<P: Parts>(n: usize) -> (crate::contact::ContactOutput, Vec3) {
        let p = ContactParams::DEFAULT;
        let mut m =
            ContactModel::<Libm, Plane, P>::with_parts(p, Plane::default(), Quat::IDENTITY, 1e-4)
                .unwrap();
        let probe_m = Vec3::new(0.0, 0.0, p.fingertip_radius_m - 0.001);
        let mut q = Quat::IDENTITY;
        let mut input = ContactInput {
            q,
            probe_m,
            probe_vel: Vec3::ZERO,
        };
        for _ in 0..4 {
            m.contact_step(&input);
        }
        let (dq, _) = Quat::from_rotation_vector::<Libm>(Vec3::new(1e-3, 0.0, 1e-3));
        let mut out = m.contact_step(&input);
        for _ in 0..n {
            q = dq * q;
            input.q = q;
            out = m.contact_step(&input);
        }
        (out, m.rolling().surface().contact_point())
    }

    /// What each choice leaves out is absent from its output, and what it keeps agrees with the
    /// full model while nothing slides (20 steps: 20 mrad of roll and twist, well inside the
    /// friction limits at 2 N).
    #[test]
    fn a_choice_renders_what_its_parts_give() {
        let (full, full_point) = press_roll_twist::<Full>(20);
        assert_eq!(full.state, ContactState::Rolling);
        assert!(full.tau_n_nm > 0.0 && full_point.y.abs() > 1e-4, "{full:?}");
        let (point, point_at) = press_roll_twist::<PointFriction>(20);
        assert_eq!(
            (point.tau_n_nm, point_at),
            (0.0, Vec3::ZERO),
            "no spin, no rolling"
        );
        // Rolling without the spin: the same contact point and force as the full model, no torque.
        let (rolling, rolling_at) = press_roll_twist::<RollingOnly>(20);
        assert_eq!(rolling.tau_n_nm, 0.0);
        assert_eq!(rolling_at, full_point);
        assert_eq!(rolling.force_n, full.force_n);
        let (spin, spin_at) = press_roll_twist::<WithSpin>(20);
        assert_eq!(spin_at, Vec3::ZERO, "no rolling");
        // Inside the limit surface the limits do not act: the same spin torque (measured 1 ulp
        // apart at most: the contact frame does not move in the plane, both use the rotation
        // vector's z).
        assert!(
            (spin.tau_n_nm - full.tau_n_nm).abs() <= 1e-9,
            "{spin:?} {full:?}"
        );
        let (roll, roll_at) = press_roll_twist::<WithRolling>(20);
        assert_eq!(roll.force_n, full.force_n);
        assert_eq!(roll.tau_n_nm, full.tau_n_nm);
        assert_eq!(roll_at, full_point);
    }

    #[test]
    fn names_round_trip_and_the_choices_add_one_part_each() {
        for c in ModelChoice::ALL {
            assert_eq!(ModelChoice::from_name(c.name()), Some(c));
            assert!(c.within(c) && c.within(ModelChoice::Full));
            assert!(ModelChoice::PointFriction.within(c));
        }
        assert_eq!(ModelChoice::from_name("fulll"), None);
        let count = |p: (bool, bool, bool)| p.0 as u8 + p.1 as u8 + p.2 as u8;
        let parts = ModelChoice::ALL.map(|c| count(c.parts()));
        assert_eq!(parts, [0, 1, 1, 2, 3]);
        for c in ModelChoice::ALL {
            // The limit surface needs the spin.
            assert!(!c.parts().2 || c.parts().0, "{c:?}");
            // Every choice but the least has one with exactly one part fewer within it.
            if c != ModelChoice::PointFriction {
                assert!(ModelChoice::ALL
                    .iter()
                    .any(|&d| d.within(c) && count(d.parts()) + 1 == count(c.parts())));
            }
        }
        assert!(!ModelChoice::Rolling.within(ModelChoice::Spin));
        assert!(!ModelChoice::Spin.within(ModelChoice::Rolling));
        // The macro binds the compiled type of each choice.
        for c in ModelChoice::ALL {
            assert_eq!(crate::with_parts!(c, P => P::NAME), c.name());
        }
    }
}

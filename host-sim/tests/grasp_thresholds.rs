//! The grasp's closed forms bracketed just below and just above each threshold, on whole runs of
//! `host-sim grasp`'s scene (simulated hands, the core's grasp at 10 kHz):
//!
//! - lift: held when m·g < 2·μ_s·F_grip; the state machine leaves rolling only beyond the static
//!   cone widened by its hysteresis h, so it must slip beyond 2·μ_s·F_grip·(1 + h) (between the
//!   two it may do either);
//! - twist (no gravity): held when |τ| < 2·τ_max(F_grip), turned above;
//! - both at once: held when |τ| < 2·τ_max·√(1 − (m·g/(2·μ_s·F))²) (each contact's load inside its
//!   limit surface), turned above;
//! - torsion off: any torque turns the object.

use host_sim::experiments::grasp::simulate::{run, GraspConfig, Shape};
use host_sim::experiments::grasp::verdict::{judge, Verdict};
use softfinger_core::contact::ContactParams;

const BELOW: f64 = 0.97;
const ABOVE: f64 = 1.03;

fn verdict(c: &GraspConfig) -> Verdict {
    let v = judge(&run(c).unwrap());
    assert!(!v.non_finite, "{c:?}");
    v
}

fn lift_limit_kg(c: &GraspConfig) -> f64 {
    2.0 * c.mu_s * c.grip_n / c.gravity_m_s2
}

fn hysteresis() -> f64 {
    f64::from(ContactParams::DEFAULT.tolerances.hysteresis)
}

/// Both contacts' torsional limit at the grip, N·m, as the model computes it.
fn twist_limit_nm(c: &GraspConfig) -> f64 {
    let r = run(&GraspConfig {
        duration_s: 1e-3,
        torsion: true,
        ..*c
    })
    .unwrap();
    r.tau_max_nm[0] + r.tau_max_nm[1]
}

#[test]
fn lift_is_held_just_below_two_mu_f_and_slips_just_above_the_hysteresis() {
    for shape in [Shape::Sphere, Shape::Cylinder] {
        for (grip_n, mu_s) in [(5.0, 0.8), (3.0, 1.0)] {
            let base = GraspConfig {
                shape,
                grip_n,
                mu_s,
                ..GraspConfig::default()
            };
            let m = lift_limit_kg(&base);
            let low = verdict(&GraspConfig {
                mass_kg: BELOW * m,
                ..base
            });
            assert!(low.held, "{shape:?} F {grip_n} mu {mu_s}: {low:?}");
            let high = verdict(&GraspConfig {
                mass_kg: ABOVE * (1.0 + hysteresis()) * m,
                ..base
            });
            assert!(
                !high.held && high.slip_mm > 10.0,
                "{shape:?} F {grip_n} mu {mu_s}: {high:?}"
            );
        }
    }
}

#[test]
fn twist_is_held_just_below_the_combined_torsional_limit_and_turns_just_above() {
    for shape in [Shape::Sphere, Shape::Cylinder] {
        let base = GraspConfig {
            shape,
            gravity_m_s2: 0.0,
            lift_mm: 0.0,
            duration_s: 1.0,
            ..GraspConfig::default()
        };
        let lim = twist_limit_nm(&base);
        let low = verdict(&GraspConfig {
            torque_nm: BELOW * lim,
            ..base
        });
        assert!(low.held, "{shape:?}: {low:?}");
        let high = verdict(&GraspConfig {
            torque_nm: ABOVE * lim,
            ..base
        });
        assert!(
            !high.held && high.rotation_rad > 0.01,
            "{shape:?}: {high:?}"
        );
        // Either sense.
        let neg = verdict(&GraspConfig {
            torque_nm: -ABOVE * lim,
            ..base
        });
        assert!(!neg.held, "{shape:?}: {neg:?}");
    }
}

#[test]
fn lift_and_twist_at_once_are_bounded_by_the_limit_surface() {
    let base = GraspConfig {
        mass_kg: 0.5,
        duration_s: 1.5,
        ..GraspConfig::default()
    };
    let load = base.mass_kg * base.gravity_m_s2 / (2.0 * base.mu_s * base.grip_n);
    let lim = twist_limit_nm(&base) * (1.0 - load * load).sqrt();
    let low = verdict(&GraspConfig {
        torque_nm: BELOW * lim,
        ..base
    });
    assert!(low.held, "{low:?}");
    let high = verdict(&GraspConfig {
        torque_nm: ABOVE * lim,
        ..base
    });
    assert!(!high.held, "{high:?}");
    // The same torque without the weight is held: the tangential load took the torsional budget.
    let light = verdict(&GraspConfig {
        torque_nm: ABOVE * lim,
        gravity_m_s2: 0.0,
        ..base
    });
    assert!(light.held, "{light:?}");
}

#[test]
fn without_torsion_any_torque_turns_the_object() {
    let base = GraspConfig {
        gravity_m_s2: 0.0,
        lift_mm: 0.0,
        duration_s: 1.0,
        torsion: false,
        ..GraspConfig::default()
    };
    let lim = twist_limit_nm(&base);
    for frac in [0.05, 0.5] {
        let v = verdict(&GraspConfig {
            torque_nm: frac * lim,
            ..base
        });
        assert!(!v.held && v.rotation_rad > 0.01, "{frac}: {v:?}");
        let on = verdict(&GraspConfig {
            torque_nm: frac * lim,
            torsion: true,
            ..base
        });
        assert!(on.held, "{frac}: {on:?}");
    }
    // No torque, no turn, even without torsion.
    let none = verdict(&base);
    assert!(none.held, "{none:?}");
}

#[test]
fn opened_hands_drop_the_object() {
    let c = GraspConfig {
        release_s: Some(0.5),
        duration_s: 1.0,
        ..GraspConfig::default()
    };
    let r = run(&c).unwrap();
    let v = judge(&r);
    assert!(!v.held);
    let last = r.samples.last().unwrap();
    // Free fall for the last ~0.45 s after the fingertips leave: at least 0.5 m below the hands.
    assert!(last.tips_m[0][2] - last.pos_m[2] > 0.5, "{last:?}");
    assert_eq!(last.f_n, [0.0, 0.0]);
}

#[test]
fn a_heavy_object_slips_out_without_nan() {
    let v = verdict(&GraspConfig {
        mass_kg: 50.0,
        ..GraspConfig::default()
    });
    assert!(!v.held && v.slip_mm.is_finite());
}

//! The paper's scene through the whole contact step, once per contact model choice
//! ([`softfinger_core::contact::parts`]): what the paper's experiment costs with each model a scene
//! can name, timed in the same rounds as the classical RK45 runs.
//!
//! Setup: the fingertip (radius `scene.radius`) pressed [`PRESS_M`] into the plane `z = 0`, its
//! centre kept over the closed-form contact point of each sample (so the tangential spring stays
//! slack and the contact keeps rolling, as in the paper's experiment), orientation from the
//! scene's samples (f32), at the scene's step `dt`. The contact is made at the first sample before
//! a timed pass starts; each pass then runs one contact step per further sample and reads both
//! contact points after it, as [`super::ours`] does. The fast backend, the firmware's.

use super::errors::PathErrors;
use super::timing::Case;
use crate::sim::reference::scene::Scene;
use crate::sim::reference::ReferencePaths;
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::Plane;
use softfinger_core::contact::{
    ContactInput, ContactModel, ContactParams, ModelChoice, ParamError, Parts,
};
use softfinger_core::{Fast, Quat, Vec3};
use std::hint::black_box;

/// Depth the fingertip is pressed into the plane, m (2 N at the default 2000 N/m).
pub const PRESS_M: f32 = 0.001;

/// One contact model choice on the paper's scene.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelRun {
    /// The choice.
    pub choice: ModelChoice,
    /// Contact paths against the RK45 reference, mm per axis.
    pub errors: PathErrors,
    /// Steps (after the touch) that were not in the rolling state.
    pub not_rolling_steps: usize,
    /// Median time per contact step, ns (NaN until timed).
    pub ns_per_step: f64,
    /// The cheapest matched RK45 run's time over this one's, per timing round (None when no RK45 run
    /// matched the best variant's accuracy, or this choice misses [`super::TARGET_MM`]).
    pub speedup_spread: Option<super::timing::Spread>,
}

/// The contact step's inputs for every sample: f32 orientation, probe over the closed-form
/// contact point.
fn inputs(scene: &Scene, closed: &ReferencePaths) -> Vec<ContactInput> {
    let r = scene.radius as f32;
    scene
        .samples
        .iter()
        .zip(&closed.plane)
        .map(|(q, p)| ContactInput {
            q: Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32),
            probe_m: Vec3::new(p[0] as f32, p[1] as f32, r - PRESS_M),
            probe_vel: Vec3::ZERO,
        })
        .collect()
}

/// The model of parts `P` in contact at the first sample.
fn touched<P: Parts>(
    scene: &Scene,
    inputs: &[ContactInput],
) -> Result<ContactModel<Fast, Plane, P>, ParamError> {
    let params = ContactParams {
        fingertip_radius_m: scene.radius as f32,
        ..ContactParams::DEFAULT
    };
    let first = inputs.first().copied().unwrap_or_default();
    let mut m = ContactModel::<Fast, Plane, P>::with_parts(
        params,
        Plane::default(),
        first.q,
        scene.dt as f32,
    )?;
    // Make contact and let the make dwell pass.
    for _ in 0..64 {
        if m.contact_step(&first).state == ContactState::Rolling {
            break;
        }
    }
    Ok(m)
}

fn row(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn run_with<P: Parts>(
    choice: ModelChoice,
    scene: &Scene,
    inputs: &[ContactInput],
    reference: &ReferencePaths,
) -> Result<ModelRun, ParamError> {
    let mut m = touched::<P>(scene, inputs)?;
    let (mut plane, mut sphere) = (
        vec![row(m.rolling().surface().point)],
        vec![row(m.rolling().finger_point())],
    );
    let mut not_rolling = 0;
    for i in inputs.iter().skip(1) {
        let out = m.contact_step(i);
        not_rolling += usize::from(out.state != ContactState::Rolling);
        plane.push(row(m.rolling().surface().point));
        sphere.push(row(m.rolling().finger_point()));
    }
    Ok(ModelRun {
        choice,
        errors: PathErrors::between(&plane, &sphere, &reference.plane, &reference.sphere),
        not_rolling_steps: not_rolling,
        ns_per_step: f64::NAN,
        speedup_spread: None,
    })
}

fn case_with<'a, P: Parts>(
    scene: &Scene,
    inputs: &'a [ContactInput],
) -> Result<Case<'a>, ParamError> {
    let start = touched::<P>(scene, inputs)?;
    Ok(Case::new(inputs.len().saturating_sub(1), move || {
        let mut m = black_box(start);
        for i in inputs.iter().skip(1) {
            black_box(m.contact_step(black_box(i)));
            black_box((m.rolling().surface().point, m.rolling().finger_point()));
        }
        m
    }))
}

/// The contact inputs of the paper's scene (see the module doc).
pub fn scene_inputs(scene: &Scene, closed: &ReferencePaths) -> Vec<ContactInput> {
    inputs(scene, closed)
}

/// Every choice on the scene, its errors against `reference` (not yet timed).
pub fn runs(
    scene: &Scene,
    inputs: &[ContactInput],
    reference: &ReferencePaths,
) -> Result<Vec<ModelRun>, ParamError> {
    ModelChoice::ALL
        .into_iter()
        .map(|c| softfinger_core::with_parts!(c, P => run_with::<P>(c, scene, inputs, reference)))
        .collect()
}

/// A timing case per run, in order.
pub fn cases<'a>(
    scene: &Scene,
    inputs: &'a [ContactInput],
    runs: &[ModelRun],
) -> Result<Vec<Case<'a>>, ParamError> {
    runs.iter()
        .map(|r| softfinger_core::with_parts!(r.choice, P => case_with::<P>(scene, inputs)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiments::validate::{closed_form, reference_for, TARGET_MM};
    use crate::sim::reference::scene::paper_scene;

    /// With rolling, the contact step's paths are the rolling step's (within the target: measured
    /// below 1e-4 mm, as `validate` prints); without rolling the contact point stays put and
    /// the error is the path's length (measured over 10 mm).
    #[test]
    fn the_choices_with_rolling_follow_the_reference_and_the_others_do_not() {
        let scene = paper_scene();
        let closed = closed_form(&scene).unwrap();
        let reference = reference_for(&scene, &closed).unwrap();
        let inputs = scene_inputs(&scene, &closed);
        for r in runs(&scene, &inputs, &reference.paths).unwrap() {
            let rolls = r.choice.parts().1;
            assert_eq!(r.not_rolling_steps, 0, "{r:?}");
            if rolls {
                assert!(r.errors.max_mm() <= TARGET_MM, "{r:?}");
            } else {
                assert!(r.errors.max_mm() > 10.0, "{r:?}");
            }
        }
    }
}

//! Our rolling step (softfinger-core, f32) run over a scene: the contact paths it produces and its time
//! per step, for every decomposition method × math backend.

use nalgebra::UnitQuaternion;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::surface::Plane;
use softfinger_core::{Math, Quat};
use std::hint::black_box;

use super::timing::Case;

use crate::sim::backend::dispatch;
pub use crate::sim::backend::Backend;

/// One of our variants: a decomposition method with a math backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// Decomposition method.
    pub method: Method,
    /// Math backend.
    pub backend: Backend,
}

impl Variant {
    /// Every method × backend: exact first (the method we recommend), then rpy, then paper-verbatim.
    pub fn all() -> Vec<Variant> {
        [Method::Exact, Method::Rpy, Method::PaperVerbatim]
            .into_iter()
            .flat_map(|method| {
                Backend::ALL
                    .into_iter()
                    .map(move |backend| Variant { method, backend })
            })
            .collect()
    }

    /// `method/backend`, e.g. `exact/libm`.
    pub fn name(self) -> String {
        format!("{}/{}", self.method.name(), self.backend.name())
    }
}

/// Orientation samples rounded to the core's f32 (what the device would receive).
pub fn to_f32(samples: &[UnitQuaternion<f64>]) -> Vec<Quat> {
    samples
        .iter()
        .map(|q| Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32))
        .collect()
}

/// Contact paths in metres, one row per sample (row 0 the initial contact), in the layout of
/// [`crate::sim::reference::ReferencePaths`]: on the plane (object frame) and on the sphere (fingertip frame).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Paths {
    /// Contact point on the plane `z = 0`, m.
    pub plane: Vec<[f64; 3]>,
    /// Contact point on the fingertip sphere, fingertip frame, m.
    pub sphere: Vec<[f64; 3]>,
}

/// The rolling state at the first sample: plane contact at the origin, fingertip at `samples[0]`.
fn start(samples: &[Quat], radius_m: f32, method: Method) -> Rolling<Plane> {
    let q0 = samples.first().copied().unwrap_or(Quat::IDENTITY);
    Rolling::new(Plane::default(), radius_m, q0, method)
}

fn paths_with<M: Math>(samples: &[Quat], radius_m: f32, method: Method) -> Paths {
    let mut r = start(samples, radius_m, method);
    let row = |v: softfinger_core::Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let mut out = Paths {
        plane: vec![row(r.surface().point)],
        sphere: vec![row(r.finger_point())],
    };
    for &q in samples.iter().skip(1) {
        r.step::<M>(q);
        out.plane.push(row(r.surface().point));
        out.sphere.push(row(r.finger_point()));
    }
    out
}

/// One pass over the scene: every step, and both contact points after it (on the plane and on the
/// fingertip), as the classical cases compute both paths; the final state returned (for
/// `black_box`).
fn pass<M: Math>(start: Rolling<Plane>, samples: &[Quat]) -> Rolling<Plane> {
    let mut r = start;
    for &q in samples.iter().skip(1) {
        black_box(r.step::<M>(black_box(q)));
        black_box((r.surface().point, r.finger_point()));
    }
    r
}

fn case_with<'a, M: Math>(samples: &'a [Quat], radius_m: f32, method: Method) -> Case<'a> {
    let s = start(samples, radius_m, method);
    let steps = samples.len().saturating_sub(1);
    Case::new(steps, move || pass::<M>(black_box(s), samples))
}

impl Variant {
    /// The contact paths this variant computes for `samples` (f32) on a fingertip of `radius_m`.
    pub fn paths(self, samples: &[Quat], radius_m: f32) -> Paths {
        dispatch!(self.backend, M => paths_with::<M>(samples, radius_m, self.method))
    }

    /// A timing case: one pass of rolling steps through `samples`.
    pub fn case(self, samples: &[Quat], radius_m: f32) -> Case<'_> {
        dispatch!(self.backend, M => case_with::<M>(samples, radius_m, self.method))
    }
}

//! Tests of the delta kinematics against an independent f64 reference (nalgebra): forward
//! kinematics by Newton iteration on the constraint equations (not the closed form), the jacobian
//! by central finite differences of that reference, and constraint residuals evaluated in f64.

extern crate std;
use super::*;
use crate::math::{Fast, Libm};
use nalgebra::{Matrix3, Vector3};

type V = Vector3<f64>;

const G: DeltaGeometry = DeltaGeometry::OMEGA_LIKE;
const DEG: f64 = core::f64::consts::PI / 180.0;

/// f64 copy of the geometry.
struct Ref {
    r: f64,
    la: f64,
    lb: f64,
}

impl Ref {
    fn new(g: &DeltaGeometry) -> Ref {
        Ref {
            r: g.base_radius_m as f64 - g.effector_radius_m as f64,
            la: g.upper_arm_m as f64,
            lb: g.forearm_m as f64,
        }
    }
    fn radial(i: usize) -> V {
        let phi = 120.0 * DEG * i as f64;
        V::new(phi.cos(), phi.sin(), 0.0)
    }
    /// Sphere centre cᵢ = bᵢ − eᵢ + L_a·uᵢ(θ), built from the module doc's definitions.
    fn centre(&self, i: usize, theta: f64) -> V {
        let u = Self::radial(i) * theta.cos() - V::z() * theta.sin();
        Self::radial(i) * self.r + u * self.la
    }
    /// Constraint residuals |p − cᵢ| − L_b, m.
    fn residuals(&self, theta: [f64; 3], p: V) -> [f64; 3] {
        [0, 1, 2].map(|i| (p - self.centre(i, theta[i])).norm() - self.lb)
    }
    /// Forward kinematics by Newton's method on gᵢ(p) = |p − cᵢ|² − L_b², started well below the
    /// centres so it converges to the lower branch. None when it does not converge.
    fn forward(&self, theta: [f64; 3]) -> Option<V> {
        let c = [0, 1, 2].map(|i| self.centre(i, theta[i]));
        let mean_z = (c[0].z + c[1].z + c[2].z) / 3.0;
        let mut p = V::new(0.0, 0.0, mean_z - self.lb);
        for _ in 0..100 {
            let g = V::from_fn(|i, _| (p - c[i]).norm_squared() - self.lb * self.lb);
            let jx = Matrix3::from_fn(|i, k| 2.0 * (p - c[i])[k]);
            let step = jx.lu().solve(&g)?;
            p -= step;
            if step.norm() < 1e-15 {
                break;
            }
        }
        let res = self.residuals(theta, p);
        (res.iter().all(|r| r.abs() < 1e-12) && p.z < mean_z).then_some(p)
    }
    /// Jacobian dp/dθ by central differences of the Newton forward kinematics.
    fn jacobian_fd(&self, theta: [f64; 3]) -> Option<Matrix3<f64>> {
        // h = 1e-6 rad: truncation error ~h²·|p'''| ≈ 1e-13 m, rounding ~1e-16/1e-6 = 1e-10 m/rad.
        let h = 1e-6;
        let mut j = Matrix3::zeros();
        for k in 0..3 {
            let mut plus = theta;
            let mut minus = theta;
            plus[k] += h;
            minus[k] -= h;
            let col = (self.forward(plus)? - self.forward(minus)?) / (2.0 * h);
            j.set_column(k, &col);
        }
        Some(j)
    }
    /// Forearm volume |s₀·(s₁×s₂)|/L_b³ at a configuration.
    fn volume(&self, theta: [f64; 3], p: V) -> f64 {
        let s = [0, 1, 2].map(|i| p - self.centre(i, theta[i]));
        s[0].dot(&s[1].cross(&s[2])).abs() / self.lb.powi(3)
    }
}

fn v64(v: Vec3) -> V {
    V::new(v.x as f64, v.y as f64, v.z as f64)
}
fn a64(a: [f32; 3]) -> [f64; 3] {
    a.map(|x| x as f64)
}
fn a32(a: [f64; 3]) -> [f32; 3] {
    a.map(|x| x as f32)
}

/// Points of the design cylinder (scaled by `scale` in radius and height): 7 heights, rings at
/// 1/4 … 4/4 of the radius with 8 points per quarter radius, plus the axis.
fn cylinder_points(scale: f64) -> impl Iterator<Item = V> {
    let centre = v64(DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M);
    let radius = DeltaGeometry::OMEGA_LIKE_WORKSPACE_RADIUS_M as f64 * scale;
    let height = DeltaGeometry::OMEGA_LIKE_WORKSPACE_HEIGHT_M as f64 * scale;
    (0..7).flat_map(move |iz| {
        let z = centre.z - height / 2.0 + height * iz as f64 / 6.0;
        let axis = core::iter::once(V::new(0.0, 0.0, z));
        let rings = (1..=4).flat_map(move |ir| {
            let rr = radius * ir as f64 / 4.0;
            let m = 8 * ir;
            (0..m).map(move |k| {
                let a = 2.0 * core::f64::consts::PI * k as f64 / m as f64;
                V::new(rr * a.cos(), rr * a.sin(), z)
            })
        });
        axis.chain(rings)
    })
}

/// Arm angles from −30° to 90° in 15° steps, all combinations (729 configurations).
fn angle_grid() -> impl Iterator<Item = [f64; 3]> {
    let steps = || (0..9).map(|k| (-30.0 + 15.0 * k as f64) * DEG);
    steps().flat_map(move |a| steps().flat_map(move |b| steps().map(move |c| [a, b, c])))
}

#[test]
fn forward_matches_the_f64_newton_reference_over_an_arm_angle_sweep() {
    let r = Ref::new(&G);
    let mut compared = 0;
    for theta in angle_grid() {
        let (p, flags) = G.forward::<Libm>(a32(theta));
        match r.forward(a64(a32(theta))) {
            // Reference converged on the lower branch with a clear margin from the boundary:
            // the closed form must agree.
            Some(p_ref) if r.volume(theta, p_ref) > 0.05 => {
                assert!(flags.is_empty(), "{theta:?}: {flags:?}");
                let err = (v64(p) - p_ref).norm();
                // f32 resolves ~6e-8 relative of the ~0.2 m lengths involved (1.2e-8 m); the
                // circumcentre and h = √(L_b² − |p₀|²) amplify that a few times. Measured max on
                // this grid: 8.18e-8 m; bound 3x, 2.5e-7 m.
                assert!(err < 2.5e-7, "{theta:?}: err {err} m");
                compared += 1;
            }
            _ => {}
        }
    }
    // The whole grid (729) is assemblable with margin; make sure the comparison was not vacuous.
    assert!(compared > 700, "only {compared} configurations compared");
}

#[test]
fn inverse_then_forward_round_trips_over_the_design_cylinder_and_beyond() {
    let r = Ref::new(&G);
    for p in cylinder_points(1.15) {
        let (theta, flags) = G.inverse::<Libm>(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
        assert!(flags.is_empty(), "{p:?}: {flags:?}");
        // The f32 angles satisfy the constraints, checked in f64: f32 atan2/sqrt are good to a
        // few 1e-7 rad, times the arm (0.105 m) ~3e-8 m. Measured max: 3.98e-8 m; bound 3x.
        let p32 = V::new(p.x as f32 as f64, p.y as f32 as f64, p.z as f32 as f64);
        for res in r.residuals(a64(theta), p32) {
            assert!(res.abs() < 1.2e-7, "{p:?}: residual {res}");
        }
        let (back, flags) = G.forward::<Libm>(theta);
        assert!(flags.is_empty(), "{p:?}: {flags:?}");
        let err = (v64(back) - p32).norm();
        // Inverse and forward errors add; measured max 7.78e-8 m (libm) and 7.49e-8 m (Fast);
        // bound 3x, 2.3e-7 m, for both.
        assert!(err < 2.3e-7, "{p:?}: round trip err {err} m");
        // Same with the project's own backend.
        let (theta_f, _) = G.inverse::<Fast>(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
        let (back_f, _) = G.forward::<Fast>(theta_f);
        assert!((v64(back_f) - p32).norm() < 2.3e-7);
    }
}

#[test]
fn inverse_picks_the_elbow_out_branch() {
    let r = Ref::new(&G);
    for p in cylinder_points(1.0) {
        let (theta, _) = G.inverse::<Libm>(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
        for (i, &t) in theta.iter().enumerate() {
            // The other solution of the chain's constraint: the elbow reflected across the line
            // from the motor axis to the effector joint, found in f64 by bisection-free algebra:
            // both solutions satisfy q_x cos θ − q_z sin θ = K; the other is θ' = −2α − θ.
            let rad = Ref::radial(i);
            let q = p - rad * r.r;
            let qx = q.dot(&rad);
            let alpha = q.z.atan2(qx);
            let other = -2.0 * alpha - t as f64;
            // Measured residual 4.27e-8 m (the f32 angle's); bound 3x.
            assert!(
                r.residuals([other; 3], p)[i].abs() < 1.3e-7,
                "not the other root"
            );
            // Elbow radial coordinate r + L_a cos θ: the chosen root's is the larger.
            assert!(
                (t as f64).cos() > other.cos() - 1e-9,
                "{p:?} chain {i}: {t} vs {other}"
            );
        }
    }
}

#[test]
fn jacobian_matches_the_f64_finite_difference_reference() {
    let r = Ref::new(&G);
    for p in cylinder_points(1.0).step_by(7) {
        let pf = Vec3::new(p.x as f32, p.y as f32, p.z as f32);
        let (theta, _) = G.inverse::<Libm>(pf);
        let (pe, _) = G.forward::<Libm>(theta);
        let (j, flags) = G.jacobian::<Libm>(theta, pe);
        assert!(flags.is_empty());
        let j_ref = r
            .jacobian_fd(a64(theta))
            .expect("reference converges in the workspace");
        for (row, ref_row) in j.iter().zip(j_ref.row_iter()) {
            for (&x, &y) in row.iter().zip(ref_row.iter()) {
                // Entries are ~0.1 m/rad; f32 rounding (~1e-7 relative) grows a few times through
                // the Cramer division (forearm volume > 0.6 here); the FD reference is good to
                // ~1e-10. Measured max 3.95e-8 m/rad; bound 3x, 1.2e-7 m/rad.
                assert!((x as f64 - y).abs() < 1.2e-7, "{p:?}: {x} vs {y}");
            }
        }
    }
}

#[test]
fn joint_torques_satisfy_virtual_work_against_the_f64_reference() {
    let r = Ref::new(&G);
    let forces = [
        V::new(0.0, 0.0, 1.0),
        V::new(1.0, 0.0, 0.0),
        V::new(0.0, -1.0, 0.0),
        V::new(3.0, -7.0, 5.0),
    ];
    for p in cylinder_points(1.0).step_by(5) {
        let pf = Vec3::new(p.x as f32, p.y as f32, p.z as f32);
        let (theta, _) = G.inverse::<Libm>(pf);
        let (pe, _) = G.forward::<Libm>(theta);
        let j_ref = r.jacobian_fd(a64(theta)).expect("reference converges");
        for f in forces {
            let (tau, flags) =
                G.joint_torques::<Libm>(theta, pe, Vec3::new(f.x as f32, f.y as f32, f.z as f32));
            assert!(flags.is_empty());
            let tau_ref = j_ref.transpose() * f;
            // |τ| ≲ 0.12 N·m per N. Measured max error 4.13e-7 N·m, at most 4.5e-8 N·m per N of
            // force; bound 3x, 1.4e-7 N·m per N: far below any sign or transpose mistake.
            let scale = 1.4e-7 * f.norm().max(1.0);
            for k in 0..3 {
                assert!(
                    (tau[k] as f64 - tau_ref[k]).abs() < scale,
                    "{p:?} F {f:?}: tau {tau:?} vs {tau_ref:?}"
                );
            }
            // Virtual work on an explicit small displacement, with f64 forward kinematics:
            // τ·δθ = F·δp for δθ = 1e-5 rad on every arm (central difference, O(δθ³) error).
            let dtheta = [1e-5, -2e-5, 1.5e-5];
            let th = a64(theta);
            let plus = r.forward([0, 1, 2].map(|i| th[i] + dtheta[i])).unwrap();
            let minus = r.forward([0, 1, 2].map(|i| th[i] - dtheta[i])).unwrap();
            let work_cart = f.dot(&(plus - minus)) / 2.0;
            let work_joint: f64 = (0..3).map(|i| tau[i] as f64 * dtheta[i]).sum();
            // Work ~1e-6 J; f32 torque error 1e-5 relative gives ~1e-11 J. Measured: at most 0.48
            // of this bound (the difference's O(δθ³) term), 2.1x below it.
            assert!(
                (work_cart - work_joint).abs() < 1e-5 * work_cart.abs().max(1e-7),
                "{work_cart} vs {work_joint}"
            );
        }
    }
}

#[test]
fn an_upward_force_needs_arms_pushed_up_at_the_workspace_centre() {
    // Independent sanity check of the sign: to push the user's hand up (+z), each arm must be
    // driven towards smaller θ (arm up), equally by symmetry.
    let (theta, _) = G.inverse::<Libm>(DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M);
    // Measured exactly symmetric (angles and torques).
    assert_eq!((theta[1], theta[2]), (theta[0], theta[0]));
    let (p, _) = G.forward::<Libm>(theta);
    let (tau, _) = G.joint_torques::<Libm>(theta, p, Vec3::Z);
    for t in tau {
        assert!(t < 0.0, "{tau:?}");
        assert_eq!(t, tau[0], "{tau:?}");
    }
}

#[test]
fn omega_like_workspace_covers_the_datasheet_cylinder() {
    let r = Ref::new(&G);
    let mut angle_min = f64::MAX;
    let mut angle_max = f64::MIN;
    let mut volume_min = f64::MAX;
    let mut torque_per_newton_max = 0.0f64;
    let mut count = 0;
    for p in cylinder_points(1.0) {
        let (theta, flags) = G.inverse::<Libm>(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
        assert!(flags.is_empty(), "{p:?} unreachable");
        for t in theta {
            angle_min = angle_min.min(t as f64);
            angle_max = angle_max.max(t as f64);
        }
        volume_min = volume_min.min(r.volume(a64(theta), p));
        // Largest arm torque per newton over all force directions: the largest row norm of Jᵀ,
        // i.e. the largest column norm of J.
        let j = r.jacobian_fd(a64(theta)).unwrap();
        for col in j.column_iter() {
            torque_per_newton_max = torque_per_newton_max.max(col.norm());
        }
        count += 1;
    }
    std::eprintln!(
        "design cylinder ({count} points): arm angles {:.1}..{:.1} deg, min forearm volume {:.3}, \
         max arm torque per newton {:.4} N·m/N",
        angle_min / DEG,
        angle_max / DEG,
        volume_min,
        torque_per_newton_max
    );
    // The figures documented on DeltaGeometry::OMEGA_LIKE.
    assert!(angle_min > -32.0 * DEG && angle_max < 95.0 * DEG);
    assert!(volume_min > 0.6);
    assert!(torque_per_newton_max < 0.115);
}

#[test]
fn non_finite_input_gives_zero_output_and_a_flag() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            G.forward::<Libm>([0.3, bad, 0.3]),
            (Vec3::ZERO, Flags::NON_FINITE_INPUT)
        );
        assert_eq!(
            G.inverse::<Libm>(Vec3::new(0.0, bad, -0.15)),
            ([0.0; 3], Flags::NON_FINITE_INPUT)
        );
        let p = Vec3::new(0.0, 0.0, -0.15);
        assert_eq!(
            G.joint_torques::<Libm>([0.3; 3], p, Vec3::new(bad, 0.0, 0.0)),
            ([0.0; 3], Flags::NON_FINITE_INPUT)
        );
        assert_eq!(
            G.joint_torques::<Libm>([bad; 3], p, Vec3::Z),
            ([0.0; 3], Flags::NON_FINITE_INPUT)
        );
        assert_eq!(
            G.jacobian::<Libm>([0.3; 3], Vec3::new(0.0, 0.0, bad)).1,
            Flags::NON_FINITE_INPUT
        );
    }
}

#[test]
fn unreachable_and_singular_configurations_are_flagged_with_zero_output() {
    // Forearms too short to close the loop: the spheres do not meet.
    let short = DeltaGeometry {
        forearm_m: 0.02,
        ..G
    };
    assert_eq!(
        short.forward::<Libm>([0.0, 0.5, 1.0]),
        (Vec3::ZERO, Flags::KINEMATICS_SINGULAR)
    );
    // A point far out of reach.
    assert_eq!(
        G.inverse::<Libm>(Vec3::new(0.0, 0.0, -1.0)),
        ([0.0; 3], Flags::KINEMATICS_SINGULAR)
    );
    // R_b = R_e and every arm straight down: all three sphere centres coincide (collinear).
    let degenerate = DeltaGeometry {
        effector_radius_m: G.base_radius_m,
        ..G
    };
    let down = core::f32::consts::FRAC_PI_2;
    assert_eq!(
        degenerate.forward::<Libm>([down; 3]),
        (Vec3::ZERO, Flags::KINEMATICS_SINGULAR)
    );
    // Effector in the plane of the (horizontal) sphere centres: the forearms are coplanar,
    // det J_x = 0, and no finite torque renders a vertical force.
    let theta = [0.4f32; 3];
    let plane = Vec3::new(0.0, 0.0, -G.upper_arm_m * libm::sinf(0.4));
    assert_eq!(
        G.joint_torques::<Libm>(theta, plane, Vec3::Z),
        ([0.0; 3], Flags::KINEMATICS_SINGULAR)
    );
    assert_eq!(
        G.jacobian::<Libm>(theta, plane),
        ([[0.0; 3]; 3], Flags::KINEMATICS_SINGULAR)
    );
    // A geometry with NaN inside (never validated) still gives finite, flagged output.
    let nan_geometry = DeltaGeometry {
        forearm_m: f32::NAN,
        ..G
    };
    let (p, f) = nan_geometry.forward::<Libm>([0.3; 3]);
    assert!(p.is_finite() && f.contains(Flags::KINEMATICS_SINGULAR));
    let (t, f) = nan_geometry.inverse::<Libm>(Vec3::new(0.0, 0.0, -0.15));
    assert!(all_finite(&t) && f.contains(Flags::KINEMATICS_SINGULAR));
    let (t, f) = nan_geometry.joint_torques::<Libm>([0.3; 3], Vec3::new(0.0, 0.0, -0.15), Vec3::Z);
    assert!(all_finite(&t) && f.contains(Flags::KINEMATICS_SINGULAR));
}

#[test]
fn huge_forces_never_produce_non_finite_torques() {
    let (theta, _) = G.inverse::<Libm>(DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M);
    let (p, _) = G.forward::<Libm>(theta);
    let (tau, flags) = G.joint_torques::<Libm>(theta, p, Vec3::new(3e38, -3e38, 3e38));
    assert!(all_finite(&tau));
    assert!(flags.is_empty() || flags == Flags::OUT_OF_RANGE);
}

#[test]
fn arm_grid_edges_stay_finite_for_every_backend() {
    // Far outside the working range (arms folded up, crossed): never NaN, whatever the flags.
    for k in -12..=12 {
        let a = k as f32 * 0.5;
        let angles = [a, -a, 0.5 * a];
        for (p, _) in [
            G.forward::<Libm>(angles),
            G.forward::<Fast>(angles),
            G.forward::<crate::math::Micromath>(angles),
        ] {
            assert!(p.is_finite(), "{angles:?}");
        }
    }
}

/// `pose` + `torques_at` (one evaluation of the arms' trigonometry) give exactly what `forward` and
/// `joint_torques` give separately, over the workspace, and agree on singular configurations.
#[test]
fn pose_matches_forward_and_joint_torques() {
    let g = DeltaGeometry::OMEGA_LIKE;
    let f = Vec3::new(1.0, -2.0, 3.0);
    let mut compared = 0;
    for i in 0..11 {
        for j in 0..11 {
            for k in 0..11 {
                let a = [
                    -0.6 + 0.2 * i as f32,
                    -0.6 + 0.2 * j as f32,
                    -0.6 + 0.2 * k as f32,
                ];
                let (p, pf) = g.forward::<Libm>(a);
                let (pose, flags) = g.pose::<Libm>(a);
                if !pf.is_empty() {
                    assert_eq!(flags, pf, "{a:?}");
                    continue;
                }
                assert_eq!(pose.effector_m, p);
                let (t1, f1) = g.joint_torques::<Libm>(a, p, f);
                let (t2, f2) = g.torques_at(&pose, f);
                assert_eq!((t1, f1), (t2, f2), "{a:?}");
                compared += 1;
            }
        }
    }
    assert!(compared > 500, "{compared}");
}

//! Per-step cost of the rolling contact update: each method × math backend, the same step written
//! with nalgebra (f64 and f32) as the peer a Rust user would reach for, all in the same run.
//!
//! `cargo bench -p host-sim --bench step`. Report ratios between rows of one run, not absolute
//! times.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::surface::Plane;
use softfinger_core::{Fast, Libm, Math, Micromath, Quat};
use std::hint::black_box;

/// The paper's per-sample increment Rz(0.05)·Ry(0.02)·Rx(0.03), applied body-fixed.
fn paper_samples(n: usize) -> Vec<Quat> {
    let inc = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.05)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.02)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.03);
    let mut q = UnitQuaternion::identity();
    (0..n)
        .map(|_| {
            q *= inc;
            Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32)
        })
        .collect()
}

fn bench_rolling<M: Math>(c: &mut Criterion, samples: &[Quat]) {
    let mut group = c.benchmark_group("rolling_step");
    for method in Method::ALL {
        group.bench_with_input(
            BenchmarkId::new(method.name(), M::NAME),
            &method,
            |b, &method| {
                let mut r = Rolling::new(Plane::default(), 0.01, Quat::IDENTITY, method);
                let mut k = 0usize;
                b.iter(|| {
                    let s = r.step::<M>(black_box(samples[k]));
                    k = (k + 1) % samples.len();
                    if k == 0 {
                        r = Rolling::new(Plane::default(), 0.01, Quat::IDENTITY, method);
                    }
                    black_box(s)
                });
            },
        );
    }
    group.finish();
}

/// The peer: what a user of nalgebra would write for the paper's algorithm: the relative rotation
/// as a `Rotation3` from axis and angle (Rodrigues), `euler_angles`, then eqs. (2)-(3). Generic over
/// the scalar so f64 and f32 run the same code.
fn nalgebra_rpy<T: nalgebra::RealField + Copy>(
    c: &mut Criterion,
    name: &str,
    qs: &[UnitQuaternion<T>],
) {
    let radius: T = nalgebra::convert(0.01);
    c.benchmark_group("rolling_step")
        .bench_function(BenchmarkId::new("nalgebra-rpy", name), |b| {
            let mut prev = UnitQuaternion::<T>::identity();
            let mut p = Vector3::<T>::zeros();
            let mut k = 0usize;
            b.iter(|| {
                let q = black_box(qs[k]);
                let dq = q * prev.inverse();
                let rot = match dq.axis_angle() {
                    Some((axis, angle)) => Rotation3::from_axis_angle(&axis, angle),
                    None => Rotation3::identity(),
                };
                let (psi, theta, _phi) = rot.euler_angles();
                p += Vector3::new(radius * theta, -radius * psi, T::zero());
                prev = q;
                k += 1;
                if k == qs.len() {
                    k = 0;
                }
                black_box(p)
            });
        });
}

/// The exact method written with nalgebra in f64: `scaled_axis` of the increment.
fn nalgebra_exact(c: &mut Criterion, q64: &[UnitQuaternion<f64>]) {
    c.benchmark_group("rolling_step").bench_function(
        BenchmarkId::new("nalgebra-exact", "f64"),
        |b| {
            let mut prev = UnitQuaternion::identity();
            let mut p = Vector3::<f64>::zeros();
            let mut k = 0usize;
            b.iter(|| {
                let q = black_box(q64[k]);
                let w = (q * prev.inverse()).scaled_axis();
                p += Vector3::new(0.01 * w.y, -0.01 * w.x, 0.0);
                prev = q;
                k += 1;
                if k == q64.len() {
                    k = 0;
                }
                black_box(p)
            });
        },
    );
}

fn bench_nalgebra(c: &mut Criterion, samples: &[Quat]) {
    let q64: Vec<UnitQuaternion<f64>> = samples
        .iter()
        .map(|q| {
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q.w as f64, q.x as f64, q.y as f64, q.z as f64,
            ))
        })
        .collect();
    let q32: Vec<UnitQuaternion<f32>> = samples
        .iter()
        .map(|q| UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w, q.x, q.y, q.z)))
        .collect();
    nalgebra_rpy(c, "f64", &q64);
    nalgebra_rpy(c, "f32", &q32);
    nalgebra_exact(c, &q64);
}

fn benches(c: &mut Criterion) {
    let samples = paper_samples(100);
    bench_rolling::<Libm>(c, &samples);
    bench_rolling::<Fast>(c, &samples);
    bench_rolling::<Micromath>(c, &samples);
    bench_nalgebra(c, &samples);
}

criterion_group!(step, benches);
criterion_main!(step);

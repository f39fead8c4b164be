//! `host-sim validate` and `host-sim chart`, in-process: the accuracy claims of the paper's §3.1
//! reproduction, the JSON layout scripts rely on, and the SVG files. Accuracy only: speed is measured by
//! `cargo bench -p host-sim --bench reference` and printed by the commands, never asserted here.

use host_sim::experiments::validate::ours::{Backend, Variant};
use host_sim::experiments::validate::{closed_form, reference_for, run_ours, TARGET_MM};
use host_sim::sim::reference::scene::{paper_scene, paper_scene_at_rate, Scene};
use host_sim::sim::reference::ReferencePaths;
use softfinger_core::contact::decompose::Method;
use std::fs;
use std::path::PathBuf;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softfinger-validate-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// Largest error (mm) per path of `variant` on `scene` against `reference`: (plane, sphere).
fn worst_mm(variant: Variant, scene: &Scene, reference: &ReferencePaths) -> (f64, f64) {
    let e = run_ours(variant, scene, reference).errors;
    let max = |a: [f64; 3]| a.into_iter().fold(0.0f64, f64::max);
    (max(e.plane_mm), max(e.sphere_mm))
}

fn exact(backend: Backend) -> Variant {
    Variant {
        method: Method::Exact,
        backend,
    }
}

/// The exact method in f32 on the paper's scene (100 Hz) against the RK45 reference. Measured with
/// both backends: plane path 5.26e-6 mm, sphere path 2.13e-6 mm (f32 rounding of ~10 mm
/// coordinates over 100 steps; the scene's steps are below 0.39 rad, so both backends run the same
/// series branch). Bounds about 3x: 1.6e-5 mm and 6.4e-6 mm, well inside the project's 0.001 mm
/// target.
#[test]
fn exact_method_meets_the_accuracy_target_on_the_paper_scene() {
    let scene = paper_scene();
    let closed = closed_form(&scene).unwrap();
    let reference = reference_for(&scene, &closed).unwrap();
    const PLANE_MM: f64 = 1.6e-5;
    const SPHERE_MM: f64 = 6.4e-6;
    const { assert!(PLANE_MM < TARGET_MM && SPHERE_MM < TARGET_MM) };
    for backend in [Backend::Libm, Backend::Fast] {
        let v = exact(backend);
        let (plane, sphere) = worst_mm(v, &scene, &reference.paths);
        assert!(plane <= PLANE_MM, "{} plane {plane:e} mm", v.name());
        assert!(sphere <= SPHERE_MM, "{} sphere {sphere:e} mm", v.name());
    }
    // The first-order rpy method: measured 0.74428 mm (FINDINGS.md: ~0.74 mm in f64). A reproduced
    // figure, pinned to ±1 % (its f32 rounding, ~1e-5 mm, is far inside; a change of the method's
    // first-order term is not).
    let rpy = Variant {
        method: Method::Rpy,
        backend: Backend::Libm,
    };
    let (plane, _) = worst_mm(rpy, &scene, &reference.paths);
    assert!((plane - 0.7443).abs() < 0.01 * 0.7443, "rpy {plane} mm");
}

/// The paper's motion sampled at 20 kHz (20 000 steps of ~2 µm onto ~10 mm coordinates) against
/// host-sim's closed form: the plane's Kahan-compensated contact point. Measured with Kahan:
/// plane 3.41e-5 mm, sphere 3.07e-6 mm (both backends); bounds 3x: 1e-4 mm and 9.2e-6 mm.
/// With plain f32 summation (the compensation removed from `core/src/contact/surface.rs`) the plane path
/// measured 3.51e-3 mm (when this test was written): it fails then, 35x above the bound.
#[test]
fn plane_path_stays_compensated_over_twenty_thousand_steps() {
    let scene = paper_scene_at_rate(20_000.0);
    assert_eq!(scene.samples.len(), 20_001);
    let closed = closed_form(&scene).unwrap();
    for backend in [Backend::Libm, Backend::Fast] {
        let v = exact(backend);
        let (plane, sphere) = worst_mm(v, &scene, &closed);
        assert!(plane <= 1e-4, "{} plane {plane:e} mm", v.name());
        assert!(sphere <= 9.2e-6, "{} sphere {sphere:e} mm", v.name());
    }
}

/// The reference (RK45 at rtol 1e-12) against the closed form on every axis. Measured: largest
/// per-axis error 6.33e-12 mm on the plane path, 1.93e-12 mm on the sphere path; largest point
/// distance 6.34e-12 mm (plane) and 2.13e-12 mm (sphere). Bounds 3x each. (Useful to validate
/// f32 methods, whose errors are ≥ 1e-6 mm.)
#[test]
fn reference_agrees_with_the_closed_form() {
    let scene = paper_scene();
    let closed = closed_form(&scene).unwrap();
    let r = reference_for(&scene, &closed).unwrap();
    assert_eq!(r.paths.plane.len(), 101);
    let worst = |axes: [f64; 3]| axes.into_iter().fold(0.0, f64::max);
    assert!(worst(r.errors.plane_mm) < 1.9e-11, "{:?}", r.errors);
    assert!(worst(r.errors.sphere_mm) < 5.8e-12, "{:?}", r.errors);
    assert!(r.max_distance_mm.0 < 1.9e-11 && r.max_distance_mm.1 < 6.4e-12);
}

#[test]
fn json_output_has_our_rows_and_the_rk45_rows() {
    let text = host_sim::experiments::validate::render(&host_sim::experiments::validate::Args {
        json: true,
        quick: true,
    })
    .unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = doc["methods"].as_array().expect("methods array");
    let names: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    // Every method x backend of ours.
    for m in ["exact", "rpy", "paper-verbatim"] {
        for b in host_sim::sim::backend::Backend::ALL {
            assert!(
                names.contains(&format!("{m}/{b}").as_str()),
                "{m}/{b} in {names:?}"
            );
        }
    }
    // The classical rows: the reference, ode45 defaults (three call styles) and matched accuracy.
    for n in [
        "rk45-reference/restart",
        "rk45-ode45-defaults/restart",
        "rk45-ode45-defaults/per-sample-call",
        "rk45-ode45-defaults/single-call",
    ] {
        assert!(names.contains(&n), "{n} in {names:?}");
    }
    assert!(names.iter().any(|n| n.starts_with("rk45-matched/")));
    for r in rows {
        for key in ["plane_max_error_mm", "sphere_max_error_mm"] {
            let a = r[key].as_array().expect(key);
            assert_eq!(a.len(), 3);
            assert!(a.iter().all(|v| v.as_f64().is_some_and(|x| x >= 0.0)));
        }
        assert!(r["ns_per_step"].as_f64().is_some_and(|x| x > 0.0));
        let rk45 = r["method"].as_str().unwrap().starts_with("rk45");
        assert_eq!(r["rtol"].is_number(), rk45);
    }
    // The ode45 defaults row has Matlab's tolerances; the best is an exact variant.
    let d = rows
        .iter()
        .find(|r| r["method"] == "rk45-ode45-defaults/single-call")
        .unwrap();
    assert_eq!(
        (d["rtol"].as_f64(), d["atol"].as_f64()),
        (Some(1e-3), Some(1e-6))
    );
    assert!(doc["best"].as_str().unwrap().starts_with("exact/"));
}

#[test]
fn validate_command_exits_zero() {
    assert_eq!(host_sim::cli::run(["host-sim", "validate", "--quick"]), 0);
}

#[test]
fn chart_writes_its_svgs_and_skips_the_mcu_chart_without_json() {
    let dir = tmpdir("chart");
    let missing = dir.join("no-such-mcu-bench.json");
    let code = host_sim::cli::run([
        "host-sim",
        "chart",
        "--quick",
        // Two rates (RK45 runs at every rate; 20 kHz takes minutes in a debug build).
        "--rates-hz",
        "100,1000",
        "--out",
        dir.to_str().unwrap(),
        "--mcu-json",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    for (file, must_contain) in [
        ("speed-accuracy.svg", "Pareto front"),
        ("fig3-trajectories.svg", "Fig. 3"),
    ] {
        let svg = fs::read_to_string(dir.join(file)).unwrap();
        assert!(svg.starts_with("<svg"), "{file}");
        assert!(svg.contains(must_contain), "{file} mentions {must_contain}");
        assert!(
            svg.contains("exact/libm"),
            "{file} has the exact/libm legend"
        );
    }
    assert!(!dir.join("mcu-speed-accuracy.svg").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn chart_draws_the_mcu_chart_from_mcu_bench_json() {
    let dir = tmpdir("mcu");
    let json = dir.join("mcu-bench.json");
    // The layout of `scripts/mcu-bench --json`; entries the chart does not use are ignored.
    fs::write(
        &json,
        r#"[{"name": "rolling_plane_exact", "backend": "libm", "instructions": 412},
            {"name": "rolling_plane_rpy", "backend": "micromath", "instructions": 391},
            {"name": "contact_step", "backend": "fast", "instructions": 902},
            {"name": "sin", "backend": "libm", "instructions": 1240}]"#,
    )
    .unwrap();
    let r =
        host_sim::experiments::speed_accuracy::run(&host_sim::experiments::speed_accuracy::Args {
            out: dir.clone(),
            mcu_json: Some(json),
            quick: true,
            rates_hz: Some(vec![100.0]),
        })
        .unwrap();
    let mcu = r.mcu.expect("MCU points");
    assert_eq!(mcu.len(), 3);
    // Each point carries its variant's error on the 100 Hz scene: exact/libm within the target.
    assert!(mcu[0].error_mm <= TARGET_MM && mcu[1].error_mm > 0.1);
    let svg = fs::read_to_string(dir.join("mcu-speed-accuracy.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("instructions per step"));
    // 9 variants at one rate plus the two RK45 curves of 10 tolerances.
    assert_eq!(r.points.len(), 9 + 20);
    assert!(!r.front.is_empty());
    let _ = fs::remove_dir_all(&dir);
}

//! `host-sim validate` and `host-sim chart`, in-process: the accuracy claims of the paper's §3.1
//! reproduction, the JSON layout scripts rely on, and the SVG files. Accuracy only: speed is measured by
//! `cargo bench -p host-sim --bench reference` and printed by the commands, never asserted here.

use host_sim::reference::scene::paper_scene;
use host_sim::validate::ours::{Backend, Variant};
use host_sim::validate::{closed_form, reference_for, run_ours, TARGET_MM};
use softfinger_core::decompose::Method;
use std::fs;
use std::path::PathBuf;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softfinger-validate-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// The exact method in f32 meets the project's 0.001 mm target on the paper's scene, on every axis of
/// both paths, with Libm and with Fast. The measured error is ~5e-6 mm (f32 rounding of ~10 mm
/// coordinates, ulp ≈ 1e-6 mm, over 100 steps), so the bound has a margin of ~200x yet still fails for
/// the rpy method (0.74 mm) or any real mistake in the rolling update.
#[test]
fn exact_method_meets_the_accuracy_target_on_the_paper_scene() {
    let scene = paper_scene();
    let closed = closed_form(&scene).unwrap();
    let reference = reference_for(&scene, &closed).unwrap();
    for backend in [Backend::Libm, Backend::Fast] {
        let v = Variant {
            method: Method::Exact,
            backend,
        };
        let run = run_ours(v, &scene, &reference.paths);
        for (path, e) in [
            ("plane", run.errors.plane_mm),
            ("sphere", run.errors.sphere_mm),
        ] {
            for (axis, &err) in ["x", "y", "z"].iter().zip(&e) {
                assert!(
                    err <= TARGET_MM,
                    "{} {path} {axis}: {err:e} mm > {TARGET_MM} mm",
                    v.name()
                );
            }
        }
    }
    // The bound is not vacuous: the first-order rpy method misses it by far (FINDINGS.md: ~0.74 mm).
    let rpy = Variant {
        method: Method::Rpy,
        backend: Backend::Libm,
    };
    assert!(run_ours(rpy, &scene, &reference.paths).errors.max_mm() > 0.1);
}

/// The reference (RK45 at rtol 1e-12) agrees with the closed form within 1e-9 mm (1e-12 m) on every
/// axis: the reference module measured ~6e-12 mm, and the reference is only useful to validate f32
/// methods (errors ≥ 1e-6 mm) if it is orders of magnitude better than that.
#[test]
fn reference_agrees_with_the_closed_form() {
    let scene = paper_scene();
    let closed = closed_form(&scene).unwrap();
    let r = reference_for(&scene, &closed).unwrap();
    assert_eq!(r.paths.plane.len(), 101);
    assert!(r.errors.max_mm() < 1e-9, "{:?}", r.errors);
    assert!(r.max_distance_mm.0 < 1e-9 && r.max_distance_mm.1 < 1e-9);
}

#[test]
fn json_output_has_our_rows_and_the_rk45_rows() {
    let text = host_sim::validate::render(&host_sim::validate::Args {
        json: true,
        quick: true,
    })
    .unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = doc["methods"].as_array().expect("methods array");
    let names: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    // Every method x backend of ours.
    for m in ["exact", "rpy", "paper-verbatim"] {
        for b in ["libm", "fast", "micromath"] {
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
    assert_eq!(doc["paper"]["speedup"].as_f64(), Some(35.0));
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
    let r = host_sim::chart::run(&host_sim::chart::Args {
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

//! `host-sim replay`: round trips against the closed form, and every bad-input error.

use nalgebra::{UnitQuaternion, Vector3};
use std::fs;
use std::path::{Path, PathBuf};

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softfinger-replay-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn run(input: &Path, out: &Path, extra: &[&str]) -> u8 {
    let mut argv = vec![
        "host-sim",
        "replay",
        "--input",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    argv.extend_from_slice(extra);
    host_sim::cli::run(argv)
}

fn write_quats(path: &Path, qs: &[(f64, UnitQuaternion<f64>)]) {
    let mut s = String::from("t_s,qw,qx,qy,qz\n");
    for (t, q) in qs {
        s += &format!("{t},{},{},{},{}\n", q.w, q.i, q.j, q.k);
    }
    fs::write(path, s).unwrap();
}

fn read_rows(path: &Path) -> Vec<Vec<String>> {
    let text = fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        host_sim::experiments::replay::OUTPUT_HEADER
    );
    lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// A smooth roll-and-spin trajectory replayed with `exact` matches the closed form computed here
/// in f64 (plane point += R·(w_y, −w_x) with w = log(q[k+1]·q[k]⁻¹); sphere point = q[k]⁻¹·(0,0,−R))
/// over 2000 samples: each f32 step adds ~1e-10 m of rounding (see the core's rolling tests);
/// measured at most 3.1e-9 m (bounds below, 3× each coordinate's measurement).
#[test]
fn exact_replay_matches_the_closed_form() {
    let dir = tmpdir("roundtrip");
    let r = 0.01;
    let qs: Vec<(f64, UnitQuaternion<f64>)> = (0..2000)
        .map(|k| {
            let t = k as f64 * 1e-3;
            (
                t,
                UnitQuaternion::from_euler_angles(
                    0.5 * (2.0 * t).sin(),
                    0.3 * t,
                    0.8 * (1.5 * t).sin(),
                ),
            )
        })
        .collect();
    write_quats(&dir.join("in.csv"), &qs);
    assert_eq!(run(&dir.join("in.csv"), &dir.join("out.csv"), &[]), 0);
    let rows = read_rows(&dir.join("out.csv"));
    assert_eq!(rows.len(), qs.len());
    let mut plane = Vector3::zeros();
    for (k, row) in rows.iter().enumerate() {
        if k > 0 {
            let w = (qs[k].1 * qs[k - 1].1.inverse()).scaled_axis();
            plane += Vector3::new(r * w.y, -r * w.x, 0.0);
        }
        let sphere = qs[k].1.inverse() * Vector3::new(0.0, 0.0, -r);
        let got: Vec<f64> = row[1..8].iter().map(|v| v.parse().unwrap()).collect();
        // Measured at worst over the 2000 rows (m): plane 3.1e-9 in x, 2.8e-9 in y; sphere 1.7e-9,
        // 1.4e-9, 1.4e-9. Bounds 3× each.
        assert!(
            (got[0] - plane.x).abs() < 9.3e-9 && (got[1] - plane.y).abs() < 8.3e-9,
            "row {k}: {row:?} vs {plane:?}"
        );
        for (i, bound) in [5.1e-9, 4.2e-9, 4.2e-9].into_iter().enumerate() {
            assert!((got[2 + i] - sphere[i]).abs() < bound, "row {k} sphere {i}");
        }
        assert_eq!(row[8], "rolling");
    }
    // Row 0 is the initial contact: plane (0, 0), sphere R₀ᵀ(0, 0, −R).
    assert_eq!(&rows[0][1..3], &["0", "0"]);
}

/// Pure spin rows are where paper-verbatim fails: they are named `singular`, and nothing written
/// is NaN or inf.
#[test]
fn paper_verbatim_singular_rows_are_named_and_finite() {
    let dir = tmpdir("singular");
    let qs: Vec<(f64, UnitQuaternion<f64>)> = (0..50)
        .map(|k| {
            (
                k as f64 * 0.01,
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.02 * k as f64),
            )
        })
        .collect();
    write_quats(&dir.join("in.csv"), &qs);
    assert_eq!(
        run(
            &dir.join("in.csv"),
            &dir.join("out.csv"),
            &["--method", "paper-verbatim"]
        ),
        0
    );
    let rows = read_rows(&dir.join("out.csv"));
    assert!(rows[1..].iter().all(|r| r[8] == "singular"));
    for r in &rows {
        for v in &r[1..8] {
            assert!(v.parse::<f64>().unwrap().is_finite());
        }
    }
    // The exact method on the same input: rolling, and the spin accumulates 0.02 rad per step.
    assert_eq!(
        run(
            &dir.join("in.csv"),
            &dir.join("out2.csv"),
            &["--method", "exact"]
        ),
        0
    );
    let rows = read_rows(&dir.join("out2.csv"));
    // Measured 1.6e-7 rad off 49 × 0.02 (f32 accumulation); bound 3×.
    let spin: f64 = rows[49][6].parse().unwrap();
    assert!((spin - 0.98).abs() < 4.8e-7, "spin {spin}");
}

/// Each bad input: exit code 2, no output file (not even a temporary one), and the message names
/// the line (checked on the library's error text).
#[test]
fn bad_inputs_are_rejected_with_the_line_and_leave_nothing() {
    let cases: &[(&str, &str, &str)] = &[
        ("missing header", "0,1,0,0,0\n", "line 1"),
        ("wrong header", "t,qw,qx,qy,qz\n0,1,0,0,0\n", "line 1"),
        (
            "non-numeric",
            "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,abc,0,0,0\n",
            "line 3",
        ),
        (
            "nan",
            "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,NaN,0,0,0\n",
            "line 3",
        ),
        (
            "inf",
            "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,inf,0,0\n",
            "line 3",
        ),
        ("zero quaternion", "t_s,qw,qx,qy,qz\n0,0,0,0,0\n", "line 2"),
        (
            "non-unit",
            "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1.01,0,0,0\n",
            "line 3",
        ),
        (
            "time goes back",
            "t_s,qw,qx,qy,qz\n0.2,1,0,0,0\n0.1,1,0,0,0\n",
            "line 3",
        ),
        (
            "short row",
            "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0\n",
            "line 3",
        ),
        ("header only", "t_s,qw,qx,qy,qz\n", "no samples"),
    ];
    for (name, text, needle) in cases {
        let dir = tmpdir(&name.replace(' ', "-"));
        let input = dir.join("in.csv");
        fs::write(&input, text).unwrap();
        let out = dir.join("out.csv");
        assert_eq!(run(&input, &out, &[]), 2, "case {name}");
        let leftovers: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(
            leftovers.len(),
            1,
            "case {name}: only the input remains, found {leftovers:?}"
        );
        let err = host_sim::experiments::replay::read_samples(&input)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(needle),
            "case {name}: '{err}' should name '{needle}'"
        );
    }
    // A norm within 1e-3 of unity is accepted and normalised.
    let dir = tmpdir("near-unit");
    fs::write(dir.join("in.csv"), "t_s,qw,qx,qy,qz\n0,1.0005,0,0,0\n").unwrap();
    assert_eq!(run(&dir.join("in.csv"), &dir.join("out.csv"), &[]), 0);
    // A missing input file.
    let dir = tmpdir("missing");
    assert_eq!(run(&dir.join("nope.csv"), &dir.join("out.csv"), &[]), 2);
    assert!(!dir.join("out.csv").exists());
}

fn column(rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let header: Vec<&str> = host_sim::experiments::replay::OUTPUT_HEADER
        .split(',')
        .collect();
    let i = header.iter().position(|h| *h == name).unwrap();
    rows.iter().map(|r| r[i].parse().unwrap()).collect()
}

/// `--surface` on every object against host-sim's Montana-form reference (Montana's contact
/// equations integrated by RK45 at rtol 1e-12, f64, importing nothing from the core; itself within
/// 4.7e-12 mm of the Cartesian RK45 of the rolling constraint), 10 s at 1 kHz, r = 10 mm,
/// R = 50 mm. Measured here, object / fingertip path: plane 3.30e-5 / 6.86e-6 mm, sphere
/// 1.379e-4 / 3.09e-5 mm, bowl 1.156e-4 / 2.60e-5 mm, cylinder 3.56e-5 / 6.64e-6 mm (the same as
/// `host-sim validate` on the same motion). Bounds 3× each, all inside the 0.001 mm
/// target.
#[test]
fn every_surface_follows_the_rolling_reference() {
    use host_sim::experiments::validate::surfaces::samples;
    use host_sim::sim::reference::{reference_paths_on, Ground, ReferenceMethod};
    let dir = tmpdir("surfaces");
    let s = samples();
    let qs: Vec<(f64, UnitQuaternion<f64>)> = s
        .iter()
        .enumerate()
        .map(|(k, q)| (k as f64 * 1e-3, *q))
        .collect();
    write_quats(&dir.join("in.csv"), &qs);
    let method = ReferenceMethod::Rk45 {
        rtol: 1e-12,
        atol: 1e-14,
    };
    for (name, ground, object_mm, finger_mm) in [
        ("plane", Ground::Plane, 1e-4, 2.1e-5),
        ("sphere", Ground::Sphere { radius: 0.05 }, 4.1e-4, 9.3e-5),
        ("bowl", Ground::Bowl { radius: 0.05 }, 3.5e-4, 7.8e-5),
        ("cylinder", Ground::Cylinder { radius: 0.05 }, 1.1e-4, 2e-5),
    ] {
        let out = dir.join(format!("{name}.csv"));
        let args = ["--surface", name, "--object-radius-m", "0.05"];
        assert_eq!(run(&dir.join("in.csv"), &out, &args), 0, "{name}");
        let rows = read_rows(&out);
        let reference = reference_paths_on(ground, method, &s, 1e-3, 0.01).unwrap();
        let cols = |p: &str| {
            let x = column(&rows, &format!("{p}_x_m"));
            let y = column(&rows, &format!("{p}_y_m"));
            let z = column(&rows, &format!("{p}_z_m"));
            (x, y, z)
        };
        for (p, r, bound) in [
            ("object", &reference.plane, object_mm),
            ("finger", &reference.sphere, finger_mm),
        ] {
            let (x, y, z) = cols(p);
            let worst = (0..rows.len())
                .map(|k| {
                    let e = [x[k] - r[k][0], y[k] - r[k][1], z[k] - r[k][2]];
                    1e3 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()
                })
                .fold(0.0, f64::max);
            assert!(worst < bound, "{name} {p}: {worst:e} mm");
            assert!(worst > 0.0, "{name} {p}: an f32 path cannot be exact");
        }
        // The old columns: plane_x/y are the object point's x/y, sphere_* the fingertip point.
        assert_eq!(column(&rows, "plane_x_m"), column(&rows, "object_x_m"));
        assert_eq!(column(&rows, "sphere_z_m"), column(&rows, "finger_z_m"));
    }
    // The start conventions: (0, 0, R) on the sphere and the cylinder, (0, 0, −R) in the bowl.
    for (name, z0) in [
        ("sphere", 0.05),
        ("bowl", -0.05),
        ("cylinder", 0.05),
        ("plane", 0.0),
    ] {
        let rows = read_rows(&dir.join(format!("{name}.csv")));
        assert_eq!(column(&rows, "object_z_m")[0], z0, "{name}");
    }
}

/// No creep at rest, through the command: identical samples leave every column of every row equal
/// to row 0's; a fingertip dithering between two orientations one wrist count apart (about a
/// tangent axis and about the normal, 10 000 samples) is back exactly where it started on every
/// even row. Every surface; the plane with every method.
#[test]
fn a_fingertip_at_rest_does_not_creep() {
    let dir = tmpdir("creep");
    let q = UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3);
    let count = std::f64::consts::TAU / 4096.0;
    let tilt = q * UnitQuaternion::from_euler_angles(count, 0.0, 0.0);
    let twist = q * UnitQuaternion::from_euler_angles(0.0, 0.0, count);
    let same: Vec<_> = (0..10_000).map(|k| (k as f64 * 1e-4, q)).collect();
    let dither: Vec<_> = (0..10_000)
        .map(|k| {
            let d = [q, tilt, q, twist][k % 4];
            (k as f64 * 1e-4, d)
        })
        .collect();
    write_quats(&dir.join("same.csv"), &same);
    write_quats(&dir.join("dither.csv"), &dither);
    let mut cases = vec![];
    for m in ["exact", "rpy", "paper-verbatim"] {
        cases.push(vec!["--method", m]);
    }
    for s in ["sphere", "bowl", "cylinder"] {
        cases.push(vec!["--surface", s]);
    }
    for extra in cases {
        let out = dir.join("out.csv");
        assert_eq!(run(&dir.join("same.csv"), &out, &extra), 0);
        let rows = read_rows(&out);
        for r in &rows {
            // Every number (the state column may name the paper's singularity).
            assert_eq!(r[1..8], rows[0][1..8], "{extra:?} identical samples");
            assert_eq!(r[9..], rows[0][9..], "{extra:?} identical samples");
        }
        // Exact on every surface with the exact method; the Euler methods on the plane.
        assert_eq!(run(&dir.join("dither.csv"), &out, &extra), 0);
        let rows = read_rows(&out);
        // The paper's printed equations turn a one-count tilt into a spin of about π/2, which
        // slips the torsion spring: it keeps its offset (friction), so its torque (column 7) does
        // not return; the contact points and the spin do.
        let last = if extra[1] == "paper-verbatim" { 7 } else { 8 };
        for r in rows.iter().step_by(2) {
            assert_eq!(r[1..last], rows[0][1..last], "{extra:?} dither");
            assert_eq!(r[9..], rows[0][9..], "{extra:?} dither");
        }
        // It did move in between (the check above is not vacuous).
        assert_ne!(rows[1][1..3], rows[0][1..3], "{extra:?}");
    }
}

#[test]
fn bad_object_radius_is_rejected() {
    let dir = tmpdir("radius");
    let q = UnitQuaternion::identity();
    write_quats(&dir.join("in.csv"), &[(0.0, q), (0.001, q)]);
    let out = dir.join("out.csv");
    for args in [
        ["--surface", "sphere", "--object-radius-m", "0"],
        ["--surface", "sphere", "--object-radius-m", "inf"],
        ["--surface", "cylinder", "--object-radius-m", "-0.05"],
        ["--surface", "bowl", "--object-radius-m", "0.01"],
        ["--surface", "sphere", "--object-radius-m", "nan"],
    ] {
        assert_eq!(run(&dir.join("in.csv"), &out, &args), 2, "{args:?}");
        assert!(!out.exists(), "{args:?}: nothing written");
    }
    assert_eq!(run(&dir.join("in.csv"), &out, &["--surface", "dish"]), 2);
    // Just above the bowl's limit (R > r = 0.01) is accepted.
    let ok = ["--surface", "bowl", "--object-radius-m", "0.0101"];
    assert_eq!(run(&dir.join("in.csv"), &out, &ok), 0);
}

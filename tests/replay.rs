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
    assert_eq!(lines.next().unwrap(), host_sim::replay::OUTPUT_HEADER);
    lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// A smooth roll-and-spin trajectory replayed with `exact` matches the closed form computed here
/// in f64 (plane point += R·(w_y, −w_x) with w = log(q[k+1]·q[k]⁻¹); sphere point = q[k]⁻¹·(0,0,−R))
/// within 1e-7 m over 2000 samples: each f32 step adds ~1e-10 m of rounding (see the core's
/// rolling tests), so 2000 steps stay two orders of magnitude inside.
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
        assert!(
            (got[0] - plane.x).abs() < 1e-7 && (got[1] - plane.y).abs() < 1e-7,
            "row {k}: {row:?} vs {plane:?}"
        );
        for i in 0..3 {
            assert!((got[2 + i] - sphere[i]).abs() < 1e-7, "row {k} sphere {i}");
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
    let spin: f64 = rows[49][6].parse().unwrap();
    assert!((spin - 0.98).abs() < 1e-5, "spin {spin}");
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
        let err = host_sim::replay::read_samples(&input).unwrap_err();
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

//! `host-sim grasp` from the command line: the JSON it prints, and bad options rejected with one
//! line naming the option, exit 2, nothing written.

use std::process::Command;

fn host_sim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("softfinger-grasp-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn json_has_the_fields_the_issue_names_and_the_charts_are_written() {
    let out = tmp("json");
    let o = host_sim()
        .args([
            "grasp",
            "--json",
            "--duration-s",
            "0.4",
            "--sweep-points",
            "0",
            "--torque-nm",
            "0.01",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["held"], serde_json::Value::Bool(true));
    for k in ["slip_mm", "rotation_rad"] {
        assert!(v[k].as_f64().unwrap() >= 0.0, "{k}");
    }
    for k in ["tau_max_nm", "f_max_n"] {
        let a = v[k].as_array().unwrap();
        assert_eq!(a.len(), 2);
        assert!(a.iter().all(|x| x.as_f64().unwrap() > 0.0), "{k}");
    }
    // f_max = mu_s * F_grip at the defaults (0.8 * 5 N).
    assert!((v["f_max_n"][0].as_f64().unwrap() - 4.0).abs() < 1e-5);
    for f in [
        "pose.svg",
        "contacts.svg",
        "limit_surface.svg",
        "index.html",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_options_are_named_exit_2_and_write_nothing() {
    for (flag, value, names) in [
        ("--mass-kg", "0", "--mass-kg"),
        ("--mass-kg", "NaN", "--mass-kg"),
        ("--grip-n", "-1", "--grip-n"),
        ("--mu-s", "inf", "--mu-s"),
        ("--torque-nm", "NaN", "--torque-nm"),
        ("--duration-s", "0", "--duration-s"),
    ] {
        let out = tmp("bad");
        let o = host_sim()
            .args(["grasp", &format!("{flag}={value}")])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{flag} {value}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(names) && err.lines().count() == 1,
            "{flag} {value}: {err}"
        );
        assert!(!out.exists(), "{flag} {value}: output written");
    }
    let o = host_sim()
        .args(["grasp", "--torsion", "maybe"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}

/// Part 5's chart: the twist sweep holds both cases, torsion on and off, against the combined
/// limit; the JSON's sweep has both series, torsion on held at zero torque, torsion off turned at
/// its first non-zero torque.
#[test]
fn the_twist_sweep_chart_shows_torsion_on_and_off() {
    let out = tmp("sweep");
    let o = host_sim()
        .args([
            "grasp",
            "--json",
            "--sweep-points",
            "3",
            "--duration-s",
            "0.6",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(out.join("twist_sweep.svg")).unwrap();
    for s in [
        "torsion on (soft fingers)",
        "torsion off (point contacts)",
        "2 tau_max",
    ] {
        assert!(svg.contains(s), "{s}");
    }
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let sweep = &v["twist_sweep"];
    let (on, off) = (
        sweep["torsion_on"].as_array().unwrap(),
        sweep["torsion_off"].as_array().unwrap(),
    );
    assert_eq!((on.len(), off.len()), (3, 3));
    assert_eq!(on[0]["held"], serde_json::Value::Bool(true));
    assert_eq!(off[1]["held"], serde_json::Value::Bool(false));
    let _ = std::fs::remove_dir_all(&out);
}

/// The device options are checked before anything runs: named, exit 2, nothing written.
#[test]
fn bad_device_options_are_named_exit_2_and_write_nothing() {
    for (flag, value) in [
        ("--model-hz", "99"),
        ("--model-hz", "300"),
        ("--latency-ms", "-1"),
        ("--latency-ms", "NaN"),
    ] {
        let out = tmp("bad-dev");
        let o = host_sim()
            .args(["grasp", "--plant", "devices", &format!("{flag}={value}")])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{flag} {value}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(flag), "{flag} {value}: {err}");
        assert!(!out.exists(), "{flag} {value}: output written");
    }
}

//! `host-sim stability` end to end: a short run exits 0 and writes every chart and the summary.

use std::fs;
use std::path::{Path, PathBuf};

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "softfinger-stability-{name}-{}",
        std::process::id()
    ));
    let _ = fs::remove_dir_all(&d);
    d
}

/// `host-sim stability --out DIR OPTIONS...`: the exit code.
fn stability(dir: &Path, options: &[&str]) -> u8 {
    let out = dir.to_str().unwrap();
    let argv = ["host-sim", "stability", "--out", out];
    host_sim::cli::run(argv.iter().chain(options))
}

/// The charts the command promises, each a non-trivial SVG document.
const CHARTS: [&str; 8] = [
    "decomp_map.svg",
    "decomp_worst_error.svg",
    "drift.svg",
    "haptic_kmax.svg",
    "haptic_energy.svg",
    "haptic_kmax_timing.svg",
    "haptic_impact.svg",
    "chatter.svg",
];

#[test]
fn short_run_writes_every_chart_and_the_tables() {
    // The output folder does not exist yet: the command creates it.
    let dir = tmpdir("short").join("nested");
    let code = stability(
        &dir,
        &[
            "--drift-steps",
            "10000",
            "--haptic-seconds",
            "2",
            "--skip-closed-loop",
            "--chatter-steps",
            "20000",
        ],
    );
    assert_eq!(code, 0);
    for name in CHARTS {
        let text = fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            text.starts_with("<svg") && text.trim_end().ends_with("</svg>"),
            "{name}"
        );
        assert!(
            text.contains("<text"),
            "{name}: axis labels and legends are text"
        );
    }
    let summary = fs::read_to_string(dir.join("summary.txt")).unwrap();
    for part in ["Part 1.", "Part 2.", "Part 3.", "Part 4."] {
        assert!(summary.contains(part), "summary lacks {part}");
    }
    assert!(summary.contains("10000 steps"));
    // index.html shows every chart and links the summary.
    let html = fs::read_to_string(dir.join("index.html")).unwrap();
    for name in CHARTS {
        assert!(
            html.contains(&format!("<img src=\"{name}\"")),
            "{name} not on the page"
        );
    }
    assert!(html.contains("<a href=\"summary.txt\">"));
}

#[test]
fn bad_options_exit_2_and_write_nothing() {
    let dir = tmpdir("bad");
    let code = stability(&dir, &["--drift-steps", "0"]);
    assert_eq!(code, 2);
    assert!(!dir.exists());
}

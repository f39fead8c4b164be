//! `host-sim run`'s, `chart`'s and `stability`'s `index.html`, opened in a headless browser: every
//! chart the command wrote is on the page and loads with a non-zero size, and the page's own check
//! notices a missing or broken chart. Needs Debian's `chromium-headless-shell` (or `chromium`); without one the browser part is
//! skipped with a message, unless the environment variable `CI` is set, where it is required.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Browser binaries tried, in order, on the PATH.
const BROWSERS: [&str; 3] = ["chromium-headless-shell", "chromium", "chromium-browser"];

fn find_browser() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    BROWSERS.iter().find_map(|name| {
        std::env::split_paths(&path)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    })
}

/// What the page's check reported: `(data-total, data-broken)` of `#chart-check`.
#[derive(Debug, PartialEq)]
struct Check {
    total: usize,
    broken: Vec<String>,
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let start = tag.find(&format!("{name}=\""))? + name.len() + 2;
    let len = tag[start..].find('"')?;
    Some(tag[start..start + len].to_string())
}

/// Loads `index` in the browser (scripts run, images load) and reads the check's result from the
/// DOM the browser dumps.
fn browser_check(browser: &Path, index: &Path, profile: &Path) -> Check {
    let url = format!("file://{}", index.canonicalize().unwrap().display());
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=10000",
            &format!("--user-data-dir={}", profile.display()),
            "--dump-dom",
            &url,
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("{}: cannot start: {e}", browser.display()));
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("{} did not finish within 120 s", browser.display());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    let tag = dom
        .find("<p id=\"chart-check\"")
        .map(|i| &dom[i..i + dom[i..].find('>').unwrap_or(0)])
        .unwrap_or_else(|| panic!("no #chart-check in the browser's DOM:\n{dom}"));
    let total = attribute(tag, "data-total")
        .unwrap_or_else(|| panic!("the page's check did not run: {tag}"))
        .parse()
        .unwrap();
    let broken = attribute(tag, "data-broken")
        .unwrap_or_default()
        .split_whitespace()
        .map(String::from)
        .collect();
    Check { total, broken }
}

fn svgs_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".svg"))
        .collect();
    v.sort();
    v
}

#[test]
fn index_html_shows_the_summary_and_every_chart_in_a_browser() {
    let dir = std::env::temp_dir().join(format!("softfinger-index-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // A short run of the scene with the most charts (it adds the limit-surface path).
    let args = host_sim::experiments::run::Args {
        scene: "finger-slide-twist".into(),
        duration_s: Some(0.5),
        out: dir.clone(),
        ..Default::default()
    };
    host_sim::experiments::run::main(&args).unwrap();
    let index = dir.join("index.html");
    let html = std::fs::read_to_string(&index).unwrap();
    let svgs = svgs_in(&dir);
    assert_eq!(
        svgs,
        ["contact_path.svg", "forces.svg", "limit_surface_path.svg"]
    );
    for f in &svgs {
        assert!(html.contains(&format!("<img src=\"{f}\"")), "{f} not shown");
    }
    assert!(html.contains("<a href=\"run.csv\">"));
    for line in [
        "scene finger-slide-twist",
        "max force",
        "limit surface (1 = static ellipse)",
    ] {
        assert!(html.contains(line), "summary line {line:?} missing");
    }

    let Some(browser) = find_browser() else {
        let msg = format!(
            "no headless browser found (tried {BROWSERS:?} on PATH): index.html was not opened; \
             install one with `apt-get install chromium-headless-shell`"
        );
        assert!(std::env::var_os("CI").is_none(), "CI is set and {msg}");
        eprintln!("SKIPPED the browser check: {msg}");
        return;
    };
    let profile = dir.join(".browser-profile");
    let ok = browser_check(&browser, &index, &profile);
    assert_eq!(
        ok,
        Check {
            total: svgs.len(),
            broken: vec![]
        }
    );

    // The page's check catches a missing chart and a broken one.
    std::fs::remove_file(dir.join("forces.svg")).unwrap();
    std::fs::write(
        dir.join("contact_path.svg"),
        "<svg xmlns=\"http://www.w3.org/2000/svg\"",
    )
    .unwrap();
    let bad = browser_check(&browser, &index, &profile);
    assert_eq!(bad.total, svgs.len());
    assert_eq!(bad.broken, ["forces.svg", "contact_path.svg"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `chart` (one rate, quick timing) and `stability` (short runs) write an index.html showing every
/// chart they wrote, and every chart loads in the browser.
#[test]
fn chart_and_stability_pages_show_every_chart_in_a_browser() {
    let root = std::env::temp_dir().join(format!("softfinger-pages-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let (chart, stability) = (root.join("chart"), root.join("stability"));
    let code = host_sim::cli::run([
        "host-sim",
        "chart",
        "--quick",
        "--rates-hz",
        "100",
        "--mcu-json",
        root.join("none.json").to_str().unwrap(),
        "--out",
        chart.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    let code = host_sim::cli::run([
        "host-sim",
        "stability",
        "--drift-steps",
        "1000",
        // 0.2 s is too short to find a passive wall at 10 kHz (the command then fails); 0.3 s
        // finds one.
        "--haptic-seconds",
        "0.3",
        "--skip-closed-loop",
        "--chatter-steps",
        "1000",
        "--out",
        stability.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    let browser = find_browser();
    for dir in [&chart, &stability] {
        let index = dir.join("index.html");
        let html = std::fs::read_to_string(&index).unwrap();
        let svgs = svgs_in(dir);
        assert!(svgs.len() >= 3, "{svgs:?}");
        for f in &svgs {
            assert!(html.contains(&format!("<img src=\"{f}\"")), "{f} not shown");
        }
        let Some(browser) = &browser else {
            assert!(
                std::env::var_os("CI").is_none(),
                "CI is set and no headless browser found (tried {BROWSERS:?})"
            );
            eprintln!("SKIPPED the browser check: no headless browser found");
            continue;
        };
        let ok = browser_check(browser, &index, &dir.join(".browser-profile"));
        assert_eq!(
            ok,
            Check {
                total: svgs.len(),
                broken: vec![]
            },
            "{}",
            dir.display()
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}

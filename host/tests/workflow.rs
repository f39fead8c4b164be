//! The workflow a user follows with the `softfinger` binary against the virtual device (in
//! process, port 0): exit codes, messages and the files left, for each problem of the first
//! user trial — an `arm` that lets go when its process leaves, `home` that returned before
//! homing ended, idle recordings, a stream across a device restart, `bench` leaving the device
//! changed, `params` parsing and refusals, Ctrl-C leaving a temporary file, and the device's
//! event log.

use host_sim::serve::{Args, Server};
use softfinger_host::bench::{self, BenchConfig};
use softfinger_host::protocol::{LocalModel, Mode, SurfaceShape};
use softfinger_host::{Device, LinkError, Target};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

fn args(listen: &str) -> Args {
    Args {
        listen: listen.into(),
        scene: "finger-on-plane".into(),
        blend_ms: 2.0,
        watchdog_ms: 200.0,
        auto_arm: false,
        duration_s: None,
        quiet: true,
        flash: None,
        devices: 1,
    }
}

fn server() -> Server {
    Server::start(&args("127.0.0.1:0")).expect("server starts")
}

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softfinger-wf-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn sf(s: &Server, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_softfinger"))
        .arg("--connect")
        .arg(format!("tcp:{}", s.addr()))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Column `name` of every data row of a CSV.
fn column(csv: &Path, name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = head.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(i).unwrap().to_string())
        .collect()
}

/// Problems 1-3: `home` waits for homing and says so; `arm` before it is refused naming the
/// mode and what it needs; `arm` from a process that then leaves warns, and the recording after
/// it (the watchdog let go) exits non-zero naming comm-timeout; an unhomed recording likewise;
/// `stream --arm` records rendered force; `status` shows mode, model and flags.
#[test]
fn idle_recordings_fail_and_home_waits() {
    let s = server();
    let dir = folder("idle");
    let csv = dir.join("s.csv");
    let c = csv.to_str().unwrap();

    // Unhomed: a recording of nothing fails, but is written (mode and flags in it).
    let out = sf(&s, &["stream", "--seconds", "0.2", "--csv", c]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("not rendering force in 200 of 200 samples (mode unhomed: 200)"),
        "{}",
        stderr(&out)
    );
    assert!(column(&csv, "mode").iter().all(|m| m == "unhomed"));
    let out = sf(&s, &["arm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains(
            "arm refused: the device is unhomed; it needs homing first: `softfinger home`"
        ),
        "{}",
        stderr(&out)
    );

    // Homing in the background: arm is refused naming the mode; status shows it.
    let t0 = Instant::now();
    let out = sf(&s, &["home", "--no-wait"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("homing started"));
    let out = sf(&s, &["arm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("the device is homing; homing is in progress"),
        "{}",
        stderr(&out)
    );
    assert!(stdout(&sf(&s, &["status"])).starts_with("mode homing"));
    // A second `home` is refused while homing; wait for it through the library.
    let mut d = Device::connect(&Target::Tcp(s.addr().to_string())).unwrap();
    while d.status().unwrap().mode == Mode::Homing {
        assert!(t0.elapsed() < Duration::from_secs(20), "homing ends");
        std::thread::sleep(Duration::from_millis(100));
    }
    drop(d);
    // Homing again from disarmed: `home` returns when it is over.
    let t0 = Instant::now();
    let out = sf(&s, &["home"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let took = t0.elapsed().as_secs_f64();
    assert!(stdout(&out).starts_with("homed in "), "{}", stdout(&out));
    assert!(took > 0.5, "home waited for the homing ({took} s)");
    let st = stdout(&sf(&s, &["status"]));
    assert!(
        st.starts_with("mode disarmed") && st.contains("model 0: plane"),
        "{st}"
    );

    // Problem 1: arm in one process, record in the next.
    let out = sf(&s, &["arm"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("watchdog (200 ms)") && stderr(&out).contains("softfinger session"),
        "{}",
        stderr(&out)
    );
    // Well past the 200 ms watchdog, also when a loaded machine runs the device late.
    std::thread::sleep(Duration::from_millis(1500));
    let out = sf(&s, &["stream", "--seconds", "0.2", "--csv", c]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{} {}",
        stderr(&out),
        std::fs::read_to_string(&csv).unwrap()
    );
    assert!(
        stderr(&out).contains("armed with comm-timeout latched: 200"),
        "{}",
        stderr(&out)
    );
    assert!(column(&csv, "flag_names")
        .iter()
        .all(|f| f.contains("comm-timeout")));
    let json: serde_json::Value =
        serde_json::from_slice(&sf(&s, &["status", "--json"]).stdout).unwrap();
    assert_eq!(json["mode"], "armed");
    assert!(json["flags"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f == "comm-timeout"));
    // ... accepted when asked for.
    let out = sf(
        &s,
        &["stream", "--seconds", "0.2", "--allow-idle", "--csv", c],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("note: the device was not rendering"));

    // The fix: arm on the stream's own connection; disarmed at the end.
    let out = sf(&s, &["stream", "--arm", "--seconds", "0.3", "--csv", c]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(column(&csv, "mode").iter().all(|m| m == "armed"));
    assert!(column(&csv, "flag_names")
        .iter()
        .all(|f| !f.contains("comm-timeout")));
    assert!(stdout(&sf(&s, &["status"])).starts_with("mode disarmed"));
    assert_eq!(files_in(&dir), ["s.csv"], "no temporary file left");
    std::fs::remove_dir_all(&dir).unwrap();
    s.stop();
}

/// Problem 4: a stream across a device restart stops at the restart, keeps the first session's
/// samples (time never goes back in the file) and says so; exit 2.
#[test]
fn a_stream_never_joins_two_device_sessions() {
    let s = server();
    let addr = s.addr().to_string();
    let dir = folder("restart");
    let csv = dir.join("s.csv");
    let child = Command::new(env!("CARGO_BIN_EXE_softfinger"))
        .args([
            "--connect",
            &format!("tcp:{addr}"),
            "stream",
            "--seconds",
            "30",
        ])
        .args([
            "--allow-idle",
            "--rate-hz",
            "100",
            "--csv",
            csv.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    s.stop();
    std::thread::sleep(Duration::from_millis(300));
    let s2 = Server::start(&args(&addr)).unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let e = stderr(&out);
    assert!(
        e.contains("the device restarted during the stream") && e.contains("s.csv"),
        "{e}"
    );
    let ticks: Vec<u64> = column(&csv, "tick")
        .iter()
        .map(|t| t.parse().unwrap())
        .collect();
    assert!(
        ticks.len() > 10,
        "the first session's samples: {}",
        ticks.len()
    );
    assert!(
        ticks.windows(2).all(|w| w[1] > w[0]),
        "one session: time only goes on"
    );
    assert_eq!(files_in(&dir), ["s.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
    s2.stop();
}

/// Problem 8: Ctrl-C during `stream` leaves no file at all, and exits 130.
#[test]
fn ctrl_c_leaves_no_file() {
    let s = server();
    let dir = folder("ctrlc");
    let csv = dir.join("s.csv");
    let child = Command::new(env!("CARGO_BIN_EXE_softfinger"))
        .args([
            "--connect",
            &format!("tcp:{}", s.addr()),
            "stream",
            "--seconds",
            "30",
        ])
        .args(["--allow-idle", "--csv", csv.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Recording has started once its temporary file exists.
    let t0 = Instant::now();
    while files_in(&dir).is_empty() {
        assert!(t0.elapsed() < Duration::from_secs(10), "stream starts");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("interrupted: nothing written"),
        "{}",
        stderr(&out)
    );
    assert!(files_in(&dir).is_empty(), "left: {:?}", files_in(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
    s.stop();
}

/// Problem 6: `params` parses negative numbers and needs an option; the device names the
/// field out of range and its range, the CLI prints both; the force limit is tested at the
/// device's limit and just above; `get` prints units and JSON.
#[test]
fn params_are_checked_and_refusals_name_the_field_and_range() {
    let s = server();
    let out = sf(&s, &["params", "set"]);
    assert_eq!(out.status.code(), Some(2), "usage error");
    assert!(stderr(&out).contains("required"), "{}", stderr(&out));
    let cases: [(&[&str], &str); 4] = [
        (&["--stiffness", "-100"], "the device refused --stiffness -100: normal_stiffness must be within [0, 10000000] N/m"),
        (&["--mu-s", "0.3", "--mu-k", "0.9"], "the device refused --mu-k 0.9: mu_k must be within (0, 0.3]"),
        (&["--max-force", "100"], "--max-force 100 N is above the device's force limit of 12 N"),
        (&["--max-force", "12.001"], "--max-force 12.001 N is above the device's force limit of 12 N"),
    ];
    for (a, want) in cases {
        let mut v = vec!["params", "set"];
        v.extend_from_slice(a);
        let out = sf(&s, &v);
        assert_eq!(out.status.code(), Some(2), "{a:?}");
        assert!(stderr(&out).contains(want), "{a:?}: {}", stderr(&out));
    }
    let out = sf(
        &s,
        &["params", "set", "--max-force", "12", "--damping", "2.5"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("max_force_n 12 N (was 12 N)"),
        "{}",
        stdout(&out)
    );
    let get = stdout(&sf(&s, &["params", "get"]));
    assert!(
        get.contains("normal_damping") && get.contains("2.5 N·s/m"),
        "{get}"
    );
    let v: serde_json::Value =
        serde_json::from_slice(&sf(&s, &["params", "get", "--json"]).stdout).unwrap();
    assert_eq!(v["normal_damping"], 2.5);
    assert_eq!(v["units"]["normal_stiffness"], "N/m");
    // The device itself refuses a force limit above its own, with the field and the range.
    let mut d = Device::connect(&Target::Tcp(s.addr().to_string())).unwrap();
    let mut p = d.contact_params().unwrap();
    p.max_force_n = 12.5;
    match d.set_contact_params(p) {
        Err(LinkError::Rejected { field, .. }) => {
            assert_eq!((field.field.as_str(), field.max), ("max_force_n", 12.0));
        }
        other => panic!("{other:?}"),
    }
    p.max_force_n = 12.0;
    d.set_contact_params(p).unwrap();
    s.stop();
}

/// A device changed from its defaults, as a user leaves it before `bench`: homed, a sphere
/// model, a non-default damping. Returns the model and parameters set.
fn changed_device(t: &Target) -> (LocalModel, softfinger_host::protocol::ContactParamsWire) {
    let mut d = Device::connect(t).unwrap();
    let sphere = LocalModel {
        seq: 5,
        shape: SurfaceShape::Sphere { radius_m: 0.04 },
        position_m: [0.0, 0.0, -0.2],
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: 1500.0,
        damping_n_s_per_m: 1.0,
        mu_s: 0.7,
        mu_k: 0.5,
        spin_stiffness_nm_per_rad: 0.02,
        max_age_ms: 0,
    };
    // Homed (a model waits for the controller to run, which it does from homing on).
    d.home().unwrap();
    let t0 = Instant::now();
    while d.status().unwrap().mode != Mode::Disarmed {
        assert!(t0.elapsed() < Duration::from_secs(20), "homing ends");
        std::thread::sleep(Duration::from_millis(100));
    }
    // Parameters first: they re-base the model in force (as `scene set` sends them).
    let mut p = d.contact_params().unwrap();
    p.normal_damping = 3.0;
    d.set_contact_params(p).unwrap();
    d.set_local_model(sphere).unwrap();
    let t0 = Instant::now();
    while d.status().unwrap().model.seq != 5 {
        assert!(t0.elapsed() < Duration::from_secs(5), "{:?}", d.status());
        std::thread::sleep(Duration::from_millis(10));
    }
    (sphere, p)
}

/// The device is as [`changed_device`] left it: its model, parameters, mode and watchdog.
fn assert_as_found(
    t: &Target,
    sphere: LocalModel,
    p: softfinger_host::protocol::ContactParamsWire,
) {
    let mut d = Device::connect(t).unwrap();
    let st = d.status().unwrap();
    assert_eq!(
        LocalModel { seq: 0, ..st.model },
        LocalModel { seq: 0, ..sphere }
    );
    assert_eq!(d.contact_params().unwrap(), p);
    assert_eq!(st.mode, Mode::Disarmed, "as found");
    assert_eq!(
        st.flags & softfinger_core::Flags::COMM_TIMEOUT.0,
        0,
        "no timeout left latched"
    );
    assert_eq!(d.info().unwrap().watchdog_ms, 200);
}

/// Problem 5: `bench` puts back the scene, model, parameters, watchdog and mode it found.
#[test]
fn bench_leaves_the_device_as_found() {
    let s = server();
    let t = Target::Tcp(s.addr().to_string());
    let (sphere, p) = changed_device(&t);
    let cfg = BenchConfig {
        stream_s: 0.5,
        pings: 50,
        model_s: 0.2,
        watchdog_ms: 100,
        stop: None,
    };
    let r = bench::run(&t, &cfg).unwrap();
    let b = &r.restored;
    assert!(b.complete() && b.notes.is_empty(), "{b:?}");
    assert_as_found(&t, sphere, p);
    s.stop();
}

/// Problem 5, interrupted: Ctrl-C in the middle of `bench` (its 30 s stream phase) ends it
/// within a second, exit 130, and the device is still put back as found.
#[test]
fn bench_stopped_by_ctrl_c_leaves_the_device_as_found() {
    let s = server();
    let t = Target::Tcp(s.addr().to_string());
    let (sphere, p) = changed_device(&t);
    let child = Command::new(env!("CARGO_BIN_EXE_softfinger"))
        .args(["--connect", &format!("tcp:{}", s.addr()), "bench"])
        .args(["--seconds", "30", "--pings", "100000"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let t0 = Instant::now();
    let out = child.wait_with_output().unwrap();
    assert!(t0.elapsed() < Duration::from_secs(10), "stops promptly");
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("interrupted before the end; the device was put back as found"),
        "{}",
        stderr(&out)
    );
    assert_as_found(&t, sphere, p);
    s.stop();
}

/// A sink the test reads.
#[derive(Clone, Default)]
struct Lines(Arc<Mutex<Vec<u8>>>);

impl Write for Lines {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Problem 9: the virtual device logs connections, mode changes, model and parameter changes
/// and faults, one line each starting with the device time.
#[test]
fn the_device_logs_each_event_with_its_time() {
    let sink = Lines::default();
    let s = Server::start_logging(
        &args("127.0.0.1:0"),
        Some(Arc::new(Mutex::new(sink.clone()))),
    )
    .unwrap();
    let t = Target::Tcp(s.addr().to_string());
    let mut d = Device::connect(&t).unwrap();
    d.home().unwrap();
    while d.status().unwrap().mode == Mode::Homing {
        std::thread::sleep(Duration::from_millis(100));
    }
    // A command-line process comes and goes.
    let out = sf(&s, &["status"]);
    assert!(
        stdout(&out).starts_with("mode disarmed"),
        "{}",
        stdout(&out)
    );
    d.set_local_model(LocalModel {
        seq: 1,
        shape: SurfaceShape::Sphere { radius_m: 0.05 },
        position_m: [0.0, 0.0, -0.2],
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: 2000.0,
        damping_n_s_per_m: 2.0,
        mu_s: 0.8,
        mu_k: 0.6,
        spin_stiffness_nm_per_rad: 0.01,
        max_age_ms: 0,
    })
    .unwrap();
    d.arm().unwrap();
    // Silence: the watchdog fires.
    d.set_heartbeat(false);
    std::thread::sleep(Duration::from_millis(600));
    drop(d);
    s.stop();
    let text = String::from_utf8(sink.0.lock().unwrap().clone()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    for l in &lines {
        assert!(
            l.starts_with('[')
                && l[1..]
                    .trim_start()
                    .split(' ')
                    .next()
                    .unwrap()
                    .parse::<f64>()
                    .is_ok(),
            "{l}"
        );
    }
    let has = |p: &str| lines.iter().any(|l| l.contains(p));
    assert!(has("] connection 1 opened (1 open)"), "{text}");
    assert!(has("] mode unhomed -> homing"), "{text}");
    assert!(has("] mode homing -> disarmed (homed)"), "{text}");
    assert!(
        has("] model 1 from connection 1: sphere r 50.0 mm at (0.0, 0.0, -200.0) mm"),
        "{text}"
    );
    assert!(has("] mode disarmed -> armed"), "{text}");
    assert!(
        has("] comm-timeout (no message in the watchdog time"),
        "{text}"
    );
    assert!(has("] connection 2 opened (2 open)"), "{text}");
    assert!(has("] connection 2 closed (1 open)"), "{text}");
}

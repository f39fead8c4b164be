//! The host library against the virtual device on 127.0.0.1 (port 0: any free port), in
//! process: version negotiation, requests and typed refusals, bad input from one client while
//! another streams, local-model switches and the watchdog, reconnection, and the `softfinger`
//! binary. Timing figures are measured by `softfinger bench`, not asserted here; these tests check
//! behaviour (counts, flags, no step where the blend must prevent one).

use host_sim::serve::{Args, Server};
use softfinger_host::bench::{self, BenchConfig};
use softfinger_host::protocol::{
    encode_frame, DeviceMsg, ErrorCode, FrameDecoder, HostMsg, Mode, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};
use softfinger_host::{Device, LinkError, Target};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

fn server_at(listen: &str) -> Server {
    Server::start(&Args {
        listen: listen.into(),
        scene: "finger-on-plane".into(),
        blend_ms: 2.0,
        watchdog_ms: 200.0,
        auto_arm: false,
        flash: None,
        devices: 1,
        duration_s: None,
        quiet: true,
    })
    .expect("server starts")
}

fn target(s: &Server) -> Target {
    Target::Tcp(s.addr().to_string())
}

#[test]
fn info_counters_and_typed_refusals() {
    let s = server_at("127.0.0.1:0");
    let mut d = Device::connect(&target(&s)).unwrap();
    let info = d.info().unwrap();
    assert_eq!(info.control_rate_hz, 10_000);
    assert!(info.virtual_device);
    assert_eq!(info.surfaces.len(), 4);
    // No force before homing: arming is refused with a typed code.
    assert!(matches!(
        d.arm(),
        Err(LinkError::Refused(ErrorCode::WrongMode))
    ));
    // A stream divisor of 0 stops; a watchdog beyond 60 s is refused.
    d.set_stream(0).unwrap();
    let mut p = d.contact_params().unwrap();
    p.mu_k = p.mu_s + 0.1;
    // Refused naming the field and its range.
    match d.set_contact_params(p) {
        Err(LinkError::Rejected { code, field }) => {
            assert_eq!(code, ErrorCode::InvalidValue);
            assert_eq!((field.field.as_str(), field.max), ("mu_k", p.mu_s));
        }
        other => panic!("{other:?}"),
    }
    let c = d.counters().unwrap();
    assert_eq!(c.connections, 1);
    assert_eq!(c.rx_errors, 0);
    assert!(c.rx_frames >= 6, "{c:?}");
    s.stop();
}

/// A host that speaks only the next two versions is told the device's version and no agreement.
#[test]
fn version_negotiation_refuses_other_versions() {
    let s = server_at("127.0.0.1:0");
    let mut tcp = TcpStream::connect(s.addr()).unwrap();
    tcp.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(
        &HostMsg::Hello {
            min_version: PROTOCOL_VERSION + 1,
            max_version: PROTOCOL_VERSION + 2,
        },
        &mut buf,
    )
    .unwrap();
    tcp.write_all(&buf[..n]).unwrap();
    let mut dec = FrameDecoder::new();
    let mut byte = [0u8; 1];
    let reply = loop {
        tcp.read_exact(&mut byte).unwrap();
        if let Some(r) = dec.push::<DeviceMsg>(byte[0]) {
            break r.unwrap();
        }
    };
    assert_eq!(
        reply,
        DeviceMsg::HelloReply {
            version: None,
            device_version: PROTOCOL_VERSION
        }
    );
    s.stop();
}

/// One client streams at 1 kHz, one pings, one sends garbage, truncated, oversized,
/// wrong-version and wrong-CRC frames: each kind is counted, the bad client is answered and stays
/// usable, and the stream has no gap.
#[test]
fn bad_input_is_counted_and_the_other_clients_go_on() {
    let s = server_at("127.0.0.1:0");
    let t = target(&s);
    let (stream, rtt, bad) = std::thread::scope(|sc| {
        let a = sc.spawn(|| bench_stream(&t, 3.0));
        let b = sc.spawn(|| bench_rtt(&t, 200));
        let c = sc.spawn(|| bench_bad(&t, 1.0));
        (a.join().unwrap(), b.join().unwrap(), c.join().unwrap())
    });
    // No sample missing; the rate itself is a benchmark figure (a debug build on a loaded
    // machine runs the device slower than real time).
    assert_eq!(stream.missing, 0, "{stream:?}");
    assert!(stream.samples >= 100, "{stream:?}");
    assert_eq!(rtt.n, 200);
    // 5 of each crafted kind; the garbage adds COBS (and maybe CRC/decode) errors on top.
    assert!(bad.still_usable);
    let c = &bad.counted;
    assert_eq!(c.rx_version, 5, "{bad:?}");
    assert_eq!(c.rx_oversized, 5, "{bad:?}");
    assert!(c.rx_crc >= 5, "{bad:?}");
    assert!(c.rx_cobs >= 5, "{bad:?}");
    assert_eq!(
        c.rx_errors,
        c.rx_cobs + c.rx_crc + c.rx_version + c.rx_decode + c.rx_oversized
    );
    assert_eq!(bad.answered, c.rx_errors, "every bad frame answered");
    s.stop();
}

fn bench_stream(t: &Target, s: f64) -> bench::StreamReport {
    bench::stream_phase(t, s, &BenchConfig::default()).unwrap()
}
fn bench_rtt(t: &Target, n: usize) -> bench::RttReport {
    bench::rtt_phase(t, n, &BenchConfig::default()).unwrap()
}
fn bench_bad(t: &Target, delay: f64) -> bench::BadInputReport {
    bench::bad_input_phase(t, delay, &BenchConfig::default()).unwrap()
}

/// A pressed finger: local models at 1 kHz are all applied, 1 mm jumps (2 N) are blended (no tick
/// changes by a quarter of the jump; measured ~0.11 N with a 2 ms blend, where a switch without
/// blend steps by 2 N); the watchdog fades the force to zero within its 20 ms fade plus a tick,
/// latches until re-armed, and force comes back after.
#[test]
fn local_models_switch_without_steps_and_the_watchdog_fades() {
    let s = server_at("127.0.0.1:0");
    let cfg = BenchConfig {
        model_s: 0.5,
        ..BenchConfig::default()
    };
    let (m, w) = bench::models_phase(&target(&s), 10_000, &cfg).unwrap();
    assert!(m.mean_force_n > 0.5, "the finger presses: {m:?}");
    assert_eq!(m.stream_refused, 0);
    assert!(m.last_applied);
    assert!(m.max_step_jumps_n < 0.25 * m.jump_force_n, "{m:?}");
    assert!(w.force_before_n > 0.5, "{w:?}");
    assert!(w.fade_ms > 0.0 && w.fade_ms <= 20.1, "{w:?}");
    assert!(w.latched && w.recovered, "{w:?}");
    s.stop();
}

/// The device goes away and comes back on the same address: the connection is restored with its
/// stream.
#[test]
fn reconnects_when_the_device_comes_back() {
    let s = server_at("127.0.0.1:0");
    let addr = s.addr().to_string();
    let mut d = Device::connect(&Target::Tcp(addr.clone())).unwrap();
    d.set_stream(100).unwrap();
    assert!(d.next_state(Duration::from_secs(2)).unwrap().is_some());
    s.stop();
    // Drain what was queued; then the connection reports itself gone.
    let gone = loop {
        match d.next_state(Duration::from_secs(2)) {
            Ok(Some(_)) => continue,
            other => break other,
        }
    };
    assert!(matches!(gone, Err(LinkError::Disconnected)), "{gone:?}");
    assert!(d.reconnect().is_err(), "nothing listens yet");
    let s2 = server_at(&addr);
    d.reconnect().unwrap();
    let sample = d
        .next_state(Duration::from_secs(2))
        .unwrap()
        .expect("stream restored");
    assert_eq!(sample.mode, Mode::Unhomed, "a fresh device");
    s2.stop();
}

#[test]
fn the_binary_streams_to_csv_and_rejects_bad_arguments() {
    let s = server_at("127.0.0.1:0");
    let exe = env!("CARGO_BIN_EXE_softfinger");
    let dir = std::env::temp_dir().join(format!("softfinger-host-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("s.csv");
    let connect = format!("tcp:{}", s.addr());
    let run = |args: &[&str]| {
        std::process::Command::new(exe)
            .arg("--connect")
            .arg(&connect)
            .args(args)
            .output()
            .unwrap()
    };
    // The device is unhomed: an idle recording, accepted as such.
    let out = run(&[
        "stream",
        "--seconds",
        "0.5",
        "--allow-idle",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("t_s,tick,"));
    assert_eq!(lines.len(), 501, "header + 0.5 s at 1 kHz");
    let ticks: Vec<u64> = lines[1..]
        .iter()
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(ticks.windows(2).all(|w| w[1] == w[0] + 10), "no gap");

    let bad = dir.join("bad.csv");
    for args in [
        vec!["stream", "--seconds", "0", "--csv", bad.to_str().unwrap()],
        vec![
            "stream",
            "--seconds",
            "1",
            "--rate-hz",
            "30000",
            "--csv",
            bad.to_str().unwrap(),
        ],
        vec!["scene", "set", "no-such-scene.toml"],
    ] {
        let out = run(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!out.stderr.is_empty());
        assert!(!bad.exists(), "nothing written for {args:?}");
    }
    let out = run(&["scene", "set", "finger-on-sphere"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = run(&["info", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["link"]["rx_errors"], 0);
    std::fs::remove_dir_all(&dir).unwrap();
    s.stop();
}

/// The virtual device's watchdog is on (200 ms) and the library's heartbeat keeps a connection
/// that only reads the stream alive; without the heartbeat the device latches COMM_TIMEOUT, and
/// arming with the heartbeat back clears it.
#[test]
fn the_heartbeat_keeps_the_default_watchdog_fed() {
    use softfinger_core::Flags;
    let s = server_at("127.0.0.1:0");
    let mut d = Device::connect(&target(&s)).unwrap();
    assert_eq!(d.info().unwrap().watchdog_ms, 200);
    d.home().unwrap();
    d.set_stream(10).unwrap();
    let timed_out =
        |x: &softfinger_host::protocol::StateSample| x.flags & Flags::COMM_TIMEOUT.0 != 0;
    let next = |d: &Device| {
        d.next_state(Duration::from_secs(5))
            .unwrap()
            .expect("a sample")
    };
    // Homing against the plant, then 1 s of device time reading only.
    let mut x = next(&d);
    while x.mode != Mode::Disarmed {
        x = next(&d);
    }
    let t0 = x.tick;
    while x.tick < t0 + 10_000 {
        assert!(!timed_out(&x), "fed by the heartbeat: {x:?}");
        x = next(&d);
    }
    d.set_heartbeat(false);
    let t1 = x.tick;
    while !timed_out(&x) {
        assert!(
            x.tick < t1 + 20_000,
            "no timeout 2 s after the heartbeat stopped"
        );
        x = next(&d);
    }
    d.set_heartbeat(true);
    d.arm().unwrap();
    let t2 = x.tick;
    while timed_out(&x) {
        assert!(x.tick < t2 + 10_000, "re-arming did not clear the timeout");
        x = next(&d);
    }
    assert_eq!(x.mode, Mode::Armed);
    s.stop();
}

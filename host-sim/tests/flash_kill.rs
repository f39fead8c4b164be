//! `host-sim serve --flash FILE` killed with SIGKILL around a settings save, then restarted: the
//! settings it reads back are the old or the new ones, never the defaults after a completed save,
//! and a save that was acknowledged before the kill is always there.
//! `cargo test -p host-sim --test flash_kill -- --nocapture` prints the counts; CI runs the
//! default 30 kills, `SOFTFINGER_FLASH_KILLS=N` runs N (the figure over many kills).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use softfinger_protocol::config::{ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::{encode_frame, DeviceMsg, FrameDecoder, HostMsg, Request, MAX_FRAME_LEN};
use softfinger_store::Identity;

/// Kills in a run: `SOFTFINGER_FLASH_KILLS`, else 30 (a few seconds).
fn kills() -> u32 {
    match std::env::var("SOFTFINGER_FLASH_KILLS") {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("SOFTFINGER_FLASH_KILLS={v}: not a count")),
        Err(_) => 30,
    }
}

fn start(flash: &std::path::Path) -> (Child, TcpStream) {
    start_with(flash, &[])
}

fn start_with(flash: &std::path::Path, extra: &[&str]) -> (Child, TcpStream) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(["serve", "--listen", "127.0.0.1:0", "--flash"])
        .arg(flash)
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("host-sim starts");
    let mut line = String::new();
    BufReader::new(child.stdout.as_mut().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .split_whitespace()
        .find(|w| w.starts_with("127.0.0.1:"))
        .expect("address printed")
        .to_string();
    let s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    (child, s)
}

fn send(s: &mut TcpStream, seq: u16, req: Request) -> std::io::Result<()> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(&HostMsg::Request { seq, req }, &mut buf).unwrap();
    s.write_all(&buf[..n])
}

fn recv(s: &mut TcpStream) -> std::io::Result<DeviceMsg> {
    let mut d = FrameDecoder::new();
    let mut b = [0u8; 1];
    loop {
        s.read_exact(&mut b)?;
        if let Some(Ok(m)) = d.push::<DeviceMsg>(b[0]) {
            return Ok(m);
        }
    }
}

fn identity(serial: u32) -> Identity {
    let mut name = heapless::String::new();
    name.push_str("kill-test").unwrap();
    Identity { serial, name }
}

/// The serial the device reads back and its store status.
fn read_back(s: &mut TcpStream) -> (u32, StoreStatus) {
    send(s, 1, Request::ConfigGet(ConfigSection::Status)).unwrap();
    let DeviceMsg::Config {
        value: ConfigValue::Status { store, .. },
        ..
    } = recv(s).unwrap()
    else {
        panic!()
    };
    send(s, 2, Request::ConfigGet(ConfigSection::Identity)).unwrap();
    let DeviceMsg::Config {
        value: ConfigValue::Identity(id),
        ..
    } = recv(s).unwrap()
    else {
        panic!()
    };
    (id.serial, store)
}

#[test]
fn a_sigkill_around_a_save_leaves_the_old_or_the_new_settings() {
    let dir = std::env::temp_dir().join(format!("softfinger-flash-kill-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let flash = dir.join("device.flash");
    let _ = std::fs::remove_file(&flash);
    let (mut acked, mut unacked, mut got_old, mut got_new) = (0, 0, 0, 0);
    let mut last_saved: Option<u32> = None;
    let mut x: u64 = 0x2545_F491_4F6C_DD1D;
    let kills = kills();
    for i in 1..=kills {
        let (mut child, mut s) = start(&flash);
        let (serial, store) = read_back(&mut s);
        match last_saved {
            None => assert!(
                matches!(store, StoreStatus::Absent | StoreStatus::Read),
                "{store:?}"
            ),
            Some(prev) => {
                assert_eq!(
                    store,
                    StoreStatus::Read,
                    "kill {i}: defaults after a completed save"
                );
                assert!(
                    serial == prev || serial == prev + 1,
                    "kill {i}: serial {serial}, saved {prev}"
                );
            }
        }
        if let Some(prev) = last_saved {
            if serial == prev {
                got_old += 1
            } else {
                got_new += 1
            }
        }
        last_saved = Some(serial);
        // Set the next serial, save, and kill after a random delay of 0..2 ms.
        let next = serial + 1;
        send(
            &mut s,
            3,
            Request::ConfigSet(ConfigValue::Identity(identity(next))),
        )
        .unwrap();
        let _ = recv(&mut s).unwrap();
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let delay = Duration::from_micros(x % 2000);
        send(&mut s, 4, Request::ConfigSave).unwrap();
        std::thread::sleep(delay);
        s.set_nonblocking(true).unwrap();
        let mut b = [0u8; 64];
        let answered = matches!(s.read(&mut b), Ok(n) if n > 0);
        child.kill().unwrap(); // SIGKILL
        let _ = child.wait();
        if answered {
            acked += 1;
            let (mut c2, mut s2) = start(&flash);
            let (got, store) = read_back(&mut s2);
            assert_eq!(
                (got, store),
                (next, StoreStatus::Read),
                "kill {i}: an acknowledged save is lost"
            );
            c2.kill().unwrap();
            let _ = c2.wait();
            last_saved = Some(next - 1);
        } else {
            unacked += 1;
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "serve --flash killed with SIGKILL {kills} times around a save: {acked} after the acknowledgement, \
         {unacked} before it; read back the old settings {got_old} times, the new {got_new}, defaults 0"
    );
}

/// The next answer that is not a state sample, and how many samples came before it.
fn answer(s: &mut TcpStream) -> (DeviceMsg, u32) {
    let mut samples = 0;
    loop {
        match recv(s).unwrap() {
            DeviceMsg::State(_) => samples += 1,
            m => return (m, samples),
        }
    }
}

/// The next answer is an `Ack` of `Ok`; the state samples that came before it.
fn acked(s: &mut TcpStream) -> u32 {
    let (m, samples) = answer(s);
    assert!(
        matches!(
            m,
            DeviceMsg::Ack {
                result: softfinger_protocol::AckResult::Ok,
                ..
            }
        ),
        "{m:?}"
    );
    samples
}

/// The stored stream and watchdog defaults act after a restart, as on the firmware
/// (`softfinger_app::boot_defaults`): samples arrive without a `SetStream`, and a host's Arm
/// turns the stored timeout on.
#[test]
fn saved_stream_and_watchdog_defaults_apply_after_a_restart() {
    use softfinger_store::schema::{StreamDefaults, WatchdogDefaults};
    let dir = std::env::temp_dir().join(format!("softfinger-boot-defaults-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let flash = dir.join("device.flash");
    let _ = std::fs::remove_file(&flash);
    // Disarmed: settings are written only then.
    let (mut child, mut s) = start(&flash);
    for (seq, value) in [
        (1, ConfigValue::Stream(StreamDefaults { rate_hz: 100 })),
        (
            2,
            ConfigValue::Watchdog(WatchdogDefaults { timeout_ms: 50 }),
        ),
    ] {
        send(&mut s, seq, Request::ConfigSet(value)).unwrap();
        assert_eq!(acked(&mut s), 0, "a stream before the restart");
    }
    send(&mut s, 3, Request::ConfigSave).unwrap();
    acked(&mut s);
    child.kill().unwrap();
    child.wait().unwrap();

    // Armed from the bench (no watchdog) so that a host's Arm re-arms at once.
    let (mut child, mut s) = start_with(&flash, &["--auto-arm"]);
    // 100 Hz from the connection on: 0.3 s of device time gives samples before the answer.
    std::thread::sleep(Duration::from_millis(300));
    send(&mut s, 4, Request::Arm).unwrap();
    let samples = acked(&mut s);
    assert!(
        samples >= 5,
        "{samples} samples in 0.3 s at the stored 100 Hz"
    );
    send(&mut s, 5, Request::GetInfo).unwrap();
    let DeviceMsg::Info { info, .. } = answer(&mut s).0 else {
        panic!("no device info")
    };
    assert_eq!(
        info.watchdog_ms, 50,
        "the host's Arm turns on the stored timeout"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

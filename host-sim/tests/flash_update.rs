//! Updates of `host-sim serve --flash FILE` over the protocol, as `softfinger update FILE` sends
//! them: a wrong signature, a truncated image and a corrupted chunk are each refused, naming why,
//! with the running image byte for byte untouched (read from the flash file) and still running
//! after a reset; a good image is applied at the reset, confirmed, and still runs after a SIGKILL
//! and restart; an image failing its self-test is rolled back at the reset.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use softfinger_protocol::update::{
    BootStateWire, UpdateChunk, UpdatePhase, UpdateRefusal, UpdateStatus, UPDATE_CHUNK_LEN,
};
use softfinger_protocol::{
    encode_frame, AckResult, DeviceMsg, FrameDecoder, HostMsg, Request, MAX_FRAME_LEN,
};
use softfinger_update::keys::parse_hex_key;
use softfinger_update::layout::G474;
use softfinger_update::package::{sign, ImageTrailer, FLAG_SIMULATE_SELF_TEST_FAILURE};
use softfinger_update::session::chunk_crc;

struct Device {
    child: Child,
    link: TcpStream,
    seq: u16,
}

impl Device {
    fn start(flash: &std::path::Path) -> Device {
        let mut child = Command::new(env!("CARGO_BIN_EXE_host-sim"))
            .args(["serve", "--listen", "127.0.0.1:0", "--flash"])
            .arg(flash)
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
        let link = TcpStream::connect(addr).unwrap();
        link.set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        Device {
            child,
            link,
            seq: 0,
        }
    }

    fn request(&mut self, req: Request) -> DeviceMsg {
        self.seq = self.seq.wrapping_add(1);
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode_frame(&HostMsg::Request { seq: self.seq, req }, &mut buf).unwrap();
        self.link.write_all(&buf[..n]).unwrap();
        let mut d = FrameDecoder::new();
        let mut b = [0u8; 1];
        loop {
            self.link.read_exact(&mut b).unwrap();
            if let Some(Ok(m)) = d.push::<DeviceMsg>(b[0]) {
                return m;
            }
        }
    }

    fn status(&mut self) -> UpdateStatus {
        match self.request(Request::UpdateStatus) {
            DeviceMsg::Update { status, .. } => status,
            other => panic!("update status: {other:?}"),
        }
    }

    fn reboot(&mut self) {
        match self.request(Request::Reboot) {
            DeviceMsg::Ack {
                result: AckResult::Ok,
                ..
            } => {}
            other => panic!("reboot: {other:?}"),
        }
    }

    fn kill(mut self) {
        self.child.kill().unwrap(); // SIGKILL
        let _ = self.child.wait();
    }

    /// Begin, send `img` up to `until` bytes (a chunk at `corrupt` with a wrong CRC), finish.
    /// Returns the first refusal, or the status after finish.
    fn send(
        &mut self,
        img: &[u8],
        sig: &[u8; 64],
        until: usize,
        corrupt: Option<u32>,
    ) -> Result<UpdateStatus, UpdateRefusal> {
        let answer = |m: DeviceMsg| match m {
            DeviceMsg::Update { status, .. } => Ok(status),
            DeviceMsg::UpdateRefused { refusal, .. } => Err(refusal),
            other => panic!("update answer: {other:?}"),
        };
        answer(self.request(Request::UpdateBegin {
            len: img.len() as u32,
            signature: heapless::Vec::from_slice(sig).unwrap(),
        }))?;
        for (i, c) in img[..until].chunks(UPDATE_CHUNK_LEN).enumerate() {
            let offset = (i * UPDATE_CHUNK_LEN) as u32;
            let mut crc = chunk_crc(c);
            if corrupt == Some(offset) {
                crc ^= 0x8000;
            }
            answer(self.request(Request::UpdateChunk(UpdateChunk {
                offset,
                crc,
                data: heapless::Vec::from_slice(c).unwrap(),
            })))?;
        }
        answer(self.request(Request::UpdateFinish))
    }
}

fn seed() -> [u8; 32] {
    parse_hex_key(include_str!("../../update/keys/dev-signing-key.hex").trim())
}

fn image(tag: u32, version: &str, fail_self_test: bool) -> Vec<u8> {
    let mut x = tag.wrapping_mul(2_654_435_761) | 1;
    let mut v: Vec<u8> = (0..3000)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    let flags = if fail_self_test {
        FLAG_SIMULATE_SELF_TEST_FAILURE
    } else {
        0
    };
    v.extend_from_slice(&ImageTrailer::new(version, flags).unwrap().to_bytes());
    v
}

fn active_slot(flash: &std::path::Path) -> Vec<u8> {
    std::fs::read(flash).unwrap()[G474.active.start as usize..G474.active.end as usize].to_vec()
}

#[test]
fn bad_updates_are_refused_a_good_one_applied_and_a_failing_one_rolled_back() {
    let dir = std::env::temp_dir().join(format!("softfinger-flash-update-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let flash = dir.join("device.flash");
    let _ = std::fs::remove_file(&flash);

    let mut dev = Device::start(&flash);
    let factory = dev.status();
    assert_eq!(factory.boot, BootStateWire::Normal);
    assert!(factory.version.starts_with("host-sim"), "{factory:?}");
    let running = active_slot(&flash);

    let good = image(1, "test-1.0", false);
    let sig = sign(&good, &seed());
    let mut wrong = sig;
    wrong[10] ^= 0x01;
    assert_eq!(
        dev.send(&good, &wrong, good.len(), None),
        Err(UpdateRefusal::BadSignature)
    );
    let other_key = sign(&good, &[9u8; 32]);
    assert_eq!(
        dev.send(&good, &other_key, good.len(), None),
        Err(UpdateRefusal::BadSignature)
    );
    let half = good.len() / 2 / UPDATE_CHUNK_LEN * UPDATE_CHUNK_LEN;
    assert_eq!(
        dev.send(&good, &sig, half, None),
        Err(UpdateRefusal::Truncated {
            received: half as u32,
            len: good.len() as u32
        })
    );
    assert_eq!(
        dev.send(&good, &sig, good.len(), Some(256)),
        Err(UpdateRefusal::ChunkCrc { offset: 256 })
    );
    assert_eq!(
        active_slot(&flash),
        running,
        "a refused update wrote the active slot"
    );
    dev.reboot();
    let after = dev.status();
    assert_eq!(
        (after.version.as_str(), after.boot),
        (factory.version.as_str(), BootStateWire::Normal),
        "a reset after the refusals runs the same image"
    );
    assert_eq!(active_slot(&flash), running);

    // A good image: verified, swapped in at the reset, confirmed; it survives a SIGKILL.
    let verified = dev.send(&good, &sig, good.len(), None).unwrap();
    assert_eq!(verified.phase, UpdatePhase::Verified);
    assert_eq!(
        verified.version, factory.version,
        "not swapped before the reset"
    );
    dev.reboot();
    let st = dev.status();
    assert_eq!(
        (st.version.as_str(), st.boot),
        ("test-1.0", BootStateWire::Normal)
    );
    assert_eq!(&active_slot(&flash)[..good.len()], &good[..]);
    dev.kill();
    let mut dev = Device::start(&flash);
    let st = dev.status();
    assert_eq!(
        (st.version.as_str(), st.boot),
        ("test-1.0", BootStateWire::Normal)
    );

    // An image failing its self-test: swapped in at the reset, not confirmed, swapped back.
    let failing = image(2, "test-2.0", true);
    let sig2 = sign(&failing, &seed());
    assert_eq!(
        dev.send(&failing, &sig2, failing.len(), None)
            .unwrap()
            .phase,
        UpdatePhase::Verified
    );
    dev.reboot();
    let st = dev.status();
    assert_eq!(
        (st.version.as_str(), st.boot),
        ("test-1.0", BootStateWire::RolledBack)
    );
    assert_eq!(&active_slot(&flash)[..good.len()], &good[..]);
    dev.kill();
    let _ = std::fs::remove_dir_all(&dir);
}

//! One client sends bad frames of every kind; its connection must stay usable and the device must
//! count each kind.

use super::BenchConfig;
use crate::{Device, LinkError, Target};
use serde::Serialize;
use softfinger_protocol::frame::encode_frame_with_version;
use softfinger_protocol::{encode_frame, HostMsg, LinkCounters, Request, MAX_FRAME_LEN};
use std::time::Duration;

/// What the bad client sent and what the device counted.
#[derive(Clone, Debug, Serialize)]
pub struct BadInputReport {
    /// Bytes of pseudo-random garbage sent.
    pub garbage_bytes: usize,
    /// Frames of each crafted kind sent (truncated, oversized, wrong version, wrong CRC).
    pub crafted_each: u32,
    /// What the device counted meanwhile: its counters after minus before
    /// ([`LinkCounters::since`]).
    pub counted: LinkCounters,
    /// `FrameError` answers the bad client received.
    pub answered: u32,
    /// The bad client's own requests still worked afterwards.
    pub still_usable: bool,
}

fn frame(msg: &HostMsg) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(msg, &mut buf).unwrap_or(0);
    buf[..n].to_vec()
}

/// `n` bytes of a fixed pseudo-random sequence (xorshift), about 1 in 16 of them zero.
fn garbage(n: usize) -> Vec<u8> {
    let mut x: u32 = 0x2545_f491;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            if x.is_multiple_of(16) {
                0
            } else {
                (x >> 8) as u8
            }
        })
        .collect()
}

/// After `delay_s`, send the bad input, then check the connection.
pub fn run(target: &Target, delay_s: f64, cfg: &BenchConfig) -> Result<BadInputReport, LinkError> {
    let mut d = Device::connect(target)?;
    cfg.sleep(Duration::from_secs_f64(delay_s.max(0.0)))?;
    let before = d.counters()?;
    let ping = frame(&HostMsg::Request {
        seq: 60_000,
        req: Request::Ping,
    });
    let crafted_each = 5;
    let g = garbage(4000);
    d.send_raw(&[0])?; // end whatever came before
    d.send_raw(&g)?;
    d.send_raw(&[0])?;
    for _ in 0..crafted_each {
        let mut truncated = ping[..ping.len() / 2].to_vec();
        truncated.push(0);
        d.send_raw(&truncated)?;
        let mut over = vec![0x55u8; 2 * MAX_FRAME_LEN];
        over.push(0);
        d.send_raw(&over)?;
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode_frame_with_version(
            &HostMsg::Request {
                seq: 60_001,
                req: Request::Ping,
            },
            99,
            &mut buf,
        )
        .unwrap_or(0);
        d.send_raw(&buf[..n])?;
        // The last byte before the delimiter is CRC data (the frame's last COBS group holds
        // data for this message); flip a bit, keeping it non-zero.
        let mut bad_crc = ping.clone();
        let i = bad_crc.len() - 2;
        bad_crc[i] = if bad_crc[i] == 1 { 3 } else { bad_crc[i] ^ 1 };
        d.send_raw(&bad_crc)?;
    }
    // The connection goes on: a normal request works and sees the counters.
    std::thread::sleep(Duration::from_millis(100));
    let still_usable = d.ping().is_ok();
    let after = d.counters()?;
    Ok(BadInputReport {
        garbage_bytes: g.len(),
        crafted_each,
        counted: after.since(&before),
        answered: d.rejected_by_device(),
        still_usable,
    })
}

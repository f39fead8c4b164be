//! `Device::over` any byte stream: the path the USB serial port takes, exercised here against a
//! fake device on in-memory pipes (no hardware exists on this machine).

use softfinger_host::protocol::{
    encode_frame, AckResult, DeviceMsg, ErrorCode, FrameDecoder, HostMsg, Request, StateSample,
    MAX_FRAME_LEN, PROTOCOL_VERSION,
};
use softfinger_host::{Device, LinkError};
use std::io::{self, Read, Write};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::time::Duration;

/// The reading end of an in-memory pipe.
struct PipeReader {
    rx: Receiver<Vec<u8>>,
    pending: Vec<u8>,
}

impl Read for PipeReader {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.pending.is_empty() {
            match self.rx.recv() {
                Ok(v) => self.pending = v,
                Err(_) => return Ok(0), // the other end hung up: end of stream
            }
        }
        let n = buf.len().min(self.pending.len());
        buf[..n].copy_from_slice(&self.pending[..n]);
        self.pending.drain(..n);
        Ok(n)
    }
}

/// The writing end.
struct PipeWriter(Sender<Vec<u8>>);

impl Write for PipeWriter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0
            .send(buf.to_vec())
            .map_err(|_| io::Error::from(io::ErrorKind::BrokenPipe))?;
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn pipe() -> (PipeWriter, PipeReader) {
    let (tx, rx) = channel();
    (
        PipeWriter(tx),
        PipeReader {
            rx,
            pending: Vec::new(),
        },
    )
}

/// A fake device: answers hello and pings, refuses arming, sends `n` samples on SetStream, and
/// hangs up after `requests` requests.
fn fake_device(mut from_host: PipeReader, mut to_host: PipeWriter, requests: usize) {
    std::thread::spawn(move || {
        let send = |w: &mut PipeWriter, m: &DeviceMsg| {
            let mut buf = [0u8; MAX_FRAME_LEN];
            let n = encode_frame(m, &mut buf).unwrap();
            w.write_all(&buf[..n]).unwrap();
        };
        let mut dec = FrameDecoder::new();
        let mut seen = 0;
        let mut byte = [0u8; 1];
        while seen < requests && from_host.read(&mut byte).unwrap_or(0) == 1 {
            let Some(Ok(msg)) = dec.push::<HostMsg>(byte[0]) else {
                continue;
            };
            match msg {
                HostMsg::Hello { .. } => send(
                    &mut to_host,
                    &DeviceMsg::HelloReply {
                        version: Some(PROTOCOL_VERSION),
                        device_version: PROTOCOL_VERSION,
                    },
                ),
                HostMsg::Request { seq, req } => {
                    // The heartbeat's pings (every 20 ms) are not the test's requests: counted,
                    // they made the hang-up come early on a loaded machine.
                    if seq != softfinger_host::device::HEARTBEAT_SEQ {
                        seen += 1;
                    }
                    let result = match req {
                        Request::Arm => AckResult::Err(ErrorCode::WrongMode),
                        _ => AckResult::Ok,
                    };
                    send(&mut to_host, &DeviceMsg::Ack { seq, result });
                    if let Request::SetStream { divisor } = req {
                        for k in 0..5u64 {
                            let s = StateSample {
                                tick: k * divisor as u64,
                                ..StateSample::default()
                            };
                            send(&mut to_host, &DeviceMsg::State(s));
                        }
                    }
                }
            }
        }
        // Dropping the writer hangs up.
    });
}

#[test]
fn requests_states_refusals_and_hang_up_over_a_byte_stream() {
    let (host_w, dev_r) = pipe();
    let (dev_w, host_r) = pipe();
    fake_device(dev_r, dev_w, 4);
    let mut d = Device::over(Box::new(host_r), Box::new(host_w)).unwrap();
    d.set_timeout(Duration::from_secs(2));
    assert!(d.ping().is_ok());
    assert!(matches!(
        d.arm(),
        Err(LinkError::Refused(ErrorCode::WrongMode))
    ));
    d.set_stream(10).unwrap();
    let ticks: Vec<u64> = (0..5)
        .map(|_| d.next_state(Duration::from_secs(2)).unwrap().unwrap().tick)
        .collect();
    assert_eq!(ticks, vec![0, 10, 20, 30, 40]);
    assert!(d.ping().is_ok(), "the fourth request");
    // The device hangs up: requests fail, the stream reports it, reconnecting has no target.
    assert!(matches!(
        d.ping(),
        Err(LinkError::Disconnected | LinkError::Io(_) | LinkError::Timeout)
    ));
    assert!(matches!(
        d.next_state(Duration::from_secs(2)),
        Err(LinkError::Disconnected)
    ));
    assert!(d.reconnect().is_err());
    assert_eq!(d.rx_errors().total(), 0);
}

//! One TCP connection of the virtual device: a reader thread that decodes frames and hands
//! messages to the device loop, and a writer thread that sends what the device queued.
//!
//! A bad frame is counted (per kind, over all connections) and answered with
//! [`DeviceMsg::FrameError`]; the connection goes on. The outgoing queue is bounded: a client
//! that stops reading loses state samples (counted), never stalls the device loop.

use softfinger_protocol::{
    encode_frame, DeviceMsg, FrameDecoder, FrameErrorKind, HostMsg, LinkCounters, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};
use std::io::{Read, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
use std::sync::mpsc::{sync_channel, Receiver, Sender, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread;

/// Frames a connection may have queued for sending before samples are dropped (4 s of a 1 kHz
/// stream would not fit; 0.5 s does).
pub const OUT_QUEUE_FRAMES: usize = 512;

/// Link counters over all connections, shared by the threads.
#[derive(Debug, Default)]
pub struct LinkStats {
    rx_frames: AtomicU32,
    rx_cobs: AtomicU32,
    rx_crc: AtomicU32,
    rx_version: AtomicU32,
    rx_decode: AtomicU32,
    rx_oversized: AtomicU32,
    tx_frames: AtomicU32,
    tx_dropped: AtomicU32,
    connections: AtomicU32,
}

impl LinkStats {
    /// The counters now.
    pub fn snapshot(&self) -> LinkCounters {
        let g = |a: &AtomicU32| a.load(Relaxed);
        let (cobs, crc, version, decode, oversized) = (
            g(&self.rx_cobs),
            g(&self.rx_crc),
            g(&self.rx_version),
            g(&self.rx_decode),
            g(&self.rx_oversized),
        );
        LinkCounters {
            rx_frames: g(&self.rx_frames),
            rx_errors: cobs + crc + version + decode + oversized,
            rx_cobs: cobs,
            rx_crc: crc,
            rx_version: version,
            rx_decode: decode,
            rx_oversized: oversized,
            tx_frames: g(&self.tx_frames),
            tx_dropped: g(&self.tx_dropped),
            connections: g(&self.connections).min(u16::MAX as u32) as u16,
        }
    }

    fn count_error(&self, kind: FrameErrorKind) {
        let c = match kind {
            FrameErrorKind::Cobs => &self.rx_cobs,
            FrameErrorKind::Crc => &self.rx_crc,
            FrameErrorKind::Version => &self.rx_version,
            FrameErrorKind::Decode => &self.rx_decode,
            FrameErrorKind::Oversized => &self.rx_oversized,
        };
        c.fetch_add(1, Relaxed);
    }
}

/// What the connections tell the device loop.
#[derive(Debug)]
pub enum Event {
    /// A client connected; send to it through `out`.
    Connected { id: u32, out: Outbox },
    /// A client sent a valid message.
    Message { id: u32, msg: HostMsg },
    /// A client went away.
    Disconnected { id: u32 },
}

/// The sending side of one connection's bounded queue.
#[derive(Clone, Debug)]
pub struct Outbox {
    tx: SyncSender<Vec<u8>>,
    stats: Arc<LinkStats>,
}

impl Outbox {
    /// Queue `msg`; false (and counted as dropped) when the queue is full or the client gone.
    pub fn send(&self, msg: &DeviceMsg) -> bool {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let Ok(n) = encode_frame(msg, &mut buf) else {
            self.stats.tx_dropped.fetch_add(1, Relaxed);
            return false;
        };
        match self.tx.try_send(buf[..n].to_vec()) {
            Ok(()) => {
                self.stats.tx_frames.fetch_add(1, Relaxed);
                true
            }
            Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => {
                self.stats.tx_dropped.fetch_add(1, Relaxed);
                false
            }
        }
    }
}

/// Serve one accepted connection: spawns its writer, then reads until the client goes away.
pub fn serve_connection(stream: TcpStream, id: u32, events: Sender<Event>, stats: Arc<LinkStats>) {
    let _ = stream.set_nodelay(true);
    let Ok(write_half) = stream.try_clone() else {
        return;
    };
    let (tx, rx) = sync_channel(OUT_QUEUE_FRAMES);
    let out = Outbox {
        tx,
        stats: stats.clone(),
    };
    stats.connections.fetch_add(1, Relaxed);
    let writer = thread::spawn(move || write_loop(write_half, rx));
    if events
        .send(Event::Connected {
            id,
            out: out.clone(),
        })
        .is_ok()
    {
        read_loop(&stream, id, &events, &stats, &out);
    }
    let _ = events.send(Event::Disconnected { id });
    drop(out);
    let _ = stream.shutdown(Shutdown::Both);
    let _ = writer.join();
    stats.connections.fetch_sub(1, Relaxed);
}

fn write_loop(mut stream: TcpStream, rx: Receiver<Vec<u8>>) {
    while let Ok(frame) = rx.recv() {
        if stream.write_all(&frame).is_err() {
            break;
        }
    }
    let _ = stream.shutdown(Shutdown::Both);
}

fn read_loop(
    mut stream: &TcpStream,
    id: u32,
    events: &Sender<Event>,
    stats: &LinkStats,
    out: &Outbox,
) {
    let mut decoder = FrameDecoder::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        for &b in &buf[..n] {
            match decoder.push::<HostMsg>(b) {
                None => {}
                Some(Ok(msg)) => {
                    stats.rx_frames.fetch_add(1, Relaxed);
                    if events.send(Event::Message { id, msg }).is_err() {
                        return;
                    }
                }
                Some(Err(e)) => {
                    stats.count_error(e.kind);
                    out.send(&DeviceMsg::FrameError {
                        kind: e.kind,
                        device_version: PROTOCOL_VERSION,
                    });
                }
            }
        }
    }
}

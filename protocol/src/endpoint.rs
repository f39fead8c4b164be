//! The device side of one link, for a low-priority task on the MCU (or a connection thread on a
//! host): bytes in, link-level messages answered on the spot, control requests handed to the
//! caller, state samples streamed at the link's divisor. No allocation, no blocking: every frame
//! goes out through a caller-supplied `send` that returns `false` when its queue is full (the
//! frame is then dropped and counted), so a host that stops reading never stalls the device.
//!
//! Answered here: [`HostMsg::Hello`], [`Request::GetCounters`], [`Request::SetStream`] and every
//! rejected frame ([`DeviceMsg::FrameError`]). Everything else is returned by
//! [`DeviceEndpoint::receive`] for the control side (to be queued to the tick, e.g. in a
//! `heapless::spsc::Queue`), which answers with [`DeviceEndpoint::reply`] or
//! [`DeviceEndpoint::send`]. A device with several links at once (the virtual device's TCP
//! clients) holds one endpoint per link made with [`DeviceEndpoint::one_of_several`]: it hands
//! `GetCounters` on, and the device answers with the counters over all its links.

use crate::frame::{encode_frame, FrameDecoder, FrameErrorCounts};
use crate::info::LinkCounters;
use crate::messages::{AckResult, DeviceMsg, ErrorCode, HostMsg, Request};
use crate::state::StateSample;
use crate::{MAX_FRAME_LEN, PROTOCOL_VERSION};

/// One link's device side: decoder, counters, stream divisor.
#[derive(Clone, Debug)]
pub struct DeviceEndpoint {
    decoder: FrameDecoder,
    min_divisor: u16,
    divisor: u16,
    tx_frames: u32,
    tx_dropped: u32,
    stream_dropped: u32,
    /// `GetCounters` answered here with this link's counters (false: handed on).
    counters_here: bool,
}

impl DeviceEndpoint {
    /// A link whose stream may be at most `control rate / min_divisor` (`min_divisor` ≥ 1).
    pub const fn new(min_divisor: u16) -> Self {
        DeviceEndpoint {
            decoder: FrameDecoder::new(),
            min_divisor: if min_divisor == 0 { 1 } else { min_divisor },
            divisor: 0,
            tx_frames: 0,
            tx_dropped: 0,
            stream_dropped: 0,
            counters_here: true,
        }
    }

    /// One of several links of a device (`min_divisor` as in [`DeviceEndpoint::new`]):
    /// `GetCounters` is returned by [`DeviceEndpoint::receive`] like a control request, for the
    /// device to answer with the counters over every link ([`LinkCounters::plus`] of each link's
    /// [`DeviceEndpoint::counters`]).
    pub const fn one_of_several(min_divisor: u16) -> Self {
        let mut e = DeviceEndpoint::new(min_divisor);
        e.counters_here = false;
        e
    }

    /// The counters of this link.
    pub fn counters(&self) -> LinkCounters {
        let e: FrameErrorCounts = self.decoder.errors();
        LinkCounters {
            rx_frames: self.decoder.frames(),
            rx_errors: e.total(),
            rx_cobs: e.cobs,
            rx_crc: e.crc,
            rx_version: e.version,
            rx_decode: e.decode,
            rx_oversized: e.oversized,
            tx_frames: self.tx_frames,
            tx_dropped: self.tx_dropped,
            connections: 1,
        }
    }

    /// The stream divisor in force (0: no stream).
    pub fn divisor(&self) -> u16 {
        self.divisor
    }

    /// Start the stream at `divisor` (0: off) without a request: the device's stored default.
    /// A divisor faster than the link's fastest is refused, as `SetStream` refuses it, and the
    /// divisor in force stays.
    pub fn set_divisor(&mut self, divisor: u16) -> Result<(), ErrorCode> {
        if divisor != 0 && divisor < self.min_divisor {
            return Err(ErrorCode::StreamTooFast);
        }
        self.divisor = divisor;
        Ok(())
    }

    /// Encode `msg` and hand it to `send`; counts what was sent and dropped.
    pub fn send(&mut self, msg: &DeviceMsg, send: &mut impl FnMut(&[u8]) -> bool) -> bool {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let ok = match encode_frame(msg, &mut buf) {
            Ok(n) => send(&buf[..n]),
            Err(_) => false,
        };
        if ok {
            self.tx_frames = self.tx_frames.wrapping_add(1);
        } else {
            self.tx_dropped = self.tx_dropped.wrapping_add(1);
        }
        ok
    }

    /// Take one received byte. Link-level messages and bad frames are answered through `send`;
    /// a control request is returned with its sequence number.
    pub fn receive(
        &mut self,
        byte: u8,
        send: &mut impl FnMut(&[u8]) -> bool,
    ) -> Option<(u16, Request)> {
        let msg = match self.decoder.push::<HostMsg>(byte)? {
            Ok(m) => m,
            Err(e) => {
                let answer = DeviceMsg::FrameError {
                    kind: e.kind,
                    device_version: PROTOCOL_VERSION,
                };
                self.send(&answer, send);
                return None;
            }
        };
        let (seq, req) = match msg {
            HostMsg::Hello {
                min_version,
                max_version,
            } => {
                self.send(&DeviceMsg::hello_reply(min_version, max_version), send);
                return None;
            }
            HostMsg::Request { seq, req } => (seq, req),
        };
        match req {
            Request::GetCounters if self.counters_here => {
                let counters = self.counters();
                self.send(&DeviceMsg::Counters { seq, counters }, send);
                None
            }
            Request::SetStream { divisor } => {
                let result = match self.set_divisor(divisor) {
                    Ok(()) => AckResult::Ok,
                    Err(e) => AckResult::Err(e),
                };
                self.send(&DeviceMsg::Ack { seq, result }, send);
                None
            }
            other => Some((seq, other)),
        }
    }

    /// Answer a control request.
    pub fn reply(&mut self, seq: u16, result: AckResult, send: &mut impl FnMut(&[u8]) -> bool) {
        self.send(&DeviceMsg::Ack { seq, result }, send);
    }

    /// Offer the state of control tick `sample.tick`: sent when the divisor divides the tick,
    /// with this link's count of samples it could not send. Returns whether one was sent.
    pub fn offer_state(
        &mut self,
        sample: &StateSample,
        send: &mut impl FnMut(&[u8]) -> bool,
    ) -> bool {
        if self.divisor == 0 || !sample.tick.is_multiple_of(self.divisor as u64) {
            return false;
        }
        let s = StateSample {
            dropped: self.stream_dropped,
            ..*sample
        };
        let sent = self.send(&DeviceMsg::State(s), send);
        if !sent {
            self.stream_dropped = self.stream_dropped.wrapping_add(1);
        }
        sent
    }
}

#[cfg(test)]
mod tests;

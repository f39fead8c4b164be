//! Firmware updates from the host: send a signed update file (`softfinger-sign sign ...`) in
//! chunks with a CRC each, resuming where the device stopped after a disconnect, have the device
//! check its signature and mark it, reboot it, and read the version it runs afterwards.

use crate::{Device, LinkError};
use softfinger_protocol::update::{
    UpdateChunk, UpdatePhase, UpdateRefusal, UpdateStatus, UPDATE_CHUNK_LEN,
};
use softfinger_protocol::{DeviceMsg, Request};
use softfinger_update::package::Package;
use softfinger_update::session::chunk_crc;

/// What an update did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UpdateOutcome {
    /// The device's status before.
    pub before: UpdateStatus,
    /// After the reboot.
    pub after: UpdateStatus,
    /// The version the file carries.
    pub offered: String,
    /// Reconnections during the transfer.
    pub resumed: u32,
}

/// A refusal in words.
pub fn describe(r: &UpdateRefusal) -> String {
    match r {
        UpdateRefusal::Armed => "refused while armed: disarm first".into(),
        UpdateRefusal::NotReceiving => "no update in progress on the device".into(),
        UpdateRefusal::Empty => "the image is empty".into(),
        UpdateRefusal::TooLarge { len, max } => format!("the image is {len} bytes, the device's slot {max}"),
        UpdateRefusal::OutOfOrder { expected } => format!("chunk out of order (device expects offset {expected})"),
        UpdateRefusal::ChunkCrc { offset } => format!("chunk at offset {offset} arrived corrupted (CRC mismatch)"),
        UpdateRefusal::ChunkLen { offset } => format!("chunk at offset {offset} has a bad length"),
        UpdateRefusal::Truncated { received, len } => {
            format!("image truncated: the device received {received} of {len} bytes")
        }
        UpdateRefusal::BadSignature => {
            "the signature does not verify against the device's public key; nothing marked, the running image untouched"
                .into()
        }
        UpdateRefusal::TrialNotConfirmed => "the running image has not confirmed itself yet (trial boot)".into(),
        UpdateRefusal::Flash => "the device's flash failed; update abandoned".into(),
        UpdateRefusal::BadSignatureLength => "the signature is not 64 bytes".into(),
    }
}

fn answer(msg: DeviceMsg) -> Result<UpdateStatus, LinkError> {
    match msg {
        DeviceMsg::Update { status, .. } => Ok(status),
        DeviceMsg::UpdateRefused { refusal, .. } => Err(LinkError::Context(describe(&refusal))),
        other => Err(LinkError::Protocol(format!("{other:?}"))),
    }
}

fn refusal_of(msg: &DeviceMsg) -> Option<UpdateRefusal> {
    match msg {
        DeviceMsg::UpdateRefused { refusal, .. } => Some(*refusal),
        _ => None,
    }
}

/// How long a device may take to answer an update's begin (it erases its update slot), s.
const BEGIN_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(10);

impl Device {
    /// The device's update status and running version.
    pub fn update_status(&mut self) -> Result<UpdateStatus, LinkError> {
        answer(self.request(Request::UpdateStatus)?)
    }

    /// Begin (or resume) sending `pkg`; the offset to send from.
    fn update_begin(&mut self, pkg: &Package<'_>) -> Result<u32, LinkError> {
        let signature = heapless::Vec::from_slice(&pkg.signature)
            .map_err(|_| LinkError::Context("signature".into()))?;
        // A new image's begin erases the device's whole update slot first: 115 pages of 2 KiB on
        // the STM32G474, 22 ms each typically and 40 ms at most (RM0440), so up to ~4.6 s.
        let usual = self.timeout();
        self.set_timeout(BEGIN_TIMEOUT);
        let reply = self.request(Request::UpdateBegin {
            len: pkg.image.len() as u32,
            signature,
        });
        self.set_timeout(usual);
        let s = answer(reply?)?;
        match s.phase {
            UpdatePhase::Receiving { received, .. } => Ok(received),
            other => Err(LinkError::Protocol(format!("update begin: {other:?}"))),
        }
    }

    /// Send the update file `file`, have the device verify and mark it, reboot it, and report the
    /// versions. `progress(sent, total)` after each chunk. `corrupt_chunk_at`: for tests, send the
    /// chunk at that offset with a bad CRC once (the device must refuse it and the transfer go on).
    pub fn update(
        &mut self,
        file: &[u8],
        mut progress: impl FnMut(u32, u32),
        corrupt_chunk_at: Option<u32>,
    ) -> Result<UpdateOutcome, LinkError> {
        let pkg = Package::parse(file).map_err(|e| LinkError::Context(e.to_string()))?;
        let before = self.update_status()?;
        let total = pkg.image.len() as u32;
        let mut off = self.update_begin(&pkg)?;
        let mut resumed = 0;
        let mut corrupt = corrupt_chunk_at;
        while off < total {
            let end = (off as usize + UPDATE_CHUNK_LEN).min(pkg.image.len());
            let data = &pkg.image[off as usize..end];
            let mut crc = chunk_crc(data);
            if corrupt == Some(off) {
                crc ^= 1;
                corrupt = None;
            }
            let chunk = UpdateChunk {
                offset: off,
                crc,
                data: heapless::Vec::from_slice(data)
                    .map_err(|_| LinkError::Context("chunk".into()))?,
            };
            match self.request(Request::UpdateChunk(chunk)) {
                Ok(msg) => match refusal_of(&msg) {
                    Some(UpdateRefusal::OutOfOrder { expected }) => off = expected,
                    Some(UpdateRefusal::ChunkCrc { .. }) => {} // resend the same chunk
                    Some(r) => return Err(LinkError::Context(describe(&r))),
                    None => match answer(msg)?.phase {
                        UpdatePhase::Receiving { received, .. } => off = received,
                        p => return Err(LinkError::Protocol(format!("update chunk: {p:?}"))),
                    },
                },
                Err(LinkError::Timeout | LinkError::Disconnected | LinkError::Io(_))
                    if resumed < 5 =>
                {
                    resumed += 1;
                    self.reconnect()?;
                    off = self.update_begin(&pkg)?;
                }
                Err(e) => return Err(e),
            }
            progress(off, total);
        }
        let s = answer(self.request(Request::UpdateFinish)?)?;
        if s.phase != UpdatePhase::Verified {
            return Err(LinkError::Protocol(format!("update finish: {:?}", s.phase)));
        }
        match self.command(Request::Reboot) {
            Ok(()) => {}
            // A device that resets drops the link: reconnect.
            Err(LinkError::Timeout | LinkError::Disconnected | LinkError::Io(_)) => {}
            Err(e) => return Err(e),
        }
        let after = match self.update_status() {
            Ok(s) => s,
            Err(_) => {
                std::thread::sleep(std::time::Duration::from_secs(2));
                self.reconnect()?;
                self.update_status()?
            }
        };
        Ok(UpdateOutcome {
            before,
            after,
            offered: pkg.trailer.version().to_string(),
            resumed,
        })
    }
}

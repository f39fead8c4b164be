//! # softfinger-host
//!
//! Talk to a softfinger device over USB, or to the virtual device of `host-sim serve` over TCP,
//! with the messages of `softfinger-protocol`. An application embeds [`Device`]:
//!
//! ```no_run
//! use softfinger_host::{Device, Target};
//! use softfinger_host::protocol::{LocalModel, SurfaceShape};
//! use std::time::Duration;
//!
//! # fn main() -> Result<(), softfinger_host::LinkError> {
//! let mut dev = Device::connect(&"tcp:127.0.0.1:7700".parse::<Target>()?)?;
//! println!("{}", dev.info()?.name);
//! dev.home_and_wait(Duration::from_secs(10))?; // returns once homed
//! dev.arm()?;
//! // A sphere of 5 cm whose top is 7 cm above the base origin; sent at up to 1 kHz.
//! dev.set_local_model(LocalModel {
//!     seq: 1,
//!     shape: SurfaceShape::Sphere { radius_m: 0.05 },
//!     position_m: [0.0, 0.0, 0.02],
//!     orientation: [1.0, 0.0, 0.0, 0.0],
//!     stiffness_n_per_m: 2000.0,
//!     damping_n_s_per_m: 2.0,
//!     mu_s: 0.8,
//!     mu_k: 0.6,
//!     spin_stiffness_nm_per_rad: 0.01,
//!     max_age_ms: 0,
//! })?;
//! dev.set_stream(10)?; // every 10th control tick: 1 kHz at 10 kHz
//! while let Some(s) = dev.next_state(Duration::from_secs(1))? {
//!     println!("{:?} N, {}", s.force_n, s.contact.name());
//! }
//! # Ok(())
//! # }
//! ```
//!
//! Every call blocks until the device answers (default timeout 1 s, [`Device::set_timeout`]);
//! refusals come back typed ([`LinkError::Refused`] with the device's
//! [`protocol::ErrorCode`]). After the device goes away, [`Device::reconnect`] opens it again and
//! restores the stream and the watchdog.
//!
//! The library alone is `default-features = false`: `softfinger-protocol`, `softfinger-core` and
//! `serialport`. The default feature `cli` adds the `softfinger` command line, its link
//! measurements (`bench`) and the scene-file loader (`softfinger-scene`).

// The command line's link measurements and its scene loader (feature `cli`, on by default).
#[cfg(feature = "cli")]
pub mod bench;
#[cfg(feature = "cli")]
pub use softfinger_scene::wire as scene;

#[cfg(feature = "settings")]
pub mod config;
pub mod device;
pub mod error;
pub mod flags;
pub mod target;
#[cfg(feature = "settings")]
pub mod update;
pub mod usb;

pub use device::{Device, Latest, LatestState, StateQueue};
pub use error::LinkError;
pub use softfinger_protocol as protocol;
pub use target::Target;

//! Where the device is: `tcp:HOST:PORT` (the virtual device), `usb` (the first softfinger USB
//! device) or `usb:PATH` (a given serial port), and opening it as a byte stream.

use crate::error::LinkError;
use crate::usb;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// A device address.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// The virtual device (or anything speaking the protocol) at `HOST:PORT`.
    Tcp(String),
    /// The first USB device that identifies as a softfinger.
    FirstUsb,
    /// A USB CDC-ACM serial port by path.
    UsbPath(String),
}

impl std::str::FromStr for Target {
    type Err = LinkError;
    fn from_str(s: &str) -> Result<Target, LinkError> {
        if let Some(addr) = s.strip_prefix("tcp:") {
            if addr
                .rsplit_once(':')
                .is_some_and(|(h, p)| !h.is_empty() && p.parse::<u16>().is_ok())
            {
                return Ok(Target::Tcp(addr.to_string()));
            }
        } else if s == "usb" {
            return Ok(Target::FirstUsb);
        } else if let Some(path) = s.strip_prefix("usb:") {
            if !path.is_empty() {
                return Ok(Target::UsbPath(path.to_string()));
            }
        }
        Err(LinkError::BadTarget(s.to_string()))
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Tcp(a) => write!(f, "tcp:{a}"),
            Target::FirstUsb => write!(f, "usb"),
            Target::UsbPath(p) => write!(f, "usb:{p}"),
        }
    }
}

/// The two halves of an open byte stream.
pub type Halves = (Box<dyn Read + Send>, Box<dyn Write + Send>);

/// Open `target`.
pub fn open(target: &Target) -> Result<Halves, LinkError> {
    open_link(target).map(|l| l.halves)
}

/// An open connection.
pub struct Link {
    /// Its two halves.
    pub halves: Halves,
    /// For TCP, the socket once more: shutting it down ends a reader blocked on the read half
    /// (a dropped [`crate::Device`] does this, so its reader thread and the device's stream to
    /// it stop).
    pub tcp: Option<TcpStream>,
}

/// Open `target`, keeping what is needed to shut it down.
pub fn open_link(target: &Target) -> Result<Link, LinkError> {
    match target {
        Target::Tcp(addr) => {
            let s = TcpStream::connect(addr)?;
            s.set_nodelay(true)?;
            let r = s.try_clone()?;
            let tcp = Some(s.try_clone()?);
            Ok(Link {
                halves: (Box::new(r), Box::new(s)),
                tcp,
            })
        }
        Target::FirstUsb => {
            let ports = serialport::available_ports().map_err(|e| LinkError::Io(e.into()))?;
            let path = usb::pick_port(&ports).ok_or(LinkError::NoDevice)?;
            Ok(Link {
                halves: usb::open(&path, Duration::from_millis(50))?,
                tcp: None,
            })
        }
        Target::UsbPath(p) => Ok(Link {
            halves: usb::open(p, Duration::from_millis(50))?,
            tcp: None,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_parse_and_print_back() {
        for s in [
            "tcp:127.0.0.1:7700",
            "usb",
            "usb:/dev/ttyACM0",
            "tcp:localhost:0",
        ] {
            let t: Target = s.parse().unwrap();
            assert_eq!(t.to_string(), s);
        }
        for bad in [
            "tcp:127.0.0.1",
            "tcp::80",
            "tcp:h:99999",
            "usb:",
            "serial:x",
            "",
        ] {
            assert!(bad.parse::<Target>().is_err(), "{bad}");
        }
    }
}

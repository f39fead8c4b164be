//! The USB link: the device enumerates as a CDC-ACM serial port (the baud rate is ignored by
//! CDC-ACM) carrying the same frames as TCP. Found by its USB vendor/product ids or its product
//! string. Uses `serialport` without libudev, so it builds without system libraries.

use crate::error::LinkError;
use crate::target::Halves;
use serialport::{SerialPortInfo, SerialPortType};
use std::io::{self, Read};
use std::time::Duration;

/// USB vendor id of the device (pid.codes' shared open-source vendor id).
pub const USB_VID: u16 = 0x1209;
/// USB product id: a placeholder until the firmware's USB descriptors fix one.
pub const USB_PID: u16 = 0x5F10;
/// Product string the firmware reports.
pub const USB_PRODUCT: &str = "softfinger";

/// The first port that is a softfinger: by ids, else by product string.
pub fn pick_port(ports: &[SerialPortInfo]) -> Option<String> {
    let usb = |p: &SerialPortInfo| match &p.port_type {
        SerialPortType::UsbPort(u) => Some(u.clone()),
        _ => None,
    };
    ports
        .iter()
        .find(|p| usb(p).is_some_and(|u| u.vid == USB_VID && u.pid == USB_PID))
        .or_else(|| {
            ports.iter().find(|p| {
                usb(p).is_some_and(|u| {
                    u.product
                        .as_deref()
                        .is_some_and(|s| s.to_ascii_lowercase().contains(USB_PRODUCT))
                })
            })
        })
        .map(|p| p.port_name.clone())
}

/// A serial port's read half that turns read timeouts into "try again" instead of errors, so
/// the reader thread keeps waiting for the device.
struct PatientReader(Box<dyn serialport::SerialPort>);

impl Read for PatientReader {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            match self.0.read(buf) {
                Err(e) if e.kind() == io::ErrorKind::TimedOut => continue,
                other => return other,
            }
        }
    }
}

/// Open a serial port by path.
pub fn open(path: &str, timeout: Duration) -> Result<Halves, LinkError> {
    let port = serialport::new(path, 115_200)
        .timeout(timeout)
        .open()
        .map_err(|e| LinkError::Io(e.into()))?;
    let reader = port.try_clone().map_err(|e| LinkError::Io(e.into()))?;
    Ok((Box::new(PatientReader(reader)), Box::new(port)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serialport::UsbPortInfo;

    fn usb_port(name: &str, vid: u16, pid: u16, product: Option<&str>) -> SerialPortInfo {
        SerialPortInfo {
            port_name: name.into(),
            port_type: SerialPortType::UsbPort(UsbPortInfo {
                vid,
                pid,
                serial_number: None,
                manufacturer: None,
                product: product.map(str::to_string),
            }),
        }
    }

    #[test]
    fn picks_by_ids_then_by_product_string() {
        let other = usb_port("/dev/ttyACM0", 0x0483, 0x374b, Some("STLink"));
        let by_name = usb_port("/dev/ttyACM1", 0x1234, 0x0001, Some("SoftFinger haptic"));
        let by_ids = usb_port("/dev/ttyACM2", USB_VID, USB_PID, None);
        let plain = SerialPortInfo {
            port_name: "/dev/ttyS0".into(),
            port_type: SerialPortType::Unknown,
        };
        assert_eq!(
            pick_port(&[other.clone(), by_name.clone(), by_ids]).as_deref(),
            Some("/dev/ttyACM2")
        );
        assert_eq!(
            pick_port(&[plain.clone(), other.clone(), by_name]).as_deref(),
            Some("/dev/ttyACM1")
        );
        assert_eq!(pick_port(&[plain, other]), None);
    }

    #[test]
    fn a_missing_port_is_an_error_not_a_panic() {
        assert!(open("/dev/softfinger-does-not-exist", Duration::from_millis(10)).is_err());
    }
}

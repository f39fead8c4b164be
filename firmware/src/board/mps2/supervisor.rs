//! Fault reporting of the emulated board: logs every change of the control loop's fault latch and
//! mirrors it on the FPGA's LED 0 (lit while a fault is latched), as the STM32 build's supervisor
//! does with LD2.
#![allow(unsafe_code)]

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embassy_time::{Duration, Ticker};
use softfinger_core::Flags;

use super::control::LATCHED;
use crate::config;

/// mps2 FPGAIO LED register (bit 0: LED 0).
const FPGAIO_LED: *mut u32 = 0x4002_8000 as *mut u32;

fn led(on: bool) {
    // SAFETY: the FPGAIO LED register of mps2-an386 (QEMU hw/misc/mps2-fpgaio.c).
    unsafe { FPGAIO_LED.write_volatile(u32::from(on)) };
}

#[embassy_executor::task]
pub async fn supervisor() {
    let mut ticker = Ticker::every(Duration::from_millis(config::SUPERVISOR_POLL_MS));
    let mut previous = Flags::NONE;
    loop {
        let latched = Flags(LATCHED.load(Ordering::Relaxed));
        if latched != previous {
            let new = Flags(latched.0 & !previous.0);
            if !new.is_empty() {
                warn!("FAULT latched: {} (drivers disabled, zero torque)", new);
            }
            if latched.is_empty() {
                info!("faults cleared; drivers may be enabled");
            }
            previous = latched;
        }
        led(!latched.is_empty());
        ticker.next().await;
    }
}

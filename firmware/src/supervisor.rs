//! Fault reporting and the operator's clear action.
//!
//! - [`supervisor`] watches the control loop's fault latch, logs every transition (warn when a
//!   fault latches, info when cleared) and mirrors it on LD2 (lit while a fault is latched).
//! - [`clear_button`] turns a press of the B1 user button into a request, served by the next
//!   control tick, to clear latched faults in the controller and the output guard.

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embassy_stm32::exti::ExtiInput;
use embassy_stm32::gpio::Output;
use embassy_stm32::mode::Async;
use embassy_time::{Duration, Ticker, Timer};
use softfinger_core::Flags;

use crate::config;
use crate::control::{CLEAR_REQUEST, LATCHED};

#[embassy_executor::task]
pub async fn supervisor(mut led: Output<'static>) {
    let mut ticker = Ticker::every(Duration::from_millis(config::SUPERVISOR_POLL_MS));
    let mut previous = Flags::NONE;
    loop {
        let latched = Flags(LATCHED.load(Ordering::Relaxed));
        if latched != previous {
            let new = Flags(latched.0 & !previous.0);
            if !new.is_empty() {
                warn!(
                    "FAULT latched: {} (drivers disabled, zero torque); press B1 to clear",
                    new
                );
            }
            if latched.is_empty() {
                info!("faults cleared; drivers may be enabled");
            }
            previous = latched;
        }
        if latched.is_empty() {
            led.set_low();
        } else {
            led.set_high();
        }
        ticker.next().await;
    }
}

#[embassy_executor::task]
pub async fn clear_button(mut button: ExtiInput<'static, Async>) {
    loop {
        button.wait_for_rising_edge().await;
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
        if button.is_high() {
            info!("B1 pressed: clearing latched faults");
            CLEAR_REQUEST.store(true, Ordering::Relaxed);
        }
        button.wait_for_low().await;
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
    }
}

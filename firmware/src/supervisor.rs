//! Fault reporting and the operator's clear action.
//!
//! - [`supervisor`] watches the control loop's fault latch, logs every transition (warn when a
//!   fault latches, info when cleared) and mirrors it on LD2 (lit while a fault is latched).
//! - [`clear_button`] turns a short press of the B1 user button into a request, served by the next
//!   control tick, to clear latched faults in the controller and the output guard; a long press
//!   (≥ 1 s) requests the next surface-stiffness preset, which the tick hands to the controller's
//!   validated `set_contact_params` (a run-time parameter change from a low-priority task).

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embassy_stm32::exti::ExtiInput;
use embassy_stm32::gpio::Output;
use embassy_stm32::mode::Async;
use embassy_time::{Duration, Ticker, Timer};
use softfinger_core::Flags;

use crate::config;
use crate::control::{CLEAR_REQUEST, LATCHED, PARAM_APPLIED, PARAM_REQUEST, PARAM_RESULT};
use softfinger_core::params::ContactParams;

#[embassy_executor::task]
pub async fn supervisor(mut led: Output<'static>) {
    let mut ticker = Ticker::every(Duration::from_millis(config::SUPERVISOR_POLL_MS));
    let mut previous = Flags::NONE;
    let mut previous_param = 0u32;
    loop {
        let param = PARAM_RESULT.load(Ordering::Relaxed);
        if param != previous_param {
            if param & 3 == PARAM_APPLIED {
                info!("contact parameters applied (request {=u32})", param >> 2);
            } else {
                warn!(
                    "contact parameters REJECTED (request {=u32}); previous ones kept",
                    param >> 2
                );
            }
            previous_param = param;
        }
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

/// Surface stiffness presets (N/m) cycled by a long press of B1: soft, the default, stiff.
const STIFFNESS_PRESETS: [f32; 3] = [500.0, 2000.0, 5000.0];

#[embassy_executor::task]
pub async fn clear_button(mut button: ExtiInput<'static, Async>) {
    let mut preset = 1; // the default stiffness
    loop {
        button.wait_for_rising_edge().await;
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
        if !button.is_high() {
            continue;
        }
        let long = embassy_time::with_timeout(
            Duration::from_millis(config::LONG_PRESS_MS),
            button.wait_for_low(),
        )
        .await
        .is_err();
        if long {
            preset = (preset + 1) % STIFFNESS_PRESETS.len();
            let stiffness = STIFFNESS_PRESETS[preset];
            info!(
                "B1 held: requesting surface stiffness {=f32} N/m",
                stiffness
            );
            let params = ContactParams {
                normal_stiffness: stiffness,
                ..ContactParams::DEFAULT
            };
            critical_section::with(|cs| PARAM_REQUEST.borrow(cs).set(Some(params)));
            button.wait_for_low().await;
        } else {
            info!("B1 pressed: clearing latched faults");
            CLEAR_REQUEST.store(true, Ordering::Relaxed);
        }
        Timer::after_millis(config::BUTTON_DEBOUNCE_MS).await;
    }
}

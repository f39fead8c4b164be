//! The control tick on the NUCLEO-G474RE: interrupt priorities and debug freeze before and after
//! the HAL's initialisation, the hand-over of the control loop to TIM6's interrupt (started in step
//! with TIM1's PWM, see the parent module's "Output timing"), and the interrupt handler.

use embassy_stm32::{interrupt, pac};

use super::Stm32Control;
use softfinger_app::isr_cell::IsrCell;
use softfinger_app::tick::ControlLoop;

/// Priority byte of every device interrupt until one is raised: the lowest (15).
const LOWEST_PRIORITY: u8 = 0xF0;

/// Where the tick's state stream goes: the USB link's queue, or nowhere without a link.
pub type StreamTx = heapless::spsc::Producer<'static, softfinger_app::stream::StreamPoint>;

/// The control loop, handed to the TIM6 interrupt by [`start_tick`].
static CONTROL: IsrCell<ControlLoop<Stm32Control, StreamTx>> = IsrCell::new();

/// [`start_tick`] was called before.
#[derive(Debug, defmt::Format)]
pub struct AlreadyStarted;

/// Before `embassy_stm32::init`: every device interrupt at the lowest priority (only the tick is
/// ever raised to P0, see `critical_section_basepri`), and TIM1, TIM6 and the IWDG frozen while a
/// debugger halts the core, so a breakpoint never leaves the bridges driven.
pub fn prepare_core(nvic: &mut cortex_m::peripheral::NVIC) {
    // STM32G474: 102 device interrupts (0..=101).
    for ipr in nvic.ipr.iter().take(102) {
        // SAFETY: no device interrupt is enabled yet, so changing priorities cannot break a
        // priority-based critical section in progress.
        unsafe { ipr.write(LOWEST_PRIORITY) };
    }
    pac::DBGMCU.apb2fzr().modify(|w| w.set_tim1(true));
    pac::DBGMCU.apb1lfzr().modify(|w| {
        w.set_tim6(true);
        w.set_iwdg(true);
    });
}

/// After `embassy_stm32::init`: flash prefetch on (with the instruction and data caches), the
/// core's LOCKUP output onto TIM1's break (a fault inside the HardFault handler locks the core up;
/// the PWM outputs then cut in hardware), and the interrupt priorities (DMA's is in
/// `hal_config`): the tick (TIM6, P0, still masked), then the HAL's interrupts between it and
/// thread mode.
pub fn after_hal_init() {
    // Write-once until reset. SYSCFG's clock is on (embassy_stm32::init enables it).
    pac::SYSCFG.cfgr2().modify(|w| w.set_cll(true));
    pac::FLASH.acr().modify(|w| {
        w.set_prften(true);
        w.set_icen(true);
        w.set_dcen(true);
    });
    use embassy_stm32::interrupt::{InterruptExt, Priority};
    interrupt::TIM6_DAC.set_priority(Priority::P0); // the control tick (unmasked by start_tick)
    interrupt::TIM1_BRK_TIM15.set_priority(Priority::P2); // embassy-time driver (TIM15)
    interrupt::EXTI15_10.set_priority(Priority::P3); // B1
}

/// Hand the loop to the TIM6 interrupt (priority 0, set in [`after_hal_init`] with every other
/// interrupt priority) and start it: the watchdog, then TIM1
/// and TIM6 restarted together from 0, so every tick event is a PWM period boundary (the shared
/// board timing's convention: both count the same 170 MHz clock, 4250 and 17 000 counts per
/// period, so once aligned they stay aligned), then unmask. Returns TIM1's count minus TIM6's,
/// read back to back right after the start (the start skew plus the spacing of the two reads,
/// a few counts). A second call is refused.
pub fn start_tick(mut control: ControlLoop<Stm32Control, StreamTx>) -> Result<i32, AlreadyStarted> {
    use embassy_stm32::interrupt::InterruptExt;
    control.hw_mut().watchdog.unleash();
    CONTROL.install(control).map_err(|_| AlreadyStarted)?;

    let (t1, t6) = (pac::TIM1, pac::TIM6);
    t1.cr1().modify(|w| w.set_cen(false));
    t6.cr1().modify(|w| w.set_cen(false));
    t1.cnt().write(|w| w.set_cnt(0));
    t6.cnt().write(|w| w.set_cnt(0));
    t6.sr().write(|w| w.set_uif(false));
    interrupt::TIM6_DAC.unpend();
    let mut cr1_1 = t1.cr1().read();
    cr1_1.set_cen(true);
    let mut cr1_6 = t6.cr1().read();
    cr1_6.set_cen(true);
    // Two consecutive stores.
    t1.cr1().write_value(cr1_1);
    t6.cr1().write_value(cr1_6);
    let (c1, c6) = (t1.cnt().read().cnt(), t6.cnt().read().cnt());
    // SAFETY: unmasking is unsafe because it could break a critical section relying on this
    // interrupt staying masked. None does: the handler shares nothing with other contexts except
    // atomics and lock-free SPSC queues, and it takes no critical section over shared data.
    unsafe { interrupt::TIM6_DAC.enable() };
    Ok(i32::from(c1) - i32::from(c6))
}

#[interrupt]
fn TIM6_DAC() {
    // First action: the tick timer's count is the start latency.
    let entry = u32::from(pac::TIM6.cnt().read().cnt());
    // SAFETY: this handler is the only caller of `CONTROL.get_mut`, and a handler never preempts
    // itself, so the reference is exclusive for the duration of this call.
    match unsafe { CONTROL.get_mut() } {
        Some(control) => control.run(entry),
        // Not installed (cannot happen: the interrupt is unmasked after install): acknowledge.
        None => pac::TIM6.sr().write(|w| w.set_uif(false)),
    }
}

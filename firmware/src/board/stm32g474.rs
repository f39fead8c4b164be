//! NUCLEO-G474RE: clocks, the six quadrature decoders, the three phase/enable bridges on TIM1 with
//! the drivers' fault line on TIM1's break input, the control-tick timer (TIM6), the watchdog, LD2
//! and B1. The pin map is in README.md; embassy-stm32's traits reject at compile time any pin that
//! cannot serve the timer channel it is given.
//!
//! The hot path (encoder reads, bridge writes) uses single register accesses through the
//! stm32-metapac register API: one volatile access each, no bounds checks, no lock.
//!
//! **Output timing** (`softfinger_core::control::pipeline::output_timing`): TIM1 runs the 40 kHz PWM with
//! preloaded compares and an update event at every PWM period (repetition counter 0); the control
//! tick is TIM6's update, started with TIM1 from 0 ([`start_tick`]), so every tick event is a PWM
//! period boundary and a compare the tick writes acts 25 µs after the event. Why TIM6 and not
//! TIM1's own update: docs/design.md#tick-timer-and-output-timing-on-the-stm32g474.

use embassy_stm32::exti::{self, ExtiInput};
use embassy_stm32::gpio::{AnyPin, Level, Output, OutputType, Pull, Speed};
use embassy_stm32::mode::Async;
use embassy_stm32::pac;
use embassy_stm32::pac::timer::vals::{Bkinp, Bkp, FilterValue, Lock, Ossi, Ossr};
use embassy_stm32::peripherals::{IWDG, TIM2, TIM20, TIM3, TIM4, TIM5, TIM8};
use embassy_stm32::time::Hertz;
use embassy_stm32::timer::low_level::{CountingMode, Timer};
use embassy_stm32::timer::qei::{self, Qei, QeiMode};
use embassy_stm32::timer::simple_pwm::{PwmPin, SimplePwm};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, interrupt, rcc, Config, Peripherals};

use softfinger_app::reset_cause::{ResetCause, ResetFlags};

use super::{BridgeCommands, ControlHw, Indicator, OperatorButton, RawSample};
use softfinger_app::config;

mod tick;
pub use tick::{after_hal_init, prepare_core, start_tick, StreamTx};

bind_interrupts!(struct Irqs {
    EXTI15_10 => exti::InterruptHandler<interrupt::typelevel::EXTI15_10>;
});

bind_interrupts!(struct UsbIrqs {
    USB_LP => embassy_stm32::usb::InterruptHandler<embassy_stm32::peripherals::USB>;
});

/// The USB peripheral and its pins (PA12 = D+, PA11 = D−), for the host link (feature `usb`).
pub struct UsbParts {
    usb: embassy_stm32::Peri<'static, embassy_stm32::peripherals::USB>,
    dp: embassy_stm32::Peri<'static, embassy_stm32::peripherals::PA12>,
    dm: embassy_stm32::Peri<'static, embassy_stm32::peripherals::PA11>,
}

impl UsbParts {
    /// The full-speed device driver. Its interrupt (USB_LP) keeps the lowest priority that
    /// [`prepare_core`] gave every device interrupt: below the tick and everything else.
    pub fn driver(self) -> embassy_stm32::usb::Driver<'static, embassy_stm32::peripherals::USB> {
        embassy_stm32::usb::Driver::new(self.usb, UsbIrqs, self.dp, self.dm)
    }
}

/// BASEPRI value that masks every interrupt priority except 0: the STM32G4 NVIC implements the
/// top 4 priority bits (`NVIC_PRIO_BITS`), so priority 1 is 0x10.
pub const BASEPRI_BELOW_TICK: u8 = 1 << (8 - pac::NVIC_PRIO_BITS);

/// Port B pins of the bridges: phase pins (PH) of motors 0..2 and the shared nSLEEP.
const PHASE_PINS: [usize; 3] = [10, 4, 5];
const N_SLEEP_PIN: usize = 0;
/// PB12: the drivers' wired-OR nFAULT, as TIM1_BKIN (AF6), read back through GPIOB_IDR.
const N_FAULT_PIN: usize = 12;
const BKIN_AF: u8 = 6;

/// Input filter on every encoder channel and on the break input: 8 samples at fDTS/4, i.e. a
/// level must hold 32 timer clocks (188 ns at 170 MHz) to count. A 2000-line encoder at 3000 rpm
/// has 10 us between edges, 50x longer.
const INPUT_FILTER: FilterValue = FilterValue::FDTS_DIV4_N8;

/// HAL configuration: 170 MHz from the board's 24 MHz crystal (HSE / 6 x 85 / 2; VCO 340 MHz),
/// range-1 boost mode as required above 150 MHz, DMA interrupts (unused) below the control tick.
pub fn hal_config() -> Config {
    let mut c = Config::default();
    c.rcc.hse = Some(rcc::Hse {
        freq: Hertz(config::HSE_HZ),
        mode: rcc::HseMode::Oscillator,
    });
    c.rcc.pll = Some(rcc::Pll {
        source: rcc::PllSource::HSE,
        prediv: rcc::PllPreDiv::DIV6,
        mul: rcc::PllMul::MUL85,
        divp: None,
        divq: None,
        divr: Some(rcc::PllRDiv::DIV2),
    });
    c.rcc.sys = rcc::Sysclk::PLL1_R;
    c.rcc.boost = true;
    c.bdma_interrupt_priority = interrupt::Priority::P4;
    // USB's 48 MHz from the internal HSI48, trimmed by the clock recovery system (CRS) to the
    // host's start-of-frame packets: no crystal needed for USB.
    {
        c.rcc.hsi48 = Some(rcc::Hsi48Config {
            sync_from_usb: true,
        });
        c.rcc.mux.clk48sel = rcc::mux::Clk48sel::HSI48;
    }
    c
}

/// Zero every bridge output with raw register writes, from any context, without owning anything:
/// PWM main output off (EN pins forced to their idle level, low), compares 0, phase pins and nSLEEP
/// low. For the panic and HardFault handlers; idempotent.
#[inline(always)]
pub fn emergency_stop() {
    pac::TIM1.bdtr().modify(|w| w.set_moe(false));
    for ch in 0..3 {
        pac::TIM1.ccr(ch).write(|w| w.set_ccr(0));
    }
    let mut reset = 1u32 << (16 + N_SLEEP_PIN);
    for pin in PHASE_PINS {
        reset |= 1 << (16 + pin);
    }
    pac::GPIOB.bsrr().write_value(pac::gpio::regs::Bsrr(reset));
}

/// The non-maskable interrupt (on the G474: the clock security system, a flash ECC double error,
/// an SRAM parity error): bridges off first, then logged; it waits for the watchdog (returning
/// would re-enter for a source still asserted).
#[cortex_m_rt::exception]
unsafe fn NonMaskableInt() -> ! {
    emergency_stop();
    defmt::error!("NMI; bridges off, waiting for the watchdog");
    softfinger_app::failsafe::halt()
}

/// Why the MCU last reset (RCC_CSR), read once at start-up; the flags are then cleared (RMVF) so
/// the next boot reads only its own.
pub fn take_reset_cause() -> ResetCause {
    let csr = pac::RCC.csr().read();
    let flags = ResetFlags {
        low_power: csr.lpwrrstf(),
        window_watchdog: csr.wwdgrstf(),
        independent_watchdog: csr.iwdgrstf(),
        software: csr.sftrstf(),
        option_bytes: csr.oblrstf(),
        brown_out: csr.borrstf(),
        pin: csr.pinrstf(),
    };
    pac::RCC.csr().modify(|w| w.set_rmvf(true));
    ResetCause::from_flags(flags)
}

/// Write-protect the CCM SRAM pages (1 KiB each, SYSCFG_SWPR, until the next reset) that hold the
/// tick's code, `start..end` (CCM addresses, from `ccm::loaded_range`): a stray write, e.g. past
/// the end of RAM into CCM's alias at 0x2001_8000, then faults instead of changing the tick.
/// SYSCFG's clock must be on (`embassy_stm32::init` enables it).
pub fn write_protect_ccm(start: u32, end: u32) {
    const CCM_BASE: u32 = 0x1000_0000;
    const PAGE: u32 = 1024;
    let first = (start.saturating_sub(CCM_BASE) / PAGE) as usize;
    let last = (end.saturating_sub(CCM_BASE).div_ceil(PAGE)) as usize;
    let mut swpr = pac::SYSCFG.swpr().read();
    for page in first..last.min(32) {
        swpr.set_page_wp(page, true);
    }
    pac::SYSCFG.swpr().write_value(swpr);
}

/// The six quadrature decoders: motor 0..2 (TIM2/3/4), wrist 0..2 (TIM5/8/20).
type Encoders = (
    Qei<'static, TIM2>,
    Qei<'static, TIM3>,
    Qei<'static, TIM4>,
    Qei<'static, TIM5>,
    Qei<'static, TIM8>,
    Qei<'static, TIM20>,
);

/// The hardware the control interrupt owns. Holding the HAL handles keeps the pins and timers
/// reserved; the hot path goes through the registers directly.
pub struct Stm32Control {
    _encoders: Encoders,
    _bridges: (
        SimplePwm<'static, embassy_stm32::peripherals::TIM1>,
        [Output<'static>; 4],
    ),
    _tick_timer: Timer<'static, embassy_stm32::peripherals::TIM6>,
    watchdog: IndependentWatchdog<'static, IWDG>,
}

impl ControlHw for Stm32Control {
    #[inline(always)]
    fn tick_period_counts(&self) -> u32 {
        config::TICK_PERIOD_COUNTS
    }

    #[inline(always)]
    fn tick_timer_count(&self) -> u32 {
        u32::from(pac::TIM6.cnt().read().cnt())
    }

    #[inline(always)]
    fn ack_tick(&mut self) {
        // rc_w0: writing 0 clears UIF; TIM6 has no other status flag.
        pac::TIM6.sr().write(|w| w.set_uif(false));
    }

    #[inline(always)]
    fn tick_event_pending(&self) -> bool {
        pac::TIM6.sr().read().uif()
    }

    #[inline(always)]
    fn read_inputs(&mut self) -> RawSample {
        // TIM2 and TIM5 are 32-bit; their low 16 bits follow the same modulo-2^16 sequence.
        let counts = [
            pac::TIM2.cnt().read() as u16,
            pac::TIM3.cnt().read().cnt(),
            pac::TIM4.cnt().read().cnt(),
            pac::TIM5.cnt().read() as u16,
            pac::TIM8.cnt().read().cnt(),
            pac::TIM20.cnt().read().cnt(),
        ];
        let n_fault_low = pac::GPIOB.idr().read().idr(N_FAULT_PIN) == pac::gpio::vals::Idr::LOW;
        // A break since the last read, even one shorter than a tick, is a driver fault too.
        let broke = pac::TIM1.sr().read().bif(0);
        if broke {
            pac::TIM1.sr().write(|w| {
                w.0 = !0;
                w.set_bif(0, false);
            });
        }
        RawSample {
            counts,
            driver_fault: n_fault_low || broke,
        }
    }

    /// The pipeline's ordering contract (`softfinger_core::control::pipeline::bridge`): outputs off first
    /// (MOE, then nSLEEP), then the phase pins, then the compares (preloaded: a PWM period
    /// boundary between the two writes loads the old compare, which is 0 whenever a phase
    /// changed), then outputs on (MOE, then nSLEEP).
    #[inline(always)]
    fn write_bridges(&mut self, cmd: &BridgeCommands) {
        let tim = pac::TIM1;
        if !cmd.pwm_enable {
            tim.bdtr().modify(|w| w.set_moe(false));
        }
        if !cmd.driver_awake {
            pac::GPIOB.bsrr().write(|w| w.set_br(N_SLEEP_PIN, true));
        }
        let mut bsrr = 0u32;
        for (pin, forward) in PHASE_PINS.into_iter().zip(cmd.phase_forward) {
            bsrr |= 1 << if forward { pin } else { pin + 16 };
        }
        pac::GPIOB.bsrr().write_value(pac::gpio::regs::Bsrr(bsrr));
        for (ch, compare) in cmd.compare.into_iter().enumerate() {
            tim.ccr(ch).write(|w| w.set_ccr(compare));
        }
        // MOE stays 0 while the break input is active, whatever is written here.
        if cmd.pwm_enable {
            tim.bdtr().modify(|w| w.set_moe(true));
        }
        if cmd.driver_awake {
            pac::GPIOB.bsrr().write(|w| w.set_bs(N_SLEEP_PIN, true));
        }
    }

    #[inline(always)]
    fn pet_watchdog(&mut self) {
        self.watchdog.pet();
    }
}

/// LD2 (green).
pub struct Led(Output<'static>);

impl Indicator for Led {
    fn set(&mut self, on: bool) {
        self.0.set_level(Level::from(on));
    }
}

/// B1 (blue, active high).
pub struct Button(ExtiInput<'static, Async>);

impl OperatorButton for Button {
    async fn wait_pressed(&mut self) {
        self.0.wait_for_high().await;
    }
    async fn wait_released(&mut self) {
        self.0.wait_for_low().await;
    }
    fn is_pressed(&mut self) -> bool {
        self.0.is_high()
    }
}

/// Everything the firmware uses, configured and in a safe state (drivers asleep, PWM outputs off,
/// compares 0), nothing started.
pub struct Board {
    pub control: Stm32Control,
    pub led: Led,
    pub button: Button,
    pub usb: UsbParts,
    /// The whole flash, blocking (the settings store and the update's slots, both in bank 2;
    /// softfinger-update's `layout::G474`).
    pub flash: BoardFlash,
}

/// The STM32G474's flash as the settings store and the update use it: embassy-stm32's blocking
/// driver (offsets from 0x0800_0000; dual-bank, 2 KiB pages, 8-byte writes), paced so that the
/// thread-mode heartbeat keeps going through a long erase (`softfinger_app::persist::PacedFlash`).
pub type BoardFlash = softfinger_app::persist::PacedFlash<
    embassy_stm32::flash::Flash<'static, embassy_stm32::flash::Blocking>,
>;

/// The self-test's clock check: the PLL locked and the system clock running from it.
pub fn clock_ok() -> bool {
    pac::RCC.cr().read().pllrdy() && pac::RCC.cfgr().read().sws() == pac::rcc::vals::Sw::PLL1_R
}

/// The self-test's encoder check: each of the six encoder timers enabled and counting in
/// quadrature (x4) mode. (Whether an encoder's lines move needs motion: homing checks that.)
pub fn encoders_ok() -> bool {
    use pac::timer::vals::Sms;
    let quad = Sms::ENCODER_MODE_3;
    let gp32 = [pac::TIM2, pac::TIM5]
        .iter()
        .all(|t| t.smcr().read().sms() == quad && t.cr1().read().cen());
    let gp16 = [pac::TIM3, pac::TIM4]
        .iter()
        .all(|t| t.smcr().read().sms() == quad && t.cr1().read().cen());
    let adv = [pac::TIM8, pac::TIM20]
        .iter()
        .all(|t| t.smcr().read().sms() == quad && t.cr1().read().cen());
    gp32 && gp16 && adv
}

impl Board {
    /// After a rejected configuration: drive every bridge pin low as a plain output (nSLEEP, the
    /// phase pins, the three EN/PWM pins) and keep it so; nothing else is configured.
    pub fn hold_safe(p: Peripherals) {
        let low = |pin: embassy_stm32::Peri<'static, AnyPin>| {
            core::mem::forget(Output::new(pin, Level::Low, Speed::Low))
        };
        low(p.PB0.into());
        low(p.PB10.into());
        low(p.PB4.into());
        low(p.PB5.into());
        low(p.PA8.into());
        low(p.PA9.into());
        low(p.PA10.into());
    }

    /// Configure every peripheral; outputs start low. Call only after the configuration has been
    /// validated: from here on the bridges are wired to the timer.
    pub fn new(p: Peripherals) -> Self {
        // Outputs first, driven low, so the bridges never see a floating nSLEEP or phase pin.
        let sleep_and_phase = [
            Output::new(p.PB0, Level::Low, Speed::Low),
            Output::new(p.PB10, Level::Low, Speed::Low),
            Output::new(p.PB4, Level::Low, Speed::Low),
            Output::new(p.PB5, Level::Low, Speed::Low),
        ];
        // nFAULT is open drain on DRV887x parts: pull-up, alternate function TIM1_BKIN, set
        // up before TIM1's break is armed. PB12 is only claimed here; its mode is set through the
        // registers (embassy has no BKIN pin type).
        let _ = p.PB12;
        pac::GPIOB
            .pupdr()
            .modify(|w| w.set_pupdr(N_FAULT_PIN, pac::gpio::vals::Pupdr::PULL_UP));
        pac::GPIOB
            .afr(N_FAULT_PIN / 8)
            .modify(|w| w.set_afr(N_FAULT_PIN % 8, BKIN_AF));
        pac::GPIOB
            .moder()
            .modify(|w| w.set_moder(N_FAULT_PIN, pac::gpio::vals::Moder::ALTERNATE));
        let pwm = pwm_tim1(p.TIM1, p.PA8, p.PA9, p.PA10);

        let encoders = (
            Qei::new(p.TIM2, p.PA15, p.PB3, qei_config()),
            Qei::new(p.TIM3, p.PA6, p.PA7, qei_config()),
            Qei::new(p.TIM4, p.PB6, p.PB7, qei_config()),
            Qei::new(p.TIM5, p.PA0, p.PA1, qei_config()),
            Qei::new(p.TIM8, p.PC6, p.PC7, qei_config()),
            Qei::new(p.TIM20, p.PB2, p.PC2, qei_config()),
        );
        encoder_filters();

        let tick_timer = Timer::new(p.TIM6);
        let t6 = pac::TIM6;
        t6.psc().write_value(0);
        t6.arr()
            .write(|w| w.set_arr((config::TICK_PERIOD_COUNTS - 1) as u16));
        t6.egr().write(|w| w.set_ug(true));
        t6.sr().write(|w| w.set_uif(false));
        t6.dier().write(|w| w.set_uie(true));

        Board {
            control: Stm32Control {
                _encoders: encoders,
                _bridges: (pwm, sleep_and_phase),
                _tick_timer: tick_timer,
                watchdog: IndependentWatchdog::new(p.IWDG, config::WATCHDOG_TIMEOUT_US),
            },
            led: Led(Output::new(p.PA5, Level::Low, Speed::Low)),
            button: Button(ExtiInput::new(p.PC13, p.EXTI13, Pull::Down, Irqs)),
            usb: UsbParts {
                usb: p.USB,
                dp: p.PA12,
                dm: p.PA11,
            },
            flash: softfinger_app::persist::PacedFlash(embassy_stm32::flash::Flash::new_blocking(
                p.FLASH,
            )),
        }
    }
}

/// TIM1 CH1..CH3 as the bridges' EN inputs: edge-aligned PWM at the shared board timing (prescaler
/// 1, full scale from `config`), compares preloaded, break input armed, main output off.
fn pwm_tim1(
    tim: embassy_stm32::Peri<'static, embassy_stm32::peripherals::TIM1>,
    ch1: embassy_stm32::Peri<'static, embassy_stm32::peripherals::PA8>,
    ch2: embassy_stm32::Peri<'static, embassy_stm32::peripherals::PA9>,
    ch3: embassy_stm32::Peri<'static, embassy_stm32::peripherals::PA10>,
) -> SimplePwm<'static, embassy_stm32::peripherals::TIM1> {
    let pwm = SimplePwm::new(
        tim,
        Some(PwmPin::new(ch1, OutputType::PushPull)),
        Some(PwmPin::new(ch2, OutputType::PushPull)),
        Some(PwmPin::new(ch3, OutputType::PushPull)),
        None,
        Hertz(config::PWM_FREQ_HZ),
        CountingMode::EdgeAlignedUp,
    );
    let t = pac::TIM1;
    // All in one write: BDTR's break fields can be locked, and LOCK itself is write-once. MOE = 0;
    // outputs forced to their idle level (low, CR2.OISx = 0) while MOE = 0; break on BKIN active
    // low, filtered; AOE = 0 so only software re-enables after a break; lock level 2 freezes the
    // break and idle-state configuration (and the output polarities) until reset.
    t.bdtr().write(|w| {
        w.set_moe(false);
        w.set_aoe(false);
        w.set_ossi(Ossi::IDLE_LEVEL);
        w.set_ossr(Ossr::IDLE_LEVEL);
        w.set_bke(0, true);
        w.set_bkp(0, Bkp::ACTIVE_LOW);
        w.set_bkf(0, INPUT_FILTER);
        w.set_lock(Lock::LEVEL2);
    });
    t.af1().modify(|w| {
        w.set_bkine(true);
        w.set_bkinp(Bkinp::NOT_INVERTED);
    });
    for ch in 0..3 {
        t.ccr(ch).write(|w| w.set_ccr(0));
        t.ccer().modify(|w| w.set_cce(ch, true));
    }
    // Exact period from the shared board timing: prescaler 1, ARR = full scale - 1.
    t.psc().write_value(0);
    t.arr().write(|w| w.set_arr(config::PWM_FULL_SCALE - 1));
    t.egr().write(|w| w.set_ug(true));
    t.sr().write(|w| w.0 = 0);
    pwm
}

fn qei_config() -> qei::Config {
    qei::Config {
        // Pull-ups suit open-collector encoders and are harmless on push-pull ones.
        ch1_pull: Pull::Up,
        ch2_pull: Pull::Up,
        // Count on both edges of both channels: x4 decoding.
        mode: QeiMode::Mode3,
        auto_reload: u16::MAX,
    }
}

/// Digital input filters on both channels of every decoder (CCMR1 IC1F/IC2F).
fn encoder_filters() {
    macro_rules! filter {
        ($($tim:expr),*) => {$(
            $tim.ccmr_input(0).modify(|w| {
                w.set_icf(0, INPUT_FILTER);
                w.set_icf(1, INPUT_FILTER);
            });
        )*};
    }
    filter!(
        pac::TIM2,
        pac::TIM3,
        pac::TIM4,
        pac::TIM5,
        pac::TIM8,
        pac::TIM20
    );
}

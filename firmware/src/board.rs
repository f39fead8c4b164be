//! NUCLEO-G474RE wiring: clocks, the six quadrature decoders, the three phase/enable bridges, the
//! control-tick timer, the watchdog and the user button. The pin map is documented in README.md;
//! embassy-stm32's traits reject at compile time any pin that cannot serve the timer channel it is
//! given.

use embassy_stm32::exti::{self, ExtiInput};
use embassy_stm32::gpio::{Input, Level, Output, OutputType, Pull, Speed};
use embassy_stm32::interrupt::Priority;
use embassy_stm32::mode::Async;
use embassy_stm32::peripherals::{IWDG, TIM1, TIM2, TIM20, TIM3, TIM4, TIM5, TIM6, TIM8};
use embassy_stm32::time::Hertz;
use embassy_stm32::timer::low_level::{CountingMode, RoundTo, Timer};
use embassy_stm32::timer::qei::{self, Qei, QeiMode};
use embassy_stm32::timer::simple_pwm::{PwmPin, SimplePwm, SimplePwmChannel, SimplePwmChannels};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, interrupt, rcc, Config, Peripherals};
use softfinger_core::output_guard::{phase_enable, Guarded};

use crate::config;

bind_interrupts!(struct Irqs {
    EXTI15_10 => exti::InterruptHandler<interrupt::typelevel::EXTI15_10>;
});

/// HAL configuration: 170 MHz from the internal 16 MHz oscillator (no dependence on the board's
/// crystal) with range-1 boost mode as required above 150 MHz, and the DMA interrupts (unused)
/// below the control tick's priority.
pub fn hal_config() -> Config {
    let mut c = Config::default();
    c.rcc.pll = Some(rcc::Pll {
        source: rcc::PllSource::HSI,
        prediv: rcc::PllPreDiv::DIV4,
        mul: rcc::PllMul::MUL85,
        divp: None,
        divq: None,
        divr: Some(rcc::PllRDiv::DIV2),
    });
    c.rcc.sys = rcc::Sysclk::PLL1_R;
    c.rcc.boost = true;
    c.bdma_interrupt_priority = Priority::P4;
    c
}

/// The six quadrature decoders (×4 decoding, 16-bit counters).
pub struct Encoders {
    m0: Qei<'static, TIM2>,
    m1: Qei<'static, TIM3>,
    m2: Qei<'static, TIM4>,
    w0: Qei<'static, TIM5>,
    w1: Qei<'static, TIM8>,
    w2: Qei<'static, TIM20>,
}

impl Encoders {
    /// Raw counter values `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`.
    ///
    /// TIM2 and TIM5 are 32-bit timers; reading their low 16 bits gives the same modulo-2¹⁶
    /// sequence as the 16-bit timers, which is all the count extender needs.
    #[inline]
    pub fn read(&self) -> [u16; 6] {
        [
            self.m0.count(),
            self.m1.count(),
            self.m2.count(),
            self.w0.count(),
            self.w1.count(),
            self.w2.count(),
        ]
    }
}

/// The three phase/enable bridges: one PWM channel (TIM1 CH1..CH3) and one phase pin per motor,
/// a shared enable (nSLEEP) and the drivers' wired-OR nFAULT input (active low).
pub struct Motors {
    pwm: [SimplePwmChannel<'static, TIM1>; 3],
    phase: [Output<'static>; 3],
    enable: Output<'static>,
    n_fault: Input<'static>,
    /// Compare value for 100 % duty.
    full_scale: u32,
}

impl Motors {
    /// The drivers report a fault (nFAULT low).
    #[inline]
    pub fn fault(&self) -> bool {
        self.n_fault.is_low()
    }

    /// Write one guarded output. When disabling, the enable pin drops before the duties change;
    /// when enabling, the duties are in place before the enable pin rises.
    #[inline]
    pub fn write(&mut self, out: &Guarded) {
        if !out.enable {
            self.enable.set_low();
        }
        for ((pwm, phase), duty) in self
            .pwm
            .iter_mut()
            .zip(self.phase.iter_mut())
            .zip(out.duties)
        {
            let cmd = if out.enable {
                phase_enable(duty, self.full_scale)
            } else {
                phase_enable(0.0, self.full_scale)
            };
            phase.set_level(Level::from(cmd.forward));
            // `cmd.compare <= full_scale == max_duty_cycle()`, so the driver's bound check holds.
            pwm.set_duty_cycle(cmd.compare);
        }
        if out.enable {
            self.enable.set_high();
        }
    }

    /// Compare value for 100 % duty.
    pub fn full_scale(&self) -> u32 {
        self.full_scale
    }
}

/// Everything the firmware uses, configured and in a safe state (drivers disabled, duties 0).
pub struct Board {
    pub encoders: Encoders,
    pub motors: Motors,
    /// TIM6: its update interrupt is the control tick. Configured, not yet started.
    pub tick_timer: Timer<'static, TIM6>,
    /// Configured, not yet started.
    pub watchdog: IndependentWatchdog<'static, IWDG>,
    /// B1 (blue) user button, active high.
    pub button: ExtiInput<'static, Async>,
    /// LD2 (green) user LED.
    pub led: Output<'static>,
}

fn qei_config() -> qei::Config {
    qei::Config {
        // Pull-ups suit open-collector encoders and are harmless on push-pull ones.
        ch1_pull: Pull::Up,
        ch2_pull: Pull::Up,
        // Count on both edges of both channels: ×4 decoding.
        mode: QeiMode::Mode3,
        auto_reload: u16::MAX,
    }
}

impl Board {
    /// Configure every peripheral; outputs start disabled.
    pub fn new(p: Peripherals) -> Self {
        // Outputs first, in their safe state, so the bridges never see a floating enable.
        let enable = Output::new(p.PB0, Level::Low, Speed::Low);
        let phase = [
            Output::new(p.PB10, Level::Low, Speed::Low),
            Output::new(p.PB4, Level::Low, Speed::Low),
            Output::new(p.PB5, Level::Low, Speed::Low),
        ];
        // nFAULT is open drain on DRV887x parts: pull it up.
        let n_fault = Input::new(p.PC1, Pull::Up);

        let pwm = SimplePwm::new(
            p.TIM1,
            Some(PwmPin::new(p.PA8, OutputType::PushPull)),
            Some(PwmPin::new(p.PA9, OutputType::PushPull)),
            Some(PwmPin::new(p.PA10, OutputType::PushPull)),
            None,
            Hertz(config::PWM_FREQ_HZ),
            CountingMode::EdgeAlignedUp,
        );
        let SimplePwmChannels {
            mut ch1,
            mut ch2,
            mut ch3,
            ..
        } = pwm.split();
        let full_scale = ch1.max_duty_cycle();
        for ch in [&mut ch1, &mut ch2, &mut ch3] {
            ch.set_duty_cycle(0);
            ch.enable();
        }

        let encoders = Encoders {
            m0: Qei::new(p.TIM2, p.PA15, p.PB3, qei_config()),
            m1: Qei::new(p.TIM3, p.PA6, p.PA7, qei_config()),
            m2: Qei::new(p.TIM4, p.PB6, p.PB7, qei_config()),
            w0: Qei::new(p.TIM5, p.PA0, p.PA1, qei_config()),
            w1: Qei::new(p.TIM8, p.PC6, p.PC7, qei_config()),
            w2: Qei::new(p.TIM20, p.PB2, p.PC2, qei_config()),
        };

        let tick_timer = Timer::new(p.TIM6);
        tick_timer.set_frequency(Hertz(config::CONTROL_RATE_HZ), RoundTo::Slower);
        tick_timer.enable_update_interrupt(true);

        Board {
            encoders,
            motors: Motors {
                pwm: [ch1, ch2, ch3],
                phase,
                enable,
                n_fault,
                full_scale,
            },
            tick_timer,
            watchdog: IndependentWatchdog::new(p.IWDG, config::WATCHDOG_TIMEOUT_US),
            button: ExtiInput::new(p.PC13, p.EXTI13, Pull::Down, Irqs),
            led: Output::new(p.PA5, Level::Low, Speed::Low),
        }
    }
}

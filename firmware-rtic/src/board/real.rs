//! The e-puck2 board (pins per docs/epuck2-hardware.md).

use super::Board;
use crate::drivers::{
    config::ConfigStore,
    ground::Ground as GroundDriver,
    leds::Leds,
    motors::{Motors as MotorDriver, Wheel},
    proximity::{ProxPins, Proximity as ProxDriver},
    selector::Selector,
};
use drivers_logic::stepper::{Side, TIMER_HZ};
use stm32f4xx_hal::{
    adc::{
        Adc,
        config::{AdcConfig, Clock, Resolution},
    },
    gpio::PinState,
    i2c::{DutyCycle, I2c, Mode},
    pac,
    prelude::*,
    rcc::Config,
    rng::RngExt,
    serial::{Serial, config::Config as SerialConfig},
};

/// The steppers.
pub type Motors = MotorDriver;
/// The IR ring.
pub type Proximity = ProxDriver;
/// The floor sensors.
pub type Ground = GroundDriver;

/// Core clock, for the SysTick monotonic.
pub const SYSCLK_HZ: u32 = 168_000_000;
/// This is the real robot.
pub const EMULATED: bool = false;

/// Clocks as the C firmware (HSE 24 MHz bypass, PLL to 168 MHz, APB1 42 MHz,
/// APB2 84 MHz, 48 MHz for USB), then every driver.
pub fn init(dp: pac::Peripherals) -> Board {
    let mut rcc = dp.RCC.freeze(
        Config::hse(24.MHz())
            .bypass_hse_oscillator()
            .sysclk(168.MHz())
            .pclk1(42.MHz())
            .pclk2(84.MHz())
            .require_pll48clk(),
    );
    let gpiob = dp.GPIOB.split(&mut rcc);
    let gpioc = dp.GPIOC.split(&mut rcc);
    let gpiod = dp.GPIOD.split(&mut rcc);
    let gpioe = dp.GPIOE.split(&mut rcc);

    // Steppers: left IN1..IN4 = PE9, PE8, PE11, PE10 on TIM4; right = PE13,
    // PE12, PE14, PE15 on TIM3.
    let left = Wheel::new(
        Side::Left,
        dp.TIM4.counter::<TIMER_HZ>(&mut rcc),
        [
            gpioe.pe9.into_push_pull_output().erase(),
            gpioe.pe8.into_push_pull_output().erase(),
            gpioe.pe11.into_push_pull_output().erase(),
            gpioe.pe10.into_push_pull_output().erase(),
        ],
    );
    let right = Wheel::new(
        Side::Right,
        dp.TIM3.counter::<TIMER_HZ>(&mut rcc),
        [
            gpioe.pe13.into_push_pull_output().erase(),
            gpioe.pe12.into_push_pull_output().erase(),
            gpioe.pe14.into_push_pull_output().erase(),
            gpioe.pe15.into_push_pull_output().erase(),
        ],
    );

    // Proximity: ADC1 at PCLK2/8 = 10.5 MHz (the ADC's limit is 36 MHz).
    let adc = Adc::new(
        dp.ADC1,
        true,
        AdcConfig::default()
            .clock(Clock::Pclk2_div_8)
            .resolution(Resolution::Twelve),
        &mut rcc,
    );
    let pins = ProxPins {
        ir0: gpioc.pc2.into_analog(),
        ir1: gpioc.pc3.into_analog(),
        ir2: gpioc.pc4.into_analog(),
        ir3: gpioc.pc5.into_analog(),
        ir4: gpiob.pb1.into_analog(),
        ir5: gpiob.pb0.into_analog(),
        ir6: gpioc.pc0.into_analog(),
        ir7: gpioc.pc1.into_analog(),
    };
    let pulse = [
        gpiob.pb12.into_push_pull_output().erase(),
        gpiob.pb14.into_push_pull_output().erase(),
        gpioe.pe2.into_push_pull_output().erase(),
        gpioe.pe3.into_push_pull_output().erase(),
    ];
    let prox = ProxDriver::new(adc, pins, pulse);

    // Ground module: I2C1 on PB8/PB9 at 200 kHz. First clock SCL 16 times
    // (as the C firmware does) so that a slave left mid-transfer by a reset
    // releases SDA.
    let mut scl = gpiob.pb8.into_open_drain_output_in_state(PinState::High);
    for _ in 0..16 {
        scl.set_low();
        cortex_m::asm::delay(SYSCLK_HZ / 200_000); // 5 µs
        scl.set_high();
        cortex_m::asm::delay(SYSCLK_HZ / 200_000);
    }
    let i2c = I2c::new(
        dp.I2C1,
        (scl, gpiob.pb9),
        Mode::fast(200.kHz(), DutyCycle::Ratio2to1),
        &mut rcc,
    );
    let ground = GroundDriver::new(i2c);

    let leds = Leds {
        ring: [
            gpiod
                .pd5
                .into_push_pull_output_in_state(PinState::High)
                .erase(),
            gpiod
                .pd6
                .into_push_pull_output_in_state(PinState::High)
                .erase(),
            gpiod
                .pd10
                .into_push_pull_output_in_state(PinState::High)
                .erase(),
            gpiod
                .pd11
                .into_push_pull_output_in_state(PinState::High)
                .erase(),
        ],
        body: gpiob.pb2.into_push_pull_output().erase(),
        front: gpiod.pd14.into_push_pull_output().erase(),
    };

    let selector = Selector {
        pins: (
            gpioc.pc13.into_pull_down_input(),
            gpioc.pc14.into_pull_down_input(),
            gpioc.pc15.into_pull_down_input(),
            gpiod.pd4.into_pull_down_input(),
        ),
    }
    .read();

    // The link's session nonce from the hardware RNG (PLL48 runs), so that
    // a rebooted robot starts a new session.
    let nonce = random_word(dp.RNG.constrain(&mut rcc).release());

    let serial = Serial::new(
        dp.USART3,
        (gpiod.pd8, gpiod.pd9),
        SerialConfig::default().baudrate(115_200.bps()),
        &mut rcc,
    )
    .unwrap_or_else(|_| defmt::panic!("USART3 config"));

    Board {
        motors: MotorDriver { left, right },
        prox,
        ground,
        leds,
        selector,
        nonce,
        serial,
        config: ConfigStore::new(dp.FLASH),
    }
}

/// One word from the RNG, or 1 if it reports a clock or seed error (or
/// never becomes ready) — a fixed session still works, it only makes a
/// reboot look like a reconnect to the phone.
fn random_word(rng: pac::RNG) -> u32 {
    for _ in 0..10_000 {
        let sr = rng.sr().read();
        if sr.cecs().bit() || sr.secs().bit() {
            break;
        }
        if sr.drdy().bit() {
            return rng.dr().read().rndata().bits();
        }
    }
    1
}

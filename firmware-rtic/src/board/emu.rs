//! The virtual board for QEMU's `netduinoplus2` (STM32F405).
//!
//! QEMU runs the core and SysTick at 168 MHz whatever RCC says, and models
//! the USARTs; it has no RCC (the HSE/PLL start-up would wait forever), GPIO,
//! I2C or flash controller. So: internal 16 MHz clock configuration, real
//! USART3 (QEMU's third `-serial`) for the link, USART2 (the second
//! `-serial`) for the body channel to the simulated body the host attaches
//! (`core_algo::agent::body::BodyMsg`), virtual motors integrating their
//! speed over SysTick time, and fixed virtual sensor readings (robot on a
//! line, nothing in the way) for the control task.

use super::Board;
use crate::drivers::{config::ConfigStore, leds::Leds};
use drivers_logic::ground::GroundReading;
use drivers_logic::proximity::{ProxScan, SENSORS};
use drivers_logic::selector::{cmdline_value, from_cmdline};
use drivers_logic::stepper::{Side, VirtualWheel};
use rtic_monotonics::systick::prelude::*;
use stm32f4xx_hal::{
    gpio::PinState,
    pac,
    prelude::*,
    rcc::Config,
    serial::{Serial, config::Config as SerialConfig},
};

/// SysTick runs at 168 MHz in QEMU's model regardless of RCC.
pub const SYSCLK_HZ: u32 = 168_000_000;
/// This is the emulator.
pub const EMULATED: bool = true;
/// Selector position the virtual board reports unless the QEMU command line
/// says `-append selector=N`: "run" as robot 1.
pub const SELECTOR: u8 = 1;

/// QEMU's `-append` text, read through the semihosting `SYS_GET_CMDLINE`
/// call, into `text`; returns its length (0 without one).
fn cmdline(text: &mut [u8; 256]) -> usize {
    // Parameter block: buffer address and size in; length written back.
    let mut block = [text.as_mut_ptr() as usize, text.len()];
    // SAFETY: QEMU is started with semihosting enabled (documented, and the
    // exit path needs it too); the host writes at most `text.len()` bytes
    // into `text` and one word into `block`, both live locals.
    #[allow(unsafe_code)]
    let rc = unsafe {
        cortex_m_semihosting::syscall1(
            cortex_m_semihosting::nr::GET_CMDLINE,
            block.as_mut_ptr() as usize,
        )
    };
    if rc != 0 {
        return 0;
    }
    block[1].min(text.len())
}

/// The host's wall clock in seconds (semihosting `SYS_TIME`), for a nonce
/// when the command line gives none.
fn host_time() -> u32 {
    // SAFETY: semihosting is enabled (see `cmdline`); SYS_TIME takes no
    // parameter block.
    #[allow(unsafe_code)]
    let t = unsafe { cortex_m_semihosting::syscall1(cortex_m_semihosting::nr::TIME, 0) };
    t as u32
}

/// `bench=N` on the command line: time N behaviour steps and exit (see
/// [`crate::robot::bench`]).
pub fn bench_steps() -> Option<u32> {
    let mut text = [0u8; 256];
    let len = cmdline(&mut text);
    cmdline_value(text.get(..len).unwrap_or(&[]), b"bench")
}

/// Steppers without timers: the same `Stepper` logic, advanced by elapsed
/// milliseconds of the monotonic clock whenever the motors are touched.
pub struct Motors {
    wheels: [VirtualWheel; 2],
    last_ms: u32,
}

impl Motors {
    fn new() -> Self {
        Motors {
            wheels: [
                VirtualWheel::new(Side::Left),
                VirtualWheel::new(Side::Right),
            ],
            last_ms: 0,
        }
    }

    fn sync(&mut self) {
        let now = crate::Mono::now().duration_since_epoch().as_millis();
        let elapsed = now.wrapping_sub(self.last_ms).min(1000);
        self.last_ms = now;
        for w in &mut self.wheels {
            w.advance(elapsed);
        }
    }

    /// No stepper timers in the emulator.
    pub fn on_left_timer(&mut self) {}

    /// No stepper timers in the emulator.
    pub fn on_right_timer(&mut self) {}

    /// Sets both speeds (full steps per second, clamped to ±1000).
    pub fn set_speeds(&mut self, left: i16, right: i16) -> (i16, i16) {
        self.sync();
        (
            self.wheels[0].stepper().set_speed(left),
            self.wheels[1].stepper().set_speed(right),
        )
    }

    /// Step counters (left, right), forward positive.
    pub fn steps(&mut self) -> (i32, i32) {
        self.sync();
        (
            self.wheels[0].stepper().steps(),
            self.wheels[1].stepper().steps(),
        )
    }

    /// Whether both wheels are commanded to stand still.
    pub fn is_stopped(&mut self) -> bool {
        self.wheels.iter_mut().all(|w| w.stepper().speed() == 0)
    }
}

/// The IR ring with constant virtual light: nothing in range.
pub struct Proximity {
    scan: ProxScan,
}

impl Proximity {
    /// One 1 ms tick of the real schedule over virtual readings.
    pub fn tick(&mut self) {
        self.scan.tick(|_| 3000);
    }

    /// Proximity values of the last complete scan.
    pub fn values(&self) -> [u16; SENSORS] {
        self.scan.values()
    }
}

/// Virtual floor: the robot sits on a black line on white ground.
pub struct Ground;

impl Ground {
    /// Left and right white, centre black.
    pub fn read(&mut self) -> Option<GroundReading> {
        Some(GroundReading {
            delta: [768, 256, 768],
            ambient: [1000; 3],
            revision: 0,
        })
    }
}

/// Internal clock, then the drivers QEMU can run and the virtual rest.
pub fn init(dp: pac::Peripherals) -> Board {
    let mut rcc = dp.RCC.freeze(Config::hsi());
    let gpiob = dp.GPIOB.split(&mut rcc);
    let gpiod = dp.GPIOD.split(&mut rcc);
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
    let serial = Serial::new(
        dp.USART3,
        (gpiod.pd8, gpiod.pd9),
        SerialConfig::default().baudrate(115_200.bps()),
        &mut rcc,
    )
    .unwrap_or_else(|_| defmt::panic!("USART3 config"));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let body_serial = Serial::new(
        dp.USART2,
        (gpioa.pa2, gpioa.pa3),
        SerialConfig::default().baudrate(115_200.bps()),
        &mut rcc,
    )
    .unwrap_or_else(|_| defmt::panic!("USART2 config"));
    let mut text = [0u8; 256];
    let len = cmdline(&mut text);
    let text = text.get(..len).unwrap_or(&[]);
    let selector = from_cmdline(text).unwrap_or(SELECTOR);
    // `nonce=N` from the host, else the host clock: a fresh link session
    // at every boot.
    let nonce = cmdline_value(text, b"nonce")
        .unwrap_or_else(|| host_time().rotate_left(8) ^ u32::from(selector));
    Board {
        motors: Motors::new(),
        prox: Proximity {
            scan: ProxScan::new(),
        },
        ground: Ground,
        leds,
        selector,
        nonce,
        serial,
        body_serial,
        config: ConfigStore::new(dp.FLASH),
    }
}

/// Ends the emulation through semihosting with QEMU's exit status 0 or 1.
pub fn exit(success: bool) -> ! {
    use cortex_m_semihosting::debug;
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

/// A panic must end QEMU with a failure, not spin until the timeout.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit(false)
}

/// So must a HardFault.
#[cortex_m_rt::exception]
#[allow(unsafe_code)]
unsafe fn HardFault(_frame: &cortex_m_rt::ExceptionFrame) -> ! {
    exit(false)
}

//! The 8 IR proximity sensors: ADC1 on PC2, PC3, PC4, PC5, PB1, PB0, PC0,
//! PC1 (IR0..IR7) and the four emitter pulse lines PB12, PB14, PE2, PE3.
//!
//! Driven by the 1 kHz sampling task: each tick converts the sensors the
//! schedule in `drivers_logic::proximity` asks for, then sets the emitters for
//! the next tick. Single software-started conversions (~12 µs each at 112
//! cycles) keep this simple; the C firmware's TIM2-triggered ADC + DMA scan
//! would free the CPU and is the obvious next step.

use drivers_logic::proximity::{Emitters, ProxScan, SENSORS};
use stm32f4xx_hal::{
    adc::{Adc, config::SampleTime},
    gpio::{Analog, AnyPin, Output, PB0, PB1, PC0, PC1, PC2, PC3, PC4, PC5, PushPull},
    pac::ADC1,
};

/// The analog inputs, IR0..IR7.
pub struct ProxPins {
    /// IR0, front right.
    pub ir0: PC2<Analog>,
    /// IR1, front right 45°.
    pub ir1: PC3<Analog>,
    /// IR2, right.
    pub ir2: PC4<Analog>,
    /// IR3, back right.
    pub ir3: PC5<Analog>,
    /// IR4, back left.
    pub ir4: PB1<Analog>,
    /// IR5, left.
    pub ir5: PB0<Analog>,
    /// IR6, front left 45°.
    pub ir6: PC0<Analog>,
    /// IR7, front left.
    pub ir7: PC1<Analog>,
}

/// The sensor ring.
pub struct Proximity {
    adc: Adc<ADC1>,
    pins: ProxPins,
    pulse: [AnyPin<Output<PushPull>>; 4],
    scan: ProxScan,
}

impl Proximity {
    /// Takes the configured ADC, the analog pins and the pulse lines
    /// (PULSE_0..PULSE_3, all low).
    pub fn new(adc: Adc<ADC1>, pins: ProxPins, pulse: [AnyPin<Output<PushPull>>; 4]) -> Self {
        Proximity {
            adc,
            pins,
            pulse,
            scan: ProxScan::new(),
        }
    }

    /// One 1 ms tick of the schedule.
    pub fn tick(&mut self) {
        let Proximity {
            adc,
            pins,
            pulse,
            scan,
        } = self;
        let st = SampleTime::Cycles_112;
        let emit = scan.tick(|i| match i {
            0 => adc.convert(&pins.ir0, st),
            1 => adc.convert(&pins.ir1, st),
            2 => adc.convert(&pins.ir2, st),
            3 => adc.convert(&pins.ir3, st),
            4 => adc.convert(&pins.ir4, st),
            5 => adc.convert(&pins.ir5, st),
            6 => adc.convert(&pins.ir6, st),
            _ => adc.convert(&pins.ir7, st),
        });
        for (k, p) in pulse.iter_mut().enumerate() {
            p.set_state((emit == Emitters::Pair(k as u8)).into());
        }
    }

    /// Proximity values of the last complete scan (0 = nothing).
    pub fn values(&self) -> [u16; SENSORS] {
        self.scan.values()
    }
}

//! The two stepper motors: right on TIM3, left on TIM4, each timer ticking at
//! 100 kHz with one half-step per update interrupt (as the C firmware).
//!
//! Speed changes take effect at the next update interrupt, which restarts its
//! timer with the new period; so a step is never cut short or doubled.

use drivers_logic::stepper::{Side, Stepper, TIMER_HZ};
use stm32f4xx_hal::{
    gpio::{AnyPin, Output, PushPull},
    pac::{TIM3, TIM4},
    timer::Counter,
};

type Coil = AnyPin<Output<PushPull>>;
type Timer<T> = Counter<T, TIMER_HZ>;

/// One wheel: its stepper state, timer and four coil pins (IN1..IN4).
pub struct Wheel<T> {
    stepper: Stepper,
    timer: Timer<T>,
    coils: [Coil; 4],
    loaded_period: u16,
}

impl<T: stm32f4xx_hal::timer::Instance> Wheel<T> {
    /// Takes a timer already running as a 100 kHz counter and the coil pins.
    pub fn new(side: Side, mut timer: Timer<T>, coils: [Coil; 4]) -> Self {
        use stm32f4xx_hal::Listen;
        let stepper = Stepper::new(side);
        let period = stepper.period();
        timer
            .start(fugit::TimerDurationU32::from_ticks(period as u32))
            .ok();
        timer.listen(stm32f4xx_hal::timer::Event::Update);
        Wheel {
            stepper,
            timer,
            coils,
            loaded_period: period,
        }
    }

    /// Update interrupt: clear it, output the next half-step, reload the
    /// period if the speed changed.
    pub fn on_update(&mut self) {
        self.timer.wait().ok();
        let levels = self.stepper.on_tick();
        for (pin, on) in self.coils.iter_mut().zip(levels) {
            pin.set_state(on.into());
        }
        let period = self.stepper.period();
        if period != self.loaded_period {
            self.loaded_period = period;
            self.timer
                .start(fugit::TimerDurationU32::from_ticks(period as u32))
                .ok();
        }
    }
}

/// Both wheels, shared between the two stepper interrupts (same priority, so
/// they never contend) and the control task.
pub struct Motors {
    /// Left wheel (TIM4).
    pub left: Wheel<TIM4>,
    /// Right wheel (TIM3).
    pub right: Wheel<TIM3>,
}

impl Motors {
    /// TIM4 update interrupt.
    pub fn on_left_timer(&mut self) {
        self.left.on_update();
    }

    /// TIM3 update interrupt.
    pub fn on_right_timer(&mut self) {
        self.right.on_update();
    }

    /// Sets both speeds (full steps per second, clamped to ±1000).
    pub fn set_speeds(&mut self, left: i16, right: i16) -> (i16, i16) {
        (
            self.left.stepper.set_speed(left),
            self.right.stepper.set_speed(right),
        )
    }

    /// Step counters (left, right), forward positive.
    pub fn steps(&mut self) -> (i32, i32) {
        (self.left.stepper.steps(), self.right.stepper.steps())
    }

    /// Whether both wheels are commanded to stand still.
    pub fn is_stopped(&mut self) -> bool {
        self.left.stepper.speed() == 0 && self.right.stepper.speed() == 0
    }
}

//! Stepper motor sequencing: the half-step table, direction per wheel, step
//! counting and the timer period for a speed.
//!
//! Mirrors the e-puck2 C firmware (`motors.c`): 8 half-step states per
//! electrical cycle, one half-step per timer update interrupt, a 100 kHz
//! timer tick, the period being the half-step interval in 10 µs ticks. The
//! wheels are mounted mirrored, so "forward" walks the table upwards on the
//! left wheel and downwards on the right one.

/// Timer tick rate the periods are expressed in (Hz).
pub const TIMER_HZ: u32 = 100_000;

/// Largest speed accepted, in full steps per second. The seed's interface
/// (and core-algo's controllers) use ±1000; the C firmware allows 1100.
pub const MAX_SPEED: i16 = 1000;

/// Period used while halted: the timer keeps ticking at 100 Hz so that a new
/// speed takes effect within 10 ms, but no coil is energised.
pub const HALT_PERIOD: u16 = 1000;

/// Full steps for one wheel revolution (20-step motor, 50:1 gearbox).
pub const STEPS_PER_REV: u32 = 1000;

/// Coil levels (IN1, IN2, IN3, IN4) for half-step index 0..7.
pub const HALF_STEP: [[bool; 4]; 8] = [
    [true, false, true, false],
    [false, false, true, false],
    [false, true, true, false],
    [false, true, false, false],
    [false, true, false, true],
    [false, false, false, true],
    [true, false, false, true],
    [true, false, false, false],
];

/// All coils off.
pub const COILS_OFF: [bool; 4] = [false; 4];

/// Which wheel a stepper drives; decides the direction of the table walk.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Side {
    /// Left wheel: forward = index + 1.
    Left,
    /// Right wheel: forward = index − 1.
    Right,
}

/// One stepper's state, advanced by its timer interrupt.
#[derive(Clone, Debug)]
pub struct Stepper {
    side: Side,
    index: u8,
    /// Half-steps, + on forward for both wheels.
    half_steps: i32,
    speed: i16,
}

impl Stepper {
    /// A halted stepper at table index 0 with a zero step count.
    pub const fn new(side: Side) -> Self {
        Stepper {
            side,
            index: 0,
            half_steps: 0,
            speed: 0,
        }
    }

    /// Sets the speed in full steps per second, clamped to ±[`MAX_SPEED`];
    /// returns the value applied.
    pub fn set_speed(&mut self, speed: i16) -> i16 {
        self.speed = speed.clamp(-MAX_SPEED, MAX_SPEED);
        self.speed
    }

    /// The speed applied, in full steps per second.
    pub const fn speed(&self) -> i16 {
        self.speed
    }

    /// Full steps driven since start (or the last reset), forward positive.
    pub const fn steps(&self) -> i32 {
        self.half_steps / 2
    }

    /// Resets the step counter (the coil state is kept so the rotor does not jump).
    pub fn reset_steps(&mut self) {
        self.half_steps = 0;
    }

    /// Timer period for the current speed, in ticks of [`TIMER_HZ`].
    pub fn period(&self) -> u16 {
        period_for(self.speed)
    }

    /// One timer update: moves one half-step in the commanded direction and
    /// returns the coil levels to output (all off when halted).
    pub fn on_tick(&mut self) -> [bool; 4] {
        if self.speed == 0 {
            return COILS_OFF;
        }
        let forward = self.speed > 0;
        let up = forward == (self.side == Side::Left);
        self.index = if up {
            (self.index + 1) % 8
        } else {
            (self.index + 7) % 8
        };
        self.half_steps += if forward { 1 } else { -1 };
        HALF_STEP[self.index as usize]
    }
}

/// Half-step interval for `speed` full steps per second, in 10 µs ticks
/// (`100000 / (2·|speed|)`), or [`HALT_PERIOD`] at speed 0.
pub fn period_for(speed: i16) -> u16 {
    let s = speed.unsigned_abs().min(MAX_SPEED as u16) as u32;
    if s == 0 {
        HALT_PERIOD
    } else {
        (TIMER_HZ / (2 * s)) as u16
    }
}

/// A stepper without a timer: the same [`Stepper`] advanced by elapsed
/// milliseconds, for the emulator's virtual board (and host simulations).
/// Half-steps owed are kept in thousandths so no time is lost between calls.
#[derive(Clone, Debug)]
pub struct VirtualWheel {
    stepper: Stepper,
    owed: u32,
}

impl VirtualWheel {
    /// A halted wheel.
    pub const fn new(side: Side) -> Self {
        VirtualWheel {
            stepper: Stepper::new(side),
            owed: 0,
        }
    }

    /// Runs `ms` milliseconds at the current speed.
    pub fn advance(&mut self, ms: u32) {
        self.owed += ms * 2 * self.stepper.speed().unsigned_abs() as u32;
        while self.owed >= 1000 {
            self.stepper.on_tick();
            self.owed -= 1000;
        }
    }

    /// The stepper (speed, step counter).
    pub fn stepper(&mut self) -> &mut Stepper {
        &mut self.stepper
    }
}

/// Differential drive: wheel speeds for a linear speed `v` and an angular term
/// `w` (right = v − w, left = v + w, as in the seed's `setSpeed`), each
/// clamped to ±[`MAX_SPEED`].
pub fn wheel_speeds(v: i16, w: i16) -> (i16, i16) {
    let l = (v as i32 + w as i32).clamp(-(MAX_SPEED as i32), MAX_SPEED as i32) as i16;
    let r = (v as i32 - w as i32).clamp(-(MAX_SPEED as i32), MAX_SPEED as i32) as i16;
    (l, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_a_gray_sequence() {
        // Consecutive half-steps differ in exactly one coil, including the wrap.
        for i in 0..8 {
            let a = HALF_STEP[i];
            let b = HALF_STEP[(i + 1) % 8];
            let diff = a.iter().zip(b.iter()).filter(|(x, y)| x != y).count();
            assert_eq!(diff, 1, "between {i} and {}", (i + 1) % 8);
        }
    }

    #[test]
    fn left_forward_walks_up_right_forward_walks_down() {
        let mut l = Stepper::new(Side::Left);
        let mut r = Stepper::new(Side::Right);
        l.set_speed(500);
        r.set_speed(500);
        assert_eq!(l.on_tick(), HALF_STEP[1]);
        assert_eq!(r.on_tick(), HALF_STEP[7]);
        assert_eq!(r.on_tick(), HALF_STEP[6]);
        r.set_speed(-500);
        assert_eq!(r.on_tick(), HALF_STEP[7]);
    }

    #[test]
    fn counts_full_steps_forward_positive_on_both_wheels() {
        for side in [Side::Left, Side::Right] {
            let mut s = Stepper::new(side);
            s.set_speed(300);
            for _ in 0..20 {
                s.on_tick();
            }
            assert_eq!(s.steps(), 10);
            s.set_speed(-300);
            for _ in 0..40 {
                s.on_tick();
            }
            assert_eq!(s.steps(), -10);
        }
    }

    #[test]
    fn halted_outputs_nothing_and_keeps_count() {
        let mut s = Stepper::new(Side::Left);
        assert_eq!(s.on_tick(), COILS_OFF);
        assert_eq!(s.steps(), 0);
        assert_eq!(s.period(), HALT_PERIOD);
    }

    #[test]
    fn periods() {
        assert_eq!(period_for(1000), 50); // 2000 half-steps/s = 500 µs
        assert_eq!(period_for(-1000), 50);
        assert_eq!(period_for(600), 83);
        assert_eq!(period_for(1), 50_000);
        assert_eq!(period_for(5000), 50); // clamped
        let mut s = Stepper::new(Side::Right);
        assert_eq!(s.set_speed(-3000), -MAX_SPEED);
    }

    #[test]
    fn virtual_wheel_keeps_the_rate_across_uneven_calls() {
        let mut w = VirtualWheel::new(Side::Right);
        w.stepper().set_speed(600);
        for ms in [1, 3, 7, 10, 979] {
            w.advance(ms); // 1000 ms in all
        }
        assert_eq!(w.stepper().steps(), 600);
        w.stepper().set_speed(-333);
        for _ in 0..3000 {
            w.advance(1);
        }
        assert_eq!(w.stepper().steps(), 600 - 999);
    }

    #[test]
    fn differential_drive_clamps() {
        assert_eq!(wheel_speeds(600, 100), (700, 500));
        assert_eq!(wheel_speeds(900, 300), (1000, 600));
        assert_eq!(wheel_speeds(0, -200), (-200, 200));
    }
}

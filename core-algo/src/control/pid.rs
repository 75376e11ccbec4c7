//! The seed's positional PID controller, Ziegler–Nichols tuning and a relay
//! experiment that finds the critical gain and period on the robot itself.
//!
//! The seed's law (§2.4) is
//!
//! ```text
//! u_n = K_r · [ x_n + (T/T_N) · Σ_{i=1}^{n-1} x_i + (T_V/T) · (x_n − x_{n-1}) ]
//! ```
//!
//! with control error x, interval T, reset time T_N and derivative time T_V.
//! [`Gains`] holds it multiplied out as `kp = K_r`, `ki = K_r·T/T_N`,
//! `kd = K_r·T_V/T`, in I16F16 fixed point: sixteen integer bits hold any
//! gain the line follower needs, sixteen fraction bits resolve 1.5·10⁻⁵, and
//! the Cortex-M4 multiplies them in one instruction pair. All arithmetic
//! saturates, so no input can panic or wrap.

use fixed::types::I16F16;

/// A gain or time ratio in the control path.
pub type Fix = I16F16;

/// Proportional, integral (per interval) and derivative (per interval)
/// gains of the positional law.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Gains {
    /// K_r.
    pub kp: Fix,
    /// K_r · T / T_N.
    pub ki: Fix,
    /// K_r · T_V / T.
    pub kd: Fix,
}

impl Gains {
    /// The 2010 firmware's hand-tuned gains (Kp 1.5, Ki 0.1, Kd 0.6 on the
    /// left−right error; it halved the output into the angular speed).
    pub const LEGACY: Gains = Gains {
        kp: Fix::lit("0.75"),
        ki: Fix::lit("0.05"),
        kd: Fix::lit("0.3"),
    };

    /// The seed's form: gain K_r, reset time T_N and derivative time T_V, all
    /// times in control intervals.
    pub fn from_times(kr: Fix, reset_intervals: Fix, derivative_intervals: Fix) -> Gains {
        let ki = if reset_intervals > Fix::ZERO {
            kr.saturating_div(reset_intervals)
        } else {
            Fix::ZERO
        };
        Gains {
            kp: kr,
            ki,
            kd: kr.saturating_mul(derivative_intervals),
        }
    }

    /// All three gains multiplied by `factor` (keeps T_N and T_V).
    pub fn scaled(self, factor: Fix) -> Gains {
        Gains {
            kp: self.kp.saturating_mul(factor),
            ki: self.ki.saturating_mul(factor),
            kd: self.kd.saturating_mul(factor),
        }
    }
}

/// Ziegler–Nichols with the seed's factors: K_r = 0.6·K_crit,
/// T_N = 0.5·T_crit, T_V = 0.12·T_crit.
///
/// `oscillation_period` and `interval` may be in any one time unit (ticks,
/// milliseconds); only their ratio matters. A zero interval yields a pure P
/// controller rather than a division by zero.
pub fn ziegler_nichols(critical_gain: Fix, oscillation_period: Fix, interval: Fix) -> Gains {
    let kr = critical_gain.saturating_mul(Fix::lit("0.6"));
    if interval <= Fix::ZERO {
        return Gains {
            kp: kr,
            ki: Fix::ZERO,
            kd: Fix::ZERO,
        };
    }
    let periods = oscillation_period.saturating_div(interval);
    Gains::from_times(
        kr,
        periods.saturating_mul(Fix::lit("0.5")),
        periods.saturating_mul(Fix::lit("0.12")),
    )
}

/// The positional PID with anti-wind-up (the sum of past errors is clamped)
/// and an output limit.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Pid {
    gains: Gains,
    /// Σ_{i=1}^{n-1} x_i, clamped to ±`integral_limit`.
    integral: i32,
    integral_limit: i32,
    output_limit: i32,
    last_error: Option<i32>,
}

impl Pid {
    /// A controller with an empty history. The 2010 firmware clamped the
    /// error sum to ±5000 and the angular output to ±1000.
    pub const fn new(gains: Gains, integral_limit: i32, output_limit: i32) -> Pid {
        Pid {
            gains,
            integral: 0,
            integral_limit,
            output_limit,
            last_error: None,
        }
    }

    /// The gains in use.
    pub const fn gains(&self) -> Gains {
        self.gains
    }

    /// Replaces the gains (after tuning), keeping the history.
    pub fn set_gains(&mut self, gains: Gains) {
        self.gains = gains;
    }

    /// Forgets the history: a new line, a new controller run.
    pub fn reset(&mut self) {
        self.integral = 0;
        self.last_error = None;
    }

    /// One control interval: the output for error `error`.
    pub fn update(&mut self, error: i32) -> i32 {
        let e = Fix::saturating_from_num(error);
        let delta = match self.last_error {
            Some(prev) => Fix::saturating_from_num(error.saturating_sub(prev)),
            None => Fix::ZERO,
        };
        let sum = Fix::saturating_from_num(self.integral);
        let u = self
            .gains
            .kp
            .saturating_mul(e)
            .saturating_add(self.gains.ki.saturating_mul(sum))
            .saturating_add(self.gains.kd.saturating_mul(delta));
        // The seed's sum runs to n−1: the current error joins it afterwards.
        self.integral = self
            .integral
            .saturating_add(error)
            .clamp(-self.integral_limit, self.integral_limit);
        self.last_error = Some(error);
        u.saturating_to_num::<i32>()
            .clamp(-self.output_limit, self.output_limit)
    }
}

/// The outcome of a critical-gain experiment.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Critical {
    /// K_crit: the proportional gain at the edge of stability.
    pub gain: Fix,
    /// T_crit in control intervals.
    pub period: Fix,
}

impl Critical {
    /// The Ziegler–Nichols gains for this experiment (interval 1).
    pub fn gains(self) -> Gains {
        ziegler_nichols(self.gain, self.period, Fix::ONE)
    }
}

/// What the relay experiment asks for this interval.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Relay {
    /// Apply this output (±amplitude).
    Drive(i32),
    /// The experiment is over.
    Done(Critical),
    /// No sustained oscillation appeared in time.
    Failed,
}

/// Åström–Hägglund relay experiment: a bang-bang controller drives the loop
/// into a limit cycle whose period is the critical period and whose error
/// amplitude a gives the critical gain K_crit = 4·h / (π·a).
///
/// Safer than raising a P gain until the robot oscillates: the amplitude is
/// bounded by the relay's h, so the robot stays on its line.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct RelayTuner {
    amplitude: i32,
    hysteresis: i32,
    high: bool,
    tick: u32,
    last_rise: Option<u32>,
    cycles: u16,
    skip: u16,
    measure: u16,
    period_sum: u32,
    swing_sum: u32,
    max: i32,
    min: i32,
    timeout: u32,
}

impl RelayTuner {
    /// A relay of output ±`amplitude` with `hysteresis` error units against
    /// noise; skips `skip` cycles to settle, then averages `measure` cycles.
    pub const fn new(amplitude: i32, hysteresis: i32, skip: u16, measure: u16) -> RelayTuner {
        RelayTuner {
            amplitude,
            hysteresis,
            high: true,
            tick: 0,
            last_rise: None,
            cycles: 0,
            skip,
            measure,
            period_sum: 0,
            swing_sum: 0,
            max: i32::MIN,
            min: i32::MAX,
            timeout: 3000,
        }
    }

    /// One interval with the current control error.
    pub fn update(&mut self, error: i32) -> Relay {
        self.tick = self.tick.saturating_add(1);
        if self.tick > self.timeout {
            return Relay::Failed;
        }
        self.max = self.max.max(error);
        self.min = self.min.min(error);
        if self.high && error < -self.hysteresis {
            self.high = false;
        } else if !self.high && error > self.hysteresis {
            self.high = true;
            // A rising switch closes one full cycle.
            if let Some(rise) = self.last_rise {
                self.cycles += 1;
                if self.cycles > self.skip {
                    self.period_sum += self.tick - rise;
                    let swing = self.max.saturating_sub(self.min).max(0);
                    self.swing_sum = self.swing_sum.saturating_add(swing.unsigned_abs());
                }
                if self.cycles >= self.skip + self.measure {
                    return self.finish();
                }
            }
            self.last_rise = Some(self.tick);
            self.max = error;
            self.min = error;
        }
        Relay::Drive(if self.high {
            self.amplitude
        } else {
            -self.amplitude
        })
    }

    fn finish(&self) -> Relay {
        let n = u32::from(self.measure.max(1));
        // Half the mean peak-to-peak swing.
        let a = Fix::saturating_from_num(self.swing_sum / n) / 2;
        if a <= Fix::ZERO {
            return Relay::Failed;
        }
        let four_h_over_pi =
            Fix::lit("1.2732395").saturating_mul(Fix::saturating_from_num(self.amplitude));
        Relay::Done(Critical {
            gain: four_h_over_pi.saturating_div(a),
            period: Fix::saturating_from_num(self.period_sum) / Fix::saturating_from_num(n),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zn_uses_the_seed_factors() {
        let g = ziegler_nichols(Fix::from_num(2), Fix::from_num(400), Fix::from_num(10));
        assert!((g.kp - Fix::lit("1.2")).abs() < Fix::lit("0.0001"));
        // T_N = 0.5 · 40 intervals = 20 → ki = 1.2 / 20.
        assert!((g.ki - Fix::lit("0.06")).abs() < Fix::lit("0.0001"));
        // T_V = 0.12 · 40 = 4.8 intervals → kd = 5.76.
        assert!((g.kd - Fix::lit("5.76")).abs() < Fix::lit("0.001"));
        let p = ziegler_nichols(Fix::from_num(2), Fix::from_num(400), Fix::ZERO);
        assert_eq!(p.ki, Fix::ZERO);
    }

    #[test]
    fn positional_law_sums_previous_errors() {
        let g = Gains {
            kp: Fix::ONE,
            ki: Fix::lit("0.5"),
            kd: Fix::from_num(2),
        };
        let mut pid = Pid::new(g, 100, 1000);
        assert_eq!(pid.update(10), 10); // no history yet
        assert_eq!(pid.update(10), 10 + 5); // sum of x_1 = 10
        assert_eq!(pid.update(4), 4 + 10 + 2 * -6);
    }

    #[test]
    fn integral_and_output_are_clamped() {
        let g = Gains {
            kp: Fix::ZERO,
            ki: Fix::ONE,
            kd: Fix::ZERO,
        };
        let mut pid = Pid::new(g, 50, 40);
        for _ in 0..100 {
            pid.update(30);
        }
        assert_eq!(pid.update(0), 40);
        pid.reset();
        assert_eq!(pid.update(i32::MIN), 0);
        let mut wild = Pid::new(
            Gains {
                kp: Fix::MAX,
                ki: Fix::MAX,
                kd: Fix::MAX,
            },
            i32::MAX,
            1000,
        );
        for e in [i32::MAX, i32::MIN, 0, i32::MAX] {
            assert!(wild.update(e).abs() <= 1000);
        }
    }

    /// A discrete plant with an integrator and two intervals of dead time
    /// oscillates under the relay; the experiment's period and gain match
    /// the analytic critical point within a few percent.
    #[test]
    fn relay_finds_the_critical_point_of_an_integrator_with_delay() {
        let mut tuner = RelayTuner::new(10, 0, 2, 4);
        let mut y = 0i32;
        let mut pipe = [0i32; 3];
        let result = loop {
            match tuner.update(-y) {
                Relay::Drive(u) => {
                    pipe = [pipe[1], pipe[2], u];
                    y += pipe[0];
                }
                other => break other,
            }
        };
        let Relay::Done(c) = result else {
            panic!("no result: {result:?}")
        };
        // Integrator with 3 intervals of delay: limit cycle period 4·3 = 12.
        assert_eq!(c.period, Fix::from_num(12));
        assert!(c.gain > Fix::ZERO);
    }
}

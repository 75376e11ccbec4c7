//! One control step of the whole behaviour stack, counted on a Cortex-M4
//! under QEMU with `-icount shift=0` (one instruction = 1 ns of virtual
//! time, so SysTick at the board's 25 MHz counts 1 per 40 instructions).
//! It replays a synthetic edge — line following, a cross-shaped node, the
//! node report — many times and prints instructions per step.
#![no_std]
#![no_main]

use core_algo::behaviour::{Command, Config, Mode, Robot, Sensors};
use core_algo::control::StepCount;
use core_algo::control::calibration::Calibration;
use cortex_m::peripheral::{SYST, syst::SystClkSource};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;

/// The floor a robot sees `s` steps after leaving a node, on a cross-shaped
/// node at 600 steps (sensor position), 12 mm ≈ 93 steps of crossing line.
fn floor(s: i32, wiggle: u16) -> [u16; 3] {
    let rel = s - 543;
    if rel.abs() <= 46 {
        [300, 300, 300]
    } else {
        [880 + wiggle, 310, 890 - wiggle]
    }
}

/// Runs one edge; returns the steps taken and the largest single step in
/// SysTick ticks.
fn run_edge(robot: &mut Robot, start: StepCount) -> (u32, u32) {
    let mut s = Sensors {
        steps: start,
        proximity: [20, 15, 3, 0, 0, 4, 12, 25],
        ..Sensors::default()
    };
    robot.place_on_node(s.steps);
    let _ = robot.order(Command::Move);
    let mut n = 0;
    let mut worst = 0;
    for k in 0..400u32 {
        let travelled = s.steps.travelled_since(start);
        s.floor = floor(travelled, (k % 7) as u16 * 10);
        let t0 = SYST::get_current();
        let out = robot.step(&s);
        let t1 = SYST::get_current();
        worst = worst.max(t0.wrapping_sub(t1) & 0x00ff_ffff);
        n += 1;
        s.steps.left = s.steps.left.wrapping_add(i32::from(out.wheels.left) / 100);
        s.steps.right = s
            .steps
            .right
            .wrapping_add(i32::from(out.wheels.right) / 100);
        if out.event.is_some() && robot.mode() == Mode::OnNode && k > 2 {
            break;
        }
    }
    (n, worst)
}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        debug::exit(debug::EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    };
    let syst: &mut SYST = &mut cp.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00ff_ffff);
    syst.clear_current();
    syst.enable_counter();
    let cal = Calibration::new([300; 3], [900; 3]).ok();
    let mut robot = Robot::new(Config::EPUCK, cal);
    let mut steps = 0u32;
    let mut ticks = 0u32;
    let mut worst = 0u32;
    let mut start = StepCount::default();
    for _ in 0..20 {
        let t0 = SYST::get_current();
        let (n, w) = run_edge(&mut robot, start);
        worst = worst.max(w);
        let t1 = SYST::get_current();
        // SysTick counts down; 24 bits.
        ticks += t0.wrapping_sub(t1) & 0x00ff_ffff;
        steps += n;
        start = StepCount {
            left: start.left.wrapping_add(1000),
            right: start.right.wrapping_add(1000),
        };
    }
    // Check the tick-to-instruction ratio with a known loop: delay(n)
    // executes about n instructions (a two-instruction loop, n/2 times).
    let t0 = SYST::get_current();
    cortex_m::asm::delay(4_000_000);
    let t1 = SYST::get_current();
    let loop_ticks = t0.wrapping_sub(t1) & 0x00ff_ffff;
    // 25 MHz SysTick and 1 GHz instruction clock: 40 instructions a tick.
    let per_step = ticks as u64 * 40 / steps.max(1) as u64;
    hprintln!(
        "steps={} systicks={} instructions_per_step={} worst_step_instructions<={} \
         delay(4e6)_systicks={} (8e6 instructions: expect 200000)",
        steps,
        ticks,
        per_step,
        (worst + 1) * 40,
        loop_ticks
    );
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}

//! Unit tests of the stack with a one-dimensional fake floor.

use super::*;
use std::vec::Vec;

const LINE: [u16; 3] = [300, 300, 300];
const WHITE: [u16; 3] = [900, 900, 900];

/// Integrates wheel speeds into step counters (10 ms per step).
fn advance(s: &mut Sensors, w: Wheels) {
    s.steps.left += i32::from(w.left) / CONTROL_HZ;
    s.steps.right += i32::from(w.right) / CONTROL_HZ;
}

fn calibrated() -> Robot {
    Robot::new(Config::EPUCK, Calibration::new(LINE, WHITE).ok())
}

struct Fixed(Option<Act>, u8);
impl Layer for Fixed {
    fn act(&mut self, _: &mut Context<'_>) -> Option<Act> {
        self.1 += 1;
        self.0
    }
}

#[test]
fn the_first_acting_layer_wins() {
    let mut state = calibrated().state;
    let sensors = Sensors::default();
    let mut ctx = Context {
        sensors: &sensors,
        floor: None,
        state: &mut state,
    };
    let mut a = Fixed(None, 0);
    let mut b = Fixed(Some(Act::drive(Wheels::straight(5))), 0);
    let mut c = Fixed(Some(Act::drive(Wheels::STOP)), 0);
    let got = arbitrate(&mut [&mut a, &mut b, &mut c], &mut ctx);
    assert_eq!(got, Some(Act::drive(Wheels::straight(5))));
    assert_eq!((a.1, b.1, c.1), (1, 1, 0));
}

/// Runs the calibration with a floor that reads `first` for the first
/// 100 steps of travel and `then` beyond.
fn calibrate(first: [u16; 3], then: [u16; 3]) -> (Robot, Vec<Event>, Sensors) {
    let mut robot = Robot::new(Config::EPUCK, None);
    assert_eq!(robot.order(Command::Move), Err(Refused::NotCalibrated));
    robot.order(Command::Calibrate).unwrap();
    let mut s = Sensors::default();
    let mut events = Vec::new();
    for _ in 0..400 {
        s.floor = if s.steps.left < 100 { first } else { then };
        let out = robot.step(&s);
        events.extend(out.event);
        advance(&mut s, out.wheels);
    }
    (robot, events, s)
}

#[test]
fn calibration_drives_out_and_back() {
    let (robot, events, s) = calibrate(LINE, WHITE);
    let cal = Calibration::new(LINE, WHITE).unwrap();
    assert_eq!(events, [Event::Calibrated(cal.record())]);
    assert_eq!(robot.mode(), Mode::Ready);
    assert_eq!(robot.calibration(), Some(cal));
    assert_eq!(s.steps, StepCount::default());
}

#[test]
fn a_robot_off_the_line_is_refused() {
    let (robot, events, _) = calibrate(WHITE, WHITE);
    assert_eq!(
        events,
        [Event::CalibrationRefused(CalibrationError::NoContrast {
            sensor: 0
        })]
    );
    assert_eq!(robot.mode(), Mode::Uncalibrated);
}

#[test]
fn collision_and_abyss_stop_a_moving_robot() {
    let mut robot = calibrated();
    robot.place_on_node(StepCount::default());
    robot.order(Command::Move).unwrap();
    let mut s = Sensors {
        floor: [900, 300, 900],
        ..Sensors::default()
    };
    assert_eq!(robot.step(&s).wheels, Wheels::STOP); // takes the order
    assert_eq!(robot.mode(), Mode::Moving);
    assert_eq!(robot.step(&s).wheels, Wheels::straight(600));
    s.proximity[7] = 2000;
    let out = robot.step(&s);
    assert_eq!(out.wheels, Wheels::STOP);
    assert_eq!(
        out.event,
        Some(Event::Collision {
            mask: 0x80,
            travelled: 0
        })
    );
    assert_eq!(robot.mode(), Mode::Blocked);
    s.proximity[7] = 0;
    robot.order(Command::Move).unwrap();
    robot.step(&s);
    s.floor = [0, 0, 900];
    assert_eq!(robot.step(&s).event, None);
    let out = robot.step(&s);
    assert_eq!(out.event, Some(Event::Abyss { mask: 0b011 }));
    assert_eq!(robot.mode(), Mode::AtAbyss);
}

#[test]
fn turns_are_exact_and_end_centred() {
    let mut robot = calibrated();
    robot.place_on_node(StepCount::default());
    robot.order(Command::SetSpeed(1000)).unwrap();
    robot.order(Command::Turn(Turn::Left)).unwrap();
    let mut s = Sensors {
        floor: [900, 300, 900],
        ..Sensors::default()
    };
    let mut events = Vec::new();
    for _ in 0..100 {
        let out = robot.step(&s);
        events.extend(out.event);
        advance(&mut s, out.wheels);
    }
    assert_eq!(
        s.steps,
        StepCount {
            left: -323,
            right: 323
        }
    );
    assert_eq!(events, [Event::Centred]);
    assert_eq!(robot.mode(), Mode::OnNode);
    assert_eq!(robot.state().speed, 1000);
    assert_eq!(robot.order(Command::SetSpeed(0)), Err(Refused::BadSpeed));
    for _ in 0..4 {
        robot.order(Command::Move).unwrap();
    }
    assert_eq!(robot.order(Command::Move), Err(Refused::Busy));
    robot.order(Command::Stop).unwrap();
    assert_eq!(robot.state().orders.peek(), None);
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    fn command() -> impl Strategy<Value = Command> {
        prop_oneof![
            Just(Command::Calibrate),
            Just(Command::Scan),
            Just(Command::Move),
            Just(Command::Stop),
            Just(Command::Turn(Turn::Left)),
            Just(Command::Turn(Turn::Right)),
            Just(Command::Turn(Turn::UTurn)),
            any::<i16>().prop_map(Command::SetSpeed),
        ]
    }

    proptest! {
        /// Arbitrary sensor images, step counters and orders: the stack
        /// never panics and never asks the motors for more than they can do.
        #[test]
        fn any_input_is_safe(
            calibrated in any::<bool>(),
            input in proptest::collection::vec(
                (any::<[u16; 3]>(), any::<[u16; 8]>(), any::<i32>(), any::<i32>(),
                 proptest::option::of(command())),
                1..200,
            ),
        ) {
            let mut robot = if calibrated { super::calibrated() } else { Robot::new(Config::EPUCK, None) };
            for (floor, proximity, left, right, order) in input {
                if let Some(c) = order {
                    let _ = robot.order(c);
                }
                let s = Sensors { floor, proximity, steps: StepCount { left, right } };
                let out = robot.step(&s);
                prop_assert!(out.wheels.left.abs() <= 1000 && out.wheels.right.abs() <= 1000);
            }
        }
    }
}

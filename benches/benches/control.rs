//! One 100 Hz control step of the whole behaviour stack (all seven layers):
//! with a fixed line-following image, and replaying a sensor trace recorded
//! in the sensor-level simulator (line following, a node crossing, the node
//! report, a turn and centring).
use core_algo::behaviour::{Command, Config, Mode, Robot, Sensors};
use core_algo::control::calibration::Calibration;
use core_algo::geometry::{Heading, Pos, Turn};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use phone_sim::sensor_world::field::LineField;
use phone_sim::sensor_world::scenario::calibrated_robot;
use phone_sim::sensor_world::{SimConfig, World};
use std::hint::black_box;

/// A robot that is following a line, and an image of the line centred.
fn following() -> (Robot, Sensors) {
    let cal = Calibration::new([300; 3], [900; 3]).ok();
    let mut robot = Robot::new(Config::EPUCK, cal);
    let s = Sensors {
        floor: [890, 310, 880],
        proximity: [20, 15, 3, 0, 0, 4, 12, 25],
        ..Sensors::default()
    };
    robot.place_on_node(s.steps);
    robot.order(Command::Move).expect("calibrated");
    robot.step(&s);
    assert_eq!(robot.mode(), Mode::Moving);
    (robot, s)
}

/// The robot before the trace and the orders and sensor images of one edge
/// with a node, a right turn and centring, from the simulator.
fn trace() -> (Robot, Vec<(Option<Command>, Sensors)>) {
    let mut cfg = Config::EPUCK;
    cfg.node.node_spacing_steps = 776;
    let mut w = World::new(
        LineField::lattice(3, 3, 100.0, 12.0),
        SimConfig::default(),
        1,
    );
    let i = calibrated_robot(&mut w, cfg, Pos::new(1, 0), Heading::North);
    let start = w.robots[i].robot;
    let mut out = Vec::new();
    let mut order = Some(Command::Move);
    for _ in 0..1000 {
        if let Some(c) = order.take() {
            w.order(i, c).expect("order");
            out.push((Some(c), Sensors::default()));
        }
        let ev = w.step();
        out.push((None, w.robots[i].sensors));
        if ev.iter().any(|e| e.robot == i) && w.robots[i].robot.mode() == Mode::OnNode {
            if out.iter().filter(|(c, _)| c.is_some()).count() >= 2 {
                break;
            }
            order = Some(Command::Turn(Turn::Right));
        }
    }
    (start, out)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("control");
    let (robot, s) = following();
    g.throughput(Throughput::Elements(1));
    g.bench_function("step_following", |b| {
        let mut r = robot;
        b.iter(|| r.step(black_box(&s)))
    });
    let (start, tr) = trace();
    let steps = tr.iter().filter(|(c, _)| c.is_none()).count() as u64;
    g.throughput(Throughput::Elements(steps));
    g.bench_function("step_trace_edge_node_turn", |b| {
        b.iter(|| {
            let mut r = start;
            for (c, s) in &tr {
                match c {
                    Some(c) => {
                        let _ = r.order(*c);
                    }
                    None => {
                        black_box(r.step(black_box(s)));
                    }
                }
            }
            r
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

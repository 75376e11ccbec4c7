//! Proof in the sensor-level simulator: node analysis while crossing, and
//! the start-node scan (numbers in docs/results/control.md).

use core_algo::behaviour::{Command, Config, Event, Robot};
use core_algo::control::StepCount;
use core_algo::control::calibration::Calibration;
use core_algo::geometry::{Arms, Heading, Pos};
use phone_sim::sensor_world::body::Pose;
use phone_sim::sensor_world::field::LineField;
use phone_sim::sensor_world::scenario::*;
use phone_sim::sensor_world::{Lighting, SimConfig, World, heading_theta};

const LIGHTS: [Lighting; 3] = [
    Lighting::NORMAL,
    Lighting {
        gain: 0.6,
        offset: 20.0,
    },
    Lighting {
        gain: 1.1,
        offset: -50.0,
    },
];

fn config() -> Config {
    let mut c = Config::EPUCK;
    c.node.node_spacing_steps = 776; // 100 mm
    c
}

/// Calibrates once per light (as a person would), for reuse.
fn calibrations() -> Vec<Calibration> {
    LIGHTS
        .iter()
        .enumerate()
        .map(|(k, light)| {
            let field = LineField::lattice(2, 2, 100.0, 12.0);
            let mut w = World::new(field, SimConfig::default(), 100 + k as u64);
            let pose = calibration_pose(&w, Pos::new(0, 0));
            let i = w.add_robot(Robot::new(config(), None), pose);
            w.robots[i].lighting = *light;
            calibrate(&mut w, i).expect("calibrates")
        })
        .collect()
}

/// A 3 × 3 field whose centre node has `arms` (global), its neighbours
/// connected where the centre has an arm, plus the approach arm.
fn field_with(arms: Arms) -> LineField {
    let mut f = LineField::new(3, 3, 100.0, 12.0);
    let c = Pos::new(1, 1);
    for h in arms.iter() {
        f.connect(c, h);
    }
    f
}

#[test]
fn node_analysis_classifies_every_shape() {
    let cals = calibrations();
    let crossings = 2000;
    let mut w0 = World::new(LineField::new(3, 3, 100.0, 12.0), SimConfig::default(), 42);
    let mut failures = Vec::new();
    let mut per_shape = [(0u32, 0u32); 16];
    let mut stop = Stats::default();
    for k in 0..crossings {
        // A random shape that has the approach arm (behind), a random
        // approach direction, angle, offset, light and light change.
        let r = w0.uniform(0.0, 8.0) as u8; // ahead, right, left: one bit each
        let rel = Arms::from_bits(0b0100 | (r & 0b011) | ((r & 0b100) << 1));
        let heading = Heading::from_index(w0.uniform(0.0, 4.0) as u8);
        let global = Arms::from_relative(rel, heading);
        let angle = w0.uniform(-10.0, 10.0);
        let lateral = w0.uniform(-1.5, 1.5);
        let gap = w0.uniform(3.0, 15.0);
        let which = w0.uniform(0.0, 3.0) as usize;
        let change = Lighting {
            gain: LIGHTS[which].gain * w0.uniform(0.85, 1.15),
            offset: LIGHTS[which].offset + w0.uniform(-25.0, 25.0),
        };
        let mut w = World::new(field_with(global), SimConfig::default(), 1000 + k);
        let g = w.geometry;
        // Centre sensor `gap` mm before the crossing line's near edge (line
        // half width + spot half), `lateral` mm off the line.
        let (nx, ny) = w.field.node_mm(Pos::new(1, 1));
        let theta = heading_theta(heading) + angle.to_radians();
        let back = 6.0 + 3.0 + gap;
        let (fx, fy) = (heading.delta().0 as f64, heading.delta().1 as f64);
        let (sx, sy) = (nx - fx * back + fy * lateral, ny - fy * back - fx * lateral);
        let pose = Pose {
            x: sx - g.floor_forward_mm * theta.cos(),
            y: sy - g.floor_forward_mm * theta.sin(),
            theta,
        };
        let mut robot = Robot::new(config(), Some(cals[which]));
        robot.place_on_node(StepCount::default());
        let i = w.add_robot(robot, pose);
        w.robots[i].lighting = change;
        w.order(i, Command::Move).unwrap();
        w.step(); // takes the order: the edge starts at step count 0
        // Odometry as if the robot had come from the previous node.
        let from_node = ((nx - pose.x) * fx + (ny - pose.y) * fy).abs();
        let n = ((100.0 - from_node) / g.step_mm).round() as i32;
        w.set_steps(i, StepCount { left: n, right: n });
        let got = w.run_until_event(i, 400).map(|e| e.event);
        let p = w.robots[i].body.pose;
        let off = (p.x - nx).hypot(p.y - ny);
        let slot = &mut per_shape[rel.bits() as usize];
        slot.0 += 1;
        if got == Some(Event::NodeHit { arms: rel }) && off < 10.0 {
            slot.1 += 1;
            stop.add(off);
        } else {
            failures.push(format!(
                "#{k}: shape {rel:?} from {heading} angle {angle:.1}° lateral {lateral:.1} gap {gap:.1} \
                 light {change:?}: got {got:?}, stopped {off:.1} mm from the node"
            ));
        }
    }
    let ok = per_shape.iter().map(|s| s.1).sum::<u32>();
    println!(
        "STAT nodes crossings={crossings} correct={ok} rate={:.4} stop_off_node_mean_mm={:.2} max={:.2}",
        f64::from(ok) / f64::from(crossings as u32),
        stop.mean(),
        stop.max_abs
    );
    for (bits, (n, good)) in per_shape.iter().enumerate() {
        if *n > 0 {
            println!(
                "STAT nodes shape={:?} n={n} correct={good}",
                Arms::from_bits(bits as u8)
            );
        }
    }
    for f in &failures {
        println!("STAT nodes failure {f}");
    }
    assert!(
        ok * 1000 >= 995 * crossings as u32,
        "{} failures",
        failures.len()
    );
}

#[test]
fn start_scan_classifies_all_fifteen_shapes() {
    let cals = calibrations();
    let mut w0 = World::new(LineField::new(3, 3, 100.0, 12.0), SimConfig::default(), 7);
    let mut total = 0;
    let mut ok = 0;
    let mut failures = Vec::new();
    for bits in 1..16u8 {
        for rep in 0..6 {
            let arms = Arms::from_bits(bits);
            let heading = Heading::from_index(rep as u8);
            let angle = w0.uniform(-12.0, 12.0);
            let which = rep % 3;
            let mut w = World::new(field_with(arms), SimConfig::default(), 500 + total);
            let (nx, ny) = w.field.node_mm(Pos::new(1, 1));
            let pose = Pose {
                x: nx + w0.uniform(-2.0, 2.0),
                y: ny + w0.uniform(-2.0, 2.0),
                theta: heading_theta(heading) + angle.to_radians(),
            };
            let i = w.add_robot(Robot::new(config(), Some(cals[which])), pose);
            w.robots[i].lighting = LIGHTS[which];
            w.order(i, Command::Scan).unwrap();
            let got = w.run_until_event(i, 1000).map(|e| e.event);
            let want = arms.to_relative(heading);
            total += 1;
            let theta = w.robots[i].body.pose.theta;
            let residual = (theta - heading_theta(heading)).to_degrees();
            let residual = (residual + 180.0).rem_euclid(360.0) - 180.0;
            if got == Some(Event::StartNode { arms: want }) && residual.abs() < 5.0 {
                ok += 1;
            } else {
                failures.push(format!(
                    "{arms:?} facing {heading} {angle:.1}°: {got:?} residual {residual:.1}°"
                ));
            }
        }
    }
    println!("STAT scan runs={total} correct={ok}");
    for f in &failures {
        println!("STAT scan failure {f}");
    }
    assert_eq!(ok, total);
}

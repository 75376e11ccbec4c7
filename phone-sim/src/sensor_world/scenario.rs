//! Building blocks for experiments in the sensor world: calibrate a robot
//! as a person would, drive edges while recording how well the robot keeps
//! to its line, and compare reported node shapes with the field.

use super::body::Pose;
use super::{Logged, World, heading_theta, nearest_heading};
use core_algo::behaviour::{Command, Config, Event, Robot};
use core_algo::control::calibration::{Calibration, CalibrationError};
use core_algo::geometry::{Arms, Heading, Pos};

/// Running statistics of a signed quantity (lateral error in mm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Samples.
    pub n: u64,
    sum: f64,
    sum_sq: f64,
    /// Largest absolute value.
    pub max_abs: f64,
}

impl Stats {
    /// Adds one sample.
    pub fn add(&mut self, v: f64) {
        self.n += 1;
        self.sum += v;
        self.sum_sq += v * v;
        self.max_abs = self.max_abs.max(v.abs());
    }

    /// Merges another set of samples.
    pub fn merge(&mut self, o: &Stats) {
        self.n += o.n;
        self.sum += o.sum;
        self.sum_sq += o.sum_sq;
        self.max_abs = self.max_abs.max(o.max_abs);
    }

    /// Mean.
    pub fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }

    /// Root mean square.
    pub fn rms(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            (self.sum_sq / self.n as f64).sqrt()
        }
    }
}

/// The pose for calibrating: the robot stands across a horizontal line half
/// way between nodes `p` and its east neighbour, facing north, with its
/// floor sensors on the line (background ahead).
pub fn calibration_pose(world: &World, p: Pos) -> Pose {
    let (x, y) = world.field.node_mm(p);
    Pose {
        x: x + world.field.spacing_mm / 2.0,
        y: y - world.geometry.floor_forward_mm,
        theta: heading_theta(Heading::North),
    }
}

/// Runs a calibration of robot `i` where it stands; returns the outcome.
pub fn calibrate(world: &mut World, i: usize) -> Result<Calibration, CalibrationError> {
    let _ = world.order(i, Command::Calibrate);
    match world.run_until_event(i, 2000).map(|l| l.event) {
        Some(Event::Calibrated(record)) => core_algo::control::calibration::Record::load(&record.0)
            .map_err(|_| CalibrationError::NoContrast { sensor: 9 }),
        Some(Event::CalibrationRefused(e)) => Err(e),
        _ => Err(CalibrationError::NoContrast { sensor: 9 }),
    }
}

/// Adds a robot, calibrates it on the field (under the world's current
/// lighting for new robots) and puts it on node `p` facing `h`.
pub fn calibrated_robot(world: &mut World, config: Config, p: Pos, h: Heading) -> usize {
    // Calibrate on a small field of the same paper and light, like a
    // person would on a spare line, so any field shape can be used here.
    let field = super::field::LineField::lattice(2, 2, 100.0, world.field.line_width_mm);
    let seed = world.uniform(0.0, 1e9) as u64;
    let mut bench = World::new(field, world.config, seed);
    let pose = calibration_pose(&bench, Pos::new(0, 0));
    let k = bench.add_robot(Robot::new(config, None), pose);
    let cal = calibrate(&mut bench, k).ok();
    let i = world.add_robot(Robot::new(config, None), pose);
    let pose = world.pose_on_node(p, h);
    let r = &mut world.robots[i];
    r.robot = Robot::new(config, cal);
    r.body = super::body::Body::new(pose);
    r.robot.place_on_node(r.body.steps);
    i
}

/// The result of driving one edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeRun {
    /// The event that ended the edge.
    pub end: Option<Logged>,
    /// Lateral offset of the axle from the line, mm.
    pub axle: Stats,
    /// Lateral offset of the centre floor sensor from the line, mm.
    pub sensor: Stats,
}

/// Orders robot `i` to move and runs until it reports (or `max_ticks`),
/// recording its lateral offsets while it follows the line.
pub fn drive_edge(world: &mut World, i: usize, max_ticks: u64) -> EdgeRun {
    let _ = world.order(i, Command::Move);
    let mut run = EdgeRun {
        end: None,
        axle: Stats::default(),
        sensor: Stats::default(),
    };
    for _ in 0..max_ticks {
        let events = world.step();
        let pose = world.robots[i].body.pose;
        let (sx, sy) = pose.point(world.geometry.floor_forward_mm, 0.0);
        // Only between nodes: near a node the crossing line is no "line".
        let (nx, ny) = world.field.node_mm(world.field.nearest_node(sx, sy));
        let near = (sx - nx).abs().max((sy - ny).abs()) < world.field.line_width_mm;
        if !near {
            run.sensor.add(world.lateral_offset(sx, sy, pose.theta));
            run.axle
                .add(world.lateral_offset(pose.x, pose.y, pose.theta));
        }
        if let Some(e) = events.into_iter().find(|e| e.robot == i) {
            run.end = Some(e);
            break;
        }
    }
    run
}

/// The node robot `i` stands on (nearest to its axle) and the heading it
/// faces (nearest lattice heading).
pub fn where_is(world: &World, i: usize) -> (Pos, Heading, f64) {
    let p = world.robots[i].body.pose;
    let node = world.field.nearest_node(p.x, p.y);
    let (nx, ny) = world.field.node_mm(node);
    (node, nearest_heading(p.theta), (p.x - nx).hypot(p.y - ny))
}

/// The arms of node `p` as seen by a robot facing `h`.
pub fn relative_arms(world: &World, p: Pos, h: Heading) -> Arms {
    world.field.arms(p).to_relative(h)
}

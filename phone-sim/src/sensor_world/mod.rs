//! A sensor-level 2-D simulator: e-puck bodies on a rendered line field,
//! each running the very [`core_algo::behaviour::Robot`] stack of the
//! firmware at 100 Hz.
//!
//! Every control step the world renders each robot's sensor image — three
//! floor sensors averaging a square spot of the field (with lighting gain,
//! offset and noise), eight proximity sensors against the other robots and
//! walls — hands it to the robot's behaviour stack, and moves the body with
//! the wheel speeds it returns (stepper counts, optional wheel slip). All
//! randomness comes from one seeded ChaCha generator, so a run reproduces
//! exactly.

pub mod body;
pub mod field;
pub mod scenario;

use body::{Body, Geometry, Pose, proximity_value};
use core_algo::behaviour::{Command, Event, Output, Refused, Robot, Sensors};
use core_algo::control::StepCount;
use field::LineField;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Seconds per control step.
pub const DT: f64 = 0.01;

/// Light on the floor sensors: raw = gain · reflectance · 1023 + offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    /// Multiplies the reflected light.
    pub gain: f64,
    /// Added to every reading (stray light, sensor offset).
    pub offset: f64,
}

impl Lighting {
    /// Reference light: white paper reads about 920.
    pub const NORMAL: Lighting = Lighting {
        gain: 1.0,
        offset: 0.0,
    };
}

/// Noise and surface parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Floor-sensor noise, standard deviation in raw units.
    pub floor_noise: f64,
    /// Proximity noise, standard deviation in raw units.
    pub proximity_noise: f64,
    /// Relative wheel slip per step, standard deviation (0.01 = 1 %).
    pub slip: f64,
    /// Reflectance of the paper.
    pub white: f64,
    /// Reflectance of the lines (a 70 % black reads a third of white).
    pub black: f64,
    /// Reflectance seen over the abyss.
    pub abyss: f64,
    /// Samples per spot side (n × n points per floor sensor).
    pub spot_samples: usize,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            floor_noise: 12.0,
            proximity_noise: 8.0,
            slip: 0.01,
            white: 0.9,
            black: 0.3,
            abyss: 0.02,
            spot_samples: 5,
        }
    }
}

/// One simulated robot.
#[derive(Clone, Debug)]
pub struct SimRobot {
    /// Its body in the world.
    pub body: Body,
    /// Its behaviour stack (the firmware's).
    pub robot: Robot,
    /// Light on its floor sensors.
    pub lighting: Lighting,
    /// The last sensor image it was given.
    pub sensors: Sensors,
}

/// An event with the step and the robot it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Logged {
    /// Control step number.
    pub tick: u64,
    /// Robot index.
    pub robot: usize,
    /// The event.
    pub event: Event,
    /// The robot's pose when it reported.
    pub pose: Pose,
}

/// The world: field, robots, random source.
#[derive(Clone, Debug)]
pub struct World {
    /// The floor.
    pub field: LineField,
    /// Robot dimensions.
    pub geometry: Geometry,
    /// Noise parameters.
    pub config: SimConfig,
    /// The robots.
    pub robots: Vec<SimRobot>,
    /// Control steps so far.
    pub tick: u64,
    /// Steps in which two bodies overlapped or a body touched a wall.
    pub contacts: u64,
    rng: ChaCha8Rng,
}

impl World {
    /// An empty world on `field`, seeded.
    pub fn new(field: LineField, config: SimConfig, seed: u64) -> World {
        World {
            field,
            geometry: Geometry::EPUCK,
            config,
            robots: Vec::new(),
            tick: 0,
            contacts: 0,
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    /// Adds a robot at `pose`; returns its index.
    pub fn add_robot(&mut self, robot: Robot, pose: Pose) -> usize {
        self.robots.push(SimRobot {
            body: Body::new(pose),
            robot,
            lighting: Lighting::NORMAL,
            sensors: Sensors::default(),
        });
        self.robots.len() - 1
    }

    /// The pose of a robot standing on node `p` facing heading `h`.
    pub fn pose_on_node(
        &self,
        p: core_algo::geometry::Pos,
        h: core_algo::geometry::Heading,
    ) -> Pose {
        let (x, y) = self.field.node_mm(p);
        Pose {
            x,
            y,
            theta: heading_theta(h),
        }
    }

    /// Passes an order to robot `i`.
    pub fn order(&mut self, i: usize, c: Command) -> Result<(), Refused> {
        match self.robots.get_mut(i) {
            Some(r) => r.robot.order(c),
            None => Err(Refused::Busy),
        }
    }

    /// Draws a normal deviate (Box–Muller).
    fn gauss(&mut self, sigma: f64) -> f64 {
        if sigma <= 0.0 {
            return 0.0;
        }
        let u1: f64 = self.rng.random_range(f64::EPSILON..1.0);
        let u2: f64 = self.rng.random();
        sigma * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A uniform deviate in `lo..hi`, from the world's generator.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        if hi <= lo {
            return lo;
        }
        self.rng.random_range(lo..hi)
    }

    /// The noiseless reflectance under one floor sensor at `forward`/`right`
    /// of the pose, averaged over its spot.
    pub fn spot_reflectance(&self, pose: &Pose, right: f64) -> f64 {
        let g = &self.geometry;
        let n = self.config.spot_samples.max(1);
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let fi = (i as f64 + 0.5) / n as f64 - 0.5;
                let fj = (j as f64 + 0.5) / n as f64 - 0.5;
                let (x, y) = pose.point(
                    g.floor_forward_mm + fi * g.floor_spot_mm,
                    right + fj * g.floor_spot_mm,
                );
                sum += if !self.field.on_floor(x, y) {
                    self.config.abyss
                } else if self.field.is_black(x, y) {
                    self.config.black
                } else {
                    self.config.white
                };
            }
        }
        sum / (n * n) as f64
    }

    fn floor_reading(&mut self, pose: &Pose, right: f64, light: Lighting) -> u16 {
        let r = self.spot_reflectance(pose, right);
        let noise = self.gauss(self.config.floor_noise);
        (light.gain * r * 1023.0 + light.offset + noise)
            .round()
            .clamp(0.0, 1023.0) as u16
    }

    /// Distance from a point along a ray to the nearest obstacle (other
    /// robots' bodies, walls), mm; infinite when none.
    fn ray_distance(&self, me: usize, ox: f64, oy: f64, angle: f64) -> f64 {
        let (dx, dy) = (angle.cos(), angle.sin());
        let mut best = f64::INFINITY;
        for (k, other) in self.robots.iter().enumerate() {
            if k == me {
                continue;
            }
            let (cx, cy) = (other.body.pose.x - ox, other.body.pose.y - oy);
            let along = cx * dx + cy * dy;
            let perp2 = cx * cx + cy * cy - along * along;
            let r2 = self.geometry.radius_mm * self.geometry.radius_mm;
            if along > 0.0 && perp2 <= r2 {
                best = best.min((along - (r2 - perp2).sqrt()).max(0.0));
            }
        }
        if self.field.walls {
            let (x0, y0, x1, y1) = self.field.floor_bounds();
            for (edge, d) in [(x0, dx), (x1, dx)] {
                if d != 0.0 {
                    let t = (edge - ox) / d;
                    if t > 0.0 {
                        best = best.min(t);
                    }
                }
            }
            for (edge, d) in [(y0, dy), (y1, dy)] {
                if d != 0.0 {
                    let t = (edge - oy) / d;
                    if t > 0.0 {
                        best = best.min(t);
                    }
                }
            }
        }
        best
    }

    /// The eight proximity readings of robot `i`.
    fn proximity(&mut self, i: usize) -> [u16; 8] {
        let pose = self.robots[i].body.pose;
        let g = self.geometry;
        let mut out = [0u16; 8];
        for (k, deg) in g.proximity_deg.iter().enumerate() {
            let a = pose.theta - deg.to_radians();
            let (ox, oy) = (
                pose.x + g.radius_mm * a.cos(),
                pose.y + g.radius_mm * a.sin(),
            );
            let d = [-20.0f64, 0.0, 20.0]
                .iter()
                .map(|off| self.ray_distance(i, ox, oy, a + off.to_radians()))
                .fold(f64::INFINITY, f64::min);
            let v = proximity_value(d) + self.gauss(self.config.proximity_noise).abs();
            out[k] = v.round().clamp(0.0, 4095.0) as u16;
        }
        out
    }

    /// Renders robot `i`'s sensor image.
    pub fn sense(&mut self, i: usize) -> Sensors {
        let pose = self.robots[i].body.pose;
        let light = self.robots[i].lighting;
        let side = self.geometry.floor_side_mm;
        let floor = [
            self.floor_reading(&pose, -side, light),
            self.floor_reading(&pose, 0.0, light),
            self.floor_reading(&pose, side, light),
        ];
        Sensors {
            floor,
            proximity: self.proximity(i),
            steps: self.robots[i].body.steps,
        }
    }

    /// One 100 Hz control step of every robot; returns their events.
    pub fn step(&mut self) -> Vec<Logged> {
        let mut events = Vec::new();
        let mut outputs: Vec<Output> = Vec::with_capacity(self.robots.len());
        for i in 0..self.robots.len() {
            let s = self.sense(i);
            let r = &mut self.robots[i];
            r.sensors = s;
            outputs.push(r.robot.step(&s));
        }
        let g = self.geometry;
        for (i, out) in outputs.into_iter().enumerate() {
            let slip = [
                1.0 + self.gauss(self.config.slip),
                1.0 + self.gauss(self.config.slip),
            ];
            let r = &mut self.robots[i];
            r.body.drive(&g, out.wheels, DT, slip);
            if let Some(event) = out.event {
                events.push(Logged {
                    tick: self.tick,
                    robot: i,
                    event,
                    pose: r.body.pose,
                });
            }
        }
        self.count_contacts();
        self.tick += 1;
        events
    }

    fn count_contacts(&mut self) {
        let r = self.geometry.radius_mm;
        let n = self.robots.len();
        for a in 0..n {
            for b in a + 1..n {
                let (pa, pb) = (self.robots[a].body.pose, self.robots[b].body.pose);
                if (pa.x - pb.x).hypot(pa.y - pb.y) < 2.0 * r {
                    self.contacts += 1;
                }
            }
            if self.field.walls {
                let p = self.robots[a].body.pose;
                let (x0, y0, x1, y1) = self.field.floor_bounds();
                if p.x - r < x0 || p.y - r < y0 || p.x + r > x1 || p.y + r > y1 {
                    self.contacts += 1;
                }
            }
        }
    }

    /// Runs until robot `i` reports an event or `max_ticks` pass; returns
    /// the first event of robot `i` (events of others are dropped).
    pub fn run_until_event(&mut self, i: usize, max_ticks: u64) -> Option<Logged> {
        for _ in 0..max_ticks {
            if let Some(e) = self.step().into_iter().find(|e| e.robot == i) {
                return Some(e);
            }
        }
        None
    }

    /// Moves robot `i`'s body for one step with `wheels`, bypassing its
    /// behaviour stack (for experiments such as the relay tuning).
    pub fn drive_body(&mut self, i: usize, wheels: core_algo::control::Wheels) {
        let slip = [
            1.0 + self.gauss(self.config.slip),
            1.0 + self.gauss(self.config.slip),
        ];
        let g = self.geometry;
        if let Some(r) = self.robots.get_mut(i) {
            r.body.drive(&g, wheels, DT, slip);
        }
        self.tick += 1;
    }

    /// Sets robot `i`'s step counters (to start it mid-edge with a known
    /// odometry).
    pub fn set_steps(&mut self, i: usize, steps: StepCount) {
        if let Some(r) = self.robots.get_mut(i) {
            r.body.steps = steps;
        }
    }

    /// The signed distance (mm) of a point from the centre line of the line
    /// it should be on, for a robot travelling along `theta`: the offset
    /// across the nearest grid line parallel to the travel.
    pub fn lateral_offset(&self, x: f64, y: f64, theta: f64) -> f64 {
        let s = self.field.spacing_mm;
        let east_west = theta.cos().abs() > theta.sin().abs();
        if east_west {
            y - (y / s).round() * s
        } else {
            x - (x / s).round() * s
        }
    }
}

/// The pose angle of a compass heading.
pub fn heading_theta(h: core_algo::geometry::Heading) -> f64 {
    use core_algo::geometry::Heading;
    match h {
        Heading::East => 0.0,
        Heading::North => std::f64::consts::FRAC_PI_2,
        Heading::West => std::f64::consts::PI,
        Heading::South => -std::f64::consts::FRAC_PI_2,
    }
}

/// The lattice heading nearest to `theta`.
pub fn nearest_heading(theta: f64) -> core_algo::geometry::Heading {
    use core_algo::geometry::Heading;
    let q = (theta / std::f64::consts::FRAC_PI_2).round() as i64;
    match q.rem_euclid(4) {
        0 => Heading::East,
        1 => Heading::North,
        2 => Heading::West,
        _ => Heading::South,
    }
}

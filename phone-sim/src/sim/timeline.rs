//! A run as a timeline, for reading where it loses time or stalls: one
//! line whenever a robot's body reaches a node or its agent changes mode,
//! target or retreat. Used by the `timeline` and `homecoming_hunt`
//! examples.

use super::Simulation;

/// What each robot showed last, so that only changes are printed.
pub struct Timeline {
    last: Vec<Option<String>>,
}

impl Timeline {
    /// A timeline for `sim`'s robots, nothing printed yet.
    pub fn new(sim: &Simulation) -> Self {
        Timeline {
            last: vec![None; sim.bodies().bodies().len()],
        }
    }

    /// Prints a line (time, robot, node, heading, mode, target, standing,
    /// retreat) for every robot whose state changed since the last call.
    pub fn print_changes(&mut self, sim: &Simulation) {
        let robots = sim.bodies().bodies().iter().zip(sim.firmware());
        for (i, ((b, f), last)) in robots.zip(self.last.iter_mut()).enumerate() {
            let a = f.agent();
            let line = format!(
                "({:>2},{:>2}) {:?} {:?} target {:?}{}{}",
                b.pos.x,
                b.pos.y,
                b.heading,
                a.mode(),
                a.target().map(|p| (p.x, p.y)),
                if b.is_idle() { " standing" } else { "" },
                a.retreating()
                    .map(|(p, id)| format!(" retreat to ({},{}) for r{}", p.x, p.y, id.0))
                    .unwrap_or_default()
            );
            if last.as_deref() != Some(line.as_str()) {
                println!("{:>9.2} r{i} {line}", f64::from(sim.now()) / 1000.0);
                *last = Some(line);
            }
        }
    }
}

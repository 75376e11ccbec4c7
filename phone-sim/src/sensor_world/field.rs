//! The floor: black lines on white paper, drawn from a lattice of nodes.
//!
//! A small self-contained field type for the sensor-level simulator: every
//! node has a set of [`Arms`]; each arm is a straight strip of the line
//! width from the node's centre to the midpoint of the edge, or to the
//! floor's edge when the arm leaves the lattice. The floor extends a margin
//! beyond the outermost nodes; past it is the abyss (or a wall).

use core_algo::geometry::{Arms, Heading, Pos};

/// The rendered field, in millimetres; node (0, 0) sits at the origin, x
/// east, y north.
#[derive(Clone, Debug, PartialEq)]
pub struct LineField {
    width: i16,
    height: i16,
    arms: Vec<Arms>,
    /// Distance between neighbouring nodes, mm.
    pub spacing_mm: f64,
    /// Width of the black lines, mm.
    pub line_width_mm: f64,
    /// Floor beyond the outermost nodes, mm.
    pub margin_mm: f64,
    /// Whether a wall (seen by the proximity sensors) surrounds the floor
    /// instead of a drop.
    pub walls: bool,
}

impl LineField {
    /// An empty field of `width` × `height` nodes.
    pub fn new(width: i16, height: i16, spacing_mm: f64, line_width_mm: f64) -> LineField {
        let n = usize::try_from(i32::from(width.max(0)) * i32::from(height.max(0))).unwrap_or(0);
        LineField {
            width,
            height,
            arms: vec![Arms::NONE; n],
            spacing_mm,
            line_width_mm,
            margin_mm: spacing_mm / 2.0,
            walls: false,
        }
    }

    /// A full lattice: every pair of neighbours connected.
    pub fn lattice(width: i16, height: i16, spacing_mm: f64, line_width_mm: f64) -> LineField {
        let mut f = LineField::new(width, height, spacing_mm, line_width_mm);
        for x in 0..width {
            for y in 0..height {
                let p = Pos::new(x, y);
                f.connect(p, Heading::East);
                f.connect(p, Heading::North);
            }
        }
        f
    }

    /// Nodes east–west.
    pub fn width(&self) -> i16 {
        self.width
    }

    /// Nodes south–north.
    pub fn height(&self) -> i16 {
        self.height
    }

    fn index(&self, p: Pos) -> Option<usize> {
        if p.x < 0 || p.y < 0 || p.x >= self.width || p.y >= self.height {
            return None;
        }
        usize::try_from(i32::from(p.y) * i32::from(self.width) + i32::from(p.x)).ok()
    }

    /// Whether `p` is a node of the field.
    pub fn contains(&self, p: Pos) -> bool {
        self.index(p).is_some()
    }

    /// The arms of `p` (none outside the field).
    pub fn arms(&self, p: Pos) -> Arms {
        self.index(p)
            .and_then(|i| self.arms.get(i))
            .copied()
            .unwrap_or(Arms::NONE)
    }

    /// Sets the arms of one node only (a line may then end half-way).
    pub fn set_arms(&mut self, p: Pos, arms: Arms) {
        if let Some(slot) = self.index(p).and_then(|i| self.arms.get_mut(i)) {
            *slot = arms;
        }
    }

    /// Draws the line from `p` towards `h`, with the matching arm at the
    /// neighbour when it is on the field (else the line runs to the floor's
    /// edge).
    pub fn connect(&mut self, p: Pos, h: Heading) {
        let Some(q) = p.step(h) else { return };
        if !self.contains(p) || !self.contains(q) {
            return;
        }
        self.set_arms(p, self.arms(p).with(h));
        self.set_arms(q, self.arms(q).with(h.opposite()));
    }

    /// Adds an arm from `p` that leaves the lattice towards the floor edge.
    pub fn add_outward_arm(&mut self, p: Pos, h: Heading) {
        self.set_arms(p, self.arms(p).with(h));
    }

    /// The centre of node `p`, mm.
    pub fn node_mm(&self, p: Pos) -> (f64, f64) {
        (
            f64::from(p.x) * self.spacing_mm,
            f64::from(p.y) * self.spacing_mm,
        )
    }

    /// The floor's extent: (min x, min y, max x, max y), mm.
    pub fn floor_bounds(&self) -> (f64, f64, f64, f64) {
        let m = self.margin_mm;
        (
            -m,
            -m,
            f64::from(self.width - 1) * self.spacing_mm + m,
            f64::from(self.height - 1) * self.spacing_mm + m,
        )
    }

    /// Whether (x, y) is on the floor.
    pub fn on_floor(&self, x: f64, y: f64) -> bool {
        let (x0, y0, x1, y1) = self.floor_bounds();
        x >= x0 && x <= x1 && y >= y0 && y <= y1
    }

    /// The node nearest to (x, y), clamped to the field.
    pub fn nearest_node(&self, x: f64, y: f64) -> Pos {
        let s = self.spacing_mm;
        let cx = ((x / s).round() as i64).clamp(0, i64::from(self.width - 1).max(0));
        let cy = ((y / s).round() as i64).clamp(0, i64::from(self.height - 1).max(0));
        Pos::new(cx as i16, cy as i16)
    }

    /// Whether (x, y) lies on a black line (and on the floor).
    pub fn is_black(&self, x: f64, y: f64) -> bool {
        if !self.on_floor(x, y) {
            return false;
        }
        let p = self.nearest_node(x, y);
        let arms = self.arms(p);
        if arms == Arms::NONE {
            return false;
        }
        let (nx, ny) = self.node_mm(p);
        let (dx, dy) = (x - nx, y - ny);
        let hw = self.line_width_mm / 2.0;
        if dx.abs() <= hw && dy.abs() <= hw {
            return true;
        }
        let reach = |h: Heading| {
            if p.step(h).is_some_and(|q| self.contains(q)) {
                self.spacing_mm / 2.0 + 1e-9
            } else {
                f64::INFINITY
            }
        };
        (arms.has(Heading::East) && dy.abs() <= hw && dx >= 0.0 && dx <= reach(Heading::East))
            || (arms.has(Heading::West)
                && dy.abs() <= hw
                && dx <= 0.0
                && -dx <= reach(Heading::West))
            || (arms.has(Heading::North)
                && dx.abs() <= hw
                && dy >= 0.0
                && dy <= reach(Heading::North))
            || (arms.has(Heading::South)
                && dx.abs() <= hw
                && dy <= 0.0
                && -dy <= reach(Heading::South))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_draws_lines_and_a_floor_edge() {
        let f = LineField::lattice(3, 3, 100.0, 12.0);
        assert_eq!(f.arms(Pos::new(1, 1)), Arms::CROSS);
        assert_eq!(f.arms(Pos::new(0, 0)).bits(), 0b0011);
        assert!(f.is_black(50.0, 3.0));
        assert!(!f.is_black(50.0, 7.0));
        assert!(!f.is_black(50.0, 50.0));
        assert!(f.is_black(-5.0, 0.0)); // the centre square
        assert!(!f.is_black(-10.0, 0.0));
        assert!(!f.on_floor(-60.0, 0.0));
        let mut g = LineField::new(2, 1, 100.0, 12.0);
        g.add_outward_arm(Pos::new(1, 0), Heading::East);
        assert!(g.is_black(140.0, 0.0));
        assert!(!g.is_black(160.0, 0.0)); // off the floor
    }
}

//! Positions, headings, turns and node shapes in the one frame of the project.
//!
//! x grows east, y grows north. A node's shape is the set of its arms, a 4-bit
//! mask in that frame ([`Arms`]). Every importer converts into this frame at
//! the edge; the 2010 names live in [`legacy`] so that they are used only
//! where 2010 data is read or written.

use core::fmt;

/// A lattice node, in node units (one unit = one edge of the field).
///
/// `i16` covers fields of up to 32 767 nodes a side, far beyond any floor,
/// and keeps a position at four bytes for the robot's RAM.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Pos {
    /// East coordinate.
    pub x: i16,
    /// North coordinate.
    pub y: i16,
}

impl Pos {
    /// The node at (`x`, `y`).
    pub const fn new(x: i16, y: i16) -> Self {
        Pos { x, y }
    }

    /// The neighbour one edge away in direction `h`, or `None` where the
    /// coordinate would leave the `i16` range.
    pub fn step(self, h: Heading) -> Option<Pos> {
        let (dx, dy) = h.delta();
        Some(Pos {
            x: self.x.checked_add(dx)?,
            y: self.y.checked_add(dy)?,
        })
    }

    /// Manhattan distance |dx| + |dy|, the seed's neighbourhood norm.
    pub fn manhattan(self, other: Pos) -> u32 {
        let dx = (i32::from(self.x) - i32::from(other.x)).unsigned_abs();
        let dy = (i32::from(self.y) - i32::from(other.y)).unsigned_abs();
        dx + dy
    }
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", self.x, self.y)
    }
}

/// A compass heading on the lattice. The discriminant is the number of
/// clockwise quarter turns from north, so turning is modular arithmetic.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[repr(u8)]
pub enum Heading {
    /// +y
    North = 0,
    /// +x
    East = 1,
    /// −y
    South = 2,
    /// −x
    West = 3,
}

impl Heading {
    /// All four headings in clockwise order from north.
    pub const ALL: [Heading; 4] = [Heading::North, Heading::East, Heading::South, Heading::West];

    /// The heading with `index` clockwise quarter turns from north (mod 4).
    pub const fn from_index(index: u8) -> Heading {
        match index & 3 {
            0 => Heading::North,
            1 => Heading::East,
            2 => Heading::South,
            _ => Heading::West,
        }
    }

    /// Clockwise quarter turns from north, 0..=3.
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The unit step (dx, dy) of this heading.
    pub const fn delta(self) -> (i16, i16) {
        match self {
            Heading::North => (0, 1),
            Heading::East => (1, 0),
            Heading::South => (0, -1),
            Heading::West => (-1, 0),
        }
    }

    /// The heading after `turn`.
    pub const fn turned(self, turn: Turn) -> Heading {
        Heading::from_index(self.index() + turn.quarter_turns())
    }

    /// The opposite heading.
    pub const fn opposite(self) -> Heading {
        Heading::from_index(self.index() + 2)
    }

    /// The turn that takes this heading to `target`; `None` when they are
    /// equal (drive straight on).
    pub const fn turn_to(self, target: Heading) -> Option<Turn> {
        match (target.index() + 4 - self.index()) & 3 {
            0 => None,
            1 => Some(Turn::Right),
            2 => Some(Turn::UTurn),
            _ => Some(Turn::Left),
        }
    }

    /// The single-arm mask pointing this way.
    pub const fn arm(self) -> Arms {
        Arms(1 << self.index())
    }

    /// One-letter name: N, E, S or W.
    pub const fn letter(self) -> char {
        match self {
            Heading::North => 'N',
            Heading::East => 'E',
            Heading::South => 'S',
            Heading::West => 'W',
        }
    }

    /// Parses N, E, S or W (either case).
    pub const fn from_letter(c: char) -> Option<Heading> {
        match c {
            'N' | 'n' => Some(Heading::North),
            'E' | 'e' => Some(Heading::East),
            'S' | 's' => Some(Heading::South),
            'W' | 'w' => Some(Heading::West),
            _ => None,
        }
    }
}

impl fmt::Display for Heading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// A turn on the spot, as the robot performs it on a node.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Turn {
    /// 90° counter-clockwise.
    Left,
    /// 90° clockwise.
    Right,
    /// 180°.
    UTurn,
}

impl Turn {
    /// Clockwise quarter turns, 1..=3.
    pub const fn quarter_turns(self) -> u8 {
        match self {
            Turn::Right => 1,
            Turn::UTurn => 2,
            Turn::Left => 3,
        }
    }

    /// The 2010 wire value: −1 left, +1 right, 2 U-turn.
    pub const fn legacy_code(self) -> i8 {
        match self {
            Turn::Left => -1,
            Turn::Right => 1,
            Turn::UTurn => 2,
        }
    }
}

/// The arms of a node: a 4-bit set, bit `h.index()` for heading `h`.
///
/// All 16 values are valid shapes, from no arm at all to the cross; see
/// [`NodeShape`] for their names. The invariant (high nibble zero) is kept by
/// every constructor.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Arms(u8);

impl Arms {
    /// No arm.
    pub const NONE: Arms = Arms(0);
    /// All four arms.
    pub const CROSS: Arms = Arms(0b1111);

    /// The set from its low four bits (N = bit 0, E = 1, S = 2, W = 3); higher
    /// bits are ignored.
    pub const fn from_bits(bits: u8) -> Arms {
        Arms(bits & 0b1111)
    }

    /// The 4-bit mask.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// Whether there is an arm towards `h`.
    pub const fn has(self, h: Heading) -> bool {
        self.0 & (1 << h.index()) != 0
    }

    /// This set with the arm towards `h` added.
    pub const fn with(self, h: Heading) -> Arms {
        Arms(self.0 | (1 << h.index()))
    }

    /// This set with the arm towards `h` removed.
    pub const fn without(self, h: Heading) -> Arms {
        Arms(self.0 & !(1 << h.index()))
    }

    /// Number of arms, 0..=4.
    pub const fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// The headings present, in clockwise order from north.
    pub fn iter(self) -> impl Iterator<Item = Heading> {
        Heading::ALL.into_iter().filter(move |h| self.has(*h))
    }

    /// The set turned clockwise by `quarter_turns` × 90°.
    pub const fn rotated_cw(self, quarter_turns: u8) -> Arms {
        let q = quarter_turns & 3;
        let wide = (self.0 as u16) << q;
        Arms(((wide | (wide >> 4)) & 0b1111) as u8)
    }

    /// Converts arms given relative to a robot facing `heading` (bit 0 =
    /// ahead, 1 = right, 2 = behind, 3 = left) into the global frame.
    pub const fn from_relative(relative: Arms, heading: Heading) -> Arms {
        relative.rotated_cw(heading.index())
    }

    /// The inverse of [`Arms::from_relative`].
    pub const fn to_relative(self, heading: Heading) -> Arms {
        self.rotated_cw(4 - heading.index())
    }

    /// The shape's name, independent of orientation.
    pub const fn shape(self) -> NodeShape {
        match self.0.count_ones() {
            0 => NodeShape::Empty,
            1 => NodeShape::DeadEnd,
            2 => {
                if self.0 == 0b0101 || self.0 == 0b1010 {
                    NodeShape::Straight
                } else {
                    NodeShape::Corner
                }
            }
            3 => NodeShape::Tee,
            _ => NodeShape::Cross,
        }
    }
}

impl fmt::Debug for Arms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Arms({self})")
    }
}

/// Formats as the letters of the present arms in N, E, S, W order (`NESW`
/// for a cross), or `-` for no arm. This is the native field format's token.
impl fmt::Display for Arms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0 == 0 {
            return f.write_str("-");
        }
        for h in self.iter() {
            write!(f, "{}", h.letter())?;
        }
        Ok(())
    }
}

/// The orientation-free name of a node shape.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum NodeShape {
    /// No arm: an isolated point, or "no line here".
    Empty,
    /// One arm.
    DeadEnd,
    /// Two opposite arms.
    Straight,
    /// Two perpendicular arms.
    Corner,
    /// Three arms.
    Tee,
    /// Four arms.
    Cross,
}

/// The node names of the 2010 system, for import and export only.
///
/// The 2010 code drew its maps with y growing *down* the screen, and named
/// shapes by the screen: `TOPT` has arms left, right and up the screen, which
/// is north in our frame once y is negated. Only the nine shapes below exist
/// there; dead ends and straight pieces cannot be written in 2010 formats.
pub mod legacy {
    use super::Arms;

    /// ┘ arms north (screen top) and west.
    pub const TOPLEFTEDGE: Arms = Arms::from_bits(0b1001);
    /// └ arms north and east.
    pub const TOPRIGHTEDGE: Arms = Arms::from_bits(0b0011);
    /// ┐ arms south and west.
    pub const BOTTOMLEFTEDGE: Arms = Arms::from_bits(0b1100);
    /// ┌ arms south and east.
    pub const BOTTOMRIGHTEDGE: Arms = Arms::from_bits(0b0110);
    /// ┴ arms west, east and north.
    pub const TOPT: Arms = Arms::from_bits(0b1011);
    /// ┬ arms west, east and south.
    pub const BOTTOMT: Arms = Arms::from_bits(0b1110);
    /// ┤ arms north, south and west.
    pub const LEFTT: Arms = Arms::from_bits(0b1101);
    /// ├ arms north, south and east.
    pub const RIGHTT: Arms = Arms::from_bits(0b0111);
    /// ┼ all four arms.
    pub const CROSS: Arms = Arms::CROSS;

    /// The nine 2010 names with their arms, in the order of the 2010
    /// `NodeType` enum's use on the wire (see the legacy protocol).
    pub const NAMES: [(&str, Arms); 9] = [
        ("TOPLEFTEDGE", TOPLEFTEDGE),
        ("TOPRIGHTEDGE", TOPRIGHTEDGE),
        ("BOTTOMLEFTEDGE", BOTTOMLEFTEDGE),
        ("BOTTOMRIGHTEDGE", BOTTOMRIGHTEDGE),
        ("TOPT", TOPT),
        ("RIGHTT", RIGHTT),
        ("BOTTOMT", BOTTOMT),
        ("LEFTT", LEFTT),
        ("CROSS", CROSS),
    ];

    /// The arms for a 2010 name (exact, upper case).
    pub fn from_name(name: &str) -> Option<Arms> {
        NAMES.iter().find(|(n, _)| *n == name).map(|(_, a)| *a)
    }

    /// The 2010 name of a shape, if the 2010 system had one.
    pub fn name(arms: Arms) -> Option<&'static str> {
        NAMES.iter().find(|(_, a)| *a == arms).map(|(n, _)| *n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    #[test]
    fn turning_is_modular() {
        for h in Heading::ALL {
            assert_eq!(h.turned(Turn::Right).turned(Turn::Left), h);
            assert_eq!(h.turned(Turn::UTurn), h.opposite());
            for t in Heading::ALL {
                match h.turn_to(t) {
                    None => assert_eq!(h, t),
                    Some(turn) => assert_eq!(h.turned(turn), t),
                }
            }
        }
        assert_eq!(Heading::North.turned(Turn::Right), Heading::East);
        assert_eq!(Heading::North.turned(Turn::Left), Heading::West);
    }

    #[test]
    fn deltas_match_frame() {
        let p = Pos::new(0, 0);
        assert_eq!(p.step(Heading::North), Some(Pos::new(0, 1)));
        assert_eq!(p.step(Heading::East), Some(Pos::new(1, 0)));
        assert_eq!(Pos::new(i16::MAX, 0).step(Heading::East), None);
        assert_eq!(Pos::new(1, 2).manhattan(Pos::new(-2, 0)), 5);
    }

    #[test]
    fn all_sixteen_shapes_are_named() {
        let mut counts = [0usize; 6];
        for bits in 0..16u8 {
            let i = match Arms::from_bits(bits).shape() {
                NodeShape::Empty => 0,
                NodeShape::DeadEnd => 1,
                NodeShape::Straight => 2,
                NodeShape::Corner => 3,
                NodeShape::Tee => 4,
                NodeShape::Cross => 5,
            };
            counts[i] += 1;
        }
        assert_eq!(counts, [1, 4, 2, 4, 4, 1]);
    }

    #[test]
    fn rotation_and_relative_frames() {
        let north_east = Heading::North.arm().with(Heading::East);
        assert_eq!(
            north_east.rotated_cw(1),
            Heading::East.arm().with(Heading::South)
        );
        assert_eq!(north_east.rotated_cw(4), north_east);
        for bits in 0..16 {
            let a = Arms::from_bits(bits);
            for h in Heading::ALL {
                assert_eq!(Arms::from_relative(a.to_relative(h), h), a);
            }
        }
        // A robot facing east sees a global north arm on its left (bit 3).
        assert_eq!(
            Heading::North.arm().to_relative(Heading::East),
            Arms::from_bits(0b1000)
        );
    }

    #[test]
    fn legacy_names_round_trip_and_cover_nine_shapes() {
        for (name, arms) in legacy::NAMES {
            assert_eq!(legacy::from_name(name), Some(arms));
            assert_eq!(legacy::name(arms), Some(name));
            assert!(arms.count() >= 2);
        }
        assert_eq!(legacy::name(Heading::North.arm()), None);
        assert_eq!(legacy::TOPT.to_string(), "NEW");
    }

    #[test]
    fn display_letters() {
        assert_eq!(Arms::CROSS.to_string(), "NESW");
        assert_eq!(Arms::NONE.to_string(), "-");
    }
}

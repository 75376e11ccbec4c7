//! Seeded field generators: maze, rooms, random obstacles, open grid.
//!
//! Each takes the size in nodes and a seed and returns the same field for
//! the same arguments on every machine (ChaCha8 streams are stable across
//! platforms and rand versions). Starts: up to six, packed around the
//! south-west corner ([`super::default_starts`]).

use super::validate::keep_largest_part;
use super::{Field, default_starts};
use core_algo::geometry::{Arms, Heading, Pos};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;

/// The kinds of generated field.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Kind {
    /// A perfect maze: a random spanning tree of the lattice.
    Maze,
    /// Rooms of full grid joined by single doors (recursive division).
    Rooms,
    /// A full grid with a fifth of its nodes removed at random.
    Random,
    /// A full grid.
    Open,
}

impl Kind {
    /// All kinds, in the order of the benchmark.
    pub const ALL: [Kind; 4] = [Kind::Maze, Kind::Rooms, Kind::Random, Kind::Open];

    /// Lower-case name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Maze => "maze",
            Kind::Rooms => "rooms",
            Kind::Random => "random",
            Kind::Open => "open",
        }
    }

    /// Generates a field of this kind.
    pub fn generate(self, width: u16, height: u16, seed: u64) -> Field {
        match self {
            Kind::Maze => maze(width, height, seed),
            Kind::Rooms => rooms(width, height, seed),
            Kind::Random => random(width, height, seed),
            Kind::Open => open(width, height, seed),
        }
    }
}

impl std::str::FromStr for Kind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Kind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("expected maze, rooms, random or open, found '{s}'"))
    }
}

/// Sides are clamped to 1..=4096 nodes.
fn clamp(width: u16, height: u16) -> (i16, i16) {
    (width.clamp(1, 4096) as i16, height.clamp(1, 4096) as i16)
}

fn finish(kind: Kind, width: u16, height: u16, seed: u64, mut nodes: BTreeMap<Pos, Arms>) -> Field {
    keep_largest_part(&mut nodes);
    if nodes.is_empty() {
        nodes.insert(Pos::new(0, 0), Arms::NONE);
    }
    let starts = default_starts(&nodes, 6);
    let name = format!("{}-{width}x{height}-s{seed}", kind.name());
    // Generated nodes are reciprocal and connected by construction.
    Field::new(name, nodes, starts)
        .unwrap_or_else(|e| unreachable!("generator produced an invalid field: {e}"))
}

/// Adds the edge from `a` towards `h` to both of its ends.
pub(crate) fn link(nodes: &mut BTreeMap<Pos, Arms>, a: Pos, h: Heading) {
    if let Some(b) = a.step(h) {
        let e = nodes.entry(a).or_default();
        *e = e.with(h);
        let e = nodes.entry(b).or_default();
        *e = e.with(h.opposite());
    }
}

fn unlink(nodes: &mut BTreeMap<Pos, Arms>, a: Pos, h: Heading) {
    if let Some(b) = a.step(h) {
        if let Some(e) = nodes.get_mut(&a) {
            *e = e.without(h);
        }
        if let Some(e) = nodes.get_mut(&b) {
            *e = e.without(h.opposite());
        }
    }
}

fn full_grid(w: i16, h: i16) -> BTreeMap<Pos, Arms> {
    let mut nodes = BTreeMap::new();
    for y in 0..h {
        for x in 0..w {
            let p = Pos::new(x, y);
            nodes.entry(p).or_insert(Arms::NONE);
            if x + 1 < w {
                link(&mut nodes, p, Heading::East);
            }
            if y + 1 < h {
                link(&mut nodes, p, Heading::North);
            }
        }
    }
    nodes
}

/// A full grid of `width` × `height` nodes. The seed is unused but kept so
/// that every generator has one signature.
pub fn open(width: u16, height: u16, seed: u64) -> Field {
    let (w, h) = clamp(width, height);
    finish(Kind::Open, width, height, seed, full_grid(w, h))
}

/// A perfect maze (randomised depth-first spanning tree): one path between
/// any two nodes, many dead ends.
pub fn maze(width: u16, height: u16, seed: u64) -> Field {
    let (w, h) = clamp(width, height);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut nodes = BTreeMap::new();
    let inside = |p: Pos| p.x >= 0 && p.y >= 0 && p.x < w && p.y < h;
    let mut seen = std::collections::HashSet::new();
    let start = Pos::new(0, 0);
    nodes.insert(start, Arms::NONE);
    seen.insert(start);
    let mut stack = vec![start];
    while let Some(&p) = stack.last() {
        let mut dirs = Heading::ALL;
        dirs.shuffle(&mut rng);
        let next = dirs
            .into_iter()
            .filter_map(|d| p.step(d).map(|q| (d, q)))
            .find(|(_, q)| inside(*q) && !seen.contains(q));
        match next {
            Some((d, q)) => {
                link(&mut nodes, p, d);
                seen.insert(q);
                stack.push(q);
            }
            None => {
                stack.pop();
            }
        }
    }
    finish(Kind::Maze, width, height, seed, nodes)
}

/// Rooms of full grid separated by walls with one door each (recursive
/// division until rooms are at most about 8 nodes a side).
pub fn rooms(width: u16, height: u16, seed: u64) -> Field {
    let (w, h) = clamp(width, height);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut nodes = full_grid(w, h);
    let mut regions = vec![(0i16, 0i16, w, h)];
    while let Some((x0, y0, rw, rh)) = regions.pop() {
        let split_x = rw > 8 && (rw >= rh || rh <= 8);
        let split_y = rh > 8 && !split_x;
        if split_x {
            // Cut between columns c and c + 1, leaving one door.
            let c = x0 + rng.random_range(3..rw - 4);
            let door = y0 + rng.random_range(0..rh);
            for y in y0..y0 + rh {
                if y != door {
                    unlink(&mut nodes, Pos::new(c, y), Heading::East);
                }
            }
            regions.push((x0, y0, c - x0 + 1, rh));
            regions.push((c + 1, y0, x0 + rw - c - 1, rh));
        } else if split_y {
            let r = y0 + rng.random_range(3..rh - 4);
            let door = x0 + rng.random_range(0..rw);
            for x in x0..x0 + rw {
                if x != door {
                    unlink(&mut nodes, Pos::new(x, r), Heading::North);
                }
            }
            regions.push((x0, y0, rw, r - y0 + 1));
            regions.push((x0, r + 1, rw, y0 + rh - r - 1));
        }
    }
    finish(Kind::Rooms, width, height, seed, nodes)
}

/// A full grid with about 20 % of its nodes removed at random; the largest
/// connected part is kept.
pub fn random(width: u16, height: u16, seed: u64) -> Field {
    let (w, h) = clamp(width, height);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut nodes = full_grid(w, h);
    let all: Vec<Pos> = nodes.keys().copied().collect();
    for p in all {
        if rng.random_bool(0.2) {
            for d in Heading::ALL {
                unlink(&mut nodes, p, d);
            }
            nodes.remove(&p);
        }
    }
    finish(Kind::Random, width, height, seed, nodes)
}

//! Small seeded random fields for tests and quick runs, independent of the
//! field loader: a random spanning tree of a `w` × `h` lattice plus a share
//! of extra edges, so every field is connected.

use super::Truth;
use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::map::Bounds;
use core_algo::path::neighbour_index;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A connected random field of `w` × `h` nodes: a random spanning tree
/// (randomised depth-first search) plus each remaining lattice edge with
/// probability `extra_percent` %. Starts: up to `robots` nodes along the
/// south row from the west, heading north.
pub fn random_field(
    w: u16,
    h: u16,
    seed: u64,
    extra_percent: u32,
    robots: usize,
) -> (Truth, Vec<(Pos, Heading)>) {
    let bounds = Bounds::new(Pos::new(0, 0), w.max(1), h.max(1));
    let n = bounds.area();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut arms = vec![Arms::NONE; n];
    let mut seen = vec![false; n];
    let mut stack = vec![0usize];
    seen[0] = true;
    while let Some(&i) = stack.last() {
        let mut options = [Heading::North; 4];
        let mut m = 0;
        for hd in Heading::ALL {
            if let Some(j) = neighbour_index(bounds, i, hd) {
                if !seen[j] {
                    options[m] = hd;
                    m += 1;
                }
            }
        }
        if m == 0 {
            stack.pop();
            continue;
        }
        let hd = options[rng.random_range(0..m)];
        let j = neighbour_index(bounds, i, hd).unwrap_or(i);
        arms[i] = arms[i].with(hd);
        arms[j] = arms[j].with(hd.opposite());
        seen[j] = true;
        stack.push(j);
    }
    for i in 0..n {
        for hd in [Heading::North, Heading::East] {
            if let Some(j) = neighbour_index(bounds, i, hd) {
                if !arms[i].has(hd) && rng.random_range(0..100) < extra_percent {
                    arms[i] = arms[i].with(hd);
                    arms[j] = arms[j].with(hd.opposite());
                }
            }
        }
    }
    let truth = Truth::new((0..n).map(|i| (bounds.pos(i), arms[i])));
    let starts = (0..robots.min(usize::from(w.max(1))))
        .map(|x| (Pos::new(x as i16, 0), Heading::North))
        .collect();
    (truth, starts)
}

//! The order in which homes fill. Robots cannot pass each other, so a home
//! that can only be entered through other homes must fill before them: a
//! robot already at home would otherwise plug the only way in for good.
//! The order is built backwards: the home that fills last is one still
//! reachable from the open field with every other home taken; among those,
//! the shallowest. This finds a working order whenever one exists (taking
//! a home out of a working order leaves the rest working), and every robot
//! computes the same one from the complete map and the homes.

use super::*;

/// A home opens onto the field when it reaches this many free nodes (or
/// more than half of all free nodes) without passing another home: a
/// pocket closed in by homes is smaller. Bounds the search, and its
/// memory, on large fields.
const OPEN_REGION: usize = 64;

/// Fill ranks for `homes` (robot, home, depth: the home's total distance
/// to every node, larger for dead ends): a larger rank fills first, ranks
/// are distinct, and robots not listed get 0.
pub(super) fn fill_ranks<M>(map: &KnownMap<M>, homes: &[(usize, Pos, u64)]) -> [u64; MAX_ROBOTS]
where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let mut ranks = [0; MAX_ROBOTS];
    let mut left: Vec<(usize, Pos, u64), MAX_ROBOTS> = homes.iter().copied().collect();
    let free = map.known_len().saturating_sub(homes.len());
    let mut rank = 1;
    while !left.is_empty() {
        // The home that fills last among those left: open with the others
        // taken, then the shallowest, then the highest id (the order the
        // depth alone gave before, wherever the field allows it).
        let last = left
            .iter()
            .enumerate()
            .min_by_key(|&(_, &(i, home, depth))| {
                let taken = |p: Pos| left.iter().any(|&(j, h, _)| j != i && h == p);
                (
                    !opens_onto_field(map, home, taken, free),
                    depth,
                    core::cmp::Reverse(i),
                )
            })
            .map(|(k, &(i, _, _))| (k, i));
        let Some((k, i)) = last else { break };
        if let Some(r) = ranks.get_mut(i) {
            *r = rank;
        }
        rank += 1;
        left.swap_remove(k);
    }
    ranks
}

/// Whether `home` reaches the open field (see [`OPEN_REGION`]) over known
/// arms without entering a `taken` node; `free` is the number of nodes
/// that are nobody's home.
fn opens_onto_field<M>(
    map: &KnownMap<M>,
    home: Pos,
    taken: impl Fn(Pos) -> bool,
    free: usize,
) -> bool
where
    M: AsRef<[Block]> + AsMut<[Block]>,
{
    let enough = (free / 2 + 1).min(OPEN_REGION);
    // Breadth first, the queue doubling as the set of nodes seen: small
    // enough that a linear `contains` is cheaper than a hash set.
    let mut seen: Vec<Pos, { OPEN_REGION + 1 }> = Vec::new();
    if seen.push(home).is_err() {
        return false;
    }
    let mut next = 0;
    while let Some(&p) = seen.get(next) {
        next += 1;
        let Some(arms) = map.known_arms(p) else {
            continue;
        };
        for h in Heading::ALL {
            let Some(q) = p.step(h).filter(|_| arms.has(h)) else {
                continue;
            };
            if taken(q) || seen.contains(&q) {
                continue;
            }
            if seen.push(q).is_err() || seen.len() > enough {
                return true;
            }
        }
    }
    false
}

/// The fill order as an agent knows it.
impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Whether team mate `i`'s home fills before ours: known only once the
    /// map is complete and the depths are computed.
    pub(super) fn goes_first(&self, i: usize) -> bool {
        self.depth_known && self.first_by(&self.depth, i)
    }

    /// Whether team mate `i`'s home fills before ours by the fill ranks
    /// `depth`, on the complete map.
    pub(super) fn first_by(&self, depth: &[u64; MAX_ROBOTS], i: usize) -> bool {
        let me = self.id.index();
        let (Some(&theirs), Some(&mine)) = (depth.get(i), depth.get(me)) else {
            return false;
        };
        self.map.is_complete()
            && i != me
            && (theirs, core::cmp::Reverse(i)) > (mine, core::cmp::Reverse(me))
    }

    /// Computes the order in which homes fill (`depth`, see the module docs)
    /// once the map is complete: every robot gets the same.
    pub(super) fn know_fill_order(&mut self) {
        if self.depth_known || !self.map.is_complete() {
            return;
        }
        self.depth_known = true;
        self.fill_ranks_once();
    }

    /// The fill ranks in `depth`, computed the first time they are asked
    /// for (on the complete map, which no longer changes): a yield wait
    /// asks at every tick, and each computation searches the map once per
    /// home.
    pub(super) fn fill_ranks_once(&mut self) -> [u64; MAX_ROBOTS] {
        if !self.depth_ready {
            self.depth = self.fill_ranks();
            self.depth_ready = true;
        }
        self.depth
    }

    /// The fill ranks of every robot's home on the complete map (see
    /// [`fill_ranks`]); all zero without a planner field.
    fn fill_ranks(&mut self) -> [u64; MAX_ROBOTS] {
        let me = self.id.index();
        let (map, timing, shared) = (&self.map, self.config.timing, self.shared);
        let Some(field) = self.fields.first_mut() else {
            return [0; MAX_ROBOTS];
        };
        let homes = core::iter::once((me, self.home)).chain(
            self.peers
                .iter()
                .enumerate()
                .filter(|(i, p)| *i != me && p.known)
                .map(|(i, p)| (i, p.home)),
        );
        // A home's depth: its total distance to every node (a dead end
        // scores high, a junction low).
        let mut depths: Vec<(usize, Pos, u64), MAX_ROBOTS> = Vec::new();
        let homes: Vec<(usize, Pos), MAX_ROBOTS> = homes.collect();
        let last = homes.len().saturating_sub(1);
        for (n, &(i, home)) in homes.iter().enumerate() {
            // Worked out once per team where a host runs the whole team;
            // but the last home is always searched, so that the field ends
            // holding what it always did (later decisions read ways from
            // whatever field holds one, see `round_settled_mates`).
            let kept = shared
                .filter(|_| n < last)
                .and_then(|s| s.home_depth(map, timing, home));
            let depth = kept.unwrap_or_else(|| {
                let mut sum: u64 = 0;
                let ok = field
                    .compute(map, timing, home, Heading::North, |_, d| {
                        sum = sum.saturating_add(u64::from(d));
                        Flow::Continue
                    })
                    .is_ok();
                if let (true, Some(s)) = (ok, shared) {
                    s.keep_home_depth(map, timing, home, sum);
                }
                if ok { sum } else { 0 }
            });
            let _ = depths.push((i, home, depth));
        }
        // Depth orders the homes where the field leaves a choice; a home
        // entered only through others fills before them.
        fill_ranks(map, &depths)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::Bounds;

    /// A map from rows of arm strings, `y` growing upwards (row 0 is the
    /// top line of `rows`).
    fn map(rows: &[&[&str]]) -> KnownMap<[Block; 4]> {
        let h = rows.len() as i16;
        let w = rows.first().map_or(0, |r| r.len()) as i16;
        let mut m = KnownMap::new(
            [Block::EMPTY; 4],
            Bounds::new(Pos::new(0, 0), w as u16, h as u16),
        )
        .unwrap();
        for (r, row) in rows.iter().enumerate() {
            for (x, arms) in row.iter().enumerate() {
                let a = arms.chars().fold(Arms::NONE, |a, c| {
                    a.with(match c {
                        'N' => Heading::North,
                        'E' => Heading::East,
                        'S' => Heading::South,
                        _ => Heading::West,
                    })
                });
                m.visit(Pos::new(x as i16, h - 1 - r as i16), a, RobotId(0))
                    .unwrap();
            }
        }
        m
    }

    #[test]
    fn a_home_entered_only_through_other_homes_fills_first() {
        // A 3 × 3 grid: the corner (0, 0) is entered only through (0, 1)
        // and (1, 0). Its depth is the smallest, so depth alone would fill
        // it last, behind both, and it could never be entered.
        let m = map(&[
            &["ES", "ESW", "SW"],
            &["NES", "NESW", "NSW"],
            &["NE", "NEW", "NW"],
        ]);
        let homes = [
            (0, Pos::new(0, 0), 1),
            (1, Pos::new(0, 1), 5),
            (2, Pos::new(1, 0), 6),
        ];
        let ranks = fill_ranks(&m, &homes);
        assert!(ranks[0] > ranks[1] || ranks[0] > ranks[2], "{ranks:?}");
        // Depth still orders the two that are free to go either way.
        assert!(ranks[2] > ranks[1], "{ranks:?}");
    }

    #[test]
    fn without_constraints_the_deeper_home_fills_first() {
        let m = map(&[&["E", "EW", "EW", "W"]]);
        let homes = [(0, Pos::new(1, 0), 3), (1, Pos::new(2, 0), 4)];
        // Each opens onto a free end with the other taken: depth decides.
        let ranks = fill_ranks(&m, &homes);
        assert!(ranks[1] > ranks[0], "{ranks:?}");
        assert_eq!(ranks[5], 0);
    }

    #[test]
    fn a_corridor_of_homes_fills_from_its_dead_end() {
        // (0, 0) - (1, 0) - (2, 0) - (3, 0) - (4, 0): homes on the first
        // three, the dead end first whatever the depths say.
        let m = map(&[&["E", "EW", "EW", "EW", "W"]]);
        let homes = [
            (0, Pos::new(0, 0), 1),
            (1, Pos::new(1, 0), 2),
            (2, Pos::new(2, 0), 3),
        ];
        let ranks = fill_ranks(&m, &homes);
        assert!(ranks[0] > ranks[1] && ranks[1] > ranks[2], "{ranks:?}");
    }

    /// A connected random field of `w` × `h` nodes: a random spanning tree
    /// (from `tree`, one parent choice per node) plus the extra lattice
    /// edges that `extra` selects.
    fn random_map(w: u16, h: u16, tree: &[u8], extra: u64) -> KnownMap<[Block; 4]> {
        let n = usize::from(w) * usize::from(h);
        let mut arms = std::vec![Arms::NONE; n];
        let at = |x: u16, y: u16| usize::from(y) * usize::from(w) + usize::from(x);
        let join = |arms: &mut [Arms], a: (u16, u16), h: Heading| {
            let b = match h {
                Heading::East => (a.0 + 1, a.1),
                _ => (a.0, a.1 + 1),
            };
            arms[at(a.0, a.1)] = arms[at(a.0, a.1)].with(h);
            arms[at(b.0, b.1)] = arms[at(b.0, b.1)].with(h.opposite());
        };
        // Node k > 0 hangs on its west or south neighbour (whichever
        // exists; `tree` picks when both do): always connected.
        let mut bit = 0;
        for y in 0..h {
            for x in 0..w {
                let pick = tree.get(usize::from(y * w + x)).copied().unwrap_or(0) & 1;
                match (x > 0, y > 0) {
                    (true, true) if pick == 0 => join(&mut arms, (x - 1, y), Heading::East),
                    (true, true) => join(&mut arms, (x, y - 1), Heading::North),
                    (true, false) => join(&mut arms, (x - 1, y), Heading::East),
                    (false, true) => join(&mut arms, (x, y - 1), Heading::North),
                    (false, false) => {}
                }
                for (dx, dy, hd) in [(1, 0, Heading::East), (0, 1, Heading::North)] {
                    if x + dx < w && y + dy < h {
                        if extra >> (bit % 64) & 1 == 1 {
                            join(&mut arms, (x, y), hd);
                        }
                        bit += 1;
                    }
                }
            }
        }
        let mut m = KnownMap::new([Block::EMPTY; 4], Bounds::new(Pos::new(0, 0), w, h)).unwrap();
        for y in 0..h {
            for x in 0..w {
                m.visit(Pos::new(x as i16, y as i16), arms[at(x, y)], RobotId(0))
                    .unwrap();
            }
        }
        m
    }

    /// Whether filling `order` (first fills first) lets each home in:
    /// open to the field with the homes before it taken.
    fn works(m: &KnownMap<[Block; 4]>, order: &[Pos], free: usize) -> bool {
        order.iter().enumerate().all(|(k, &home)| {
            let before = &order[..k];
            opens_onto_field(m, home, |p| before.contains(&p), free)
        })
    }

    proptest::proptest! {
        /// The greedy backwards construction finds a working order whenever
        /// one exists (checked against every order of up to five homes).
        #[test]
        fn the_fill_order_works_whenever_some_order_does(
            w in 2u16..=6,
            h in 2u16..=6,
            tree in proptest::collection::vec(0u8..2, 36),
            extra in proptest::num::u64::ANY,
            picks in proptest::collection::vec((0u16..36, 0u64..1000), 2..=5),
        ) {
            let m = random_map(w, h, &tree, extra);
            let n = usize::from(w) * usize::from(h);
            let mut homes: std::vec::Vec<(usize, Pos, u64)> = std::vec::Vec::new();
            for (k, d) in picks {
                let v = usize::from(k) % n;
                let p = Pos::new((v % usize::from(w)) as i16, (v / usize::from(w)) as i16);
                if !homes.iter().any(|&(_, q, _)| q == p) {
                    homes.push((homes.len(), p, d));
                }
            }
            let free = m.known_len().saturating_sub(homes.len());
            let ranks = fill_ranks(&m, &homes);
            let mut ours: std::vec::Vec<(u64, Pos)> =
                homes.iter().map(|&(i, p, _)| (ranks[i], p)).collect();
            ours.sort_by_key(|b| core::cmp::Reverse(b.0));
            let ours: std::vec::Vec<Pos> = ours.into_iter().map(|(_, p)| p).collect();
            // Ranks are distinct and given to every home.
            for (k, &(i, _, _)) in homes.iter().enumerate() {
                proptest::prop_assert!(ranks[i] > 0);
                for &(j, _, _) in &homes[k + 1..] {
                    proptest::prop_assert_ne!(ranks[i], ranks[j]);
                }
            }
            // Some order works: then ours does.
            let mut all: std::vec::Vec<Pos> = homes.iter().map(|&(_, p, _)| p).collect();
            let some = permutations(&mut all, 0, &|o| works(&m, o, free));
            proptest::prop_assert_eq!(works(&m, &ours, free), some, "{:?}", ours);
        }
    }

    /// Whether any order of `items[k..]` (after `items[..k]`) satisfies `ok`.
    fn permutations(items: &mut [Pos], k: usize, ok: &dyn Fn(&[Pos]) -> bool) -> bool {
        if k == items.len() {
            return ok(items);
        }
        for i in k..items.len() {
            items.swap(k, i);
            let found = permutations(items, k + 1, ok);
            items.swap(k, i);
            if found {
                return true;
            }
        }
        false
    }
}

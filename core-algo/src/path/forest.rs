//! Travel times over a known graph that is a forest: see [`Forest`].

use super::scratch::PlanCell;
use super::{MAX_DIST, arms_at, neighbour_index, searchable};
use crate::geometry::Heading;
use crate::map::{Block, Bounds, KnownMap};
use crate::timing::{Ticks, Timing};

/// A node outside the forest (its arms unknown, or not added yet).
const OUT: u32 = u32::MAX;

/// The known graph as a rooted forest with jump pointers, so that the
/// travel time between two poses is read off in O(log n), without a
/// search.
///
/// ## Why
///
/// A perfect maze is a tree, and so is every part of it a team knows. With
/// 16 robots and a few dozen frontier nodes, each team decision searched
/// from every robot until its cheapest frontier nodes were proven, and in
/// a maze those lie far apart: most of a 16-robot maze run. On a tree the
/// way between two nodes is the one path through their lowest common
/// ancestor, and its time is the edges plus the turns along it, which
/// prefix sums from the root give (a turn costs the same either way
/// along a path). So every robot's time to every frontier node costs a
/// few dozen reads, the same times a search finds.
///
/// ## How
///
/// Each node in the forest keeps its parent, a jump pointer (Myers' skew
/// binary scheme: a level ancestor or lowest common ancestor in
/// O(log depth) steps, one pointer per node), its depth, and the quarter
/// turns from its root's child down to it. Nodes join as their arms
/// become known ([`KnownMap::passable_since`]): a node with one known
/// neighbour becomes its child; one that joins several trees becomes the
/// child of the largest, and the others are re-rooted under it (smaller
/// into larger, so no node is re-rooted more than log n times). A node
/// that would close a loop means the graph is no forest: then the forest
/// answers nothing until the map is cleared.
///
/// The forest keeps its nodes in planner cells, so that a host gives it
/// storage of the type it gives fields: parent, jump pointer and depth in
/// the three words, the turns in the four offset bytes (a root keeps its
/// tree's size there).
#[derive(Clone, Copy)]
pub struct Forest<S> {
    cells: S,
    bounds: Bounds,
    /// The map revision the forest holds for; `None`: build it anew.
    revision: Option<u32>,
    /// A loop was found: the graph is no forest.
    looped: bool,
}

/// Quarter turns from heading `a` to heading `b`: 0, 1 or 2, as a search
/// counts them.
fn turns(a: Heading, b: Heading) -> u32 {
    u32::from(Timing::quarter_turns_between(a.index(), b.index()))
}

impl<S> Forest<S> {
    /// A forest over `storage`, built at the first [`Forest::sync`].
    pub fn new(storage: S) -> Self {
        Forest {
            cells: storage,
            bounds: Bounds::new(crate::geometry::Pos::new(0, 0), 0, 0),
            revision: None,
            looped: false,
        }
    }
}

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> Forest<S> {
    /// Brings the forest up to `map` as it is now: the nodes that became
    /// passable since join it, or, when the map cannot tell which (too
    /// many at once, a new window, a cleared map), it is built anew.
    pub fn sync<M: AsRef<[Block]> + AsMut<[Block]>>(&mut self, map: &KnownMap<M>) {
        let now = map.revision();
        match self.revision {
            Some(r) if r == now && self.bounds == map.bounds() => return,
            Some(r) if self.bounds == map.bounds() => {
                if let Some(new) = map.passable_since(r) {
                    for i in new {
                        self.add(map, i);
                    }
                    self.revision = Some(now);
                    return;
                }
            }
            _ => {}
        }
        self.rebuild(map);
    }

    fn rebuild<M: AsRef<[Block]> + AsMut<[Block]>>(&mut self, map: &KnownMap<M>) {
        let bounds = map.bounds();
        let area = bounds.area();
        self.bounds = bounds;
        self.looped = false;
        self.revision = Some(map.revision());
        let cells = self.cells.as_mut();
        if cells.len() < area {
            // Too small a storage: answer nothing.
            self.looped = true;
            return;
        }
        if let Some(c) = cells.get_mut(..area) {
            for c in c {
                c.base = OUT;
            }
        }
        for i in 0..area {
            if arms_at(map, i).is_some() {
                self.add(map, i);
            }
        }
    }

    fn set_size(&mut self, r: usize, n: u32) {
        if let Some(c) = self.cells.as_mut().get_mut(r) {
            c.off = n.to_le_bytes();
        }
    }

    /// Makes `i` a root.
    fn set_root(&mut self, i: usize) {
        if let Some(c) = self.cells.as_mut().get_mut(i) {
            c.base = i as u32;
            c.ring_a = i as u32;
            c.ring_b = 0;
            c.off = 1u32.to_le_bytes();
        }
    }

    /// Makes `v` a child of `p` (which is in the forest).
    fn set_child(&mut self, v: usize, p: usize) {
        let pp = self.parent(p);
        let (jp, dp) = (self.jump(p), self.depth(p));
        let (djp, jjp) = (self.depth(jp), self.jump(jp));
        // Myers: jump as far as the parent's jump's jump where the two
        // jumps are as long, else to the parent.
        let jump = if dp.saturating_sub(djp) == djp.saturating_sub(self.depth(jjp)) {
            jjp
        } else {
            p
        };
        let turn = if pp == p {
            0
        } else {
            turns(self.dir(v, p), self.dir(p, pp))
        };
        let t = self.turns_to(p) + turn;
        if let Some(c) = self.cells.as_mut().get_mut(v) {
            c.base = p as u32;
            c.ring_a = jump as u32;
            c.ring_b = dp + 1;
            c.off = t.to_le_bytes();
        }
    }

    /// Node `i`, whose arms became known, joins the forest.
    fn add<M: AsRef<[Block]> + AsMut<[Block]>>(&mut self, map: &KnownMap<M>, i: usize) {
        if self.looped || self.is_member(i) || arms_at(map, i).is_none() {
            return;
        }
        // (neighbour, its root, its tree's size), at most one per arm.
        let mut trees = [(0usize, 0usize, 0u32); 4];
        let mut n = 0;
        let joined: heapless::Vec<usize, 4> = self.joined(map, i).map(|(_, j)| j).collect();
        for j in joined {
            let r = self.root(j);
            if trees.iter().take(n).any(|&(_, q, _)| q == r) {
                self.looped = true;
                return;
            }
            if let Some(t) = trees.get_mut(n) {
                *t = (j, r, self.size(r));
                n += 1;
            }
        }
        let Some(&(j, r, _)) = trees
            .iter()
            .take(n)
            .reduce(|a, b| if b.2 > a.2 { b } else { a })
        else {
            self.set_root(i);
            return;
        };
        self.set_child(i, j);
        let mut size = self.size(r) + 1;
        for &(k, q, s) in trees.iter().take(n) {
            if q != r {
                self.reroot(map, k, i);
                size += s;
            }
        }
        self.set_size(r, size);
    }

    /// Hangs the tree that holds `j` under `p`, re-rooted at `j`: a walk
    /// down from `j` that keeps no stack (it climbs back by the new
    /// parents, and goes on after the child it came from).
    fn reroot<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        j: usize,
        p: usize,
    ) {
        self.set_child(j, p);
        let (mut v, mut next) = (j, 0u8);
        loop {
            let parent = self.parent(v);
            let child = self
                .joined(map, v)
                .find(|&(h, w)| h.index() >= next && w != parent);
            match child {
                Some((_, w)) => {
                    self.set_child(w, v);
                    (v, next) = (w, 0);
                }
                None if v == j => return,
                None => {
                    next = self.dir(parent, v).index() + 1;
                    v = parent;
                }
            }
        }
    }
}

impl<S: AsRef<[PlanCell]>> Forest<S> {
    /// Whether the forest holds for `map` as it is now, and it is a forest.
    pub fn holds<M: AsRef<[Block]> + AsMut<[Block]>>(&self, map: &KnownMap<M>) -> bool {
        !self.looped && self.revision == Some(map.revision()) && self.bounds == map.bounds()
    }

    /// A read-only view of this forest, for a
    /// [`Context`](crate::explore::Context).
    pub fn view(&self) -> Forest<&[PlanCell]> {
        Forest {
            cells: self.cells.as_ref(),
            bounds: self.bounds,
            revision: self.revision,
            looped: self.looped,
        }
    }

    fn parent(&self, i: usize) -> usize {
        self.cells.as_ref().get(i).map_or(i, |c| c.base as usize)
    }

    fn jump(&self, i: usize) -> usize {
        self.cells.as_ref().get(i).map_or(i, |c| c.ring_a as usize)
    }

    fn depth(&self, i: usize) -> u32 {
        self.cells.as_ref().get(i).map_or(0, |c| c.ring_b)
    }

    /// The quarter turns from the root's child down to `i` (0 at a root,
    /// whose word holds its tree's size instead).
    fn turns_to(&self, i: usize) -> u32 {
        match self.cells.as_ref().get(i) {
            Some(c) if c.base as usize != i => u32::from_le_bytes(c.off),
            _ => 0,
        }
    }

    fn is_member(&self, i: usize) -> bool {
        self.cells.as_ref().get(i).is_some_and(|c| c.base != OUT)
    }

    /// The tree size kept at root `r`.
    fn size(&self, r: usize) -> u32 {
        self.cells
            .as_ref()
            .get(r)
            .map_or(0, |c| u32::from_le_bytes(c.off))
    }

    /// The heading from node `a` to its neighbour `b`.
    fn dir(&self, a: usize, b: usize) -> Heading {
        let w = usize::from(self.bounds.width);
        if b == a + w {
            Heading::North
        } else if b + w == a {
            Heading::South
        } else if b == a + 1 {
            Heading::East
        } else {
            Heading::West
        }
    }

    /// The ancestor of `v` at depth `d` (at most `v`'s own).
    fn ancestor(&self, mut v: usize, d: u32) -> usize {
        while self.depth(v) > d {
            let j = self.jump(v);
            v = if self.depth(j) >= d {
                j
            } else {
                self.parent(v)
            };
        }
        v
    }

    fn root(&self, v: usize) -> usize {
        self.ancestor(v, 0)
    }

    /// The lowest common ancestor of `a` and `b`, if they share a tree.
    fn meet(&self, a: usize, b: usize) -> Option<usize> {
        let d = self.depth(a).min(self.depth(b));
        let (mut a, mut b) = (self.ancestor(a, d), self.ancestor(b, d));
        while a != b {
            if self.parent(a) == a {
                // Both roots, and not the same: two trees.
                return None;
            }
            let (ja, jb) = (self.jump(a), self.jump(b));
            // Jumps from one depth land at one depth: where they differ,
            // the common ancestor lies above both.
            (a, b) = if ja != jb {
                (ja, jb)
            } else {
                (self.parent(a), self.parent(b))
            };
        }
        Some(a)
    }

    /// The neighbours of `i` in the forest that a known arm joins it to,
    /// as (heading from `i`, neighbour).
    fn joined<'a, M: AsRef<[Block]> + AsMut<[Block]>>(
        &'a self,
        map: &'a KnownMap<M>,
        i: usize,
    ) -> impl Iterator<Item = (Heading, usize)> + 'a {
        let arms = arms_at(map, i);
        let bounds = self.bounds;
        Heading::ALL.into_iter().filter_map(move |h| {
            let j = neighbour_index(bounds, i, h).filter(|_| arms.is_some_and(|a| a.has(h)))?;
            let back = arms_at(map, j).is_some_and(|a| a.has(h.opposite()));
            (back && self.is_member(j)).then_some((h, j))
        })
    }

    /// Edges, quarter turns and the heading on arrival from pose (`a`,
    /// `h0`) to node `b`, both in the forest; `None` in another tree.
    fn way(&self, from: (usize, Heading), b: usize) -> Option<(u32, u32, Heading)> {
        self.way_and_first(from, b)
            .map(|(e, q, arrival, _)| (e, q, arrival))
    }

    /// [`Forest::way`], and the heading of its first edge (`h0` if `a`
    /// is `b`).
    fn way_and_first(
        &self,
        (a, h0): (usize, Heading),
        b: usize,
    ) -> Option<(u32, u32, Heading, Heading)> {
        if a == b {
            return Some((0, 0, h0, h0));
        }
        let c = self.meet(a, b)?;
        let dc = self.depth(c);
        let edges = (self.depth(a) + self.depth(b)).saturating_sub(2 * dc);
        let wa = (a != c).then(|| self.ancestor(a, dc + 1));
        let wb = (b != c).then(|| self.ancestor(b, dc + 1));
        let first = match wb {
            _ if a != c => self.dir(a, self.parent(a)),
            Some(wb) => self.dir(a, wb),
            None => h0,
        };
        let mut q = turns(h0, first);
        if let Some(wa) = wa {
            q += self.turns_to(a).saturating_sub(self.turns_to(wa));
        }
        if let Some(wb) = wb {
            q += self.turns_to(b).saturating_sub(self.turns_to(wb));
        }
        if let (Some(wa), Some(wb)) = (wa, wb) {
            q += turns(self.dir(wa, c), self.dir(c, wb));
        }
        let arrival = match (wa, wb) {
            (_, Some(_)) => self.dir(self.parent(b), b),
            (Some(wa), None) => self.dir(wa, c),
            (None, None) => h0,
        };
        Some((edges, q, arrival, first))
    }

    /// The time from pose (`a`, `h0`) (storage indices) to node `b`
    /// over `map`, with `timing`, as [`DistField::dist_at`] of a search
    /// from that pose gives it; `None` if `b` cannot be reached, or if
    /// the forest cannot tell (the start not in it, or it does not hold
    /// for `map`): then search.
    ///
    /// [`DistField::dist_at`]: super::DistField::dist_at
    pub fn travel<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        (a, h0): (usize, Heading),
        b: usize,
    ) -> Option<Ticks> {
        if !self.holds(map) || !self.is_member(a) {
            return None;
        }
        let t = searchable(timing);
        let time = |(e, q, _): (u32, u32, Heading)| {
            u64::from(e) * u64::from(t.edge) + u64::from(q) * u64::from(t.quarter_turn)
        };
        let best = if self.is_member(b) {
            time(self.way((a, h0), b)?)
        } else {
            self.entries(map, t, (a, h0), b).map(|(x, _)| x).min()?
        };
        Ticks::try_from(best).ok().filter(|&d| d <= MAX_DIST)
    }

    /// The ways from pose (`a`, `h0`) into frontier node `b`, one per
    /// neighbour in the forest with a known arm into it (a frontier node
    /// is entered along such an arm, and never driven through): each
    /// way's time with timing `t`, and the heading of its first edge.
    fn entries<'a, M: AsRef<[Block]> + AsMut<[Block]>>(
        &'a self,
        map: &'a KnownMap<M>,
        t: Timing,
        (a, h0): (usize, Heading),
        b: usize,
    ) -> impl Iterator<Item = (u64, Heading)> + 'a {
        Heading::ALL.into_iter().filter_map(move |h| {
            let j = neighbour_index(self.bounds, b, h)?;
            let into = h.opposite();
            if !self.is_member(j) || !arms_at(map, j).is_some_and(|x| x.has(into)) {
                return None;
            }
            let (e, q, arrival, first) = self.way_and_first((a, h0), j)?;
            let x = u64::from(e) * u64::from(t.edge)
                + u64::from(q + turns(arrival, into)) * u64::from(t.quarter_turn)
                + u64::from(t.edge);
            Some((x, if a == j { into } else { first }))
        })
    }

    /// The heading a robot at pose (`a`, `h0`) drives off in on its
    /// cheapest way to frontier node `b` (not in the forest, entered along
    /// a known arm of a neighbour in it), as [`DistField::first_heading`]
    /// of a search from that pose gives it; `None` where the forest cannot
    /// tell (it does not hold for `map`, `a` is not in it, `b` is) or
    /// where two equally cheap ways leave in different headings, whose
    /// tie only a search breaks alike: then search.
    ///
    /// Why: on a tree the way is the one path to the neighbour, so a
    /// robot given a frontier node far down a maze corridor need not
    /// search everything nearer to learn its first step (maze 256², 16
    /// robots: that search was 14 % of the run; docs/results/
    /// performance.md, stop 65).
    ///
    /// [`DistField::first_heading`]: super::DistField::first_heading
    pub fn first_heading<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        (a, h0): (usize, Heading),
        b: usize,
    ) -> Option<Heading> {
        if !self.holds(map) || !self.is_member(a) || self.is_member(b) {
            return None;
        }
        let mut best: Option<(u64, Heading)> = None;
        let mut split = false;
        for (x, first) in self.entries(map, searchable(timing), (a, h0), b) {
            match best {
                Some((bx, _)) if x > bx => {}
                Some((bx, bh)) if x == bx => split |= bh != first,
                _ => {
                    best = Some((x, first));
                    split = false;
                }
            }
        }
        let (x, h) = best?;
        (!split && x <= u64::from(MAX_DIST)).then_some(h)
    }

    /// Whether [`Forest::travel`] answers from node `i`.
    pub fn holds_start<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        i: usize,
    ) -> bool {
        self.holds(map) && self.is_member(i)
    }
}

#[cfg(test)]
mod tests;

//! Ways read from a reverse field: see [`DistField::way_out`].
//!
//! A reverse field (`DistField::compute_reverse`) holds, for every pose,
//! the cheapest time to its goal. Rooted at a robot's home on a complete
//! map it never changes again, so every robot's way home, and every team
//! mate's, is read from one search kept for the rest of the run, however
//! often the robots move: a forward field from where a robot stands had to
//! be grown again after every step (a third of a 16-robot run on open
//! 256², docs/results/performance.md).

use super::{DistField, Marked, ON_WAY, PlanCell, arms_at, neighbour_index, searchable};
use crate::geometry::{Heading, Pos, Turn};
use crate::map::{Block, KnownMap};
use crate::timing::{Ticks, Timing};

/// How far along a marked way [`DistField::mark_descent`] looks for the
/// new start before it marks the way afresh: a team mate moves a few
/// edges between two decisions of ours.
const MARK_SLIDE: usize = 16;

impl<S: AsRef<[PlanCell]> + AsMut<[PlanCell]>> DistField<S> {
    /// Whether this field is a completed reverse search to `goal` over
    /// `map` as it is now, with `timing`.
    pub fn is_reverse_to<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        timing: Timing,
        goal: Pos,
    ) -> bool {
        let bounds = map.bounds();
        self.bounds == bounds
            && self.timing == searchable(timing)
            && bounds
                .index(goal)
                .is_some_and(|g| self.reverse == Some((g, map.revision())))
    }

    /// The heading in which a robot standing on node `v` facing `heading`
    /// leaves it on a cheapest way to the goal of this reverse field;
    /// `None` at the goal, where the goal cannot be reached, or when the
    /// field is no completed reverse search of `map`. Of equally cheap
    /// ways it takes straight on first, then a left, a right and a U-turn,
    /// so that every robot reading the same field predicts the same way.
    pub fn way_out<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
    ) -> Option<Heading> {
        let (goal, revision) = self.reverse?;
        if v == goal || revision != map.revision() {
            return None;
        }
        let cells = self.cells.as_ref();
        let d = cells.get(v)?.pose_dist(usize::from(heading.index()))?;
        let arms = arms_at(map, v)?;
        let t = self.timing;
        [
            (heading, 0u32),
            (heading.turned(Turn::Left), 1),
            (heading.turned(Turn::Right), 1),
            (heading.opposite(), 2),
        ]
        .into_iter()
        .find_map(|(out, turns)| {
            let w = neighbour_index(self.bounds, v, out).filter(|_| arms.has(out))?;
            let dw = cells.get(w)?.pose_dist(usize::from(out.index()))?;
            (dw + t.edge + turns * t.quarter_turn == d).then_some(out)
        })
    }

    /// The pose one edge on along [`DistField::way_out`]: the node driven
    /// into and the heading it is entered with.
    fn step_on_way<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
    ) -> Option<(usize, Heading)> {
        let out = self.way_out(map, v, heading)?;
        Some((neighbour_index(self.bounds, v, out)?, out))
    }

    /// Follows [`DistField::way_out`] from the pose (`v`, `heading`),
    /// calling `step(node)` for every node driven into, the goal last;
    /// stops early when `step` says so. Whether the walk ended at the goal
    /// or was stopped.
    fn walk_descent<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        mut v: usize,
        mut heading: Heading,
        mut step: impl FnMut(usize) -> bool,
    ) -> bool {
        let goal = self.reverse.map(|(g, _)| g);
        for _ in 0..self.bounds.area().saturating_add(1) {
            if Some(v) == goal {
                return true;
            }
            let Some(w) = self.step_on_way(map, v, heading) else {
                return false;
            };
            (v, heading) = w;
            if !step(v) {
                return true;
            }
        }
        false
    }

    /// The first node driven into on the way from the pose (`v`,
    /// `heading`) to the goal (see [`DistField::way_out`]) for which
    /// `pred` holds, if any: a walk along the way, with no search.
    pub fn descent_find<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
        mut pred: impl FnMut(usize) -> bool,
    ) -> Option<usize> {
        let mut found = None;
        self.walk_descent(map, v, heading, |w| {
            if pred(w) {
                found = Some(w);
            }
            found.is_none()
        });
        found
    }

    /// Whether the way from the pose (`v`, `heading`) to the goal (see
    /// [`DistField::way_out`]) drives into node `via`. O(1) while that way
    /// is marked ([`DistField::mark_descent`]), else a walk along it.
    pub fn descent_passes<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
        via: usize,
    ) -> bool {
        let state = v * 4 + usize::from(heading.index());
        if self.way == Some((Marked::Descent(state), map.revision())) {
            return self
                .cells
                .as_ref()
                .get(via)
                .is_some_and(|c| c.ring_b & ON_WAY != 0);
        }
        let mut hit = false;
        self.walk_descent(map, v, heading, |w| {
            hit = w == via;
            !hit
        });
        hit
    }

    /// Whether the way from the pose (`v`, `heading`) to the goal drives
    /// into any of the nodes `vias`, as [`DistField::descent_passes`] says
    /// for each: one walk for all of them. A robot on its way home asks it
    /// of every settled team mate's home at every step (in a 16-robot maze
    /// a walk per home was a tenth of the run).
    pub fn descent_passes_any<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
        vias: &[usize],
    ) -> bool {
        let state = v * 4 + usize::from(heading.index());
        if self.way == Some((Marked::Descent(state), map.revision())) {
            return vias
                .iter()
                .any(|&via| self.descent_passes(map, v, heading, via));
        }
        let mut hit = false;
        self.walk_descent(map, v, heading, |w| {
            hit = vias.contains(&w);
            !hit
        });
        hit
    }

    /// Whether the ways to the goal from the poses `a` and `b` (see
    /// [`DistField::way_out`]) drive into any of the nodes `vias` before
    /// they meet: `b`'s own node counts, `a`'s does not. Where the ways
    /// home form a tree (a maze), the two up to where they meet are the
    /// only way from `a`'s node to `b`'s, so this answers for that way with
    /// two walks and no search. `None` if a way breaks off (no completed
    /// reverse search). With `a`'s way marked ([`DistField::mark_descent`])
    /// only `b`'s is walked, up to where it meets the marks.
    pub fn descents_meet_passing<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        a: (usize, Heading),
        b: (usize, Heading),
        vias: &[usize],
    ) -> Option<bool> {
        let (goal, _) = self.reverse?;
        let cells = self.cells.as_ref();
        // A node's cheapest time over its headings: on a tree it falls at
        // every step of a way, so the walk at the farther node steps on
        // and the two stand on the same node where their ways join. (A
        // pose's own time depends on the heading it arrived with, and one
        // walk could step past the join while the other is a turn behind.)
        let key = |v: usize| {
            cells
                .get(v)
                .and_then(|c| (0..4).filter_map(|h| c.pose_dist(h)).min())
        };
        if vias.contains(&b.0) {
            return Some(true);
        }
        if let Some(passes) = self.marked_meet_passing(map, a, b, vias, key) {
            return Some(passes);
        }
        let (mut a, mut b) = (a, b);
        let (mut ka, mut kb) = (key(a.0)?, key(b.0)?);
        // Each pose is walked into once at most by each walk.
        for _ in 0..self.bounds.area().saturating_mul(8).saturating_add(2) {
            if a.0 == b.0 {
                return Some(false);
            }
            let (walker, k) = if b.0 == goal || (ka >= kb && a.0 != goal) {
                (&mut a, &mut ka)
            } else {
                (&mut b, &mut kb)
            };
            *walker = self.step_on_way(map, walker.0, walker.1)?;
            *k = key(walker.0)?;
            let into = walker.0;
            // A node the other walk stands on was looked at when it got
            // there (or is `a`'s own, which does not count).
            if a.0 != b.0 && vias.contains(&into) {
                return Some(true);
            }
        }
        None
    }

    /// [`DistField::descents_meet_passing`] past its check of `b`'s node,
    /// read off the marks of `a`'s way where they are set: `None` where
    /// they are not, or where anything is out of the ordinary (a way that
    /// breaks off, a time that does not fall), for the two walks to
    /// answer.
    ///
    /// Why it answers as the two walks do: the time to the goal (`key`)
    /// falls at every step of a way (an edge costs more than a U-turn),
    /// so each way drives into a node at most once, and the two walks,
    /// the farther one stepping first, meet on the first node of `b`'s
    /// way that lies on `a`'s (or is `a`'s own). Before they meet, `b`'s
    /// walk drives into the nodes of its way before that node, and `a`'s
    /// into those of its way that take longer to the goal than it. A
    /// gated robot far from its spot asked this at every step and of every
    /// spot it set aside, walking its whole way home each time (maze 128²,
    /// 16 robots: 217 000 times, 155 steps each).
    fn marked_meet_passing<M: AsRef<[Block]> + AsMut<[Block]>>(
        &self,
        map: &KnownMap<M>,
        a: (usize, Heading),
        b: (usize, Heading),
        vias: &[usize],
        key: impl Fn(usize) -> Option<Ticks>,
    ) -> Option<bool> {
        let state = a.0 * 4 + usize::from(a.1.index());
        let t = self.timing;
        if self.way != Some((Marked::Descent(state), map.revision()))
            || t.quarter_turn.saturating_mul(2) >= t.edge
        {
            return None;
        }
        let cells = self.cells.as_ref();
        let marked = |v: usize| cells.get(v).is_some_and(|c| c.ring_b & ON_WAY != 0);
        // `b`'s walk, up to the node where the two meet. The walk that
        // gets there first drives into it while the other stands
        // elsewhere, so that node counts, unless it is `a`'s own.
        let (mut v, mut heading) = b;
        let mut k = key(v)?;
        let join = loop {
            if v == a.0 || marked(v) {
                break v;
            }
            let (w, out) = self.step_on_way(map, v, heading)?;
            let kw = key(w)?;
            if kw >= k {
                return None;
            }
            (v, heading, k) = (w, out, kw);
            if w != a.0 && vias.contains(&w) {
                return Some(true);
            }
        };
        // `a`'s walk drives into the marked nodes that take longer to the
        // goal than the join.
        let kj = key(join)?;
        let mut on_a = false;
        for &via in vias {
            if via != a.0 && marked(via) {
                on_a |= key(via)? > kj;
            }
        }
        Some(on_a)
    }

    /// Marks the way from the pose (`v`, `heading`) to the goal, so that
    /// [`DistField::descent_passes`] answers for it in O(1) until the field
    /// or the map changes (as [`DistField::mark_way`] does for a forward
    /// field). Returns whether the way reaches the goal.
    pub fn mark_descent<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        v: usize,
        heading: Heading,
    ) -> bool {
        self.mark(map, Marked::Descent(v * 4 + usize::from(heading.index())))
    }

    /// Moves a marked way from state `from` to state `to` (node × 4 +
    /// heading) where `to` lies a few steps along it, as when a team mate
    /// drove on along its way home: the way from `to` is the rest of the
    /// way from `from` (the descent is a function of the pose), so only the
    /// nodes driven into before `to` lose their mark. No node is driven
    /// into twice (the time left falls at every step, and a loop back to a
    /// node costs more than turning there). Whether `to` was found within
    /// [`MARK_SLIDE`] steps; if not, nothing changed.
    pub(super) fn unmark_descent_prefix<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        from: usize,
        to: usize,
    ) -> bool {
        let pose = |s: usize| (s / 4, Heading::from_index((s % 4) as u8));
        let state = |v: usize, h: Heading| v * 4 + usize::from(h.index());
        let (mut v, mut heading) = pose(from);
        for steps in 0.. {
            if state(v, heading) == to {
                break;
            }
            match self.step_on_way(map, v, heading) {
                Some(next) if steps < MARK_SLIDE => (v, heading) = next,
                _ => return false,
            }
        }
        let (mut v, mut heading) = pose(from);
        while state(v, heading) != to {
            let Some((w, out)) = self.step_on_way(map, v, heading) else {
                return false;
            };
            if let Some(c) = self.cells.as_mut().get_mut(w) {
                c.ring_b &= !ON_WAY;
            }
            (v, heading) = (w, out);
        }
        true
    }

    /// Sets or clears the mark on every node driven into on the way from
    /// `state` (node × 4 + heading); whether it reached the goal. Its own
    /// loop, not `walk_descent`: it writes the cells it walks.
    pub(super) fn set_descent_bits<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        state: usize,
        on: bool,
    ) -> bool {
        let goal = self.reverse.map(|(g, _)| g);
        let (mut v, mut heading) = (state / 4, Heading::from_index((state % 4) as u8));
        for _ in 0..self.bounds.area().saturating_add(1) {
            if Some(v) == goal {
                return true;
            }
            let Some((w, out)) = self.step_on_way(map, v, heading) else {
                return false;
            };
            if let Some(c) = self.cells.as_mut().get_mut(w) {
                if on {
                    c.ring_b |= ON_WAY;
                } else {
                    c.ring_b &= !ON_WAY;
                }
            }
            (v, heading) = (w, out);
        }
        false
    }
}

#[cfg(test)]
mod tests;

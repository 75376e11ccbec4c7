//! Retreats: a robot bumped by a team mate whose home fills first (or one
//! it keeps running into) drives to the nearest node off that team mate's
//! way and holds there until the team mate no longer needs the way: it is
//! home, has failed, has stood still for a while, or is ahead of us on our
//! own way home, so that we can follow it. Shut in behind that team mate
//! (a dead end, a line of homes), it pushes through it instead, to a spot
//! past a node where the team mate can step aside.

use super::*;

/// A retreat may end before the team mate it made way for is home, to follow
/// it, only while home is farther than this many edges.
const FOLLOW_FROM_EDGES: u32 = 8;

/// How many more spots a retreat looks at for one not behind a team mate
/// once it has found one that is (see `retreat_spot`).
const SPOTS_PAST_A_MATE: u32 = 16;

/// How many push spots (see `retreat_spot`) a retreat looks at for one
/// past a node with room aside: bounds the walks on a large field.
const PUSH_SPOTS: u32 = 1024;

/// A retreat ends when the team mate it made way for has not moved for this
/// many edges of time: it may be waiting for us (it let us go first).
const RETREAT_PATIENCE_EDGES: u32 = 20;

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Plans team mate `b`'s way from where it stands in the first field:
    /// to its retreat spot if `chained`, else home (or, while the map
    /// grows, to its target); the team mate and the goal's node if the way
    /// was found. The way is marked, as every caller asks whether it
    /// passes nodes (`DistField::path_passes`, then O(1)): `bumper_clear`
    /// asks for every node of our own way home, which walked the bumper's
    /// way back each time, a twentieth of a 16-robot maze's homecoming
    /// (docs/results/performance.md, stop 55).
    pub(super) fn plan_way_of(&mut self, b: usize, chained: bool) -> Option<(Peer, usize)> {
        let q = self.peers.get(b).copied()?;
        let goal = self
            .map
            .bounds()
            .index(way_end(&q, chained, self.map.is_complete()))?;
        let field = self.fields.first_mut()?;
        // A forward field, not the reverse one its `go_home` reads its way
        // from: the two differ only between equally short ways, and planned
        // from the reverse field, retreats cost 3 % of the makespan on the
        // system bench and stretched some maze homecomings twofold
        // (docs/results/performance.md, stop 21).
        let reached = field
            .compute_to(&self.map, self.config.timing, q.pos, q.heading, goal)
            .is_ok();
        let found = reached && field.dist_at(goal).is_some();
        if found {
            field.mark_way(&self.map, goal);
        }
        found.then_some((q, goal))
    }

    /// Plans a retreat out of team mate `b`'s way (see `plan_way_of`) and
    /// starts it (the next decision drives it); whether there is somewhere
    /// to go.
    pub(super) fn plan_retreat(&mut self, b: usize, chained: bool) -> bool {
        if !self.peers.get(b).is_some_and(|q| q.known && !q.failed) {
            return false;
        }
        let Some((q, goal)) = self.plan_way_of(b, chained) else {
            return false;
        };
        let Some((spot, leave)) = self.retreat_spot(goal, q.pos) else {
            return false;
        };
        self.retreat = Some(Retreat {
            spot,
            leave,
            bumper: b,
            chained,
            bumper_at: q.pos,
            since: self.now,
        });
        true
    }

    /// The nearest node to retreat to from a bumper standing at `from`
    /// whose way ends at node `goal` (planned in the first field): off that
    /// way, nobody else's home, not taken, and reached without driving
    /// through the bumper; and the node where our way there leaves the
    /// bumper's way (where we stand, at the latest; `None` if its way does
    /// not come through here). If every such node lies behind the bumper,
    /// and we stand ahead of it on its way far from home, any free node
    /// off its way reached past no team mate (the second pass); else a
    /// push spot through it (see the end). Plans in the second field;
    /// `None` with a single field or if there is no such node.
    fn retreat_spot(&mut self, goal: usize, from: Pos) -> Option<(Pos, Option<Pos>)> {
        let bounds = self.map.bounds();
        let blocked = bounds.index(from)?;
        let far_from_home = self.may_follow();
        // Homes of team mates that fill before ours: a spot whose way home
        // runs through one is a trap once that team mate is in (as in
        // `keep_out_of_the_way`).
        let earlier: Vec<usize, MAX_ROBOTS> = (0..self.peers.len())
            .filter(|&i| self.goes_first(i))
            .filter_map(|i| self.peers.get(i))
            .filter(|q| q.known && !q.failed)
            .filter_map(|q| bounds.index(q.home))
            .collect();
        let (me, map, peers) = (self.id.index(), &self.map, &self.peers);
        let timing = self.config.timing;
        let (theirs, rest) = self.fields.split_first_mut()?;
        let (mine, rest) = rest.split_first_mut()?;
        // With a third field: not behind the bumper's goal as seen from
        // our home, or we would only be shut in once it is there. The
        // search from home is the agent's last field, which nothing else
        // writes when the agent has one past the homecoming's spare but
        // the very same search from home (`keep_out_of_the_way` asks it
        // too): on a complete map it is then searched once, not at every
        // retreat.
        let home = self.home;
        let (homeward, spare) = match rest.split_last_mut() {
            Some((f, spare)) => (Some(f), spare),
            None => (None, &mut [][..]),
        };
        let mut homeward = homeward.and_then(|f| {
            (f.is_complete_search_from(map, timing, home, Heading::North)
                || f.compute(map, timing, home, Heading::North, |_, _| Flow::Continue)
                    .is_ok())
            .then_some(f)
        });
        let pose = (self.pos, self.heading);
        let mut through_bumper = ThroughBumper {
            whole: spare.last_mut(),
            walked: 0,
            ready: false,
        };
        let theirs = &*theirs;
        // Another team mate's home or place: never a spot, nor room aside.
        let claimed = |v: usize| {
            let p = bounds.pos(v);
            peers
                .iter()
                .enumerate()
                .any(|(i, q)| i != me && q.known && !q.failed && (q.home == p || q.pos == p))
        };
        // Seen from home: behind the bumper's goal, or behind a home that
        // fills before ours. One memoised question for all of them: asked
        // one by one, each walked the way home anew for every spot looked
        // at, minutes in a crowded maze.
        let mut behind: Vec<usize, { MAX_ROBOTS + 1 }> = Vec::new();
        // Room for the goal and every team mate: neither can fail.
        let _ = behind.push(goal);
        let _ = behind.extend_from_slice(&earlier);
        let occupied = |v: usize| {
            let p = bounds.pos(v);
            peers
                .iter()
                .enumerate()
                .any(|(i, q)| i != me && q.known && !q.failed && q.pos == p)
        };
        // `ahead`: any spot off the bumper's way that nobody stands on will
        // do, even a team mate's empty home or one behind an earlier home
        // as seen from ours, but not one behind the bumper's goal (the
        // second pass below).
        let mut free = |v: usize, ahead: bool| {
            v != blocked
                && !theirs.path_passes(map, goal, v)
                && !(if ahead { occupied(v) } else { claimed(v) })
                && !homeward.as_mut().is_some_and(|f| {
                    // Ahead, only the goal counts: behind it, we would be
                    // shut in for good once the bumper is home.
                    let set = if ahead { &[goal][..] } else { &behind[..] };
                    f.passes_any(map, v, set)
                })
        };
        // Where the other team mates stand, but the bumper.
        let mates_at: Vec<usize, MAX_ROBOTS> = peers
            .iter()
            .enumerate()
            .filter(|&(i, q)| i != me && q.known && !q.failed)
            .filter_map(|(_, q)| bounds.index(q.pos))
            .filter(|&at| at != blocked)
            .collect();
        let here = bounds.index(self.pos);
        // Only a bumper whose way comes through here can be seen to pass
        // (one that bumped us on its way elsewhere, to a retreat spot of its
        // own, say, cannot); and only then are we ahead of it on its way.
        let through_here = here.filter(|&h| theirs.path_passes(map, goal, h));
        // Standing ahead of the bumper on its way, far from home, with no
        // spot that passes every check: look again for any spot off its way
        // that we reach without passing it, before pushing back through it.
        // In a long maze corridor home the only spots that passed lay behind
        // the bumper, and pushing back through it (and whoever followed it)
        // had three robots dance until the time limit. Near the homes, the
        // same steps into empty homes swapped robots in a cycle of homes
        // (docs/results/system.md, stop 25).
        for ahead in [false, true] {
            if ahead && (through_here.is_none() || !far_from_home) {
                break;
            }
            let mut first = true;
            // The nearest spot whose way runs through a team mate standing
            // elsewhere: taken only if no spot is free of them (the team
            // mate is then asked to make way in turn, see `on_bumped`).
            let mut through_mate = None;
            // Looked for only among the next few spots after it: in a maze
            // every spot can lie behind a team mate, and checking the whole
            // field, each spot's way against each team mate, took minutes.
            let mut looks_left = SPOTS_PAST_A_MATE;
            loop {
                let next =
                    mine.next_where(map, timing, pose, first, |v, d| d > 0 && free(v, ahead));
                first = false;
                let v = match next {
                    Ok(Some(v)) => v,
                    Ok(None) if through_mate.is_none() => break,
                    _ => return through_mate,
                };
                if !through_bumper.ask(map, timing, pose, mine, (v, blocked)) {
                    let leave = through_here.and_then(|h| {
                        mine.first_back(map, v, |u| u == h || theirs.path_passes(map, goal, u))
                    });
                    let spot = Some((bounds.pos(v), leave.map(|u| bounds.pos(u))));
                    let blocked_by_mate = mine.path_passes_any(map, v, &mates_at);
                    if !blocked_by_mate {
                        return spot;
                    }
                    if ahead {
                        // Ahead, only a spot free of team mates: the way
                        // to one through a team mate led back into the
                        // crowd at the homes, and 16-robot mazes deadlocked
                        // there (docs/results/system.md, stop 25).
                        if looks_left == 0 {
                            break;
                        }
                        looks_left -= 1;
                        continue;
                    }
                    through_mate = through_mate.or(spot);
                }
                if through_mate.is_some() {
                    if looks_left == 0 {
                        return through_mate;
                    }
                    looks_left -= 1;
                }
            }
        }
        // Every spot lies behind the bumper (we stand in a dead end, or
        // in a line of homes, beyond it): push. Drive through it to the
        // nearest free spot past a node where it can step aside off our
        // way; bumped on that way, it retreats off it in turn (see
        // `on_bumped`), and once we are past it, it can get home.
        let mut first = true;
        for _ in 0..PUSH_SPOTS {
            let next = mine.next_where(map, timing, pose, first, |v, d| d > 0 && free(v, false));
            first = false;
            let v = next.ok().flatten()?;
            let aside = |u: usize| {
                map.known_arms(bounds.pos(u)).is_some_and(|arms| {
                    arms.iter().any(|h| {
                        crate::path::neighbour_index(bounds, u, h).is_some_and(|w| {
                            Some(w) != here && !mine.path_passes(map, v, w) && !claimed(w)
                        })
                    })
                })
            };
            // The nodes from the bumper on, up to the spot (excluded).
            let mut room = false;
            mine.first_back(map, v, |u| {
                room |= u != v && aside(u);
                room || u == blocked
            });
            if room {
                return Some((bounds.pos(v), None));
            }
        }
        None
    }

    /// Drives to the retreat spot and holds there until the team mate that
    /// bumped us is home (or failed, or stood still for a while: it may be
    /// waiting for us; or, far from home, no longer needs our way: see
    /// `may_follow`); `None` once the retreat is over.
    pub(super) fn retreat_decision(&mut self) -> Option<Decision> {
        let mut r = self.retreat?;
        let timing = self.config.timing;
        if let Some(q) = self.peers.get(r.bumper).filter(|q| q.pos != r.bumper_at) {
            r.bumper_at = q.pos;
            r.since = self.now;
            self.retreat = Some(r);
        }
        // Made way for a team mate whose home fills after ours (it stood
        // in our way and had nowhere to go): once it stops moving it waits
        // for us, so go soon.
        let edges = if self.goes_first(r.bumper) {
            RETREAT_PATIENCE_EDGES
        } else {
            3
        };
        let edge_ms = timing.edge.saturating_mul(TICK_MS);
        let patience =
            edge_ms.saturating_mul(edges) + self.jitter(edge_ms.saturating_mul(edges / 2), r.since);
        let over = self.peers.get(r.bumper).is_none_or(|q| {
            !q.known || q.failed || (q.pos == q.home && !(r.chained && q.target.is_some()))
        }) || self.now.wrapping_sub(r.since) > patience
            || !self.map.is_complete()
            || self.may_follow() && self.bumper_clear(r);
        // A team mate that holds our spot (its own retreat ends there) will
        // not leave it for us: look for another spot, or give up.
        let me = self.id.index();
        let held = r.spot != self.pos
            && self.peers.iter().enumerate().any(|(i, q)| {
                i != me && q.known && !q.failed && q.pos == r.spot && q.target == Some(r.spot)
            });
        if !over && held {
            self.retreat = None;
            if !self.plan_retreat(r.bumper, r.chained) {
                return None;
            }
            let mut again = self.retreat?;
            again.since = r.since;
            self.retreat = Some(again);
            r = again;
        }
        let bounds = self.map.bounds();
        let spot = bounds.index(r.spot);
        let (pos, heading, map) = (self.pos, self.heading, &self.map);
        let next = match (over, spot, self.fields.get_mut(1)) {
            (false, Some(spot), Some(field)) if r.spot != pos => {
                let reached = field.compute_to(map, timing, pos, heading, spot).is_ok();
                reached.then(|| field.first_heading(map, spot)).flatten()
            }
            _ => None,
        };
        if over || (next.is_none() && r.spot != pos) {
            self.retreat = None;
            return None;
        }
        Some(Decision {
            goal: Goal::Home,
            next,
        })
    }

    /// Whether a retreat may end to follow the team mate it made way for
    /// (or, see `retreat_spot`, step aside ahead of it into any free spot):
    /// only far from home. Near the homes the order in which robots arrive
    /// decides whether they can get in at all (a follower that arrives
    /// right behind a deeper team mate can end up swapped with it in a
    /// dead end: three times the deadlocks on crowded small fields). Checked
    /// before planning anything: the fields hold team mates' kept ways.
    fn may_follow(&self) -> bool {
        self.pos.manhattan(self.home) > FOLLOW_FROM_EDGES
    }

    /// Whether the team mate we retreated from no longer needs our way, so
    /// that going on can only follow it, never meet it head-on. Holding
    /// until it is home instead had robots stand for the whole of a long
    /// trip home and then drive it alone (the demo field: 45 s of 193 s).
    /// Either it has driven past the node where our way to the retreat spot
    /// left its way (to its target, else home), or it is ahead of us on the
    /// way we would take home now: where our way first meets its way, it
    /// drives on in our direction and gets there two edges before we
    /// could. Plans its way once, in the first field, and ours in the
    /// second.
    fn bumper_clear(&mut self, r: Retreat) -> bool {
        let bounds = self.map.bounds();
        let Some((q, goal)) = self.plan_way_of(r.bumper, r.chained) else {
            return false;
        };
        let (map, timing, pos, heading) = (&self.map, self.config.timing, self.pos, self.heading);
        let Some((theirs, rest)) = self.fields.split_first_mut() else {
            return false;
        };
        // Past where our way left its way.
        if let Some(leave) = r
            .leave
            .filter(|&p| p != q.pos)
            .and_then(|p| bounds.index(p))
        {
            if !theirs.path_passes(map, goal, leave) {
                return true;
            }
        }
        // Ahead of us on our way home.
        let (Some(home), Some(here), Some(mine)) =
            (bounds.index(self.home), bounds.index(pos), rest.first_mut())
        else {
            return false;
        };
        let planned = mine.compute_to(map, timing, pos, heading, home).is_ok()
            && mine.dist_at(home).is_some();
        if !planned {
            return false;
        }
        let theirs = &*theirs;
        let at = bounds.index(q.pos);
        let on_theirs = |v: usize| Some(v) == at || theirs.path_passes(map, goal, v);
        // Walking our way back from home (the predicate never holds: it
        // only watches the walk): the last shared node seen is the first we
        // would meet, the one before it the next.
        let (mut first, mut next) = (None, None);
        mine.first_back(map, home, |v| {
            if v != here && on_theirs(v) {
                next = first;
                first = Some(v);
            }
            false
        });
        let Some(first) = first else {
            // Our ways never meet.
            return true;
        };
        let (Some(ours), Some(their)) = (mine.dist_at(first), theirs.dist_at(first)) else {
            return false;
        };
        let same_way = next.is_none_or(|n| theirs.dist_at(n).is_some_and(|d| d > their));
        // Standing on our way, it must be on the move: one that waits (for a
        // team mate of its own) would only be run into.
        let moving = Some(first) != at
            || self.now.wrapping_sub(r.since) < timing.edge.saturating_mul(2 * TICK_MS);
        same_way && moving && their.saturating_add(timing.edge.saturating_mul(2)) <= ours
    }
}

/// Whether our cheapest way to a spot drives through the bumper, asked
/// for spot after spot, nearest first, while a retreat looks for one.
///
/// Each answer walks our way back from the spot: O(way length). Shut in
/// behind the bumper, every spot of the field is asked, and in a maze of
/// 128² with 16 robots these walks were a quarter of the run. Once the
/// walks have driven back as many edges as the map has nodes, a spare
/// field (when the agent has one) gets a whole search from our pose: the
/// same shortest-path tree, as searches are deterministic, so the same
/// answers, which [`DistField::passes`] then memoises for all spots in
/// O(map) altogether. Walking that far first costs at most about what the
/// whole search costs (the rent-or-buy rule): most retreats take one of
/// the first spots, a few edges away, and a whole search after four
/// walks, whatever their length, was 8 % of a 256² maze with 16 robots
/// (docs/results/performance.md, stop 65).
struct ThroughBumper<'a, F> {
    /// The agent's last field, if it has more than the three a retreat
    /// plans in. A strategy may keep a search there between decisions
    /// (tempo's endgame does, in team mates' slots); a search here only
    /// costs it a fresh one, as a new search forgets what a field kept.
    whole: Option<&'a mut DistField<F>>,
    /// Edges the walks so far may have driven back (each way's time in
    /// edges, an upper bound: turns add time, not edges).
    walked: u32,
    /// Whether `whole` holds the whole search.
    ready: bool,
}

impl<F: AsRef<[PlanCell]> + AsMut<[PlanCell]>> ThroughBumper<'_, F> {
    /// Whether `mine`'s cheapest way (a search from `pose`, perhaps still
    /// growing) to node `v` drives through node `blocked`.
    fn ask<M: AsRef<[Block]> + AsMut<[Block]>>(
        &mut self,
        map: &KnownMap<M>,
        timing: crate::timing::Timing,
        (pos, heading): (Pos, Heading),
        mine: &DistField<F>,
        (v, blocked): (usize, usize),
    ) -> bool {
        if !self.ready && self.walked as usize >= map.bounds().area() {
            if let Some(f) = self.whole.as_mut() {
                self.ready = f
                    .compute(map, timing, pos, heading, |_, _| Flow::Continue)
                    .is_ok();
            }
        }
        match (self.ready, self.whole.as_mut()) {
            (true, Some(f)) => f.passes(map, v, blocked),
            _ => {
                let edges = mine.dist_at(v).unwrap_or(0) / timing.edge.max(1);
                self.walked = self.walked.saturating_add(edges.max(1));
                mine.path_passes(map, v, blocked)
            }
        }
    }
}

/// Where team mate `q`'s way ends: its announced retreat spot in a chain
/// (see `on_bumped`); home once the map is complete (a target announced
/// then is a retreat spot, and the way that matters to whoever it bumps is
/// the one home, which it takes next); else its target, if any.
fn way_end(q: &Peer, chained: bool, complete: bool) -> Pos {
    match q.target {
        Some(t) if chained || !complete => t,
        _ => q.home,
    }
}

#[cfg(test)]
mod tests;

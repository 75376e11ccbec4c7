//! Homecoming: robots cannot pass each other on a line, so the way home is
//! where they get in each other's way. Two behaviours keep the team moving:
//! a robot standing in someone's way makes way when bumped, and a returning
//! robot whose home lies on a team mate's way home waits off that way.
//! A bumped robot whose bumper goes first retreats (see `retreat`).

use super::*;

/// The planner field (after our own, the first) that keeps team mate `i`'s
/// way home: one slot per team mate, so a kept way survives other team
/// mates' moves, and never the field `me` of the whole array, which a
/// strategy that plans for the team uses for our own way (tempo's way home
/// rebuilt team mate `me − 1`'s field at every step: a quarter of a
/// 16-robot run on open 256²). So a team of k needs k + 1 fields.
/// A gated robot's way to its waiting spot is read off its way home and
/// the spot's (`DistField::descents_meet_passing`) when its way home puts
/// it more than this many edges farther from home than the spot; nearer,
/// it is searched.
const GUIDED_FROM_EDGES: u32 = 16;

fn mate_slot(i: usize, me: usize) -> usize {
    if i + 1 == me { me } else { i }
}

impl<M, F, S, const K: usize> Agent<M, F, S, K>
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    S: Strategy<M, F>,
{
    /// Makes way: a robot standing idle on someone's route (typically at
    /// home, where another robot's way home may lead through) retreats to
    /// the nearest node off the way of a bumper whose home fills first and
    /// holds there until it is home (see `plan_retreat`); otherwise it
    /// drives one edge away from the other robot, waits, and plans again.
    pub(super) fn on_bumped(
        &mut self,
        toward: Heading,
        out: &mut Commands,
    ) -> Result<(), AgentError> {
        if !self.is_standing()
            || !matches!(self.mode, Mode::Explore | Mode::Return | Mode::Finished)
        {
            return Err(AgentError::Unexpected);
        }
        if self.mode == Mode::Finished {
            // Someone still moves: we were wrong that the team is done.
            self.mode = Mode::Return;
            self.finished_sent = false;
        }
        // The robot that bumped us stands on the node it came from.
        let bounds = self.map.bounds();
        let first = self.pos.step(toward).and_then(|from| {
            self.peers
                .iter()
                .position(|q| q.known && !q.failed && q.pos == from)
        });
        // At home and in the way of a bumper that retreats itself (its
        // target, once the map is complete, is its retreat spot): it needs
        // us off that way, or the robot it makes way for never gets in.
        // The chain goes on until someone reaches a free node.
        let here = bounds.index(self.pos);
        let chained = first
            .filter(|&b| self.pos == self.home && self.retreating_peer(b))
            .and_then(|b| self.plan_way_of(b, true))
            .is_some_and(|(_, goal)| {
                here.zip(self.fields.first())
                    .is_some_and(|(h, f)| f.path_passes(&self.map, goal, h))
            });
        // Once the map is complete and the bumper's home fills first, one
        // edge is not enough: in a corridor we would only be bumped again,
        // or come back into its way. Retreat to the nearest node off its
        // way and hold there until it is home.
        if let Some(b) = first.filter(|&b| chained || self.goes_first(b)) {
            if self.plan_retreat(b, chained) {
                self.decide(out);
                return Ok(());
            }
        }
        // Otherwise step off the bumper's way (to its target, else home;
        // a retreating bumper's to its spot): straight on along it, we
        // would only be bumped again, and pushed along it into the packed
        // homes.
        let way = first
            .and_then(|b| self.plan_way_of(b, self.retreating_peer(b)))
            .map(|(_, goal)| goal);
        let (map, fields, peers, me) = (&self.map, &self.fields, &self.peers, self.id.index());
        let on_way = |v: Option<usize>| match (way, v, fields.first()) {
            (Some(goal), Some(v), Some(field)) => field.path_passes(map, goal, v),
            _ => false,
        };
        let occupied = |p: Pos| peers.iter().any(|q| q.known && !q.failed && q.pos == p);
        let someones_home = |p: Pos| {
            peers
                .iter()
                .enumerate()
                .any(|(i, q)| i != me && q.known && !q.failed && q.home == p)
        };
        let candidates = [
            toward.opposite(),
            toward.turned(Turn::Right),
            toward.turned(Turn::Left),
        ];
        let escape = candidates
            .into_iter()
            .filter(|h| self.can_move(*h))
            .min_by_key(|h| {
                let next = self.pos.step(*h);
                (
                    next.is_some_and(occupied),
                    on_way(next.and_then(|p| bounds.index(p))),
                    next.is_some_and(someones_home),
                )
            });
        let Some(h) = escape else {
            return Err(AgentError::Unexpected);
        };
        self.escaping = true;
        self.made_way_for = first;
        if let Some(t) = self.heading.turn_to(h) {
            self.heading = h;
            push(out, Command::Turn(t));
        }
        self.start_move(out);
        Ok(())
    }

    /// Whether we stepped aside for a team mate that retreats and now holds
    /// its spot, while every team mate whose home fills before ours is in
    /// and every other retreating one holds its spot too: the way is then
    /// ours, and those holding wait for us. The yield wait (see `on_node`)
    /// ends early then. A robot whose home fills first was bumped by a
    /// team mate retreating *for it* and stood out the whole wait while
    /// everyone waited for it: test.sim with 4 and 5 robots took 47.4 and
    /// 53.9 s, 37.2 and 33.1 s with this rule (docs/results/system.md,
    /// stops 32 and 33). Ending the wait as soon as the earlier homes are
    /// in, before the bumper holds, sent robots back into bumpers still
    /// shut in behind them.
    pub(super) fn made_way_for_a_holding_retreat(&mut self) -> bool {
        let holds = |q: &Peer| q.target == Some(q.pos);
        let bumper_holds = self
            .made_way_for
            .is_some_and(|b| self.retreating_peer(b) && self.peers.get(b).is_some_and(holds));
        if !bumper_holds {
            return false;
        }
        // A robot that made way right after the map was complete has not
        // decided since and does not know the fill order: it works it out
        // for this question only. Kept, it changed how the robot made way
        // next, and in one hunt case (claim, seed 3387) robots that had
        // come home fine danced in a corridor until the time limit.
        let depth = self.fill_ranks_once();
        (0..self.peers.len()).all(|i| {
            let q = self.peers.get(i).copied().unwrap_or(NO_PEER);
            let in_or_gone = !q.known || q.failed || q.pos == q.home;
            (!self.first_by(&depth, i) || in_or_gone) && (!self.retreating_peer(i) || holds(&q))
        })
    }

    /// Whether team mate `i` is retreating: once the map is complete, the
    /// only target a robot announces is its retreat spot.
    pub(super) fn retreating_peer(&self, i: usize) -> bool {
        self.map.is_complete()
            && i != self.id.index()
            && self
                .peers
                .get(i)
                .is_some_and(|q| q.known && !q.failed && q.target.is_some())
    }

    /// A way home through a team mate that stands at a home filling before
    /// ours runs into it: it can only make way by leaving home, and in
    /// packed homes it has nowhere to go (the two then dance for ever).
    /// Takes the cheapest way round every such team mate instead, if there
    /// is one: a
    /// node-weighted field where entering a settled home costs more than
    /// any way round (turns are left out of that field; they only pick
    /// the first move, and the next decision plans again).
    pub(super) fn round_settled_mates(&mut self, decision: Decision) -> Decision {
        if decision.goal != Goal::Home || decision.next.is_none() || !self.map.is_complete() {
            return decision;
        }
        let bounds = self.map.bounds();
        let Some(home) = bounds.index(self.home) else {
            return decision;
        };
        // Only those whose homes fill before ours stay put: the others make
        // way for us when we bump them.
        self.know_fill_order();
        let settled: Vec<usize, MAX_ROBOTS> = self
            .peers
            .iter()
            .enumerate()
            .filter(|&(i, q)| q.known && !q.failed && q.pos == q.home && self.goes_first(i))
            .filter_map(|(_, q)| bounds.index(q.pos))
            .collect();
        let (map, timing, pos, heading) = (&self.map, self.config.timing, self.pos, self.heading);
        let Some(at) = bounds.index(pos).filter(|_| !settled.is_empty()) else {
            return decision;
        };
        // The way the decision drives: the descent of the reverse field our
        // way home was read from (see `explore::go_home`), else a forward
        // field's. A way other than the one driven made robots flip between
        // two ways round a settled team mate and back.
        let kept = self
            .fields
            .iter()
            .find(|f| f.is_reverse_to(map, timing, self.home))
            .map(|f| f.descent_passes_any(map, at, heading, &settled));
        let Some(field) = self.fields.first_mut() else {
            return decision;
        };
        let through = kept.unwrap_or_else(|| {
            field.compute_to(map, timing, pos, heading, home).is_ok()
                && field.dist_at(home).is_some()
                && field.path_passes_any(map, home, &settled)
        });
        if !through {
            return decision;
        }
        let edge = timing.edge.max(1);
        let wall = edge
            .saturating_mul(
                u32::try_from(bounds.area())
                    .unwrap_or(u32::MAX)
                    .saturating_add(1),
            )
            .min(crate::path::MAX_DIST / 32);
        let round = field
            .compute_weighted(
                map,
                pos,
                |v| if settled.contains(&v) { wall } else { edge },
                |v, _| {
                    if v == home {
                        Flow::Stop
                    } else {
                        Flow::Continue
                    }
                },
            )
            .is_ok()
            && field.dist_at(home).is_some_and(|d| d < wall);
        match field.weighted_first_heading(home).filter(|_| round) {
            Some(h) => Decision {
                goal: Goal::Home,
                next: Some(h),
            },
            None => decision,
        }
    }

    /// Homecoming without deadlock: robots cannot pass each other on a
    /// line, so a robot whose home lies on the way home of a returning team
    /// mate with a deeper home waits off every returning team mate's way,
    /// as near to its home as it can, until they are in. Needs one planner field per team mate
    /// (`K > 1`); with a single field the decision is kept as it is.
    pub(super) fn keep_out_of_the_way(&mut self, decision: Decision) -> Decision {
        self.know_fill_order();
        let bounds = self.map.bounds();
        let Some(my_home) = bounds.index(self.home) else {
            return decision;
        };
        let me = self.id.index();
        let (timing, pos, heading) = (self.config.timing, self.pos, self.heading);
        let map = &self.map;
        let Some((mine, rest)) = self.fields.split_first_mut() else {
            return decision;
        };
        let depth = self.depth;
        let my_depth = depth.get(me).copied().unwrap_or(0);
        // (field in `rest`, the pose its way starts from, goes first) of
        // every returning team mate.
        let mut pending: Vec<(usize, (usize, Heading), bool), MAX_ROBOTS> = Vec::new();
        let peers = &self.peers;
        let shared = self.shared;
        let homes: Vec<Pos, MAX_ROBOTS> = peers
            .iter()
            .enumerate()
            .filter(|(i, p)| *i != me && p.known && !p.failed)
            .map(|(_, p)| p.home)
            .collect();
        // Plans the way home of every returning team mate that goes first
        // (`firsts`) or of every other one: the others' ways only matter
        // once we know we are gated, so most decisions never plan them.
        let plan = |firsts: bool,
                    pending: &mut Vec<(usize, (usize, Heading), bool), MAX_ROBOTS>,
                    rest: &mut [DistField<F>]| {
            for (i, p) in peers.iter().enumerate() {
                if i == me || !p.known || p.failed {
                    continue;
                }
                // The deeper home fills first, else a robot already home
                // would plug a corridor for good. Depth is the home's total
                // distance to every node of the complete map (a dead end
                // scores high, a junction low): the same for every robot and
                // independent of where anyone stands, so it is a total order
                // (ties by id) and no two robots ever wait for each other,
                // nor flip their minds as they move.
                let theirs = depth.get(i).copied().unwrap_or(0);
                let first = (theirs, core::cmp::Reverse(i)) > (my_depth, core::cmp::Reverse(me));
                if first != firsts {
                    continue;
                }
                // A team mate's way home is read from a reverse field
                // rooted at its home: the way its own `go_home` drives (up to
                // a bump or a wait), from wherever it stands. Once the map is
                // complete that field never changes, so it is searched once
                // and kept in the team mate's own slot however often the
                // team mate moves (a forward field from where it stood had
                // to be grown again after every step: a fifth of a 16-robot
                // run on open 256²).
                let slot = mate_slot(i, me);
                let (false, Some(at), Some(field)) =
                    (p.pos == p.home, bounds.index(p.pos), rest.get_mut(slot))
                else {
                    continue;
                };
                let kept = field.is_reverse_to(map, timing, p.home)
                    || shared.is_some_and(|s| s.recall_reverse(map, timing, p.home, field))
                    || {
                        let searched = field
                            .compute_reverse(map, timing, p.home, |_, _, _| Flow::Continue)
                            .is_ok();
                        if let (true, Some(s)) = (searched, shared) {
                            s.keep_reverse(map, timing, p.home, field);
                        }
                        searched
                    };
                if kept {
                    let _ = pending.push((slot, (at, p.heading), first));
                }
            }
        };
        plan(true, &mut pending, rest);
        mark_ways(&pending, rest, map);
        let gated = pending.iter().any(|&(s, (at, h), _)| {
            rest.get(s)
                .is_some_and(|f| f.descent_passes(map, at, h, my_home))
        });
        // Never wait for ever: after a while in which no team mate we wait
        // for moved and none came home, go and let the make-way behaviour
        // sort it out. A team mate still driving (from the far end of a
        // large maze, say) is progress, not a deadlock: going home before
        // it would plug its way.
        let now = self.now;
        let mut progress: u32 = 0;
        for (i, p) in peers.iter().enumerate() {
            if i == me || !p.known || p.failed {
                continue;
            }
            let home = u32::from(p.pos == p.home);
            let waited_for = pending.iter().any(|&(s, (at, h), _)| {
                s == mate_slot(i, me)
                    && rest
                        .get(s)
                        .is_some_and(|f| f.descent_passes(map, at, h, my_home))
            });
            let at = if waited_for {
                ((p.pos.x as u16 as u32) << 16) | p.pos.y as u16 as u32
            } else {
                0
            };
            progress = progress
                .wrapping_mul(0x9E37_79B1)
                .wrapping_add(at ^ home ^ ((i as u32) << 1));
        }
        if progress != self.gated_progress {
            self.gated_progress = progress;
            self.gated_since = None;
        }
        let since = *self.gated_since.get_or_insert(now);
        let edge_ms = timing.edge.saturating_mul(TICK_MS);
        let patience = edge_ms.saturating_mul(40)
            + super::decide::draw(self.id, pos, since, edge_ms.saturating_mul(20));
        if !gated || now.wrapping_sub(since) > patience {
            if !gated {
                self.gated_since = None;
            }
            return decision;
        }
        plan(false, &mut pending, rest);
        mark_ways(&pending, rest, map);
        // The spots are searched in a spare field past every team mate's
        // slot where there is one: the first field holds the way home a
        // strategy keeps (`explore::go_home`), which a search here would
        // throw away at every step of a gated robot.
        let (rest, spare) = rest.split_at_mut(MAX_ROBOTS.min(rest.len()));
        let (spare, past) = match spare.split_first_mut() {
            Some((f, past)) => (Some(f), past),
            None => (None, &mut [][..]),
        };
        let (mine, mut first) = match spare {
            Some(f) => (f, Some(mine)),
            None => (mine, None),
        };
        // Whether a spot's way home passes an earlier home is asked of
        // a whole search from home in the agent's last field, past the
        // spare, where a retreat keeps it too (`retreat_spot`): the same
        // search tree as the spot search's, so the same answers, and its
        // memo answers every spot of every decision in O(map) altogether
        // (maze 256², 16 robots: a walk back home per spot was 4 % of the
        // run; docs/results/performance.md, stop 65).
        let (home, north) = (self.home, Heading::North);
        let mut homeward = past.last_mut().and_then(|f| {
            let whole = f.is_complete_search_from(map, timing, home, north)
                || f.compute(map, timing, home, north, |_, _| Flow::Continue)
                    .is_ok();
            whole.then_some(f)
        });
        // The way home the strategy keeps (a reverse field rooted at our
        // home, see `explore::go_home`) guides the search of the way to a
        // spot near home: far from home, that way runs along the way home,
        // and a plain search from where we stand grew over everything
        // nearer than the spot (most of a gated robot's time in a maze).
        // Tempo keeps it in our own field of the team's (robot `me`'s),
        // which is among `rest`; others in the first.
        // Far from home our own way home is marked in it, so that asking
        // whether the way to a spot passes a team mate walks only the
        // spot's way (see `DistField::descents_meet_passing`). As we drive
        // along it, the marks slide on with us.
        let far = GUIDED_FROM_EDGES.saturating_mul(timing.edge);
        let way_home = first
            .as_deref_mut()
            .into_iter()
            .chain(rest.iter_mut())
            .find(|f| f.is_reverse_to(map, timing, home));
        if let (Some(f), Some(at)) = (way_home, bounds.index(pos)) {
            if f.dist_pose(pos, heading).is_some_and(|d| d > far) {
                f.mark_descent(map, at, heading);
            }
        }
        let (first, rest) = (first.map(|f| &*f), &*rest);
        let landmark = first
            .into_iter()
            .chain(rest.iter())
            .find(|f| f.is_reverse_to(map, timing, home));
        let on_someones_way = |v: usize| {
            pending.iter().any(|&(s, (at, h), _)| {
                rest.get(s).is_some_and(|f| f.descent_passes(map, at, h, v))
            })
        };
        // Gated: wait at the node nearest to our home (not to where we
        // stand) that is off every returning robot's way, nobody's home and
        // nobody's place, so that we are close when our turn comes: robots
        // waiting wherever they stood would come home one long trip after
        // another. Then drive there (or stay, if here).
        let places: Vec<usize, MAX_ROBOTS> = peers
            .iter()
            .enumerate()
            .filter(|(i, q)| *i != me && q.known && !q.failed)
            .filter_map(|(_, q)| bounds.index(q.pos))
            .collect();
        let occupied = |v: usize| places.contains(&v);
        // A spot whose way home passes the home of a robot that goes first
        // is a trap: once that robot is in, we could not get out.
        let earlier: Vec<usize, MAX_ROBOTS> = peers
            .iter()
            .enumerate()
            .filter(|(i, q)| {
                let theirs = depth.get(*i).copied().unwrap_or(0);
                *i != me
                    && q.known
                    && !q.failed
                    && (theirs, core::cmp::Reverse(*i)) > (my_depth, core::cmp::Reverse(me))
            })
            .filter_map(|(_, q)| bounds.index(q.home))
            .collect();
        // Spots we cannot reach: the way from here runs through a team mate.
        let mut unreachable: Vec<usize, 4> = Vec::new();
        // Whether `mine` still holds this decision's search from home,
        // stopped at a spot found unreachable: the next spot is then the
        // next free node that search reports, so it goes on instead of
        // starting over (every node before that spot was not free, and a
        // spot set aside as unreachable makes none free). On maze 128²
        // with 16 robots, three spot searches in four had started over:
        // 238 920 searches fell to 66 966, the same run.
        let mut searching = false;
        loop {
            let free = |v: usize| {
                v != my_home
                    && !homes.contains(&bounds.pos(v))
                    && !on_someones_way(v)
                    && !occupied(v)
                    && !unreachable.contains(&v)
            };
            let mut spot = None;
            let mut first = !searching;
            let found = loop {
                let mut reached = |v: usize, _| {
                    if free(v) {
                        spot = Some(v);
                        return Flow::Stop;
                    }
                    Flow::Continue
                };
                let result = if first {
                    mine.compute(map, timing, self.home, Heading::North, &mut reached)
                } else {
                    mine.resume(map, &mut reached)
                };
                first = false;
                let Some(v) = spot.filter(|_| result.is_ok()) else {
                    break result;
                };
                // One walk back for all those homes (in a 16-robot maze a
                // walk per home was a seventh of the run).
                let trapped = match homeward.as_deref_mut() {
                    Some(f) => f.passes_any(map, v, &earlier),
                    None => mine.path_passes_any(map, v, &earlier),
                };
                if !trapped {
                    break result;
                }
                spot = None;
            };
            // None whose cheapest way home is clear: then the nearest that
            // any way leaves without passing those homes. Else, with the
            // homes next to ours filling first and every spot beyond them
            // taken or cut off by the team mates coming home, we stood in
            // their corridor for good (hunt seed 2423).
            searching = found.is_ok() && spot.is_some();
            let found = match (found, spot) {
                (Ok(()), None) => mine.compute_avoiding(
                    map,
                    timing,
                    (self.home, Heading::North),
                    |v| earlier.contains(&v),
                    |v, _| {
                        if free(v) {
                            spot = Some(v);
                            return Flow::Stop;
                        }
                        Flow::Continue
                    },
                ),
                (other, _) => other,
            };
            let computed = match (found, spot) {
                (Ok(()), Some(v)) if bounds.index(pos) != Some(v) => {
                    // Guided by the way home only from afar: near the spot
                    // it says little of the way there, and a plain search
                    // there is small.
                    let spot = bounds.pos(v);
                    let guide = landmark.filter(|l| {
                        let at_spot = Heading::ALL
                            .iter()
                            .filter_map(|&h| l.dist_pose(spot, h))
                            .max();
                        match (l.dist_pose(pos, heading), at_spot) {
                            (Some(here), Some(there)) => {
                                here > there
                                    .saturating_add(GUIDED_FROM_EDGES.saturating_mul(timing.edge))
                            }
                            _ => false,
                        }
                    });
                    // Far from the spot, the way there runs along our way
                    // home to where it meets the spot's own (the ways home
                    // of a kept reverse field form a tree in a maze): two
                    // walks tell whether it passes a team mate, and the
                    // first step is the way home's. A search from here,
                    // even guided by the landmark, settled every side
                    // corridor as deep as the spot lies off our way, at
                    // every step (maze 256², 16 robots: 31 000 searches of
                    // 15 000 poses each, a seventh of the run). A spot
                    // beyond a team mate is out of reach for now.
                    let through_mate = guide.zip(bounds.index(pos)).and_then(|(l, at)| {
                        let out = Heading::ALL
                            .into_iter()
                            .min_by_key(|&h| l.dist_pose(spot, h).unwrap_or(u32::MAX))?;
                        let passes =
                            l.descents_meet_passing(map, (at, heading), (v, out), &places)?;
                        Some((passes, l.way_out(map, at, heading)))
                    });
                    if let Some((passes, next)) = through_mate {
                        if !passes || unreachable.push(v).is_err() {
                            return Decision {
                                goal: Goal::Home,
                                next,
                            };
                        }
                        continue;
                    }
                    // Near the spot, a plain search; from afar only if a way
                    // broke off, then A* guided by the way home.
                    searching = false;
                    match guide {
                        Some(l) => mine
                            .astar_by_landmark(map, timing, pos, heading, spot, l)
                            .map(|_| ()),
                        None => mine.compute_to(map, timing, pos, heading, v),
                    }
                }
                (Ok(()), Some(_)) => return Decision::STAY,
                (other, _) => other,
            };
            let Some(v) = spot.filter(|_| computed.is_ok()) else {
                return Decision::STAY;
            };
            let through_mate = mine.path_passes_any(map, v, &places);
            if !through_mate || unreachable.push(v).is_err() {
                return Decision {
                    goal: Goal::Home,
                    next: mine.first_heading(map, v),
                };
            }
        }
    }
}

/// Marks the pending team mates' ways in their fields, so that asking
/// whether a node is on one of them costs O(1) (see `DistField::mark_way`).
fn mark_ways<M, F>(
    pending: &[(usize, (usize, Heading), bool)],
    rest: &mut [DistField<F>],
    map: &KnownMap<M>,
) where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    for &(s, (at, h), _) in pending {
        if let Some(f) = rest.get_mut(s) {
            f.mark_descent(map, at, h);
        }
    }
}

//! Lower bounds on the makespan that hold under this project's completion
//! rule, and the offline upper reference.
//!
//! ## The rule and why the classic bound breaks
//!
//! Exploration is complete when every reachable node's shape is known and
//! every robot is home. An unvisited node whose four lattice neighbours are
//! visited is known (seed §4.1), so a team need not visit it. The layered
//! bound of exploration-research §2.2 counts every node as must-visit; here,
//! beyond each radius t, we subtract the most nodes a team could skip.
//!
//! The skipped set U is independent in the lattice (a skipped node needs its
//! four neighbours visited), contains no start and only *candidates*: nodes
//! whose four lattice neighbours are reachable field nodes. So
//! |U ∩ {d > t}| ≤ α(C_{>t}), the maximum independent set of the candidates
//! beyond t, which on the bipartite lattice is |C_{>t}| − ν(C_{>t}) (König).
//! The matching ν is grown incrementally as t falls, one distance level at
//! a time (see `Matching`). Any matching M gives |C| − |M| ≥ α, so the
//! bound stays valid at a level where M is not yet maximum, only looser;
//! M is made maximum whenever 1/64 more vertices came in, and at t = 0. On
//! every generated and 2010 field measured the bounds are the ones a
//! maximum matching at every level gives (docs/results/performance.md).
//!
//! ## The bounds, in edge traversals of the busiest robot
//!
//! With M_t = N_{>t} − α(C_{>t}) nodes that must be visited beyond t, and
//! each robot visiting at most one new node per edge, not before its d-th
//! edge and (with return) not after its (E − d)-th:
//! - explore only: E ≥ max_t [t + ⌈M_t / k⌉] over t with M_t ≥ 1;
//! - with return:  E ≥ max_t [2t + 1 + ⌈M_t / k⌉] over t with M_t ≥ 1.
//!
//! The visited set V must also stay connected: the robots' walks cover it
//! from at most k' distinct starts, so the field edges inside V are at least
//! |V| − k'. A skipped node u takes its deg(u) edges out of V and U has no
//! inner edges, so Σ_{u∈U} (deg(u) − 1) ≤ E − n + k' (the cycle budget). The
//! most candidates that fit the budget, cheapest degree first, is a second
//! cap on |U ∩ {d > t}|; the bound uses the smaller cap. On an open grid it
//! allows a third of the nodes to be skipped instead of a half.
//!
//! The budget also holds beyond each radius t, and is tighter there. Shrink
//! the nodes with d ≤ t to one root r: every excursion beyond t is then a
//! closed walk through r, so the visited nodes beyond t, V_t, and r stay
//! connected by the field edges with an end beyond t (E_t of them), less
//! the deg(u) edges of each skipped node: Σ_{u∈U_t} (deg(u) − 1) ≤ E_t − N_t.
//! (E − n + k' is never smaller: the nodes within t form at most k'
//! components.)
//!
//! Bridges count beyond t too. A bridge of the field whose start-free side
//! lies wholly beyond t (its far end has d > t) is a bridge of the shrunk
//! field, and the excursions' union is a closed walk there: every such
//! bridge with a node to visit behind it is driven twice, on top of a tree
//! spanning V_t and r (|V_t| edges). Each robot that goes beyond t drives t
//! edges out and t back besides, so with return
//! E ≥ max_t [2t + ⌈(M_t + B_t) / k⌉], B_t the bridges beyond t. On a maze
//! this doubles every level of the layered bound, not only t = 0.
//!
//! In these closed-walk bounds a skip can cost a drive as well. Say a
//! skipped node u has a neighbour v beyond t (no nearer the starts than u,
//! so never shrunk into the root) whose only other edge e′ is no bridge.
//! Then v is a dead end of the visited nodes, and the walks drive e′ twice.
//! Because e′ is no bridge it is not among B_t. No other skipped node can
//! charge e′ too: that would leave v and e′'s other end, both beyond t,
//! cut off from the root. (Asking e′ not to be a bridge leaves out a lone
//! leaf u on a corridor v, where the bridge is counted already.) Such a
//! skip saves nothing, so these bounds skip only the other candidates,
//! called *free*: M_t is counted over them.
//!
//! And, because every robot ends where it started, a bridge of the field is
//! crossed an even number of times by each robot's closed walk. The union of
//! the walks spans the visited nodes in at most k' components (k' distinct
//! starts), so all robots together drive at least
//! (n − α(C) − k') + B edges, where B counts the bridges whose start-free
//! side holds a node that must be visited (two or more nodes: two
//! neighbours cannot both be skipped; one node: unless it is a candidate).
//! Hence, with return, E ≥ ⌈((n − α(C) − k') + B) / k⌉. On a maze (a tree)
//! this doubles the layered bound. (It is the closed-walk bound beyond
//! t = 0, with every start shrunk into the root.)
//!
//! One drive more, often. In the closed-walk bounds the drives counted are
//! D = |V_t| + B_t (plus the dead ends' drives), the edges of a tree
//! spanning V_t and r with the needed bridges driven twice. The union H
//! of the excursions beyond t is connected through r, so either H has a
//! cycle, and then an edge more than a tree (at least D + 1 drives), or H
//! is a tree, and then every edge of it is driven twice: 2|V_t| drives,
//! at least 2(N_t − S_t) with S_t the most nodes beyond t that can be
//! skipped at all (free or not). So the numerator is D + 1 whenever
//! 2(N_t − S_t) > D (`one_more`). On a maze it seldom is (a tree's walk
//! drives every edge twice, which D already counts); on fields with
//! cycles it nearly always is, but there parity often takes the drive
//! already.
//!
//! Every return bound is even: the lattice is bipartite (each edge joins
//! a node with x + y even to one with x + y odd), so a closed walk has even
//! length, and an odd bound on the busiest robot's walk rounds up.
//!
//! Time bounds multiply by the edge time (turns only add time).

use crate::world::Truth;
use core_algo::geometry::{Heading, Pos};
use core_algo::path::neighbour_index;
use std::collections::VecDeque;

/// The bounds of one (field, start set), in edge traversals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LowerBounds {
    /// Every node must be visited, explore only (exploration-research §2.2).
    pub all_nodes_explore: u64,
    /// Every node must be visited, with the return to the starts.
    pub all_nodes_return: u64,
    /// Valid under the completion rule, explore only.
    pub explore: u64,
    /// Valid under the completion rule, with the return: the bound the
    /// benchmark compares makespans with.
    pub with_return: u64,
    /// Offline upper reference D + ⌈2(n − 1)/k⌉ (known map, explore only).
    pub offline_upper: u64,
    /// Offline upper reference with return, 2D + ⌈2(n − 1)/k⌉.
    pub offline_upper_return: u64,
}

fn bfs(truth: &Truth, sources: &[usize]) -> Vec<u32> {
    let mut dist = vec![u32::MAX; truth.bounds().area()];
    let mut q = VecDeque::new();
    for &s in sources {
        if dist.get(s) == Some(&u32::MAX) {
            dist[s] = 0;
            q.push_back(s);
        }
    }
    while let Some(i) = q.pop_front() {
        for h in Heading::ALL {
            if let Some(j) = truth.along(i, h) {
                if dist[j] == u32::MAX {
                    dist[j] = dist[i] + 1;
                    q.push_back(j);
                }
            }
        }
    }
    dist
}

/// Incremental maximum matching on the lattice graph of the candidates.
///
/// Vertices come in one distance level at a time, each matched greedily to
/// a free neighbour; `settle` then matches in phases (Kuhn's algorithm
/// with one visited stamp per phase): a search from every free vertex of
/// one colour (an augmenting path joins a free vertex of each colour),
/// until a phase finds no augmenting path; then the matching is maximum.
/// Settling at every level made a 1024² maze's bound take minutes (stop
/// 19); settling at every 1/64 growth takes 4 s. One depth-first search
/// per added vertex,
/// as before stop 19, explored the whole alternating tree at every vertex
/// that could not be matched: on open 256² that took 15 s, more than the
/// 16-robot run it bounds.
struct Matching {
    mate: Vec<usize>,
    present: Vec<bool>,
    stamp: Vec<u32>,
    round: u32,
    size: usize,
    /// Free present vertices of the searched colour.
    left: Vec<usize>,
    /// The augmenting search's frames, kept between searches.
    stack: Vec<(usize, usize, usize)>,
    /// Vertices present.
    count: usize,
    /// Vertices added since the last `settle`.
    pending: usize,
}

/// `Matching::settle` runs once the vertices added since the last time
/// make up this share (1 / SETTLE_SHARE) of those present, and at the
/// last level.
const SETTLE_SHARE: usize = 64;

const NONE: usize = usize::MAX;

impl Matching {
    fn new(area: usize) -> Matching {
        Matching {
            mate: vec![NONE; area],
            present: vec![false; area],
            stamp: vec![0; area],
            round: 0,
            size: 0,
            left: Vec::new(),
            stack: Vec::new(),
            count: 0,
            pending: 0,
        }
    }

    /// Searches an augmenting path from the free vertex `root` (depth
    /// first, skipping vertices stamped this round) and flips it.
    fn augment(&mut self, truth: &Truth, root: usize) -> bool {
        // An explicit stack, not recursion: an augmenting path can be as
        // long as the field is large, too deep for the thread's stack on a
        // 1024² field. A frame is (vertex, next heading to try, the
        // neighbour it went on through).
        let b = truth.bounds();
        let mut stack = core::mem::take(&mut self.stack);
        stack.clear();
        stack.push((root, 0usize, NONE));
        let mut found = false;
        while let Some(&(v, next, _)) = stack.last() {
            let Some(&h) = Heading::ALL.get(next) else {
                stack.pop();
                continue;
            };
            if let Some(top) = stack.last_mut() {
                top.1 += 1;
            }
            let Some(u) = neighbour_index(b, v, h) else {
                continue;
            };
            if !self.present[u] || self.stamp[u] == self.round {
                continue;
            }
            self.stamp[u] = self.round;
            if let Some(top) = stack.last_mut() {
                top.2 = u;
            }
            let w = self.mate[u];
            if w == NONE {
                found = true;
                break;
            }
            stack.push((w, 0, NONE));
        }
        if found {
            for &(v, _, u) in &stack {
                self.mate[u] = v;
                self.mate[v] = u;
            }
        }
        self.stack = stack;
        found
    }

    /// Adds the vertices `vs`, each matched to a free present neighbour
    /// where it has one (greedy: the matching stays a matching, so
    /// |C| − |M| stays an upper bound of α, just not always the least).
    fn add_level(&mut self, truth: &Truth, vs: &[usize]) {
        let b = truth.bounds();
        for &v in vs {
            self.present[v] = true;
            self.count += 1;
            self.pending += 1;
            let p = b.pos(v);
            if (p.x + p.y).rem_euclid(2) == 0 {
                self.left.push(v);
            }
            let free = Heading::ALL.iter().find_map(|&h| {
                neighbour_index(b, v, h).filter(|&u| self.present[u] && self.mate[u] == NONE)
            });
            if let Some(u) = free {
                self.mate[u] = v;
                self.mate[v] = u;
                self.size += 1;
            }
        }
    }

    /// Whether enough vertices came in since the last `settle` to settle
    /// again: one in `SETTLE_SHARE` of those present. Settling at every
    /// level costs a phase over every free vertex per level; a 1024² maze
    /// has hundreds of thousands of levels, and that took minutes.
    fn due(&self) -> bool {
        self.pending > 0 && self.pending * SETTLE_SHARE >= self.count
    }

    /// Augments in phases until no augmenting path is left: the matching
    /// is then maximum on the vertices present.
    fn settle(&mut self, truth: &Truth) {
        self.pending = 0;
        loop {
            self.round += 1;
            let mut grew = false;
            let mut left = core::mem::take(&mut self.left);
            // Matched vertices stay matched: only the free ones are kept.
            left.retain(|&v| {
                if self.mate[v] == NONE && self.augment(truth, v) {
                    self.size += 1;
                    grew = true;
                }
                self.mate[v] == NONE
            });
            self.left = left;
            if !grew {
                break;
            }
        }
    }
}

/// The bounds for `k` robots starting on `starts` (distinct or not).
pub fn lower_bounds(truth: &Truth, starts: &[Pos], k: usize) -> LowerBounds {
    let k = k.max(1) as u64;
    let b = truth.bounds();
    let sources: Vec<usize> = starts.iter().filter_map(|&p| b.index(p)).collect();
    let dist = bfs(truth, &sources);
    let reach = |i: usize| dist.get(i).is_some_and(|&d| d != u32::MAX);
    let ecc = truth
        .indices()
        .filter(|&i| reach(i))
        .map(|i| dist[i])
        .max()
        .unwrap_or(0) as usize;
    let n = truth.indices().filter(|&i| reach(i)).count() as u64;
    let is_start: Vec<bool> = {
        let mut v = vec![false; b.area()];
        for &s in &sources {
            v[s] = true;
        }
        v
    };
    let candidate = |i: usize| {
        reach(i)
            && !is_start[i]
            && Heading::ALL.iter().all(|&h| {
                neighbour_index(b, i, h).is_some_and(|j| truth.arms_at(j).is_some() && reach(j))
            })
    };
    // The cycle budget E − n + k' and candidates beyond t by degree.
    let k_distinct = {
        let mut d = sources.clone();
        d.sort_unstable();
        d.dedup();
        d.len() as u64
    };
    let degree = |i: usize| truth.arms_at(i).map_or(0, |a| a.count()) as usize;
    // Edges by their farther end's distance: the local cycle budget
    // beyond t counts the edges with an end beyond t, the global one all.
    let mut edges_at = vec![0u64; ecc + 1];
    for i in truth.indices().filter(|&i| reach(i)) {
        for h in [Heading::North, Heading::East] {
            if let Some(j) = truth.along(i, h).filter(|&j| reach(j)) {
                edges_at[dist[i].max(dist[j]) as usize] += 1;
            }
        }
    }
    let budget = (edges_at.iter().sum::<u64>() + k_distinct).saturating_sub(n);
    let mut by_degree = [0u64; 5];
    let fit = |by_degree: &[u64; 5], budget: u64| -> u64 {
        let mut left = budget;
        let mut count = by_degree[0] + by_degree[1];
        for (d, &c) in by_degree.iter().enumerate().skip(2) {
            let cost = d as u64 - 1;
            let take = c.min(left / cost);
            count += take;
            left -= take * cost;
        }
        count
    };
    let mut by_dist: Vec<Vec<usize>> = vec![Vec::new(); ecc + 1];
    for i in truth.indices().filter(|&i| reach(i)) {
        by_dist[dist[i] as usize].push(i);
    }
    let mut edges_beyond = 0u64;
    // Needed bridges by their far end's distance (see the module docs).
    let (b_needed, b_all, far_ends, bridge_arms) =
        needed_bridges(truth, &dist, &is_start, &candidate);
    // A candidate is *free* to skip for a closed walk unless a neighbour v
    // (no nearer the starts) has one other edge, not a bridge: skipping it
    // leaves v a dead end, whose edge the walk then drives twice (see the
    // module docs).
    let free = |u: usize| {
        !Heading::ALL.iter().any(|&h| {
            truth.along(u, h).is_some_and(|v| {
                dist[v] >= dist[u]
                    && degree(v) == 2
                    && Heading::ALL.iter().any(|&h2| {
                        h2 != h.opposite()
                            && truth.along(v, h2).is_some()
                            && bridge_arms[v] & 1 << h2.index() == 0
                    })
            })
        })
    };
    let mut free_by_degree = [0u64; 5];
    let mut free_cands = 0u64;
    // While every candidate so far is free (on a tree, all are), the free
    // candidates' matching is `m` itself: `mf` is only built, from
    // `free_seen`, once one is not (it doubled a 1024² maze's bound time).
    let mut mf = Matching::new(b.area());
    let mut free_level = Vec::new();
    let mut free_seen = Vec::new();
    let mut mirror = true;
    let mut bridges_at = vec![0u64; ecc + 1];
    for d in far_ends {
        if let Some(c) = bridges_at.get_mut(d as usize) {
            *c += 1;
        }
    }
    let mut bridges_beyond = 0u64;
    let mut m = Matching::new(b.area());
    let mut level = Vec::new();
    let (mut beyond, mut cands) = (0u64, 0u64);
    let (mut ae, mut ar, mut se, mut sr) = (0u64, 0u64, 0u64, 0u64);
    // α of the free candidates beyond t (at the end: of all of them).
    let mut alpha_free = 0u64;
    // The most nodes beyond t = 0 skipped, free or not.
    let mut skip_at_0 = 0u64;
    // t runs from ecc down to 0; `beyond` counts nodes with d > t.
    for t in (0..=ecc).rev() {
        if t < ecc {
            level.clear();
            free_level.clear();
            edges_beyond += edges_at[t + 1];
            bridges_beyond += bridges_at[t + 1];
            for &i in &by_dist[t + 1] {
                beyond += 1;
                if candidate(i) {
                    cands += 1;
                    by_degree[degree(i).min(4)] += 1;
                    level.push(i);
                    if free(i) {
                        free_cands += 1;
                        free_by_degree[degree(i).min(4)] += 1;
                        free_level.push(i);
                    }
                }
            }
            m.add_level(truth, &level);
            if t == 0 || m.due() {
                m.settle(truth);
            }
            if mirror {
                free_seen.extend_from_slice(&free_level);
                if free_cands < cands {
                    mirror = false;
                    mf.add_level(truth, &free_seen);
                    mf.settle(truth);
                    free_seen = Vec::new();
                }
            } else {
                mf.add_level(truth, &free_level);
                if t == 0 || mf.due() {
                    mf.settle(truth);
                }
            }
        }
        let t64 = t as u64;
        if beyond >= 1 {
            ae = ae.max(t64 + beyond.div_ceil(k));
            ar = ar.max(2 * t64 + 1 + beyond.div_ceil(k));
        }
        let local = edges_beyond.saturating_sub(beyond);
        let skip = (cands - m.size as u64).min(fit(&by_degree, local));
        skip_at_0 = skip;
        let must = beyond - skip;
        if must >= 1 {
            se = se.max(t64 + must.div_ceil(k));
            sr = sr.max(2 * t64 + 1 + must.div_ceil(k));
        }
        alpha_free = if mirror {
            cands - m.size as u64
        } else {
            free_cands - mf.size as u64
        };
        let skip_free = alpha_free.min(fit(&free_by_degree, local));
        let visit = beyond - skip_free;
        if visit >= 1 {
            let more = one_more(visit + bridges_beyond, beyond - skip);
            sr = sr.max(2 * t64 + (visit + bridges_beyond + more).div_ceil(k));
        }
    }
    // The bridge bound (return only), with and without skipping.
    let k_d = k_distinct;
    let alpha = alpha_free.min(fit(&free_by_degree, budget));
    let visit = n.saturating_sub(alpha + k_d);
    let more = one_more(visit + b_needed, n.saturating_sub(k_d + skip_at_0));
    sr = sr.max((visit + b_needed + more).div_ceil(k));
    ar = ar.max((n.saturating_sub(k_d) + b_all).div_ceil(k));
    let diam = sources
        .iter()
        .map(|&s| {
            bfs(truth, &[s])
                .into_iter()
                .filter(|&d| d != u32::MAX)
                .max()
                .unwrap_or(0)
        })
        .max()
        .unwrap_or(0) as u64;
    let tour = (2 * n.saturating_sub(1)).div_ceil(k);
    // The lattice is bipartite, so every robot's closed walk home is of
    // even length, and so is the busiest one's: an odd bound rounds up.
    let (ar, sr) = (ar.next_multiple_of(2), sr.next_multiple_of(2));
    LowerBounds {
        all_nodes_explore: ae,
        all_nodes_return: ar,
        explore: se,
        with_return: sr,
        offline_upper: diam + tour,
        offline_upper_return: 2 * diam + tour,
    }
}

/// 1 if the closed-walk drives beyond a radius can be shown to be one more
/// than `drives` (the visits plus the needed bridges, see the module docs):
/// the walks' union beyond t with the root is either a tree, every edge of
/// it driven twice, at least `2 × least_visited` drives, or it has a cycle
/// and so an edge more than a tree.
fn one_more(drives: u64, least_visited: u64) -> u64 {
    u64::from(2 * least_visited > drives)
}

/// Bridges whose start-free side must be entered: (under the skipping rule,
/// with every node must-visit), and the distance of each needed one's far
/// end (on the start-free side). Iterative Tarjan over the reachable field.
fn needed_bridges(
    truth: &Truth,
    dist: &[u32],
    is_start: &[bool],
    candidate: &dyn Fn(usize) -> bool,
) -> (u64, u64, Vec<u32>, Vec<u8>) {
    let area = truth.bounds().area();
    let Some(root) = (0..area).find(|&i| is_start.get(i) == Some(&true)) else {
        return (0, 0, Vec::new(), vec![0b1111; area]);
    };
    let reach = |i: usize| dist.get(i).is_some_and(|&d| d != u32::MAX);
    let total_nodes = (0..area)
        .filter(|&i| reach(i) && truth.arms_at(i).is_some())
        .count() as u64;
    let total_starts = (0..area).filter(|&i| is_start[i]).count() as u64;
    let total_noncand = (0..area)
        .filter(|&i| reach(i) && truth.arms_at(i).is_some() && !candidate(i))
        .count() as u64;
    let mut disc = vec![u32::MAX; area];
    let mut low = vec![0u32; area];
    // Per node: subtree size, starts and non-candidates.
    let mut size = vec![0u64; area];
    let mut starts = vec![0u64; area];
    let mut noncand = vec![0u64; area];
    let (mut needed, mut all) = (0u64, 0u64);
    let mut far_ends = Vec::new();
    let mut bridge_arms = vec![0u8; area];
    let mut time = 0u32;
    // Stack frames: (node, parent, next heading index).
    let mut stack: Vec<(usize, usize, usize)> = vec![(root, usize::MAX, 0)];
    disc[root] = 0;
    low[root] = 0;
    while let Some(&mut (v, parent, ref mut next)) = stack.last_mut() {
        if *next < 4 {
            let h = Heading::ALL[*next];
            *next += 1;
            let Some(u) = truth.along(v, h) else { continue };
            if u == parent {
                continue;
            }
            if disc[u] == u32::MAX {
                time += 1;
                disc[u] = time;
                low[u] = time;
                stack.push((u, v, 0));
            } else {
                low[v] = low[v].min(disc[u]);
            }
            continue;
        }
        stack.pop();
        size[v] += 1;
        starts[v] += u64::from(is_start[v]);
        noncand[v] += u64::from(!candidate(v));
        if parent == usize::MAX {
            continue;
        }
        low[parent] = low[parent].min(low[v]);
        size[parent] += size[v];
        starts[parent] += starts[v];
        noncand[parent] += noncand[v];
        if low[v] > disc[parent] {
            // (parent, v) is a bridge; find its start-free side.
            for h in Heading::ALL {
                if truth.along(parent, h) == Some(v) {
                    bridge_arms[parent] |= 1 << h.index();
                    bridge_arms[v] |= 1 << h.opposite().index();
                }
            }
            let side = if starts[v] == 0 {
                Some((size[v], noncand[v], v))
            } else if starts[v] == total_starts {
                Some((total_nodes - size[v], total_noncand - noncand[v], parent))
            } else {
                None
            };
            if let Some((n, nc, far)) = side {
                if n >= 1 {
                    all += 1;
                }
                if n >= 2 || nc >= 1 {
                    needed += 1;
                    far_ends.push(dist.get(far).copied().unwrap_or(0));
                }
            }
        }
    }
    // Outside the searched component nothing is known: call every arm
    // there a bridge, which makes no skip costly.
    for (arms, &d) in bridge_arms.iter_mut().zip(&disc) {
        if d == u32::MAX {
            *arms = 0b1111;
        }
    }
    (needed, all, far_ends, bridge_arms)
}

#[cfg(test)]
mod tests;

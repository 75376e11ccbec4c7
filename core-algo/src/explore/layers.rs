//! The seed's explorer (seed §4.1): a chain of cost layers over the frontier.
//!
//! - Layer 0, distance: the turn-aware travel time from the robot, from one
//!   distance field per decision (never one A* per frontier).
//! - Layer 1, residual areas: +1 edge for a frontier node enclosed by
//!   explored area, so that large unexplored regions are preferred.
//! - Layer 2, cooperation: around another robot's announced target, +5 edges
//!   on the target, +4 on its Manhattan neighbours, … down to +1 at distance
//!   4; where obstacles or unknown area block the direct route between the
//!   two nodes, that node gets nothing.
//!
//! The 2010 code overwrote layer 2 with layer 0 and left layer 1 out of the
//! chain (original-system §3.4); here the costs add up as designed. Weights
//! are in edges and converted to ticks with [`Timing::edge`](crate::timing::Timing::edge), so "one" means
//! "as costly as driving one more edge".

use super::{Context, Decision, Strategy, cheapest_frontier, explore_decision, go_home};
use crate::geometry::{Heading, Pos};
use crate::map::{Block, KnownMap};
use crate::path::{DistField, PlanCell, PlanError, arms_at};
use crate::timing::Ticks;

/// One layer of the seed's chain: a non-negative extra cost for a frontier
/// node. Non-negative, so that the explorer can stop its distance field as
/// soon as the distance alone exceeds the best sum.
pub trait Layer<M> {
    /// The layer's name, for logs.
    fn name(&self) -> &'static str;

    /// The extra cost of frontier node `p` (storage index `i`) for the
    /// deciding robot.
    fn cost(&self, ctx: &Context<'_, M>, i: usize, p: Pos) -> Ticks;
}

/// Layer 1: a frontier node enclosed by explored area costs `weight` edges
/// more. Enclosed, as in the 2010 InnerBehaviour: looking along ±x and ±y
/// from the node, each ray meets a visited node within `reach` nodes.
#[derive(Clone, Copy, Debug)]
pub struct ResidualLayer {
    /// Extra cost in edges (the seed: 1).
    pub weight: u32,
    /// How far a ray looks for a visited node.
    pub reach: u16,
}

impl ResidualLayer {
    /// Whether `p` is enclosed by visited nodes within `reach` on all four
    /// rays.
    pub fn enclosed<M: AsRef<[Block]> + AsMut<[Block]>>(&self, map: &KnownMap<M>, p: Pos) -> bool {
        Heading::ALL.iter().all(|&h| {
            let mut q = p;
            for _ in 0..self.reach {
                match q.step(h) {
                    Some(n) if map.bounds().contains(n) => q = n,
                    _ => return false,
                }
                if map.is_visited(q) {
                    return true;
                }
            }
            false
        })
    }
}

impl<M: AsRef<[Block]> + AsMut<[Block]>> Layer<M> for ResidualLayer {
    fn name(&self) -> &'static str {
        "residual"
    }

    fn cost(&self, ctx: &Context<'_, M>, _i: usize, p: Pos) -> Ticks {
        if self.weight > 0 && self.enclosed(ctx.map, p) {
            self.weight.saturating_mul(ctx.timing.edge)
        } else {
            0
        }
    }
}

/// Layer 2: cooperation. For every other robot's announced target `a`, a
/// frontier node `p` with `d = |p − a|₁ ≤ radius` whose direct route to `a`
/// is open costs `peak − d` edges more (the seed: peak 5, radius 4).
#[derive(Clone, Copy, Debug)]
pub struct CooperationLayer {
    /// Extra cost on the announced target itself, in edges.
    pub peak: u32,
    /// The largest Manhattan distance that still gets a penalty.
    pub radius: u32,
}

impl CooperationLayer {
    /// The penalty in edges for a node at Manhattan distance `d` from an
    /// announced target, before the route check.
    pub fn penalty_edges(&self, d: u32) -> u32 {
        if d <= self.radius {
            self.peak.saturating_sub(d)
        } else {
            0
        }
    }

    /// Whether a monotone lattice path (one of Manhattan length) joins `a`
    /// and `p` through known nodes along known arms: the seed's "direct
    /// route". An edge between two unknown nodes counts as open (nothing is
    /// known to block it); any unknown node strictly between blocks.
    pub fn direct_route_open<M: AsRef<[Block]> + AsMut<[Block]>>(
        map: &KnownMap<M>,
        a: Pos,
        p: Pos,
    ) -> bool {
        let dx = i32::from(p.x) - i32::from(a.x);
        let dy = i32::from(p.y) - i32::from(a.y);
        let (w, h) = (dx.unsigned_abs() as usize, dy.unsigned_abs() as usize);
        // Reachability over the (w+1) × (h+1) box, at most 9 × 9 for the
        // radii in use; larger boxes are refused as blocked.
        const SIDE: usize = 9;
        if w >= SIDE || h >= SIDE {
            return false;
        }
        let hx = if dx >= 0 {
            Heading::East
        } else {
            Heading::West
        };
        let hy = if dy >= 0 {
            Heading::North
        } else {
            Heading::South
        };
        let bounds = map.bounds();
        let at = |i: usize, j: usize| -> Pos {
            let x = i32::from(a.x) + if dx >= 0 { i as i32 } else { -(i as i32) };
            let y = i32::from(a.y) + if dy >= 0 { j as i32 } else { -(j as i32) };
            Pos::new(x as i16, y as i16)
        };
        let known = |q: Pos| bounds.index(q).and_then(|k| arms_at(map, k));
        let edge_open = |from: Pos, to: Pos, hd: Heading| -> bool {
            match (known(from), known(to)) {
                (Some(f), _) => f.has(hd),
                (None, Some(t)) => t.has(hd.opposite()),
                (None, None) => true,
            }
        };
        let mut reach = [[false; SIDE]; SIDE];
        for j in 0..=h {
            for i in 0..=w {
                let q = at(i, j);
                let ok = if i == 0 && j == 0 {
                    true
                } else {
                    let interior = !(i == w && j == h);
                    if interior && known(q).is_none() {
                        false
                    } else {
                        let from_x = i > 0
                            && reach.get(j).and_then(|r| r.get(i - 1)).copied() == Some(true)
                            && edge_open(at(i - 1, j), q, hx);
                        let from_y = j > 0
                            && reach.get(j - 1).and_then(|r| r.get(i)).copied() == Some(true)
                            && edge_open(at(i, j - 1), q, hy);
                        from_x || from_y
                    }
                };
                if let Some(cell) = reach.get_mut(j).and_then(|r| r.get_mut(i)) {
                    *cell = ok;
                }
            }
        }
        reach.get(h).and_then(|r| r.get(w)).copied() == Some(true)
    }
}

impl<M: AsRef<[Block]> + AsMut<[Block]>> Layer<M> for CooperationLayer {
    fn name(&self) -> &'static str {
        "cooperation"
    }

    fn cost(&self, ctx: &Context<'_, M>, _i: usize, p: Pos) -> Ticks {
        let mut edges = 0u32;
        for (j, r) in ctx.robots.iter().enumerate() {
            if j == ctx.me {
                continue;
            }
            let Some(a) = r.target else { continue };
            let d = p.manhattan(a);
            let pen = self.penalty_edges(d);
            if pen > 0 && Self::direct_route_open(ctx.map, a, p) {
                edges = edges.saturating_add(pen);
            }
        }
        edges.saturating_mul(ctx.timing.edge)
    }
}

/// The weights of the seed's explorer.
#[derive(Clone, Copy, Debug)]
pub struct SeedConfig {
    /// Layer 1.
    pub residual: ResidualLayer,
    /// Layer 2.
    pub cooperation: CooperationLayer,
}

impl Default for SeedConfig {
    /// The seed's numbers: +1 enclosed (rays of 16 nodes), +5 … +1 around
    /// announced targets.
    fn default() -> Self {
        SeedConfig {
            residual: ResidualLayer {
                weight: 1,
                reach: 16,
            },
            cooperation: CooperationLayer { peak: 5, radius: 4 },
        }
    }
}

/// The seed's explorer: the frontier node with the smallest sum of layers 0,
/// 1 and 2; ties to the smaller storage index.
#[derive(Clone, Copy, Debug, Default)]
pub struct SeedExplorer {
    /// Its weights.
    pub config: SeedConfig,
}

impl SeedExplorer {
    /// The layered cost of every frontier node is distance + Σ layers;
    /// returns the cheapest (index, total) from `field`, computed from the
    /// deciding robot's pose.
    pub fn choose<M, F>(
        &self,
        ctx: &Context<'_, M>,
        field: &mut DistField<F>,
    ) -> Result<Option<(usize, Ticks)>, PlanError>
    where
        M: AsRef<[Block]> + AsMut<[Block]>,
        F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
    {
        let layers: [&dyn Layer<M>; 2] = [&self.config.residual, &self.config.cooperation];
        cheapest_frontier(ctx, field, |i, p, _| {
            Some(layers.iter().map(|l| l.cost(ctx, i, p)).sum())
        })
    }
}

impl<M, F> Strategy<M, F> for SeedExplorer
where
    M: AsRef<[Block]> + AsMut<[Block]>,
    F: AsRef<[PlanCell]> + AsMut<[PlanCell]>,
{
    fn name(&self) -> &'static str {
        "seed"
    }

    fn decide(
        &mut self,
        ctx: &Context<'_, M>,
        fields: &mut [DistField<F>],
    ) -> Result<Decision, PlanError> {
        let Some(field) = fields.first_mut() else {
            return Ok(Decision::STAY);
        };
        match self.choose(ctx, field)? {
            Some((i, _)) => Ok(explore_decision(ctx, field, i)),
            None => go_home(ctx, field),
        }
    }
}

//! Shared helpers for the criterion benches.

use core_algo::geometry::Pos;
use core_algo::map::{Block, KnownMap, blocks_for};
use core_algo::team::RobotId;
use phone_sim::field::Field;

/// Half of `f` known, visited in BFS order from its first start: the map,
/// the BFS order and the number of known nodes (the first `half` of it).
/// Decision benches place their robots on that known half.
pub fn half_known(f: &Field) -> (KnownMap<Vec<Block>>, Vec<Pos>, usize) {
    let order = f.bfs_order(f.starts()[0].pos);
    let half = order.len() / 2;
    (bfs_known(f, &order, half), order, half)
}

/// The map of `f` with the first `known` nodes of `order` visited.
pub fn bfs_known(f: &Field, order: &[Pos], known: usize) -> KnownMap<Vec<Block>> {
    let b = f.bounds();
    let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).expect("capacity");
    for p in &order[..known] {
        let _ = map.visit(*p, f.arms(*p).unwrap_or_default(), RobotId(0));
    }
    map
}

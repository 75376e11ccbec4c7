//! The host's whole fields of complete maps, for every agent it runs (see
//! [`core_algo::agent::SharedFields`]): each team mate's home field is
//! searched once per team, not once per robot.
//!
//! A field or depth is handed over only for a map with the print of the
//! map it was worked out on ([`MapPrint`]: maps that read the same at every
//! node), in the same window and with the same timing, so what this holds
//! (another robot's field, another run's) never changes a decision.

use core_algo::agent::SharedFields;
use core_algo::geometry::Pos;
use core_algo::map::{Block, Bounds, KnownMap, MapPrint};
use core_algo::path::{DistField, PlanCell, min_cells};
use core_algo::timing::Timing;
use std::collections::VecDeque;
use std::sync::Mutex;

/// Bytes of fields kept at most, oldest out first: a 256² team of 16
/// needs 16 fields of about 1 MiB.
const MAX_BYTES: usize = 64 << 20;

/// See the module docs.
pub struct HostFields {
    kept: Mutex<VecDeque<Kept>>,
    /// Homes' depths (see [`SharedFields::home_depth`]), newest last.
    depths: Mutex<VecDeque<Depth>>,
}

/// Home depths kept at most, oldest out first: 16 a team.
const MAX_DEPTHS: usize = 256;

/// What a kept field or depth was worked out over: a map with this print,
/// in this window, with this timing.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Over {
    timing: Timing,
    bounds: Bounds,
    print: MapPrint,
}

impl Over {
    fn of<M: AsRef<[Block]> + AsMut<[Block]>>(map: &KnownMap<M>, timing: Timing) -> Over {
        Over {
            timing,
            bounds: map.bounds(),
            print: map.print(),
        }
    }
}

/// One home's depth.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Depth {
    home: Pos,
    over: Over,
    depth: u64,
}

impl std::fmt::Debug for HostFields {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.kept.lock().map_or(0, |k| k.len());
        f.debug_struct("HostFields").field("kept", &n).finish()
    }
}

/// One whole reverse field to `goal`.
struct Kept {
    goal: Pos,
    over: Over,
    field: DistField<Vec<PlanCell>>,
}

impl Kept {
    fn bytes(&self) -> usize {
        min_cells(self.over.bounds.area()) * size_of::<PlanCell>()
    }
}

impl HostFields {
    /// Nothing kept yet.
    pub const fn new() -> HostFields {
        HostFields {
            kept: Mutex::new(VecDeque::new()),
            depths: Mutex::new(VecDeque::new()),
        }
    }
}

impl Default for HostFields {
    fn default() -> Self {
        HostFields::new()
    }
}

/// The fields every host-side agent shares.
pub static HOST_FIELDS: HostFields = HostFields::new();

impl SharedFields<Vec<Block>, Vec<PlanCell>> for HostFields {
    fn recall_reverse(
        &self,
        map: &KnownMap<Vec<Block>>,
        timing: Timing,
        goal: Pos,
        field: &mut DistField<Vec<PlanCell>>,
    ) -> bool {
        // A poisoned lock only means another thread panicked while holding
        // it: every entry in it is whole.
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let over = Over::of(map, timing);
        kept.iter()
            .rev()
            .find(|k| k.goal == goal && k.over == over)
            .is_some_and(|k| field.copy_reverse_from(&k.field, map))
    }

    fn keep_reverse(
        &self,
        map: &KnownMap<Vec<Block>>,
        timing: Timing,
        goal: Pos,
        field: &DistField<Vec<PlanCell>>,
    ) {
        let bounds = map.bounds();
        let mut copy = DistField::new(vec![PlanCell::EMPTY; min_cells(bounds.area())]);
        if !copy.copy_reverse_from(field, map) {
            return;
        }
        let new = Kept {
            goal,
            over: Over::of(map, timing),
            field: copy,
        };
        if new.bytes() > MAX_BYTES {
            return;
        }
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if kept.iter().any(|k| k.goal == goal && k.over == new.over) {
            return;
        }
        kept.push_back(new);
        while kept.iter().map(Kept::bytes).sum::<usize>() > MAX_BYTES {
            kept.pop_front();
        }
    }

    fn home_depth(&self, map: &KnownMap<Vec<Block>>, timing: Timing, home: Pos) -> Option<u64> {
        let over = Over::of(map, timing);
        let depths = self.depths.lock().unwrap_or_else(|e| e.into_inner());
        depths
            .iter()
            .rev()
            .find(|d| d.home == home && d.over == over)
            .map(|d| d.depth)
    }

    fn keep_home_depth(&self, map: &KnownMap<Vec<Block>>, timing: Timing, home: Pos, depth: u64) {
        let new = Depth {
            home,
            over: Over::of(map, timing),
            depth,
        };
        let mut depths = self.depths.lock().unwrap_or_else(|e| e.into_inner());
        if !depths.contains(&new) {
            depths.push_back(new);
            if depths.len() > MAX_DEPTHS {
                depths.pop_front();
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use core_algo::geometry::{Arms, Heading};
    use core_algo::map::blocks_for;
    use core_algo::path::Flow;
    use core_algo::team::RobotId;

    /// A corridor of `len` nodes in a 12-node window, known whole, learnt
    /// from west to east or east to west (also `columns`' tests).
    pub(crate) fn corridor(len: u16, eastward: bool) -> KnownMap<Vec<Block>> {
        let b = Bounds::new(Pos::new(0, 0), 12, 1);
        let mut map = KnownMap::new(vec![Block::EMPTY; blocks_for(b.area())], b).unwrap();
        let xs: Vec<u16> = if eastward {
            (0..len).collect()
        } else {
            (0..len).rev().collect()
        };
        for x in xs {
            let bits = u8::from(x > 0) << Heading::West.index()
                | u8::from(x + 1 < len) << Heading::East.index();
            let x = i16::try_from(x).unwrap();
            map.visit(Pos::new(x, 0), Arms::from_bits(bits), RobotId(0))
                .unwrap();
        }
        map
    }

    fn field() -> DistField<Vec<PlanCell>> {
        DistField::new(vec![PlanCell::EMPTY; min_cells(12)])
    }

    /// A field kept for one map is handed to a robot whose map reads the
    /// same (learnt in another order), as the field it would search; not
    /// for another goal or timing, nor for a map that reads otherwise.
    #[test]
    fn a_kept_field_goes_only_to_maps_that_read_the_same() {
        let host = HostFields::new();
        let t = Timing {
            edge: 10,
            quarter_turn: 5,
        };
        let (a, b) = (corridor(12, true), corridor(12, false));
        let goal = Pos::new(3, 0);
        let mut searched = field();
        searched
            .compute_reverse(&a, t, goal, |_, _, _| Flow::Continue)
            .unwrap();
        let mut mine = field();
        assert!(
            !host.recall_reverse(&b, t, goal, &mut mine),
            "nothing kept yet"
        );
        host.keep_reverse(&a, t, goal, &searched);
        assert!(host.recall_reverse(&b, t, goal, &mut mine));
        assert!(mine.is_reverse_to(&b, t, goal));
        let mut fresh = field();
        fresh
            .compute_reverse(&b, t, goal, |_, _, _| Flow::Continue)
            .unwrap();
        for v in 0..12 {
            for h in Heading::ALL {
                assert_eq!(mine.dist_pose_at(v, h), fresh.dist_pose_at(v, h));
            }
        }
        let slower = Timing { edge: 20, ..t };
        assert!(!host.recall_reverse(&b, slower, goal, &mut field()));
        assert!(!host.recall_reverse(&b, t, Pos::new(4, 0), &mut field()));
        // One node fewer known: another map.
        assert!(!host.recall_reverse(&corridor(11, true), t, goal, &mut field()));
    }

    /// A home's depth kept for one map is told to a robot whose map reads
    /// the same (learnt in another order), not for another home, timing
    /// or map.
    #[test]
    fn a_home_depth_goes_only_to_maps_that_read_the_same() {
        let host = HostFields::new();
        let t = Timing {
            edge: 10,
            quarter_turn: 5,
        };
        let (a, b) = (corridor(12, true), corridor(12, false));
        let home = Pos::new(0, 0);
        assert_eq!(host.home_depth(&b, t, home), None, "nothing kept yet");
        host.keep_home_depth(&a, t, home, 1234);
        assert_eq!(host.home_depth(&b, t, home), Some(1234));
        assert_eq!(host.home_depth(&b, t, Pos::new(1, 0)), None);
        let slower = Timing { edge: 20, ..t };
        assert_eq!(host.home_depth(&b, slower, home), None);
        assert_eq!(host.home_depth(&corridor(11, true), t, home), None);
    }
}

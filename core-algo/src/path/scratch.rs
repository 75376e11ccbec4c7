//! The planner's scratch: one 16-byte [`PlanCell`] per node of the map
//! window, the diamond of cells a search dirtied, and where a stopped search
//! stands (see the `path` module docs for the layout and why).

use crate::timing::Ticks;

pub(super) const DIST_MASK: u32 = 0x0FFF_FFFF;
pub(super) const SETTLED_SHIFT: u32 = 28;
pub(super) const NO_OFF: u8 = u8::MAX;
/// A node on the marked way (see [`DistField::mark_way`](super::DistField::mark_way)): the top bit of a
/// cell's second ring slot, which a queue entry (below 8 × area < 2^31)
/// never sets.
pub(super) const ON_WAY: u32 = 1 << 31;

/// The largest distance a field holds (about 31 days at 10 ms ticks);
/// farther states are left unreached.
pub const MAX_DIST: Ticks = DIST_MASK - 1;

/// The planner's scratch for one node: 16 bytes. See the module docs.
#[derive(Clone, Copy, Debug)]
pub struct PlanCell {
    pub(super) base: u32,
    pub(super) off: [u8; 4],
    pub(super) ring_a: u32,
    pub(super) ring_b: u32,
}

impl PlanCell {
    /// A cell that nothing has reached.
    pub const EMPTY: PlanCell = PlanCell {
        base: DIST_MASK,
        off: [NO_OFF; 4],
        ring_a: 0,
        ring_b: 0,
    };

    /// All bits zero: only a placeholder for `static` storage, which
    /// [`DistField::new`](super::DistField::new) clears to [`PlanCell::EMPTY`]. A zero initialiser
    /// puts the firmware's planner scratch in `.bss` instead of `.data`,
    /// whose initial image would cost 16 KiB of flash.
    pub const ZEROED: PlanCell = PlanCell {
        base: 0,
        off: [0; 4],
        ring_a: 0,
        ring_b: 0,
    };

    pub(super) fn dist(&self) -> Option<Ticks> {
        let d = self.base & DIST_MASK;
        (d != DIST_MASK).then_some(d)
    }

    pub(super) fn settled(&self, h: usize) -> bool {
        self.base & (1 << (SETTLED_SHIFT + h as u32)) != 0
    }

    /// Ring slot `ring` of this cell: 0 the edge ring's, 1 the turn
    /// ring's.
    pub(super) fn ring(&self, ring: usize) -> u32 {
        if ring == 0 { self.ring_a } else { self.ring_b }
    }

    /// [`PlanCell::ring`], to write.
    pub(super) fn ring_mut(&mut self, ring: usize) -> &mut u32 {
        if ring == 0 {
            &mut self.ring_a
        } else {
            &mut self.ring_b
        }
    }

    pub(super) fn pose_dist(&self, h: usize) -> Option<Ticks> {
        if self.settled(h) {
            Some((self.base & DIST_MASK) + u32::from(*self.off.get(h)?))
        } else {
            None
        }
    }
}

impl Default for PlanCell {
    fn default() -> Self {
        PlanCell::EMPTY
    }
}

/// Where a search settled cells: storage indices `lo..hi`, and no farther
/// than `reach / edge` lattice steps from the start (`sx`, `sy`) (a
/// settled node at distance `d` is at most `d / edge` steps away), in a
/// window `width` wide. The next search clears only that diamond: rows of
/// a wide map are much longer than a search that stops early is wide, a
/// diamond is half its bounding box, and finding it this way costs no
/// division per settled state.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Dirty {
    lo: usize,
    hi: usize,
    reach: Ticks,
    sx: usize,
    sy: usize,
    edge: Ticks,
    width: usize,
}

impl Dirty {
    /// Nothing settled yet by a search from storage index `s0` with edges
    /// of `edge` ticks in a window `width` wide.
    pub(super) fn start(s0: usize, width: usize, edge: Ticks) -> Dirty {
        let width = width.max(1);
        Dirty {
            lo: 0,
            hi: 0,
            reach: 0,
            sx: s0 % width,
            sy: s0 / width,
            edge,
            width,
        }
    }

    /// The whole of a window of `area` nodes, `width` wide (a search whose
    /// costs are not edge times).
    pub(super) fn all(area: usize, width: usize) -> Dirty {
        Dirty {
            lo: 0,
            hi: area,
            reach: 0,
            sx: 0,
            sy: 0,
            edge: 0,
            width: width.max(1),
        }
    }

    /// Index `i` settled at distance `key`.
    #[inline]
    pub(super) fn add(&mut self, i: usize, key: Ticks) {
        if self.lo >= self.hi {
            self.lo = i;
            self.hi = i + 1;
        } else {
            self.lo = self.lo.min(i);
            self.hi = self.hi.max(i + 1);
        }
        self.reach = self.reach.max(key);
    }

    /// The largest distance settled.
    pub(super) fn reach(&self) -> Ticks {
        self.reach
    }

    /// The box after every settled distance grew by `c` and index `i`
    /// (one step from the old start) became the start, settled at 0: a
    /// node `d / edge` steps from the old start lies at most
    /// `(d + c) / edge` from the new one, as `c` is at least an edge.
    pub(super) fn rebased(mut self, i: usize, c: Ticks) -> Dirty {
        self.reach = self.reach.saturating_add(c);
        self.sx = i % self.width.max(1);
        self.sy = i / self.width.max(1);
        self.add(i, 0);
        self
    }

    /// Calls `f` with the storage range of each row of the diamond (of
    /// whole rows `lo..hi` where costs are not edge times).
    pub(super) fn for_each_row(self, mut f: impl FnMut(core::ops::Range<usize>)) {
        if self.lo >= self.hi || self.width == 0 {
            return;
        }
        let r = (self.reach / self.edge.max(1)) as usize;
        for row in self.lo / self.width..=(self.hi - 1) / self.width {
            let (x0, x1) = if self.edge == 0 {
                (0, self.width)
            } else {
                let rx = r.saturating_sub(row.abs_diff(self.sy));
                (
                    self.sx.saturating_sub(rx),
                    self.sx.saturating_add(rx + 1).min(self.width),
                )
            };
            let base = row * self.width;
            f(base + x0..base + x1);
        }
    }
}

/// Where a stopped search stands: the two FIFOs and the settled state
/// still to expand.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Queues {
    pub(super) a_head: usize,
    pub(super) a_len: usize,
    pub(super) b_head: usize,
    pub(super) b_len: usize,
    /// Entries each ring received since the search began: entry `n`
    /// went to slot `n % len` (see `record`)...
    pub(super) a_pushed: usize,
    pub(super) b_pushed: usize,
    /// ...and the first entry the slots were given (0, or where a
    /// search taken over in part began to hold them): the slots hold the
    /// entries from here or from `pushed - len`, whichever is later.
    pub(super) a_from: usize,
    pub(super) b_from: usize,
    pub(super) pending: Option<(usize, usize, Ticks)>,
}

impl Queues {
    /// Whether nothing is left to settle: the search ran to the end.
    pub(super) fn ran_out(&self) -> bool {
        self.a_len == 0 && self.b_len == 0 && self.pending.is_none()
    }
}

/// Windows up to this many nodes get scratch enough that the planner's
/// queues can never overflow (see [`min_cells`]).
pub const SMALL_WINDOW: usize = 128;

/// The scratch cells a window of `area` nodes needs.
///
/// Each of the two FIFO rings holds one entry per scratch cell. Over a
/// whole search the edge ring receives at most one entry per (node,
/// heading) state and the turn ring at most two per settled state, so
/// 8 × area cells can never overflow. Small windows get that: their
/// wavefront can be most of the window (cheap edges, dear turns). Larger
/// windows get one cell per node, which holds a wavefront of `area` states,
/// far more than a search at the robots' timing keeps in flight; should it
/// ever fill, the search says [`PlanError::QueueFull`](super::PlanError::QueueFull) rather than answer
/// wrongly.
pub const fn min_cells(area: usize) -> usize {
    if area <= SMALL_WINDOW {
        8 * if area < 8 { 8 } else { area }
    } else {
        area
    }
}

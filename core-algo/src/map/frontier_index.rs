//! Which blocks of a [`KnownMap`](super::KnownMap) hold frontier nodes:
//! see [`FrontierIndex`].

/// Bits of the index: one per block on maps of up to 65 536 nodes (256²),
/// in 256 bytes; a larger map shares each bit among 2, 4, ... blocks.
pub(super) const INDEX_BITS: usize = 2048;
const WORDS: usize = INDEX_BITS / 64;

/// Which blocks hold frontier nodes, one bit per group of `1 << shift`
/// neighbouring blocks.
///
/// Why: [`KnownMap::frontier`](super::KnownMap::frontier) used to read
/// every block's frontier word to find the few that hold any. On a 256²
/// map that is 2 048 blocks, a cache line each, and a 16-robot team reads
/// the frontier at almost every decision (docs/results/performance.md,
/// stop 62). The index finds them in 32 words. A bit is set while some
/// block of its group holds frontier nodes, and only then.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrontierIndex {
    words: [u64; WORDS],
    /// log2 of the blocks per bit.
    shift: u32,
    /// Words in use: the groups of the map, rounded up to words.
    used: usize,
}

impl FrontierIndex {
    /// An empty index over `blocks` blocks.
    pub(super) fn new(blocks: usize) -> FrontierIndex {
        let mut shift = 0;
        while shift < usize::BITS - 1 && blocks.div_ceil(1 << shift) > INDEX_BITS {
            shift += 1;
        }
        let groups = blocks.div_ceil(1 << shift);
        FrontierIndex {
            words: [0; WORDS],
            shift,
            used: groups.div_ceil(64).min(WORDS),
        }
    }

    /// No block holds frontier nodes.
    pub(super) fn clear(&mut self) {
        self.words = [0; WORDS];
    }

    /// Block `b` has come to hold frontier nodes.
    pub(super) fn set(&mut self, b: usize) {
        let g = b >> self.shift;
        if let Some(w) = self.words.get_mut(g / 64) {
            *w |= 1 << (g % 64);
        }
    }

    /// Block `b` holds none any more: its group's bit goes unless
    /// `holds(other)` for another block of the group.
    pub(super) fn unset(&mut self, b: usize, holds: impl Fn(usize) -> bool) {
        let g = b >> self.shift;
        let first = g << self.shift;
        if (first..first + (1 << self.shift)).any(|o| o != b && holds(o)) {
            return;
        }
        if let Some(w) = self.words.get_mut(g / 64) {
            *w &= !(1 << (g % 64));
        }
    }

    /// Every block of the marked groups, ascending, below `len`: a
    /// superset of the blocks holding frontier nodes (all of them where
    /// a bit is one block's).
    pub(super) fn blocks(&self, len: usize) -> impl Iterator<Item = usize> + '_ {
        let shift = self.shift;
        let words = self.words.get(..self.used).unwrap_or(&[]);
        words.iter().enumerate().flat_map(move |(wi, &w)| {
            ones(w)
                .map(move |k| wi * 64 + k)
                .flat_map(move |g| (g << shift)..((g + 1) << shift).min(len))
        })
    }
}

/// The positions of the bits set in `bits`, lowest first: one step per
/// set bit, however sparse.
pub(super) fn ones(bits: u64) -> impl Iterator<Item = usize> {
    let mut rest = bits;
    core::iter::from_fn(move || {
        if rest == 0 {
            return None;
        }
        let k = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        Some(k)
    })
}

//! A map's fingerprint, and the revisions it had lately: see
//! [`KnownMap::print`](super::KnownMap::print).
//!
//! Why: a host that runs a whole team (the simulator) keeps one search for
//! all of its robots where their maps agree (see
//! `explore::SharedColumns`). Comparing two maps node by node costs as
//! much as the search it would save; their fingerprints compare in O(1).

/// A fingerprint of what a map knows: the sum, over its visited nodes, of
/// two independent 64-bit hashes of (node, arms). Every other bit a search
/// reads (deduced shapes, the frontier) follows from the visited nodes and
/// their arms, so two maps of one window with equal prints read the same
/// everywhere, but for a 2⁻¹²⁸ chance. A sum, so the order of the visits
/// does not matter.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct MapPrint(pub [u64; 2]);

impl MapPrint {
    /// The print of a map with node `i` visited, with arms `arms`, added.
    pub(super) fn with(self, i: usize, arms: u8) -> MapPrint {
        let x = ((i as u64) << 8) | u64::from(arms);
        MapPrint([
            self.0[0].wrapping_add(mix(x ^ 0x243F_6A88_85A3_08D3)),
            self.0[1].wrapping_add(mix(x ^ 0x1319_8A2E_0370_7344)),
        ])
    }
}

/// splitmix64's finaliser: every input bit flips about half the output.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// How many prints the log keeps: a host asks about the last few.
const LOG: usize = 8;

/// The last prints a map had, with the revision each had: a search kept
/// for a print of this map's past holds for that revision of this map.
#[derive(Clone, Debug)]
pub(super) struct Prints {
    log: [(u32, MapPrint); LOG],
    pushed: usize,
}

impl Prints {
    /// A log that knows only `print`, at `revision`.
    pub(super) fn new(revision: u32, print: MapPrint) -> Prints {
        Prints {
            log: [(revision, print); LOG],
            pushed: 1,
        }
    }

    /// The map now has `print`, at `revision`.
    pub(super) fn push(&mut self, revision: u32, print: MapPrint) {
        if let Some(e) = self.log.get_mut(self.pushed % LOG) {
            *e = (revision, print);
        }
        self.pushed = self.pushed.wrapping_add(1);
    }

    /// The revision the map had when its print was `print`, if that is
    /// among the last few.
    pub(super) fn revision_of(&self, print: MapPrint) -> Option<u32> {
        let kept = self.pushed.min(LOG);
        (0..kept)
            .map(|back| self.pushed.wrapping_sub(1 + back) % LOG)
            .filter_map(|n| self.log.get(n))
            .find(|(_, p)| *p == print)
            .map(|&(r, _)| r)
    }
}

//! What a search tells its recorder in runs ([`super::super::Run`]), and
//! the queue entries told from their slots.

use super::*;

/// Queue entries are told in order from the slots they went to, across
/// the wrap at the field's end and across runs of [`super::super::RUN`].
#[test]
fn queue_entries_are_told_in_order_across_the_wrap() {
    let cap = 2 * super::super::RUN + 3;
    let mut cells = vec![PlanCell::EMPTY; cap];
    for (k, c) in cells.iter_mut().enumerate() {
        *c.ring_mut(1) = k as u32;
    }
    for (from, len) in [
        (0, 0),
        (5, 1),
        (0, cap),
        (cap - 2, 4),
        (cap + 7, cap),
        (40, super::super::RUN + 1),
    ] {
        let mut out = Written::default();
        super::super::tell_queued(&mut out, &cells, 1, from..from + len);
        let want: Vec<u32> = (from..from + len).map(|n| (n % cap) as u32).collect();
        assert_eq!(out.queued[1], want, "from {from}, {len} entries");
        assert!(out.queued[0].is_empty());
    }
}

/// A run hands on every entry, in order, whole runs as they fill and
/// the rest when flushed.
#[test]
fn a_run_hands_on_every_entry_in_order() {
    for n in [
        0,
        1,
        super::super::RUN - 1,
        super::super::RUN,
        2 * super::super::RUN + 1,
    ] {
        let mut got = Vec::new();
        let mut sizes = Vec::new();
        let mut run = super::super::Run::new(0u32);
        for x in 0..n as u32 {
            run.push(x, |r| {
                got.extend_from_slice(r);
                sizes.push(r.len());
            });
        }
        run.flush(|r| {
            got.extend_from_slice(r);
            sizes.push(r.len());
        });
        assert_eq!(got, (0..n as u32).collect::<Vec<_>>());
        assert!(sizes.iter().all(|&s| s > 0 && s <= super::super::RUN));
        assert_eq!(sizes.len(), n.div_ceil(super::super::RUN));
    }
}

//! The rest of a search written down ([`DistField::resume_written_down`])
//! and taken over where another field stands ([`DistField::take_over_after`]).

use super::*;

/// Resumes `f` written down into a fresh record, stopping after `more`
/// further nodes: the record and what it reached, in order.
fn rest_written(
    f: &mut DistField<Vec<PlanCell>>,
    map: &KnownMap<Vec<Block>>,
    more: usize,
) -> Result<(Written, Vec<(usize, Ticks)>), PlanError> {
    let mut w = Written::default();
    let mut out = Vec::new();
    f.resume_written_down(map, &mut w, noted(&mut out, more))?;
    Ok((w, out))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// A search recorded on one map, then its rest as it was resumed
    /// there, both taken over on another map where every node they read
    /// reads the same, stands where a fresh search there, stopped at the
    /// same node and resumed to the same node, stands: the same times for
    /// every node and pose, and resumed, the same nodes at the same times
    /// in the same order; and the next search in it finds the field clean.
    /// The field that takes the rest over took the first part over or
    /// searched it itself; one that stands elsewhere refuses it unchanged.
    /// Plain and jumping searches, mazes and random fields, small windows
    /// and larger ones.
    #[test]
    fn the_rest_of_a_search_taken_over_goes_on_as_a_fresh_one(
        w in 1u16..16, h in 1u16..16, seed in any::<u64>(), maze in any::<bool>(),
        known in 1usize..256, other in 0usize..256, pick in any::<usize>(), heading in 0u8..4,
        stop in 0usize..256, more in 0usize..256, edge in 1u32..200, turn in 1u32..128,
        jumping in any::<bool>(), own in any::<bool>(),
    ) {
        let (b, a, other, t, start) =
            drawn((w, h), (seed, maze), (known, other), (pick, heading), (edge, turn));
        let area = b.area();
        let mut recording = field_for(area);
        let first = fits(write_as_told(&mut recording, &a, t, (start, jumping), stop))?;
        let (then, _) = fits(rest_written(&mut recording, &a, more))?;
        prop_assert!(then.state.is_some(), "written down");
        if !reads_same(&other, first.rec()) || !reads_same(&other, then.rec()) {
            return Ok(());
        }
        // A fresh search on the other map, stopped at the same two nodes.
        let mut fresh = field_for(area);
        fits(search(&mut fresh, &other, t, (start, jumping), noted(&mut Vec::new(), stop)))?;
        let mut stood = field_for(area);
        if own {
            fits(search(&mut stood, &other, t, (start, jumping), noted(&mut Vec::new(), stop)))?;
        } else {
            stood.take_over(&other, t, first.rec()).unwrap();
        }
        let mut again = Vec::new();
        fits(fresh.resume(&other, noted(&mut again, more)))?;
        let told: Vec<(usize, Ticks)> =
            then.reached.iter().map(|r| (r.node as usize, r.dist)).collect();
        prop_assert_eq!(&told, &again);
        // A field that stands elsewhere (it went on past the first part,
        // and reached something more) refuses the rest as it is.
        let mut past = field_for(area);
        past.take_over(&other, t, first.rec()).unwrap();
        let mut beyond = Vec::new();
        fits(past.resume(&other, noted(&mut beyond, 0)))?;
        if !beyond.is_empty() {
            let was = times(&past, area);
            prop_assert!(!past.take_over_after(&other, then.rec()));
            prop_assert_eq!(times(&past, area), was);
        }
        prop_assert!(stood.take_over_after(&other, then.rec()));
        prop_assert_eq!(times(&stood, area), times(&fresh, area));
        let (r1, r2) = (rest(&mut stood, &other), rest(&mut fresh, &other));
        prop_assert_eq!(&r1, &r2);
        fits(r1)?;
        prop_assert_eq!(times(&stood, area), times(&fresh, area));
        // The next search in the field clears all that the rest wrote.
        for f in [&mut stood, &mut fresh] {
            fits(f.compute(&other, t, start.0, Heading::South, |_, _| Flow::Continue))?;
        }
        prop_assert_eq!(times(&stood, area), times(&fresh, area));
    }

    /// The rest of a search is no whole search: taken over whole or in
    /// part, it is refused.
    #[test]
    fn the_rest_of_a_search_is_refused_as_a_whole_one(
        w in 2u16..12, h in 2u16..12, seed in any::<u64>(), stop in 0usize..64,
        more in 0usize..64, jumping in any::<bool>(),
    ) {
        let b = Bounds::new(Pos::new(0, 0), w, h);
        let area = b.area();
        let a = known_prefix(b, &random_arms(b, seed), area);
        let t = Timing { edge: 10, quarter_turn: 5 };
        let start = ((b.pos(0), Heading::East), jumping);
        let mut f = field_for(area);
        fits(write_as_told(&mut f, &a, t, start, stop))?;
        let (then, _) = fits(rest_written(&mut f, &a, more))?;
        let mut g = field_for(area);
        prop_assert!(g.take_over(&a, t, then.rec()).is_err());
        prop_assert!(!then.rec().holds_queues());
        prop_assert!(!matches!(g.take_over_before(&a, t, then.rec(), 0), Ok(true)));
    }
}

use super::*;
use core_algo::geometry::legacy;
use proptest::prelude::*;

/// A small field in the 2010 `.sim` format: the 2010 `test.sim` (a 5 x 2
/// strip with a 3 x 3 block below), as the project keeps it in
/// `fields/small/test.sim`.
const STRIP_SIM: &str = include_str!("../../../fields/small/test.sim");

fn strip() -> Field {
    sim::parse_sim(STRIP_SIM, "strip.sim", "strip").unwrap()
}

#[test]
fn sim_import_converts_into_our_frame() {
    let f = strip();
    assert_eq!(f.nodes().len(), 16);
    assert_eq!(f.edge_count(), 23);
    // 2010 (-3, -1) is the top-left corner on screen: north-west here.
    assert_eq!(f.arms(Pos::new(-3, 1)), Some(legacy::BOTTOMRIGHTEDGE));
    assert!(f.arms(Pos::new(-3, 1)).unwrap().has(Heading::South));
    assert_eq!(f.arms(Pos::new(-1, -2)), Some(legacy::TOPT));
    // Orientation 0 (UP, +y on the 2010 screen) faces south here.
    assert_eq!(f.starts().len(), 5);
    assert!(f.starts().iter().all(|s| s.heading == Heading::South));
    assert_eq!(f.starts()[0].pos, Pos::new(-3, 1));
    assert_eq!(f.bounds().origin, Pos::new(-3, -2));
}

#[test]
fn crlf_and_lf_read_the_same() {
    let crlf = STRIP_SIM.replace('\n', "\r\n");
    assert_eq!(sim::parse_sim(&crlf, "x.sim", "strip").unwrap(), strip());
}

#[test]
fn sim_round_trips_through_native() {
    let f = strip();
    let text = sim::write_sim(&f).unwrap();
    let native = native::write(&f);
    let back = native::parse(&native, "strip.field").unwrap();
    assert_eq!(back, f);
    assert_eq!(sim::write_sim(&back).unwrap(), text);
    assert_eq!(sim::parse_sim(&text, "again.sim", "strip").unwrap(), f);
}

#[test]
fn headings_map_both_ways() {
    for i in 0..4 {
        assert_eq!(
            sim::heading_to_legacy(sim::heading_from_legacy(i).unwrap()),
            i
        );
    }
    assert_eq!(sim::heading_from_legacy(4), None);
    let text = "1\n0 0 BOTTOMRIGHTEDGE 3\n1 0 BOTTOMLEFTEDGE\n0 1 TOPRIGHTEDGE\n1 1 TOPLEFTEDGE\n";
    let f = sim::parse_sim(text, "t.sim", "t").unwrap();
    assert_eq!(
        f.starts()[0],
        StartPose {
            pos: Pos::new(0, 0),
            heading: Heading::East
        }
    );
}

fn err_of(r: Result<Field, FieldError>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn sim_errors_name_line_and_column() {
    assert_eq!(
        err_of(sim::parse_sim("7\n", "a.sim", "a")),
        "a.sim:1:1: expected the robot count 1..=6, found '7'"
    );
    assert_eq!(
        err_of(sim::parse_sim("1\n0 0 CROSS 0\n0 x CROSS\n", "a.sim", "a")),
        "a.sim:3:3: expected the y coordinate as an integer in -32768..=32767, found 'x'"
    );
    assert!(
        err_of(sim::parse_sim("1\n0 0 KREUZ 0\n", "a.sim", "a"))
            .starts_with("a.sim:2:5: expected a node type")
    );
    assert_eq!(
        err_of(sim::parse_sim("1\n0 0 CROSS 7\n", "a.sim", "a")),
        "a.sim:2:11: expected a start orientation 0..=3, found '7'"
    );
    assert_eq!(
        err_of(sim::parse_sim(
            "1\n0 0 BOTTOMRIGHTEDGE 0\n1 0 BOTTOMLEFTEDGE 0\n",
            "a.sim",
            "a"
        )),
        "a.sim:3:20: the header declares 1 robots, but this is start 2"
    );
    // A validation problem points at the node's line.
    let e = err_of(sim::parse_sim(
        "1\n0 0 BOTTOMRIGHTEDGE 0\n1 0 TOPRIGHTEDGE\n",
        "a.sim",
        "a",
    ));
    assert!(
        e.starts_with("a.sim:2:1: node (0, 0) has an arm E, but the node there has no arm W back"),
        "{e}"
    );
    let e = err_of(sim::parse_sim(
        "2\n0 0 CROSS 0\n0 0 CROSS 0\n",
        "a.sim",
        "a",
    ));
    assert!(
        e.contains("a.sim:3:1: node (0, 0) is already defined on line 2"),
        "{e}"
    );
}

#[test]
fn native_errors_name_line_and_column() {
    let bad = [
        (
            "",
            "f:1:1: expected the header 'conquest-field 1', found an empty file",
        ),
        (
            "hello",
            "f:1:1: expected the header 'conquest-field 1', found 'hello'",
        ),
        (
            "conquest-field 2",
            "f:1:16: expected format version 1, found '2'",
        ),
        (
            "conquest-field 1\nnode 0 0 NX",
            "f:2:10: expected arms as distinct letters of NESW, or '-', found 'NX'",
        ),
        (
            "conquest-field 1\nnode 0 0 NN",
            "f:2:10: expected arms as distinct letters of NESW, or '-', found 'NN'",
        ),
        (
            "conquest-field 1\nnode 0",
            "f:2:7: expected the y coordinate",
        ),
        (
            "conquest-field 1\n  start 0 0 Q",
            "f:2:13: expected a heading N, E, S or W, found 'Q'",
        ),
        (
            "conquest-field 1\nnode 0 0 - extra",
            "f:2:12: expected the end of the line, found 'extra'",
        ),
        (
            "conquest-field 1\nwall 1 2",
            "f:2:1: expected 'name', 'spacing', 'node' or 'start', found 'wall'",
        ),
        (
            "conquest-field 1\nspacing 0",
            "f:2:9: expected a spacing in millimetres, 1..=65535, found '0'",
        ),
        (
            "conquest-field 1\nnode 0 0 -\nstart 5 5 N",
            "f:3:1: start 0 at (5, 5) is not on a node",
        ),
        (
            "conquest-field 1\nnode 0 0 -\nnode 3 3 -",
            "f:3:1: expected one connected field, found 2 parts: node (3, 3) cannot be reached from the first node",
        ),
        (
            "conquest-field 1\nnode 0 0 E",
            "f:2:1: node (0, 0) has an arm E, but there is no node at (1, 0)",
        ),
    ];
    for (text, want) in bad {
        assert_eq!(err_of(native::parse(text, "f")), want, "for {text:?}");
    }
}

#[test]
fn native_reads_comments_name_and_spacing() {
    let f = native::parse(
        "# a field\nconquest-field 1 # header\nname Two nodes\nspacing 150\nstart 1 0 W\nnode 0 0 E\nnode 1 0 W\n",
        "f",
    )
    .unwrap();
    assert_eq!(f.name(), "Two nodes");
    assert_eq!(f.spacing_mm(), 150);
    assert_eq!(
        f.starts(),
        [StartPose {
            pos: Pos::new(1, 0),
            heading: Heading::West
        }]
    );
    assert_eq!(native::parse(&native::write(&f), "g").unwrap(), f);
}

/// Names write and read back unchanged, whatever they held: a carriage
/// return inside a native name line (the `field` fuzz target's find) and a
/// `#` in a `.sim` file's stem had come back other.
#[test]
fn every_name_reads_back_as_written() {
    let f = native::parse(
        "conquest-field 1\nname a\rb\x00c \nnode 0 0 E\nnode 1 0 W\n",
        "f.field",
    )
    .unwrap();
    assert_eq!(f.name(), "a b\x00c");
    assert_eq!(native::parse(&native::write(&f), "g.field").unwrap(), f);
    let g = sim::parse_sim(STRIP_SIM, "a#b.sim", "a#b").unwrap();
    assert_eq!(g.name(), "a b");
    assert_eq!(native::parse(&native::write(&g), "g.field").unwrap(), g);
    let h = g.with_name(" two\nlines ");
    assert_eq!(h.name(), "two lines");
}

#[test]
fn sep_export_and_import() {
    let f = strip();
    let text = sim::write_sep(&f).unwrap();
    assert_eq!(text.lines().count(), 16);
    let back = sim::parse_sep(&text, "m.sep", "strip").unwrap();
    assert_eq!(back.nodes(), f.nodes());
    assert!(back.starts().is_empty());
    // Shapes the 2010 formats lack are refused with the node named.
    let maze = generate::maze(6, 6, 1);
    assert!(
        sim::write_sep(&maze)
            .unwrap_err()
            .contains("cannot express")
    );
}

#[test]
fn moving_ai_two_readings() {
    let text = "type octile\nheight 2\nwidth 3\nmap\n..@\n.T.\n";
    let cells = movingai::parse(text, "m.map", "m", MapReading::Cells).unwrap();
    // Row 0 is north: cells (0,1) (1,1) (0,0) form the largest part; (2,0) is an island.
    assert_eq!(cells.nodes().len(), 3);
    assert_eq!(
        cells.arms(Pos::new(0, 1)),
        Some(Arms::NONE.with(Heading::East).with(Heading::South))
    );
    let corners = movingai::parse(text, "m.map", "m", MapReading::Corners).unwrap();
    // Three squares in an L plus one square touching at a corner: 4 squares,
    // corners (0..=3, 0..=2) minus the missing ones.
    assert!(corners.nodes().values().all(|a| legacy::name(*a).is_some()));
    assert_eq!(corners.edge_count(), 4 * 4 - 2);
    assert_eq!(corners.starts().len(), 6);
    let e = err_of(movingai::parse(
        "type octile\nheight 1\nwidth 2\nmap\n.x\n",
        "m.map",
        "m",
        MapReading::Cells,
    ));
    assert_eq!(
        e,
        "m.map:5:2: expected a map cell (. G S @ O T W), found 'x'"
    );
    let e = err_of(movingai::parse(
        "type octile\nheight 2\nwidth 2\nmap\n..\n.\n",
        "m.map",
        "m",
        MapReading::Cells,
    ));
    assert_eq!(e, "m.map:6:2: expected 2 cells in the row, found 1");
}

#[test]
fn generators_are_seeded_and_sound() {
    for kind in generate::Kind::ALL {
        let a = kind.generate(20, 16, 7);
        assert_eq!(
            a,
            kind.generate(20, 16, 7),
            "{kind:?} must be deterministic"
        );
        assert!(a.nodes().len() > 100, "{kind:?}");
        assert_eq!(a.starts().len(), 6);
        assert!(a.bounds().width <= 20 && a.bounds().height <= 16);
    }
    let m = generate::maze(20, 16, 3);
    assert_eq!(
        m.edge_count(),
        m.nodes().len() - 1,
        "a perfect maze is a tree"
    );
    assert_ne!(m, generate::maze(20, 16, 4));
    assert_eq!(generate::open(5, 4, 0).edge_count(), 4 * 4 + 5 * 3);
    // The largest size still generates.
    assert_eq!(generate::open(1, 1, 0).nodes().len(), 1);
}

#[test]
fn validator_reports_every_problem() {
    let mut nodes = BTreeMap::new();
    nodes.insert(Pos::new(0, 0), Arms::NONE.with(Heading::East));
    nodes.insert(Pos::new(1, 0), Arms::NONE);
    nodes.insert(Pos::new(5, 5), Arms::NONE.with(Heading::North));
    let starts = vec![
        StartPose {
            pos: Pos::new(0, 0),
            heading: Heading::North,
        },
        StartPose {
            pos: Pos::new(0, 0),
            heading: Heading::East,
        },
        StartPose {
            pos: Pos::new(9, 9),
            heading: Heading::East,
        },
    ];
    let e = Field::new("bad", nodes, starts).unwrap_err();
    assert_eq!(
        e.problems,
        vec![
            Problem::ArmNotReturned {
                pos: Pos::new(0, 0),
                heading: Heading::East
            },
            Problem::ArmIntoNothing {
                pos: Pos::new(5, 5),
                heading: Heading::North
            },
            Problem::StartShared {
                index: 1,
                pos: Pos::new(0, 0)
            },
            Problem::StartOffField {
                index: 2,
                pos: Pos::new(9, 9)
            },
            Problem::Disconnected {
                parts: 2,
                unreachable: Pos::new(5, 5)
            },
        ]
    );
    assert!(Field::new("empty", BTreeMap::new(), vec![]).is_err());
}

#[test]
fn files_load_by_extension() {
    let dir = tempfile::tempdir().unwrap();
    let f = strip();
    for ext in ["field", "sim", "sep"] {
        let p = dir.path().join(format!("strip.{ext}"));
        save(&f, &p).unwrap();
        let back = load(&p).unwrap();
        assert_eq!(back.nodes(), f.nodes(), "{ext}");
    }
    let e = load(&dir.path().join("missing.sim"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.sim: cannot access file"), "{e}");
    let p = dir.path().join("x.txt");
    std::fs::write(&p, "1").unwrap();
    assert!(
        load(&p)
            .unwrap_err()
            .to_string()
            .contains("unknown field format '.txt'")
    );
    let p = dir.path().join("bin.field");
    std::fs::write(&p, b"conquest-field 1\nnode \xff").unwrap();
    assert!(
        load(&p)
            .unwrap_err()
            .to_string()
            .ends_with("bin.field:2:6: expected UTF-8 text, found a byte that is not")
    );
}

/// Fields made of random unit squares (the 2010 kind of field), via the
/// Moving AI corners reading: every node is a corner, T or cross.
fn square_fields() -> impl Strategy<Value = Field> {
    (
        1usize..7,
        1usize..7,
        proptest::collection::vec(any::<bool>(), 36),
        1usize..7,
    )
        .prop_filter_map("needs a square", |(w, h, cells, k)| {
            let passable: Vec<bool> = cells.into_iter().take(w * h).collect();
            if !passable.iter().any(|c| *c) {
                return None;
            }
            let mut nodes = movingai::lattice(&passable, w, h, MapReading::Corners);
            validate::keep_largest_part(&mut nodes);
            let starts = default_starts(&nodes, k);
            Field::new("squares", nodes, starts).ok()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn sim_native_sim_round_trip(f in square_fields()) {
        let text = sim::write_sim(&f).unwrap();
        let from_sim = sim::parse_sim(&text, "p.sim", "squares").unwrap();
        prop_assert_eq!(&from_sim, &f);
        let native = native::parse(&native::write(&from_sim), "p.field").unwrap();
        prop_assert_eq!(sim::write_sim(&native).unwrap(), text);
    }

    #[test]
    fn no_bytes_make_a_parser_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = native::parse(&text, "f");
        let _ = sim::parse_sim(&text, "f", "f");
        let _ = sim::parse_sep(&text, "f", "f");
        let _ = movingai::parse(&text, "f", "f", MapReading::Cells);
        let _ = movingai::parse(&text, "f", "f", MapReading::Corners);
    }

    #[test]
    fn mutated_valid_files_never_panic(f in square_fields(), edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6)) {
        for text in [sim::write_sim(&f).unwrap(), native::write(&f)] {
            let mut bytes = text.into_bytes();
            for (i, b) in &edits {
                let at = i.index(bytes.len());
                match b % 3 {
                    0 => bytes[at] = *b,
                    1 => { bytes.remove(at); }
                    _ => bytes.insert(at, *b),
                }
            }
            let text = String::from_utf8_lossy(&bytes);
            for r in [native::parse(&text, "m"), sim::parse_sim(&text, "m", "m")] {
                if let Err(e) = r {
                    // Every error names the file and says what was expected.
                    prop_assert!(e.to_string().starts_with("m"));
                }
            }
        }
    }
}

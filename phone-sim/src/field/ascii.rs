//! Text pictures of fields and maps, north up, for terminals and logs.
//!
//! ```text
//! +---+---+
//! |       |
//! ^---+---+
//! ```
//! `+` is a node, `-` and `|` are edges, and a mark (for example a robot's
//! heading arrow) replaces a node's `+`.

use super::Field;
use core_algo::geometry::{Arms, Heading, Pos};
use std::collections::BTreeMap;

/// The arrow drawn for a robot facing `h`.
pub fn arrow(h: Heading) -> char {
    match h {
        Heading::North => '^',
        Heading::East => '>',
        Heading::South => 'v',
        Heading::West => '<',
    }
}

/// A field with its starts drawn as arrows.
pub fn field(field: &Field) -> String {
    let marks: Vec<(Pos, char)> = field
        .starts()
        .iter()
        .map(|s| (s.pos, arrow(s.heading)))
        .collect();
    nodes(field.nodes(), &marks)
}

/// Any set of nodes with marks on some of them.
pub fn nodes(nodes: &BTreeMap<Pos, Arms>, marks: &[(Pos, char)]) -> String {
    let b = super::bounding_box(nodes.keys().copied());
    let (x0, y0) = (i32::from(b.origin.x), i32::from(b.origin.y));
    let (w, h) = (i32::from(b.width), i32::from(b.height));
    let mut out = String::new();
    for y in (y0..y0 + h).rev() {
        let mut node_row = String::new();
        let mut link_row = String::new();
        for x in x0..x0 + w {
            let p = Pos::new(x as i16, y as i16);
            let arms = nodes.get(&p);
            let mark = marks.iter().find(|(q, _)| *q == p).map(|(_, c)| *c);
            node_row.push(match (arms, mark) {
                (_, Some(c)) => c,
                (Some(_), None) => '+',
                (None, None) => ' ',
            });
            let east = arms.is_some_and(|a| a.has(Heading::East));
            node_row.push_str(if east { "---" } else { "   " });
            let south = arms.is_some_and(|a| a.has(Heading::South));
            link_row.push(if south { '|' } else { ' ' });
            link_row.push_str("   ");
        }
        out.push_str(node_row.trim_end());
        out.push('\n');
        if y > y0 {
            out.push_str(link_row.trim_end());
            out.push('\n');
        }
    }
    out
}

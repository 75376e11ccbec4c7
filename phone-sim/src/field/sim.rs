//! The 2010 formats: `.sim` simulator fields and `.sep` exported maps.
//!
//! Both are plain ASCII, LF or CRLF, one node per line as `x y TYPE`, in the
//! 2010 screen frame where y grows *down*: we negate y on the way in and out
//! (our y grows north), and TYPE names are the nine of
//! [`core_algo::geometry::legacy`]. A `.sim` file starts with the robot count
//! 1..=6; a fourth token on a node line marks a start with the 2010
//! orientation index: 0 = UP (+y on the 2010 screen, so south here),
//! 1 = LEFT (west), 2 = DOWN (north), 3 = RIGHT (east). `.sep` files have no
//! header and no starts. See `original-system.md` §5.2–5.3 for the 2010
//! parser these follow.

use super::error::{SourceMap, coordinate, numbered_lines, tokens};
use super::{Field, FieldError, StartPose};
use core_algo::geometry::{Heading, Pos, legacy};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The largest team a `.sim` header may declare.
pub const MAX_ROBOTS: usize = 6;

/// 2010 orientation index → heading in our frame.
pub fn heading_from_legacy(index: u8) -> Option<Heading> {
    match index {
        0 => Some(Heading::South),
        1 => Some(Heading::West),
        2 => Some(Heading::North),
        3 => Some(Heading::East),
        _ => None,
    }
}

/// Heading in our frame → 2010 orientation index.
pub fn heading_to_legacy(h: Heading) -> u8 {
    match h {
        Heading::South => 0,
        Heading::West => 1,
        Heading::North => 2,
        Heading::East => 3,
    }
}

/// Parses a `.sim` field; `stem` becomes its name.
pub fn parse_sim(text: &str, file: &str, stem: &str) -> Result<Field, FieldError> {
    parse(text, file, stem, true)
}

/// Parses a `.sep` map (no header, no starts).
pub fn parse_sep(text: &str, file: &str, stem: &str) -> Result<Field, FieldError> {
    parse(text, file, stem, false)
}

fn parse(text: &str, file: &str, stem: &str, with_header: bool) -> Result<Field, FieldError> {
    let mut robots = None;
    let mut nodes = BTreeMap::new();
    let mut starts = Vec::new();
    let mut source = SourceMap::default();
    for (line, raw) in numbered_lines(text) {
        let toks = tokens(raw);
        let Some(&first) = toks.first() else { continue };
        if with_header && robots.is_none() {
            let n = first
                .1
                .parse::<usize>()
                .ok()
                .filter(|n| (1..=MAX_ROBOTS).contains(n))
                .ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        first.0,
                        format!("expected the robot count 1..=6, found '{}'", first.1),
                    )
                })?;
            if let Some(extra) = toks.get(1) {
                return Err(FieldError::at(
                    file,
                    line,
                    extra.0,
                    format!(
                        "expected only the robot count on the first line, found '{}'",
                        extra.1
                    ),
                ));
            }
            robots = Some(n);
            continue;
        }
        let x = coordinate(file, line, first, "the x coordinate")?;
        let end = raw.trim_end().chars().count() + 1;
        let y_tok = toks
            .get(1)
            .ok_or_else(|| FieldError::at(file, line, end, "expected the y coordinate"))?;
        let y = coordinate(file, line, *y_tok, "the y coordinate")?;
        let type_tok = toks
            .get(2)
            .ok_or_else(|| FieldError::at(file, line, end, "expected a node type such as CROSS"))?;
        let arms = legacy::from_name(type_tok.1).ok_or_else(|| {
            FieldError::at(
                file,
                line,
                type_tok.0,
                format!(
                    "expected a node type (TOPLEFTEDGE, TOPRIGHTEDGE, BOTTOMLEFTEDGE, BOTTOMRIGHTEDGE, TOPT, RIGHTT, BOTTOMT, LEFTT, CROSS), found '{}'",
                    type_tok.1
                ),
            )
        })?;
        // The 2010 y axis points down the screen; ours points north.
        let pos = Pos::new(
            x,
            y.checked_neg()
                .ok_or_else(|| FieldError::at(file, line, y_tok.0, "expected y above -32768"))?,
        );
        if let Some(o_tok) = toks.get(3) {
            if !with_header {
                return Err(FieldError::at(
                    file,
                    line,
                    o_tok.0,
                    format!(
                        "expected the end of the line (.sep maps have no starts), found '{}'",
                        o_tok.1
                    ),
                ));
            }
            let heading = o_tok
                .1
                .parse::<u8>()
                .ok()
                .and_then(heading_from_legacy)
                .ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        o_tok.0,
                        format!("expected a start orientation 0..=3, found '{}'", o_tok.1),
                    )
                })?;
            let n = robots.unwrap_or(0);
            if starts.len() == n {
                return Err(FieldError::at(
                    file,
                    line,
                    o_tok.0,
                    format!(
                        "the header declares {n} robots, but this is start {}",
                        n + 1
                    ),
                ));
            }
            starts.push(StartPose { pos, heading });
            source.starts.push((line, first.0));
        }
        if let Some(extra) = toks.get(4) {
            return Err(FieldError::at(
                file,
                line,
                extra.0,
                format!("expected the end of the line, found '{}'", extra.1),
            ));
        }
        if let Some((l, _)) = source.nodes.get(&pos) {
            return Err(FieldError::at(
                file,
                line,
                first.0,
                format!("node ({x}, {y}) is already defined on line {l}"),
            ));
        }
        nodes.insert(pos, arms);
        source.nodes.insert(pos, (line, first.0));
    }
    if with_header && robots.is_none() {
        return Err(FieldError::at(
            file,
            1,
            1,
            "expected the robot count 1..=6, found an empty file",
        ));
    }
    Field::new(stem, nodes, starts).map_err(|e| source.locate(file, &e))
}

/// Writes a `.sim` field: header = number of starts (must be 1..=6), then
/// one line per node in the 2010 frame, starts marked with their
/// orientation. Fails if a node has a shape the 2010 system had no name for.
pub fn write_sim(field: &Field) -> Result<String, String> {
    let n = field.starts().len();
    if !(1..=MAX_ROBOTS).contains(&n) {
        return Err(format!(
            "a .sim field needs 1..=6 start poses, this field has {n}"
        ));
    }
    let mut out = format!("{n}\n");
    write_nodes(field, &mut out, true)?;
    Ok(out)
}

/// Writes a `.sep` map: one line per node in the 2010 frame, no header.
pub fn write_sep(field: &Field) -> Result<String, String> {
    let mut out = String::new();
    write_nodes(field, &mut out, false)?;
    Ok(out)
}

fn write_nodes(field: &Field, out: &mut String, with_starts: bool) -> Result<(), String> {
    // Start lines first, in robot order (the 2010 parser takes starts in file
    // order); then the other nodes column by column, top screen row first.
    let starts: Vec<StartPose> = if with_starts {
        field.starts().to_vec()
    } else {
        Vec::new()
    };
    let mut rest: Vec<Pos> = field
        .nodes()
        .keys()
        .copied()
        .filter(|p| !starts.iter().any(|s| s.pos == *p))
        .collect();
    rest.sort_by_key(|p| (p.x, std::cmp::Reverse(p.y)));
    let lines = starts
        .iter()
        .map(|s| (s.pos, Some(s.heading)))
        .chain(rest.into_iter().map(|p| (p, None)));
    for (p, heading) in lines {
        let arms = field.arms(p).unwrap_or_default();
        let name = legacy::name(arms).ok_or_else(|| {
            format!("node {p} has arms {arms}, a shape the 2010 formats cannot express (only corners, T pieces and crosses)")
        })?;
        let y = -i32::from(p.y);
        let _ = write!(out, "{} {y} {name}", p.x);
        if let Some(h) = heading {
            let _ = write!(out, " {}", heading_to_legacy(h));
        }
        out.push('\n');
    }
    Ok(())
}

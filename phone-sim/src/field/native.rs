//! The native field format, `.field`; see `docs/field-format.md`.
//!
//! ```text
//! conquest-field 1
//! # comment
//! name Demo field
//! spacing 100
//! start 0 0 N
//! node 0 0 NE
//! node 1 0 NW
//! ...
//! ```
//! Coordinates are in the project's frame (x east, y north). Arms are
//! letters of `NESW` in any order, or `-` for none. Start lines are taken in
//! file order: robot `i` starts at the `i`-th.

use super::error::{SourceMap, coordinate, numbered_lines, tokens};
use super::{Field, FieldError, StartPose};
use core_algo::geometry::{Arms, Heading, Pos};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The header's first word.
pub const MAGIC: &str = "conquest-field";
/// The version this code reads and writes.
pub const VERSION: u32 = 1;

/// Parses native text; `file` names it in errors.
pub fn parse(text: &str, file: &str) -> Result<Field, FieldError> {
    let mut nodes = BTreeMap::new();
    let mut starts = Vec::new();
    let mut source = SourceMap::default();
    let mut name = None;
    let mut spacing = None;
    let mut header_seen = false;
    for (line, raw) in numbered_lines(text) {
        let content = raw.split('#').next().unwrap_or("");
        let toks = tokens(content);
        let Some(&(col, keyword)) = toks.first() else {
            continue;
        };
        if !header_seen {
            if keyword != MAGIC {
                return Err(FieldError::at(
                    file,
                    line,
                    col,
                    format!("expected the header '{MAGIC} {VERSION}', found '{keyword}'"),
                ));
            }
            let version = toks.get(1).ok_or_else(|| {
                FieldError::at(
                    file,
                    line,
                    col + keyword.len() + 1,
                    "expected a version number after the header",
                )
            })?;
            if version.1 != VERSION.to_string() {
                return Err(FieldError::at(
                    file,
                    line,
                    version.0,
                    format!("expected format version {VERSION}, found '{}'", version.1),
                ));
            }
            expect_end(file, line, &toks, 2)?;
            header_seen = true;
            continue;
        }
        match keyword {
            "name" => {
                let start = content.find("name").map_or(0, |i| i + 4);
                name = Some(content[start..].trim().to_string());
            }
            "spacing" => {
                let tok = toks.get(1).ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        col,
                        "expected the node spacing in millimetres after 'spacing'",
                    )
                })?;
                let mm = tok
                    .1
                    .parse::<u16>()
                    .ok()
                    .filter(|v| *v > 0)
                    .ok_or_else(|| {
                        FieldError::at(
                            file,
                            line,
                            tok.0,
                            format!(
                                "expected a spacing in millimetres, 1..=65535, found '{}'",
                                tok.1
                            ),
                        )
                    })?;
                expect_end(file, line, &toks, 2)?;
                spacing = Some(mm);
            }
            "node" => {
                let (pos, rest) = position(file, line, col, &toks)?;
                let arms_tok = rest.ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        content.trim_end().chars().count() + 1,
                        "expected the node's arms (letters of NESW, or '-')",
                    )
                })?;
                let arms = parse_arms(arms_tok.1).ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        arms_tok.0,
                        format!(
                            "expected arms as distinct letters of NESW, or '-', found '{}'",
                            arms_tok.1
                        ),
                    )
                })?;
                expect_end(file, line, &toks, 4)?;
                if let Some((l, _)) = source.nodes.get(&pos) {
                    return Err(FieldError::at(
                        file,
                        line,
                        col,
                        format!("node {pos} is already defined on line {l}"),
                    ));
                }
                nodes.insert(pos, arms);
                source.nodes.insert(pos, (line, col));
            }
            "start" => {
                let (pos, rest) = position(file, line, col, &toks)?;
                let h_tok = rest.ok_or_else(|| {
                    FieldError::at(
                        file,
                        line,
                        content.trim_end().chars().count() + 1,
                        "expected the start heading (N, E, S or W)",
                    )
                })?;
                let mut chars = h_tok.1.chars();
                let heading = match (chars.next().and_then(Heading::from_letter), chars.next()) {
                    (Some(h), None) => h,
                    _ => {
                        return Err(FieldError::at(
                            file,
                            line,
                            h_tok.0,
                            format!("expected a heading N, E, S or W, found '{}'", h_tok.1),
                        ));
                    }
                };
                expect_end(file, line, &toks, 4)?;
                starts.push(StartPose { pos, heading });
                source.starts.push((line, col));
            }
            other => {
                return Err(FieldError::at(
                    file,
                    line,
                    col,
                    format!("expected 'name', 'spacing', 'node' or 'start', found '{other}'"),
                ));
            }
        }
    }
    if !header_seen {
        return Err(FieldError::at(
            file,
            1,
            1,
            format!("expected the header '{MAGIC} {VERSION}', found an empty file"),
        ));
    }
    let field =
        Field::new(name.unwrap_or_default(), nodes, starts).map_err(|e| source.locate(file, &e))?;
    Ok(match spacing {
        Some(mm) => field.with_spacing_mm(mm),
        None => field,
    })
}

type Tok<'a> = (usize, &'a str);

fn position<'a>(
    file: &str,
    line: usize,
    col: usize,
    toks: &[Tok<'a>],
) -> Result<(Pos, Option<Tok<'a>>), FieldError> {
    let end = toks.last().map_or(col, |t| t.0 + t.1.chars().count());
    let x = toks
        .get(1)
        .ok_or_else(|| FieldError::at(file, line, end, "expected the x coordinate"))?;
    let x = coordinate(file, line, *x, "the x coordinate")?;
    let y = toks
        .get(2)
        .ok_or_else(|| FieldError::at(file, line, end, "expected the y coordinate"))?;
    let y = coordinate(file, line, *y, "the y coordinate")?;
    Ok((Pos::new(x, y), toks.get(3).copied()))
}

/// Fails on a token beyond the `max` a line of this kind may have.
fn expect_end(file: &str, line: usize, toks: &[Tok<'_>], max: usize) -> Result<(), FieldError> {
    match toks.get(max) {
        None => Ok(()),
        Some(&(col, extra)) => Err(FieldError::at(
            file,
            line,
            col,
            format!("expected the end of the line, found '{extra}'"),
        )),
    }
}

/// Parses an arms token: distinct letters of NESW in any order, or `-`.
pub fn parse_arms(tok: &str) -> Option<Arms> {
    if tok == "-" {
        return Some(Arms::NONE);
    }
    let mut arms = Arms::NONE;
    for c in tok.chars() {
        let h = Heading::from_letter(c)?;
        if arms.has(h) {
            return None;
        }
        arms = arms.with(h);
    }
    (!tok.is_empty()).then_some(arms)
}

/// Writes the native text of a field: header, name, spacing, starts, then
/// nodes row by row from the north (so the file reads like the map).
pub fn write(field: &Field) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{MAGIC} {VERSION}");
    if !field.name().is_empty() {
        let _ = writeln!(out, "name {}", field.name().replace(['\n', '\r', '#'], " "));
    }
    let _ = writeln!(out, "spacing {}", field.spacing_mm());
    for s in field.starts() {
        let _ = writeln!(out, "start {} {} {}", s.pos.x, s.pos.y, s.heading);
    }
    let mut nodes: Vec<(&Pos, &Arms)> = field.nodes().iter().collect();
    nodes.sort_by_key(|(p, _)| (std::cmp::Reverse(p.y), p.x));
    for (p, a) in nodes {
        let _ = writeln!(out, "node {} {} {a}", p.x, p.y);
    }
    out
}

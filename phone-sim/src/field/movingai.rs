//! Moving AI benchmark grids (`.map`), the common currency of grid
//! path-planning research, read in one of two ways ([`MapReading`]).
//!
//! ```text
//! type octile
//! height 4
//! width 5
//! map
//! .....
//! .@@..
//! ...
//! ```
//! `.`, `G` and `S` are passable; `@`, `O`, `T` and `W` are not. The first
//! map row is the northernmost. Only the largest connected part is kept
//! (Moving AI maps often hold islands), and up to six starts are placed by
//! [`super::default_starts`].

use super::error::{numbered_lines, tokens};
use super::validate::keep_largest_part;
use super::{Field, FieldError, default_starts};
use core_algo::geometry::{Arms, Heading, Pos};
use std::collections::BTreeMap;

/// How a grid of cells becomes a lattice of lines.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum MapReading {
    /// Every passable cell is a node, with arms to its passable 4-neighbours.
    #[default]
    Cells,
    /// Every passable cell is a square of lines; the squares' corners are the
    /// nodes (so every node is a corner, a T or a cross, like the 2010
    /// fields).
    Corners,
}

impl std::str::FromStr for MapReading {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "cells" => Ok(MapReading::Cells),
            "corners" => Ok(MapReading::Corners),
            other => Err(format!("expected 'cells' or 'corners', found '{other}'")),
        }
    }
}

/// Largest grid side we accept: the lattice must fit `i16` coordinates.
const MAX_SIDE: usize = 16_000;

/// Parses a Moving AI grid.
pub fn parse(text: &str, file: &str, stem: &str, reading: MapReading) -> Result<Field, FieldError> {
    let mut lines = numbered_lines(text);
    let mut height = None;
    let mut width = None;
    let mut header_done = false;
    for (line, raw) in lines.by_ref() {
        let toks = tokens(raw);
        let Some(&(col, key)) = toks.first() else {
            continue;
        };
        match key {
            "type" => {}
            "height" | "width" => {
                let v = toks
                    .get(1)
                    .and_then(|t| {
                        t.1.parse::<usize>()
                            .ok()
                            .filter(|v| (1..=MAX_SIDE).contains(v))
                    })
                    .ok_or_else(|| {
                        FieldError::at(
                            file,
                            line,
                            col + key.len() + 1,
                            format!("expected the {key} as a number in 1..={MAX_SIDE}"),
                        )
                    })?;
                if key == "height" {
                    height = Some(v);
                } else {
                    width = Some(v);
                }
            }
            "map" => {
                header_done = true;
                break;
            }
            other => {
                return Err(FieldError::at(
                    file,
                    line,
                    col,
                    format!("expected 'type', 'height', 'width' or 'map', found '{other}'"),
                ));
            }
        }
    }
    let (Some(h), Some(w), true) = (height, width, header_done) else {
        return Err(FieldError::whole(
            file,
            "expected a header with 'height', 'width' and 'map' lines",
        ));
    };
    let mut passable = vec![false; w * h];
    let mut row = 0;
    for (line, raw) in lines {
        if row == h {
            if raw.trim().is_empty() {
                continue;
            }
            return Err(FieldError::at(
                file,
                line,
                1,
                format!("expected {h} map rows, found more"),
            ));
        }
        let mut n = 0;
        for (i, c) in raw.chars().enumerate() {
            let free = match c {
                '.' | 'G' | 'S' => true,
                '@' | 'O' | 'T' | 'W' => false,
                other => {
                    return Err(FieldError::at(
                        file,
                        line,
                        i + 1,
                        format!(
                            "expected a map cell (. G S @ O T W), found '{}'",
                            other.escape_debug()
                        ),
                    ));
                }
            };
            if i >= w {
                return Err(FieldError::at(
                    file,
                    line,
                    i + 1,
                    format!("expected {w} cells in the row, found more"),
                ));
            }
            passable[row * w + i] = free;
            n += 1;
        }
        if n < w {
            return Err(FieldError::at(
                file,
                line,
                n + 1,
                format!("expected {w} cells in the row, found {n}"),
            ));
        }
        row += 1;
    }
    if row < h {
        return Err(FieldError::whole(
            file,
            format!("expected {h} map rows, found {row}"),
        ));
    }
    let mut nodes = lattice(&passable, w, h, reading);
    keep_largest_part(&mut nodes);
    if nodes.is_empty() {
        return Err(FieldError::whole(
            file,
            "expected at least one passable cell, found none",
        ));
    }
    let starts = default_starts(&nodes, 6);
    Field::new(stem, nodes, starts).map_err(|e| FieldError::whole(file, e.to_string()))
}

/// The lattice of a passability grid (`passable[row * w + col]`, row 0 the
/// northernmost).
pub fn lattice(passable: &[bool], w: usize, h: usize, reading: MapReading) -> BTreeMap<Pos, Arms> {
    let free = |c: isize, r: isize| {
        c >= 0
            && r >= 0
            && (c as usize) < w
            && (r as usize) < h
            && passable
                .get(r as usize * w + c as usize)
                .copied()
                .unwrap_or(false)
    };
    let mut nodes: BTreeMap<Pos, Arms> = BTreeMap::new();
    for r in 0..h as isize {
        for c in 0..w as isize {
            if !free(c, r) {
                continue;
            }
            let y = (h as isize - 1 - r) as i16;
            let p = Pos::new(c as i16, y);
            match reading {
                MapReading::Cells => {
                    nodes.entry(p).or_default();
                    if free(c + 1, r) {
                        super::generate::link(&mut nodes, p, Heading::East);
                    }
                    if free(c, r - 1) {
                        super::generate::link(&mut nodes, p, Heading::North);
                    }
                }
                MapReading::Corners => {
                    // The square's south-west corner is (c, y); its four sides.
                    let ne = Pos::new(c as i16 + 1, y + 1);
                    super::generate::link(&mut nodes, p, Heading::East);
                    super::generate::link(&mut nodes, p, Heading::North);
                    super::generate::link(&mut nodes, ne, Heading::West);
                    super::generate::link(&mut nodes, ne, Heading::South);
                }
            }
        }
    }
    nodes
}

//! The true field: the lattice of lines the robots explore, with its start
//! poses.
//!
//! A [`Field`] can only be built through [`Field::new`], which runs the one
//! validator every loader shares ([`validate`]), so holding a `Field` means
//! holding a consistent one: every arm leads to a node with the matching arm
//! back, starts stand on distinct nodes, and every node can be reached.
//!
//! Formats (chosen by file extension in [`load`] and [`save`]):
//! - native `.field` ([`native`], documented in `docs/field-format.md`);
//! - the 2010 `.sim` fields and `.sep` exported maps ([`sim`]);
//! - Moving AI `.map` grids, read in one of two ways ([`movingai`]).

pub mod ascii;
pub mod error;
pub mod generate;
pub mod movingai;
pub mod native;
pub mod sim;
pub mod validate;

use core_algo::geometry::{Arms, Heading, Pos};
use core_algo::map::Bounds;
use std::collections::{BTreeMap, VecDeque};
use std::path::Path;

pub use error::{FieldError, Location};
pub use movingai::MapReading;
pub use validate::{Problem, ValidationError};

/// Where and how a robot stands when a run begins.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub struct StartPose {
    /// The node it stands on.
    pub pos: Pos,
    /// The way it faces.
    pub heading: Heading,
}

/// A field's name as a native file's `name` line holds it: line breaks and
/// `#` (which starts a comment there) become spaces, and the ends are
/// trimmed. Every field's name then writes and reads back unchanged; a
/// carriage return inside a name line, or a `.sim` file named `a#b.sim`,
/// had given a name that came back other (found by the `field` fuzz
/// target).
fn one_line_name(name: String) -> String {
    name.replace(['\n', '\r', '#'], " ").trim().to_string()
}

/// Node spacing of the 2010 floors, in millimetres.
pub const DEFAULT_SPACING_MM: u16 = 100;

/// A validated field; see the module docs.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Field {
    name: String,
    nodes: BTreeMap<Pos, Arms>,
    starts: Vec<StartPose>,
    spacing_mm: u16,
}

impl Field {
    /// Validates and builds a field.
    pub fn new(
        name: impl Into<String>,
        nodes: BTreeMap<Pos, Arms>,
        starts: Vec<StartPose>,
    ) -> Result<Field, ValidationError> {
        validate::check(&nodes, &starts)?;
        Ok(Field {
            name: one_line_name(name.into()),
            nodes,
            starts,
            spacing_mm: DEFAULT_SPACING_MM,
        })
    }

    /// The same field with other start poses (validated again).
    pub fn with_starts(self, starts: Vec<StartPose>) -> Result<Field, ValidationError> {
        validate::check(&self.nodes, &starts)?;
        Ok(Field { starts, ..self })
    }

    /// The same field with another node spacing (millimetres, at least 1).
    pub fn with_spacing_mm(self, spacing_mm: u16) -> Field {
        Field {
            spacing_mm: spacing_mm.max(1),
            ..self
        }
    }

    /// The same field under another name.
    pub fn with_name(self, name: impl Into<String>) -> Field {
        Field {
            name: one_line_name(name.into()),
            ..self
        }
    }

    /// Human-readable name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Every node with its arms, ordered by (x, y).
    pub fn nodes(&self) -> &BTreeMap<Pos, Arms> {
        &self.nodes
    }

    /// The arms of `p`, or `None` where there is no node.
    pub fn arms(&self, p: Pos) -> Option<Arms> {
        self.nodes.get(&p).copied()
    }

    /// The start poses, in file order (robot `i` starts at `starts()[i]`).
    pub fn starts(&self) -> &[StartPose] {
        &self.starts
    }

    /// Distance between neighbouring nodes on the floor.
    pub fn spacing_mm(&self) -> u16 {
        self.spacing_mm
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.nodes
            .values()
            .map(|a| a.count() as usize)
            .sum::<usize>()
            / 2
    }

    /// The bounding box of the nodes. A field always has a node, so the box
    /// is at least 1 × 1.
    pub fn bounds(&self) -> Bounds {
        bounding_box(self.nodes.keys().copied())
    }

    /// The nodes in breadth-first order from `from`, following arms.
    pub fn bfs_order(&self, from: Pos) -> Vec<Pos> {
        bfs_order(&self.nodes, from)
    }
}

/// The smallest [`Bounds`] holding every position (1 × 1 at the origin for
/// none).
pub fn bounding_box(points: impl IntoIterator<Item = Pos>) -> Bounds {
    let mut it = points.into_iter();
    let Some(first) = it.next() else {
        return Bounds::new(Pos::new(0, 0), 1, 1);
    };
    let (mut lo, mut hi) = (first, first);
    for p in it {
        lo = Pos::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Pos::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let w = (i32::from(hi.x) - i32::from(lo.x) + 1) as u16;
    let h = (i32::from(hi.y) - i32::from(lo.y) + 1) as u16;
    Bounds::new(lo, w, h)
}

fn bfs_order(nodes: &BTreeMap<Pos, Arms>, from: Pos) -> Vec<Pos> {
    let mut seen = std::collections::HashSet::new();
    let mut order = Vec::new();
    let mut queue = VecDeque::new();
    if nodes.contains_key(&from) {
        seen.insert(from);
        queue.push_back(from);
    }
    while let Some(p) = queue.pop_front() {
        order.push(p);
        let arms = nodes.get(&p).copied().unwrap_or_default();
        for h in arms.iter() {
            if let Some(q) = p.step(h)
                && nodes.contains_key(&q)
                && seen.insert(q)
            {
                queue.push_back(q);
            }
        }
    }
    order
}

/// Up to `k` start poses packed around the south-west-most node (lowest y,
/// then lowest x), in breadth-first order, each facing its first arm in
/// N, E, S, W order. Deterministic; used where a format carries no starts.
pub fn default_starts(nodes: &BTreeMap<Pos, Arms>, k: usize) -> Vec<StartPose> {
    let Some(first) = nodes.keys().min_by_key(|p| (p.y, p.x)).copied() else {
        return Vec::new();
    };
    bfs_order(nodes, first)
        .into_iter()
        .take(k)
        .map(|pos| StartPose {
            pos,
            heading: nodes
                .get(&pos)
                .and_then(|a| a.iter().next())
                .unwrap_or(Heading::North),
        })
        .collect()
}

/// How to read a file: the format follows from the extension, and `.map`
/// files need a [`MapReading`].
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    /// How Moving AI grids become a lattice.
    pub map_reading: MapReading,
}

/// Loads a field from `path`, choosing the format by extension (`.field`,
/// `.sim`, `.sep`, `.map`).
pub fn load(path: &Path) -> Result<Field, FieldError> {
    load_with(path, LoadOptions::default())
}

/// [`load`] with explicit options.
pub fn load_with(path: &Path, options: LoadOptions) -> Result<Field, FieldError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| FieldError::io(&file, &e))?;
    parse_bytes(&bytes, &file, options)
}

/// Reads a field from the bytes of a file named `file` (an upload, say),
/// choosing the format by the name's extension, as [`load`] does.
pub fn parse_bytes(bytes: &[u8], file: &str, options: LoadOptions) -> Result<Field, FieldError> {
    let path = Path::new(file);
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|b| **b == b'\n')
            .count()
            + 1;
        let column = e.valid_up_to()
            - bytes[..e.valid_up_to()]
                .iter()
                .rposition(|b| *b == b'\n')
                .map_or(0, |i| i + 1)
            + 1;
        FieldError::at(
            file,
            line,
            column,
            "expected UTF-8 text, found a byte that is not",
        )
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    match extension(path).as_str() {
        "field" => native::parse(text, file),
        "sim" => sim::parse_sim(text, file, &stem),
        "sep" => sim::parse_sep(text, file, &stem),
        "map" => movingai::parse(text, file, &stem, options.map_reading),
        other => Err(FieldError::whole(
            file,
            format!("unknown field format '.{other}': expected .field, .sim, .sep or .map"),
        )),
    }
}

/// Writes `field` to `path` in the format its extension names (`.field`,
/// `.sim`, `.sep`).
pub fn save(field: &Field, path: &Path) -> Result<(), FieldError> {
    let file = path.display().to_string();
    let text = to_text(field, &file)?;
    std::fs::write(path, text).map_err(|e| FieldError::io(&file, &e))
}

/// The text of `field` in the format the extension of `file` names
/// (`.field`, `.sim`, `.sep`): what [`save`] writes, for a download.
pub fn to_text(field: &Field, file: &str) -> Result<String, FieldError> {
    match extension(Path::new(file)).as_str() {
        "field" => Ok(native::write(field)),
        "sim" => sim::write_sim(field).map_err(|m| FieldError::whole(file, m)),
        "sep" => sim::write_sep(field).map_err(|m| FieldError::whole(file, m)),
        other => Err(FieldError::whole(
            file,
            format!("cannot write format '.{other}': expected .field, .sim or .sep"),
        )),
    }
}

fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests;

//! The files a page downloads and uploads: the explored map as a field
//! file, and field files to run.

use super::api::FieldChoice;
use crate::field::{self, Field, LoadOptions, StartPose};
use core_algo::geometry::{Arms, Pos};
use core_algo::map::{Block, KnownMap};
use std::collections::BTreeMap;

/// The largest field a page may import, in bytes.
pub const MAX_IMPORT_BYTES: usize = 4 << 20;

/// The explored part of `map` as a file of `format` (`field` or `sep`),
/// named after `field_name`; answers (file name, text). Arms into nodes
/// nobody has seen yet are left out, so that a partial map is still a
/// valid field; the file says how many.
pub fn export(
    map: &KnownMap<Vec<Block>>,
    starts: Vec<StartPose>,
    field_name: &str,
    format: &str,
) -> Result<(String, String), String> {
    if !matches!(format, "field" | "sep") {
        return Err(format!("expected format field or sep, found '{format}'"));
    }
    let known: BTreeMap<Pos, Arms> = map
        .visited()
        .filter_map(|(p, c)| c.arms().map(|a| (p, a)))
        .collect();
    let mut clipped = 0usize;
    let nodes: BTreeMap<_, _> = known
        .iter()
        .map(|(&p, &a)| {
            let mut kept = a;
            for h in a.iter() {
                if p.step(h).is_none_or(|q| !known.contains_key(&q)) {
                    kept = kept.without(h);
                    clipped += 1;
                }
            }
            (p, kept)
        })
        .collect();
    if nodes.is_empty() {
        return Err("nothing explored yet".into());
    }
    let starts = starts
        .into_iter()
        .filter(|s| nodes.contains_key(&s.pos))
        .collect();
    let name = format!("{field_name} (explored)");
    let explored = Field::new(name, nodes, starts).map_err(|e| e.to_string())?;
    let file = format!("{}-explored.{format}", slug(field_name));
    let mut text = field::to_text(&explored, &file).map_err(|e| e.to_string())?;
    if clipped > 0 && format == "field" {
        text = text.replacen(
            '\n',
            &format!("\n# partial map: {clipped} arm(s) into unexplored nodes left out\n"),
            1,
        );
    }
    Ok((file, text))
}

/// Reads an uploaded field file `name` and adds it to `library` under a
/// name no other field there has.
pub fn import(library: &mut Vec<Field>, name: &str, bytes: &[u8]) -> Result<FieldChoice, String> {
    if bytes.len() > MAX_IMPORT_BYTES {
        return Err(format!(
            "{name}: {} bytes, more than the {MAX_IMPORT_BYTES} this server takes",
            bytes.len()
        ));
    }
    let file = std::path::Path::new(name)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut f =
        field::parse_bytes(bytes, &file, LoadOptions::default()).map_err(|e| e.to_string())?;
    if f.starts().is_empty() {
        return Err(format!("{file}: the field has no start pose"));
    }
    if f.name().is_empty() || library.iter().any(|g| g.name() == f.name()) {
        let base = if f.name().is_empty() {
            file.clone()
        } else {
            f.name().to_string()
        };
        let mut n = 1;
        let mut candidate = base.clone();
        while library.iter().any(|g| g.name() == candidate) {
            n += 1;
            candidate = format!("{base} ({n})");
        }
        f = f.with_name(candidate);
    }
    let c = choice(&f);
    library.push(f);
    Ok(c)
}

/// How a page lists a field.
pub fn choice(f: &Field) -> FieldChoice {
    FieldChoice {
        name: f.name().to_string(),
        starts: f.starts().len(),
        nodes: f.nodes().len(),
    }
}

/// A file-name-safe form of a field name.
fn slug(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let s = s.trim_matches('-').to_string();
    if s.is_empty() { "map".into() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_file_names() {
        assert_eq!(
            slug("demo (rooms 14x10, seed 4)"),
            "demo--rooms-14x10--seed-4"
        );
        assert_eq!(slug("---"), "map");
    }

    #[test]
    fn imports_get_unique_names_and_bad_files_are_refused() {
        let text = b"conquest-field 1\nname twin\nstart 0 0 N\nnode 0 0 N\nnode 0 1 S\n";
        let mut library = Vec::new();
        let a = import(&mut library, "a.field", text).expect("first");
        let b = import(&mut library, "b.field", text).expect("second");
        assert_eq!(a.name, "twin");
        assert_eq!(b.name, "twin (2)");
        assert_eq!(library.len(), 2);
        let e = import(&mut library, "c.field", b"conquest-field 1\nnode 0 0 N\n");
        assert!(e.is_err_and(|m| m.contains("c.field")));
        let e = import(&mut library, "d.png", b"x");
        assert!(e.is_err_and(|m| m.contains("unknown field format")));
        assert_eq!(library.len(), 2);
    }
}

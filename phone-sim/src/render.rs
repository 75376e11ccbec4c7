//! Pictures of fields: SVG (written by hand, it is a few lines of XML) and
//! PNG (drawn with plotters' bitmap backend).
//!
//! Both draw the same [`Scene`], so they always agree: edges as lines, nodes
//! as dots, start poses as numbered arrows in the robots' colours.

use crate::field::Field;
use core_algo::geometry::{Heading, Pos};
use std::fmt::Write;
use std::path::Path;

/// Colours of robots 0..6 (repeated beyond), shared by every view.
pub const ROBOT_COLOURS: [(u8, u8, u8); 6] = [
    (230, 57, 70),
    (29, 53, 87),
    (42, 157, 143),
    (244, 162, 97),
    (131, 56, 236),
    (255, 190, 11),
];

/// Pixels per edge at the default scale.
const CELL: f64 = 32.0;
const MARGIN: f64 = 24.0;

/// Drawing primitives in pixel coordinates (y down), produced once per field.
#[derive(Debug, Default)]
pub struct Scene {
    /// Picture size.
    pub width: f64,
    /// Picture height.
    pub height: f64,
    /// Line segments.
    pub lines: Vec<[(f64, f64); 2]>,
    /// Node centres.
    pub dots: Vec<(f64, f64)>,
    /// Start poses.
    pub starts: Vec<StartGlyph>,
}

/// A start pose as drawn: an arrow in the robot's colour with its number.
#[derive(Debug)]
pub struct StartGlyph {
    /// Tip, left and right corners of the arrow.
    pub arrow: [(f64, f64); 3],
    /// The robot's colour.
    pub colour: (u8, u8, u8),
    /// Where the label goes.
    pub label_at: (f64, f64),
    /// The robot's number.
    pub label: String,
}

impl Scene {
    /// Lays out `field` at `cell` pixels per edge.
    pub fn of(field: &Field, cell: f64) -> Scene {
        let b = field.bounds();
        let px = |p: Pos| -> (f64, f64) {
            let x = f64::from(i32::from(p.x) - i32::from(b.origin.x));
            let y = f64::from(i32::from(b.origin.y) + i32::from(b.height) - 1 - i32::from(p.y));
            (MARGIN + x * cell, MARGIN + y * cell)
        };
        let mut s = Scene {
            width: 2.0 * MARGIN + f64::from(b.width.saturating_sub(1)) * cell,
            height: 2.0 * MARGIN + f64::from(b.height.saturating_sub(1)) * cell,
            ..Scene::default()
        };
        for (&p, arms) in field.nodes() {
            s.dots.push(px(p));
            for h in [Heading::East, Heading::North] {
                if arms.has(h)
                    && let Some(q) = p.step(h)
                {
                    s.lines.push([px(p), px(q)]);
                }
            }
        }
        for (i, st) in field.starts().iter().enumerate() {
            let (cx, cy) = px(st.pos);
            let (dx, dy) = st.heading.delta();
            let (dx, dy) = (f64::from(dx), -f64::from(dy));
            let r = cell * 0.35;
            let tip = (cx + dx * r, cy + dy * r);
            let left = (
                cx - dx * r * 0.6 + dy * r * 0.7,
                cy - dy * r * 0.6 - dx * r * 0.7,
            );
            let right = (
                cx - dx * r * 0.6 - dy * r * 0.7,
                cy - dy * r * 0.6 + dx * r * 0.7,
            );
            let colour = ROBOT_COLOURS[i % ROBOT_COLOURS.len()];
            s.starts.push(StartGlyph {
                arrow: [tip, left, right],
                colour,
                label_at: (cx + r, cy - r),
                label: i.to_string(),
            });
        }
        s
    }

    /// The scene as an SVG document.
    pub fn svg(&self, title: &str) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.0} {:.0}">"#,
            self.width, self.height, self.width, self.height
        );
        let _ = writeln!(o, "<title>{}</title>", escape(title));
        let _ = writeln!(o, r##"<rect width="100%" height="100%" fill="#f4f1ea"/>"##);
        let _ = writeln!(
            o,
            r##"<g stroke="#222" stroke-width="4" stroke-linecap="round">"##
        );
        for [a, b] in &self.lines {
            let _ = writeln!(
                o,
                r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}"/>"#,
                a.0, a.1, b.0, b.1
            );
        }
        o.push_str("</g>\n<g fill=\"#222\">\n");
        for (x, y) in &self.dots {
            let _ = writeln!(
                o,
                r#"<rect x="{:.1}" y="{:.1}" width="8" height="8"/>"#,
                x - 4.0,
                y - 4.0
            );
        }
        o.push_str("</g>\n");
        for StartGlyph {
            arrow: tri,
            colour: (r, g, b),
            label_at: (lx, ly),
            label,
        } in &self.starts
        {
            let _ = writeln!(
                o,
                r#"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}" fill="rgb({r},{g},{b})" stroke="white"/>"#,
                tri[0].0, tri[0].1, tri[1].0, tri[1].1, tri[2].0, tri[2].1
            );
            let _ = writeln!(
                o,
                r#"<text x="{lx:.1}" y="{ly:.1}" font-family="sans-serif" font-size="12" fill="rgb({r},{g},{b})">{label}</text>"#
            );
        }
        o.push_str("</svg>\n");
        o
    }

    /// Draws the scene into a PNG file (labels are omitted: the bitmap
    /// backend has no font without system libraries).
    pub fn png(&self, path: &Path) -> Result<(), String> {
        use plotters::prelude::*;
        let (w, h) = (self.width.ceil() as u32, self.height.ceil() as u32);
        let root = BitMapBackend::new(path, (w.max(1), h.max(1))).into_drawing_area();
        let err = |e: &dyn std::fmt::Display| format!("cannot draw {}: {e}", path.display());
        root.fill(&RGBColor(244, 241, 234)).map_err(|e| err(&e))?;
        let p = |(x, y): (f64, f64)| (x.round() as i32, y.round() as i32);
        let ink = RGBColor(34, 34, 34);
        for [a, b] in &self.lines {
            root.draw(&PathElement::new(vec![p(*a), p(*b)], ink.stroke_width(4)))
                .map_err(|e| err(&e))?;
        }
        for d in &self.dots {
            let (x, y) = p(*d);
            root.draw(&Rectangle::new(
                [(x - 4, y - 4), (x + 4, y + 4)],
                ink.filled(),
            ))
            .map_err(|e| err(&e))?;
        }
        for StartGlyph {
            arrow: tri,
            colour: (r, g, b),
            ..
        } in &self.starts
        {
            let pts: Vec<(i32, i32)> = tri.iter().map(|q| p(*q)).collect();
            root.draw(&Polygon::new(pts, RGBColor(*r, *g, *b).filled()))
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Renders `field` to `out`, SVG or PNG by extension.
pub fn render(field: &Field, out: &Path) -> Result<(), String> {
    let scene = Scene::of(field, CELL);
    match out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => std::fs::write(out, scene.svg(field.name()))
            .map_err(|e| format!("{}: cannot write: {e}", out.display())),
        Some("png") => scene.png(out),
        _ => Err(format!(
            "{}: expected an output file ending in .svg or .png",
            out.display()
        )),
    }
}

//! The benchmark's outputs: CSV, a markdown summary and an SVG plot (drawn by
//! hand, so that text needs no font file).

use super::Row;
use std::collections::BTreeSet;
use std::fmt::Write;

/// The CSV with exactly the issue's columns.
pub fn csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "map,robots,strategy,complete,makespan_s,lower_bound_s,ratio,makespan_edges,lower_bound_edges,edge_ratio,moves,turns,revisits\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{:.2},{:.2},{:.4},{},{},{:.4},{},{},{}",
            r.map,
            r.robots,
            r.strategy,
            r.stats.complete,
            r.makespan_s(),
            r.lower_bound_s(),
            r.ratio(),
            r.stats.max_edges(),
            r.lower_bound_edges,
            r.edge_ratio(),
            r.stats.moves(),
            r.stats.total_turns(),
            r.stats.revisits
        );
    }
    s
}

fn mean(xs: impl Iterator<Item = f64>) -> Option<f64> {
    let (mut n, mut sum) = (0usize, 0.0);
    for x in xs {
        n += 1;
        sum += x;
    }
    (n > 0).then(|| sum / n as f64)
}

/// Mean of `f` over the rows of `strategy` with `robots` (any if `None`)
/// and at least two robots when `team` is set.
fn mean_of(
    rows: &[Row],
    strategy: &str,
    robots: Option<usize>,
    f: impl Fn(&Row) -> f64,
) -> Option<f64> {
    mean(
        rows.iter()
            .filter(|r| r.strategy == strategy && robots.is_none_or(|k| r.robots == k))
            .map(f),
    )
}

/// A markdown summary: mean makespan / lower bound per strategy and team
/// size, mean edge ratio, completion, and the gain over nearest frontier.
pub fn markdown(rows: &[Row], strategies: &[String]) -> String {
    let ks: BTreeSet<usize> = rows.iter().map(|r| r.robots).collect();
    let maps: BTreeSet<&str> = rows.iter().map(|r| r.map.as_str()).collect();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Fields: {}. Makespan = until the last robot is home; lower bound valid under the completion rule, with return.\n",
        maps.into_iter().collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(s, "### Mean makespan / lower bound (time)\n");
    let mut head = String::from("| strategy |");
    let mut line = String::from("|---|");
    for k in &ks {
        let _ = write!(head, " k={k} |");
        line.push_str("---|");
    }
    head.push_str(" mean k≥2 | edge ratio k≥2 | complete |");
    line.push_str("---|---|---|");
    let _ = writeln!(s, "{head}\n{line}");
    for st in strategies {
        let mut l = format!("| {st} |");
        for &k in &ks {
            match mean_of(rows, st, Some(k), Row::ratio) {
                Some(v) => {
                    let _ = write!(l, " {v:.3} |");
                }
                None => l.push_str(" |"),
            }
        }
        let team: Vec<&Row> = rows
            .iter()
            .filter(|r| &r.strategy == st && r.robots >= 2)
            .collect();
        let m = mean(team.iter().map(|r| r.ratio())).unwrap_or(f64::NAN);
        let e = mean(team.iter().map(|r| r.edge_ratio())).unwrap_or(f64::NAN);
        let done = rows
            .iter()
            .filter(|r| &r.strategy == st && r.stats.complete)
            .count();
        let all = rows.iter().filter(|r| &r.strategy == st).count();
        let _ = writeln!(l, " {m:.3} | {e:.3} | {done}/{all} |");
        s.push_str(&l);
    }
    if let Some(nf) = mean(
        rows.iter()
            .filter(|r| r.strategy == "nearest" && r.robots >= 2)
            .map(|r| r.makespan_s()),
    ) {
        let _ = writeln!(
            s,
            "\n### Mean makespan (s), k ≥ 2, and gain over nearest frontier\n"
        );
        let _ = writeln!(
            s,
            "| strategy | mean makespan s | gain vs nearest |\n|---|---|---|"
        );
        for st in strategies {
            if let Some(m) = mean(
                rows.iter()
                    .filter(|r| &r.strategy == st && r.robots >= 2)
                    .map(|r| r.makespan_s()),
            ) {
                let _ = writeln!(s, "| {st} | {m:.1} | {:+.1}% |", 100.0 * (nf - m) / nf);
            }
        }
    }
    s
}

const COLOURS: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// Mean makespan / lower bound against team size, one line per strategy.
pub fn svg_plot(rows: &[Row], strategies: &[String]) -> String {
    let ks: Vec<usize> = rows
        .iter()
        .map(|r| r.robots)
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let (w, h, ml, mr, mt, mb) = (820.0, 500.0, 70.0, 170.0, 40.0, 60.0);
    let series: Vec<(&String, Vec<(usize, f64)>)> = strategies
        .iter()
        .map(|st| {
            (
                st,
                ks.iter()
                    .filter_map(|&k| mean_of(rows, st, Some(k), Row::ratio).map(|v| (k, v)))
                    .collect(),
            )
        })
        .collect();
    let ymax = series
        .iter()
        .flat_map(|(_, v)| v.iter().map(|p| p.1))
        .fold(1.0f64, f64::max)
        .ceil()
        .max(2.0);
    let kmin = ks.first().copied().unwrap_or(1) as f64;
    let kmax = ks
        .last()
        .copied()
        .unwrap_or(1)
        .max(ks.first().copied().unwrap_or(1) + 1) as f64;
    let x = |k: f64| ml + (k - kmin) / (kmax - kmin) * (w - ml - mr);
    let y = |v: f64| mt + (1.0 - (v - 1.0) / (ymax - 1.0)) * (h - mt - mb);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="15">Makespan / lower bound (mean over fields)</text>"#,
        (w - mr + ml) / 2.0
    );
    let steps = ((ymax - 1.0) / 0.5).round() as usize;
    for i in 0..=steps {
        let v = 1.0 + i as f64 * 0.5;
        let yy = y(v);
        let _ = writeln!(
            s,
            r##"<line x1="{ml}" x2="{}" y1="{yy:.1}" y2="{yy:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{v:.1}</text>"##,
            w - mr,
            ml - 6.0,
            yy + 4.0
        );
    }
    for &k in &ks {
        let xx = x(k as f64);
        let _ = writeln!(
            s,
            r#"<text x="{xx:.1}" y="{}" text-anchor="middle">{k}</text>"#,
            h - mb + 20.0
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">robots</text>"#,
        (w - mr + ml) / 2.0,
        h - 15.0
    );
    let _ = writeln!(
        s,
        r#"<rect x="{ml}" y="{mt}" width="{}" height="{}" fill="none" stroke="black"/>"#,
        w - ml - mr,
        h - mt - mb
    );
    for (n, (st, pts)) in series.iter().enumerate() {
        let c = COLOURS[n % COLOURS.len()];
        let path: Vec<String> = pts
            .iter()
            .map(|&(k, v)| format!("{:.1},{:.1}", x(k as f64), y(v)))
            .collect();
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="2"/>"#,
            path.join(" ")
        );
        for &(k, v) in pts {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="{c}"/>"#,
                x(k as f64),
                y(v)
            );
        }
        let ly = mt + 18.0 * n as f64 + 10.0;
        let _ = writeln!(
            s,
            r#"<line x1="{}" x2="{}" y1="{ly}" y2="{ly}" stroke="{c}" stroke-width="3"/><text x="{}" y="{}">{st}</text>"#,
            w - mr + 12.0,
            w - mr + 36.0,
            w - mr + 42.0,
            ly + 4.0
        );
    }
    s.push_str("</svg>\n");
    s
}

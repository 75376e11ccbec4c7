//! The `conquest` binary as a user meets it: exit codes, one-line errors,
//! and every field the project ships.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn conquest(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_conquest"))
        .args(args)
        .output()
        .expect("run conquest")
}

fn fields_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fields")
}

fn project_fields() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![fields_dir()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(d).expect("fields/") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                dirs.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn every_project_field_validates() {
    let fields = project_fields();
    assert!(fields.len() >= 8, "{fields:?}");
    for f in fields {
        let out = conquest(&["validate", f.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}: {}",
            f.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(String::from_utf8_lossy(&out.stdout).contains(": ok: "));
    }
}

#[test]
fn bad_input_is_one_line_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.sim");
    // A corrupted copy of a project field: one node type misspelt.
    let good = std::fs::read_to_string(fields_dir().join("small/ring.sim")).unwrap();
    std::fs::write(&bad, good.replacen("CROSS", "CROS", 1)).unwrap();
    let out = conquest(&["validate", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("broken.sim:") && err.contains("expected a node type"),
        "{err}"
    );
    let out = conquest(&["validate", "/nonexistent/x.field"]);
    assert_eq!(out.status.code(), Some(2));
    let out = conquest(&["generate", "maze", "--size", "0x3"]);
    assert_eq!(out.status.code(), Some(2), "clap usage errors exit 2 too");
}

#[test]
fn convert_render_generate_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    assert!(
        conquest(&[
            "generate",
            "open",
            "--size",
            "5x4",
            "--seed",
            "3",
            "--out",
            &d("g.field")
        ])
        .status
        .success()
    );
    assert!(
        conquest(&["convert", &d("g.field"), &d("g.sim")])
            .status
            .success()
    );
    assert!(
        conquest(&["convert", &d("g.sim"), &d("h.field")])
            .status
            .success()
    );
    let a = std::fs::read_to_string(d("g.field")).unwrap();
    let b = std::fs::read_to_string(d("h.field")).unwrap();
    // Only the name differs (a .sim file carries none; it takes the file's).
    assert_eq!(
        a.lines().skip(2).collect::<Vec<_>>(),
        b.lines().skip(2).collect::<Vec<_>>()
    );
    for pic in ["g.svg", "g.png"] {
        let out = conquest(&["render", &d("g.field"), "--out", &d(pic)]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(std::fs::metadata(d(pic)).unwrap().len() > 100);
    }
    let svg = std::fs::read_to_string(d("g.svg")).unwrap();
    assert_eq!(svg.matches("<line ").count(), 4 * 4 + 5 * 3);
    assert_eq!(svg.matches("<polygon ").count(), 6);
    let png = std::fs::read(d("g.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn no_arguments_runs_the_demo() {
    let out = conquest(&[]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("demo"));
}

#[test]
fn explore_localizes_and_reports_the_time() {
    let field = fields_dir().join("small/open-6x6.field");
    for how in ["local", "global"] {
        let out = conquest(&[
            "explore",
            field.to_str().unwrap(),
            "--robots",
            "3",
            "--localize",
            how,
            "--json",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(r["localize"], how);
        assert_eq!(r["poses_correct"], true, "{r}");
        assert_eq!(r["complete"], true, "{r}");
        let took = r["localize_s"].as_f64().unwrap();
        assert!(
            took > 0.0 && took < r["makespan_s"].as_f64().unwrap(),
            "{r}"
        );
    }
    // Known poses: nothing to localize.
    let out = conquest(&[
        "explore",
        field.to_str().unwrap(),
        "--robots",
        "2",
        "--json",
    ]);
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["localize"], "known");
    assert!(r["localize_s"].is_null() && r["poses_correct"].is_null());
}

#[test]
fn explore_refuses_local_localization_from_scattered_starts() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("scattered.field");
    let out = conquest(&[
        "generate",
        "open",
        "--size",
        "5x5",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&f).unwrap();
    let kept: Vec<&str> = text.lines().filter(|l| !l.starts_with("start ")).collect();
    let mut scattered = kept.join("\n");
    scattered.push_str("\nstart 0 0 N\nstart 4 4 S\n");
    std::fs::write(&f, scattered).unwrap();
    let out = conquest(&["explore", f.to_str().unwrap(), "--localize", "local"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--localize global"), "{err}");
    let out = conquest(&[
        "explore",
        f.to_str().unwrap(),
        "--localize",
        "global",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["poses_correct"], true, "{r}");
}

/// `--realtime` only delays steps: a paced run reports exactly what the
/// unpaced run does (fast factor, so the test does not wait), but for the
/// wall time and the memo's counts: which of two searches run side by
/// side is written down first, and so taken over later, depends on the
/// threads (the run itself does not).
#[test]
fn realtime_pacing_gives_the_same_run() {
    let field = fields_dir().join("small/open-6x6.field");
    let field = field.to_str().unwrap();
    let result = |extra: &[&str]| {
        let mut args = vec!["explore", field, "--robots", "2", "--json"];
        args.extend_from_slice(extra);
        let out = conquest(&args);
        assert!(out.status.success(), "{out:?}");
        let mut v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let o = v.as_object_mut().unwrap();
        for key in [
            "wall_s",
            "searches_taken_over",
            "searches_taken_over_in_part",
            "searches_taken_over_after",
            "searches_recorded",
            "searches_recorded_after",
            "column_searches_lent",
            "column_searches_given",
        ] {
            assert!(o.remove(key).is_some(), "{key} reported");
        }
        v
    };
    let plain = result(&[]);
    assert_eq!(plain["complete"], true);
    assert_eq!(result(&["--realtime", "100000"]), plain);
    for bad in ["0", "-1", "fast", "inf"] {
        let out = conquest(&["explore", field, "--realtime", bad]);
        assert_eq!(out.status.code(), Some(2), "--realtime {bad}: {out:?}");
    }
}

#[test]
fn generate_packs_starts_and_explore_refuses_teams_beyond_the_planner() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let out = conquest(&[
        "generate",
        "open",
        "--size",
        "6x6",
        "--starts",
        "16",
        "--out",
        &d("s.field"),
    ]);
    assert!(out.status.success(), "{out:?}");
    let text = std::fs::read_to_string(d("s.field")).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("start ")).count(), 16);
    // 17 is beyond the planner's team size: clap refuses it.
    let out = conquest(&["generate", "open", "--starts", "17"]);
    assert_eq!(out.status.code(), Some(2));
    // A .sim file holds at most six starts: a clear error, not a bad file.
    let out = conquest(&[
        "generate",
        "open",
        "--size",
        "6x6",
        "--starts",
        "7",
        "--out",
        &d("s.sim"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!std::path::Path::new(&d("s.sim")).exists());
    // A field with more starts than a team may have: one line, status 2.
    let more: String = (2..6).map(|i| format!("start {i} 5 N\n")).collect();
    std::fs::write(d("t.field"), text + &more).unwrap();
    let out = conquest(&["explore", &d("t.field"), "--json"]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("at most 16"), "{err}");
}

/// A run given up at its time limit says so, on stderr and in the JSON,
/// and a limit beyond the simulator's clock is cut with a warning, not
/// silently.
#[test]
fn a_run_cut_by_its_time_limit_says_so() {
    let field = fields_dir().join("small/open-6x6.field");
    let field = field.to_str().unwrap();
    let run = |limit: &str| {
        let out = conquest(&[
            "explore",
            field,
            "--robots",
            "2",
            "--max-time-s",
            limit,
            "--json",
        ]);
        assert!(out.status.success());
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        (r, String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (r, err) = run("5");
    assert_eq!(
        (&r["complete"], &r["timed_out"]),
        (&false.into(), &true.into()),
        "{r}"
    );
    assert!(err.contains("given up at its time limit"), "{err}");
    let (r, err) = run("3600");
    assert_eq!(
        (&r["complete"], &r["timed_out"]),
        (&true.into(), &false.into()),
        "{r}"
    );
    assert!(err.is_empty(), "{err}");
    let (r, err) = run("1e7");
    assert_eq!(r["complete"], true, "{r}");
    assert!(err.contains("the simulator's clock holds"), "{err}");
}

//! `pickplace batch`: many scenes planned in parallel, each plan the bytes `pickplace plan`
//! writes, one summary line per scene in the order given, resumable (docs/batch.md).

use crate::support::run_at_root as run;
use crate::support::{Scratch, fails_with, stderr, stdout};
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// The summary's lines, parsed.
fn summary(out: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(out.join("summary.jsonl")).expect("summary written");
    assert!(text.ends_with('\n'), "whole lines: {text:?}");
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
        .collect()
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn code(o: &Output) -> Option<i32> {
    o.status.code()
}

#[test]
fn batch_plans_are_the_bytes_of_pickplace_plan_and_lines_keep_the_input_order() {
    let dir = Scratch::new("batch-same");
    let out = dir.join("out");
    // Not in name order: the summary follows the order given.
    let scenes = [
        "scenes/fig10b-mug.toml",
        "scenes/fig9-near.toml",
        "scenes/fig10a-edge.toml",
    ];
    let o = run(crate::args![
        "batch",
        scenes[0],
        scenes[1],
        scenes[2],
        "--out",
        out,
        "--jobs",
        "2",
        "--no-timings"
    ]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let lines = summary(&out);
    assert_eq!(lines.len(), 3);
    for (line, scene) in lines.iter().zip(scenes) {
        assert_eq!(line["format"], "pickplace.batch/1");
        assert_eq!(line["scene"], scene);
        assert_eq!(line["status"], "planned", "{line}");
        assert!(line["time"].is_null(), "no timings: {line}");
        assert!(line["duration"].as_f64().expect("duration") > 0.0);
        assert_eq!(line["seed"], 1);
        assert_eq!(line["reasons"].as_array().expect("reasons").len(), 0);
        let stem = Path::new(scene).file_stem().expect("stem");
        let plan = out.join(stem).with_extension("json");
        assert_eq!(line["plan"], plan.to_str().expect("utf-8"));
        // The same scene through `pickplace plan`.
        let single = dir.join(&format!("{}.json", stem.to_string_lossy()));
        let p = run(crate::args!["plan", scene, "--out", single, "--no-timings"]);
        assert_eq!(code(&p), Some(0), "{}", stderr(&p));
        assert!(
            read(&plan) == read(&single),
            "{scene}: not the bytes of pickplace plan"
        );
        let v: serde_json::Value = serde_json::from_slice(&read(&plan)).expect("plan JSON");
        assert_eq!(line["strategy"], v["strategy"]);
    }
    // The table names every scene; the files are the plans and the summary, nothing else.
    let table = stdout(&o);
    for scene in scenes {
        assert!(table.contains(scene), "{table}");
    }
    assert!(table.contains("3 planned"), "{table}");
    assert_eq!(
        dir.files("out"),
        [
            "fig10a-edge.json",
            "fig10b-mug.json",
            "fig9-near.json",
            "summary.jsonl"
        ]
    );
    // Again without timings: the same bytes, summary included.
    let before = read(&out.join("summary.jsonl"));
    let o = run(crate::args![
        "batch",
        scenes[0],
        scenes[1],
        scenes[2],
        "--out",
        out,
        "--no-timings",
        "--quiet"
    ]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    assert!(
        o.stdout.is_empty() && o.stderr.is_empty(),
        "--quiet: {}",
        stderr(&o)
    );
    assert_eq!(read(&out.join("summary.jsonl")), before);
}

#[test]
fn resume_skips_valid_plans_and_plans_a_corrupted_one_again() {
    let dir = Scratch::new("batch-resume");
    let out = dir.join("out");
    let scene = "scenes/fig9-near.toml";
    let o = run(crate::args!["batch", scene, "--out", out, "--no-timings"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let plan = out.join("fig9-near.json");
    let planned = read(&plan);

    let o = run(crate::args!["batch", scene, "--out", out, "--resume"]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let line = &summary(&out)[0];
    assert_eq!(line["status"], "skipped", "{line}");
    assert_eq!(line["plan"], plan.to_str().expect("utf-8"));
    assert_eq!(line["strategy"], "right-right");
    assert!(line["time"].as_f64().is_some(), "timings on: {line}");
    assert!(line["replanned"].is_null());
    assert_eq!(read(&plan), planned, "kept as it was");

    // Half a plan: planned again, and the line says why.
    std::fs::write(&plan, &planned[..planned.len() / 2]).expect("cut");
    let o = run(crate::args![
        "batch",
        scene,
        "--out",
        out,
        "--resume",
        "--no-timings"
    ]);
    assert_eq!(code(&o), Some(0), "{}", stderr(&o));
    let line = &summary(&out)[0];
    assert_eq!(line["status"], "planned", "{line}");
    let why = line["replanned"].as_str().expect("why");
    assert!(why.contains("fig9-near.json: not a valid plan"), "{why}");
    assert!(stdout(&o).contains("re-planned"), "{}", stdout(&o));
    assert_eq!(read(&plan), planned);
}

#[test]
fn a_bad_scene_among_good_ones_is_a_line_and_exit_2() {
    let dir = Scratch::new("batch-bad");
    let out = dir.join("out");
    let bad = dir.file("broken.toml", b"format = 1\n[robot]\nurdf = 3\n");
    let o = run(crate::args![
        "batch",
        "scenes/fig9-near.toml",
        bad,
        "--out",
        out
    ]);
    assert_eq!(code(&o), Some(2), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    let lines = summary(&out);
    assert_eq!(lines[0]["status"], "planned");
    assert!(lines[0]["time"].as_f64().expect("time") > 0.0);
    assert_eq!(lines[1]["status"], "bad-input");
    assert!(lines[1]["plan"].is_null());
    // The message `pickplace plan` prints for that scene.
    let p = run(crate::args!["plan", bad]);
    assert_eq!(code(&p), Some(2));
    let message = stderr(&p);
    let message = message
        .trim_end()
        .lines()
        .last()
        .and_then(|l| l.strip_prefix("error: "))
        .expect("an error line");
    assert_eq!(lines[1]["error"], message);
    assert!(
        stdout(&o).contains(&format!("error: {message}")),
        "{}",
        stdout(&o)
    );
    assert_eq!(dir.files("out"), ["fig9-near.json", "summary.jsonl"]);
}

#[test]
fn a_scene_without_a_plan_is_a_line_with_reasons_and_exit_1() {
    let dir = Scratch::new("batch-no-plan");
    let out = dir.join("out");
    // A plan file an earlier run left is removed: the folder agrees with the summary.
    std::fs::create_dir_all(&out).expect("out");
    std::fs::write(out.join("fig9-near.json"), "{}").expect("stale");
    let o = run(crate::args![
        "batch",
        "scenes/fig9-near.toml",
        "--out",
        out,
        "--time-budget",
        "0"
    ]);
    assert_eq!(code(&o), Some(1), "{}", stderr(&o));
    let line = &summary(&out)[0];
    assert_eq!(line["status"], "no-plan");
    let reasons = line["reasons"].as_array().expect("reasons");
    assert!(!reasons.is_empty());
    assert!(
        reasons[0]
            .as_str()
            .expect("text")
            .contains("time budget of 0 s"),
        "{line}"
    );
    assert_eq!(dir.files("out"), ["summary.jsonl"]);
}

#[test]
fn scenes_with_the_same_file_name_are_refused_before_any_work() {
    let dir = Scratch::new("batch-names");
    let out = dir.join("out");
    let copy = dir.file("fig9-near.toml", b"not read");
    let o = run(crate::args![
        "batch",
        "scenes/fig9-near.toml",
        copy,
        "--out",
        out
    ]);
    fails_with(
        &o,
        &[
            "scenes/fig9-near.toml and",
            "both would be planned into fig9-near.json",
        ],
    );
    assert!(!out.exists(), "nothing written");
    // And an output that is not a folder, and no scene at all.
    let file = dir.file("file", b"x");
    let o = run(crate::args![
        "batch",
        "scenes/fig9-near.toml",
        "--out",
        file
    ]);
    fails_with(&o, &["--out", "is not a folder"]);
    let o = run(crate::args!["batch", "--out", out]);
    assert_eq!(code(&o), Some(2));
}

#[test]
fn a_closed_standard_output_ends_the_table_quietly() {
    let dir = Scratch::new("batch-closed");
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(["batch", "scenes/fig10b-mug.toml", "--out"])
        .arg(&out)
        .current_dir(crate::root())
        .env(
            "PICKPLACE_CACHE",
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache"),
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the pickplace binary runs");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("pickplace ends");
    let err = stderr(&o);
    assert!(
        !err.contains("panicked") && !err.contains("error:"),
        "{err}"
    );
    assert_eq!(code(&o), Some(0), "{err}");
    assert_eq!(summary(&out)[0]["status"], "planned");
}

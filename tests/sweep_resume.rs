//! End-to-end tests of `bumpsim sweep --resume`: a killed sweep (a journal with some rows
//! and a torn last line, next to a shard's final files) resumed gives the uninterrupted
//! run's bytes and runs only the missing points; an edited sweep reruns the changed points;
//! resume with `--shard`; bad journals exit 2 naming the file and line; and a sweep really
//! killed (SIGKILL) part-way resumes to the same bytes.

mod common;

use common::*;
use std::path::Path;

fn sweep(args: &[&str]) -> Out {
    bumpsim(&[&["sweep"], args].concat())
}

/// A 6-point sweep of the 32x32 teapot over the power table's index bits.
fn sweep_file(dir: &Path, name: &str, values: &str, sets: &str) -> String {
    let base = root().join("configs/sgi-teapot.ron");
    let file = dir.join(name);
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    sets: [{sets}],
    axes: [(path: "engine.units.spec.unit.index_bits", name: "index_bits", values: {values})],
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    file.to_str().unwrap().to_string()
}

const SETS: &str = r#""scene.width=32", "scene.height=32""#;

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn same_files(a: &Path, b: &Path, what: &str) {
    for name in ["sweep.csv", "sweep.jsonl", "sweep.json"] {
        assert_eq!(read(&a.join(name)), read(&b.join(name)), "{what}: {name}");
    }
    assert!(
        !b.join("sweep.partial.jsonl").exists(),
        "{what}: the journal is removed at the end"
    );
}

fn lines(p: &Path) -> Vec<String> {
    std::fs::read_to_string(p)
        .unwrap()
        .lines()
        .map(String::from)
        .collect()
}

#[test]
fn a_killed_sweep_resumes_to_the_uninterrupted_bytes() {
    let s = Scratch::new("sweep-resume");
    let file = sweep_file(&s.path, "s.ron", "Grid(4, 9, 6)", SETS);
    let all = s.join("all");
    sweep(&[&file, "--out", all.to_str().unwrap(), "--threads", "2"])
        .expect_code(0, "the uninterrupted sweep");
    let rows = lines(&all.join("sweep.jsonl"));
    assert_eq!(rows.len(), 6);

    // the killed run: shard 0/2 finished (rows 0, 2, 4 in its final files), then a run
    // of the whole sweep journaled rows 3 and 1 (completion order) and was killed while
    // writing row 5
    let k = s.join("killed");
    let o = sweep(&[&file, "--out", k.to_str().unwrap(), "--shard", "0/2"]);
    o.expect_code(0, "shard 0/2");
    assert!(o.stdout.contains("3 of 6 points run"), "{}", o.stdout);
    let torn = &rows[5][..rows[5].len() / 2];
    std::fs::write(
        k.join("sweep.partial.jsonl"),
        format!("{}\n{}\n{torn}", rows[3], rows[1]),
    )
    .unwrap();
    let o = sweep(&[
        &file,
        "--out",
        k.to_str().unwrap(),
        "--resume",
        "--threads",
        "1",
    ]);
    o.expect_code(0, "resume");
    assert!(
        o.stdout.contains("resume: 5 points kept") && o.stdout.contains("1 of 6 points run"),
        "only point 5 runs again: {}",
        o.stdout
    );
    same_files(&all, &k, "resumed at 1 thread vs uninterrupted at 2");

    // resuming a finished sweep runs nothing and changes no byte
    let o = sweep(&[&file, "--out", k.to_str().unwrap(), "--resume"]);
    o.expect_code(0, "resume of a finished sweep");
    assert!(o.stdout.contains("0 of 6 points run"), "{}", o.stdout);
    same_files(&all, &k, "resume of a finished sweep");

    // an edited sweep: point 5 now has 10 bits instead of 9; only it runs again, and the
    // result is a fresh run of the edited sweep
    let edited = sweep_file(&s.path, "e.ron", "List([4, 5, 6, 7, 8, 10])", SETS);
    let fresh = s.join("fresh");
    sweep(&[&edited, "--out", fresh.to_str().unwrap()]).expect_code(0, "the edited sweep");
    let o = sweep(&[&edited, "--out", k.to_str().unwrap(), "--resume"]);
    o.expect_code(0, "resume of the edited sweep");
    assert!(
        o.stdout.contains("5 points kept") && o.stdout.contains("1 earlier rows run again"),
        "{}",
        o.stdout
    );
    assert!(o.stdout.contains("1 of 6 points run"), "{}", o.stdout);
    same_files(&fresh, &k, "resumed edited sweep vs its fresh run");

    // a change every point sees (its `sets`, so every config hash) reruns them all
    let wider = sweep_file(
        &s.path,
        "w.ron",
        "List([4, 5, 6, 7, 8, 10])",
        r#""scene.width=33", "scene.height=32""#,
    );
    let o = sweep(&[&wider, "--out", k.to_str().unwrap(), "--resume"]);
    o.expect_code(0, "resume after a change to every point");
    assert!(
        o.stdout.contains("0 points kept") && o.stdout.contains("6 earlier rows run again"),
        "{}",
        o.stdout
    );
    assert!(o.stdout.contains("6 of 6 points run"), "{}", o.stdout);

    // without --resume an earlier journal is replaced and every point runs
    std::fs::write(all.join("sweep.partial.jsonl"), format!("{}\n", rows[0])).unwrap();
    let o = sweep(&[&file, "--out", all.to_str().unwrap()]);
    o.expect_code(0, "a run over a journal without --resume");
    assert!(o.stdout.contains("6 of 6 points run"), "{}", o.stdout);
    assert!(o.stderr.contains("replaced the journal"), "{}", o.stderr);
    assert_eq!(lines(&all.join("sweep.jsonl")), rows, "the same rows again");
    assert!(!all.join("sweep.partial.jsonl").exists());
}

#[test]
fn resume_combines_with_shards() {
    let s = Scratch::new("sweep-resume-shard");
    let file = sweep_file(&s.path, "s.ron", "Grid(4, 9, 6)", SETS);
    let (all, shard) = (s.join("all"), s.join("shard1"));
    sweep(&[&file, "--out", all.to_str().unwrap()]).expect_code(0, "the whole sweep");
    sweep(&[&file, "--out", shard.to_str().unwrap(), "--shard", "1/2"]).expect_code(0, "shard 1/2");
    // a timed-out array task of shard 1/2 that had journaled rows 0..3 of the whole sweep
    // (rows of other shards are not its business)
    let rows = lines(&all.join("sweep.jsonl"));
    let t = s.join("timed-out");
    std::fs::create_dir_all(&t).unwrap();
    std::fs::write(t.join("sweep.partial.jsonl"), rows[..4].join("\n") + "\n").unwrap();
    let o = sweep(&[
        &file,
        "--out",
        t.to_str().unwrap(),
        "--shard",
        "1/2",
        "--resume",
    ]);
    o.expect_code(0, "resume of shard 1/2");
    assert!(
        o.stdout.contains("resume: 2 points kept") && o.stdout.contains("1 of 6 points run"),
        "{}",
        o.stdout
    );
    same_files(&shard, &t, "resumed shard vs shard");
}

#[test]
fn bad_journals_exit_2_naming_the_file_and_line() {
    let s = Scratch::new("sweep-resume-bad");
    let file = sweep_file(&s.path, "s.ron", "Grid(4, 5, 2)", SETS);
    let d = s.join("out");
    sweep(&[&file, "--out", d.to_str().unwrap()]).expect_code(0, "the sweep");
    let good = lines(&d.join("sweep.jsonl"))[0].clone();
    let journal = d.join("sweep.partial.jsonl");
    let cases: [(Vec<u8>, &str); 4] = [
        (b"hello\n".to_vec(), ":1:1"),
        (format!("{good}\n[1, 2]\n").into_bytes(), ":2:1"),
        (
            format!("{good}\n{{\"foo\": 1}}\n").into_bytes(),
            "\"index\"",
        ),
        (b"\xff\xfe\n".to_vec(), "UTF-8"),
    ];
    for (text, needle) in cases {
        std::fs::write(&journal, &text).unwrap();
        let o = sweep(&[&file, "--out", d.to_str().unwrap(), "--resume"]);
        o.expect_code(2, needle);
        assert!(
            o.stderr.contains("sweep.partial.jsonl") && o.stderr.contains(needle),
            "{needle}: {}",
            o.stderr
        );
        assert!(!o.stderr.contains("panicked"), "{}", o.stderr);
    }
    // a bad final file is named too
    std::fs::remove_file(&journal).unwrap();
    std::fs::write(d.join("sweep.jsonl"), "{\"index\": \"x\"}\n").unwrap();
    let o = sweep(&[&file, "--out", d.to_str().unwrap(), "--resume"]);
    o.expect_code(2, "a bad sweep.jsonl");
    assert!(o.stderr.contains("sweep.jsonl:1:1"), "{}", o.stderr);
}

#[test]
fn a_sweep_killed_by_a_signal_resumes_to_the_same_bytes() {
    let s = Scratch::new("sweep-resume-kill");
    let bits: Vec<String> = (0..21).map(|i| (4 + i % 7).to_string()).collect();
    let values = format!("List([{}])", bits.join(", "));
    let file = sweep_file(&s.path, "k.ron", &values, SETS);
    let all = s.join("all");
    sweep(&[&file, "--out", all.to_str().unwrap(), "--threads", "2"])
        .expect_code(0, "the uninterrupted sweep");
    // the same sweep on one thread, killed (SIGKILL) once its journal holds 3 rows
    let k = s.join("killed");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_bumpsim"))
        .args([
            "sweep",
            &file,
            "--out",
            k.to_str().unwrap(),
            "--threads",
            "1",
        ])
        .current_dir(root())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let journal = k.join("sweep.partial.jsonl");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        let rows = std::fs::read_to_string(&journal).map_or(0, |t| t.matches('\n').count());
        if rows >= 3 {
            child.kill().unwrap();
            child.wait().unwrap();
            break;
        }
        if std::time::Instant::now() > deadline {
            child.kill().unwrap();
            panic!("the sweep journaled no 3 rows in 120 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let killed = !k.join("sweep.csv").exists();
    let journaled = std::fs::read_to_string(&journal).map_or(0, |t| t.matches('\n').count());
    eprintln!("killed: {killed}, {journaled} rows journaled");
    if killed {
        assert!((3..21).contains(&journaled), "{journaled} rows journaled");
    }
    let o = sweep(&[
        &file,
        "--out",
        k.to_str().unwrap(),
        "--resume",
        "--threads",
        "2",
    ]);
    o.expect_code(0, "resume of the killed sweep");
    // every journaled row is kept, only the others run
    let kept = if killed { journaled } else { 21 };
    assert!(
        o.stdout.contains(&format!("resume: {kept} points kept"))
            && o.stdout
                .contains(&format!("{} of 21 points run", 21 - kept)),
        "killed: {killed}, {journaled} rows journaled: {}",
        o.stdout
    );
    same_files(&all, &k, "resumed after SIGKILL vs uninterrupted");
}

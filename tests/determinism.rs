//! Renders are deterministic: the same config gives byte-identical outputs run after run and
//! whatever the number of rayon threads (the float reference renders rows in parallel).

mod common;

use common::*;

/// A render's files: (name, bytes) in name order.
type Files = Vec<(String, Vec<u8>)>;

/// Render `stem` twice and on one and on two rayon threads; every file of every run must be
/// byte-identical to the first run's (the same files, the same bytes).
fn renders_are_byte_identical(stem: &str) {
    let cfg = config(stem);
    let scratch = Scratch::new(&format!("determinism-{stem}"));
    let runs: [(&str, Option<&str>); 4] = [
        ("a", None),
        ("b", None),
        ("threads1", Some("1")),
        ("threads2", Some("2")),
    ];
    let mut outputs: Vec<(String, Files)> = Vec::new();
    for (tag, threads) in runs {
        let out = scratch.join(tag);
        let envs: Vec<(&str, &str)> = threads
            .map(|t| ("RAYON_NUM_THREADS", t))
            .into_iter()
            .collect();
        let o = bumpsim_env(
            &[
                "render".as_ref(),
                cfg.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
            &envs,
        );
        o.expect_code(0, &format!("{stem}: render run {tag}"));
        let files = listing(&out)
            .into_iter()
            .map(|f| {
                let bytes = std::fs::read(out.join(&f));
                let bytes = bytes.unwrap_or_else(|e| panic!("{tag}/{f}: {e}"));
                (f, bytes)
            })
            .collect();
        outputs.push((tag.to_string(), files));
    }
    let (first_tag, first) = &outputs[0];
    assert!(
        first.len() >= 4,
        "{stem}: {first_tag} wrote {} files",
        first.len()
    );
    for (tag, files) in &outputs[1..] {
        let names = |v: &Files| v.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
        assert_eq!(names(files), names(first), "{stem}: the files of run {tag}");
        for ((f, bytes), (_, want)) in files.iter().zip(first) {
            assert!(
                bytes == want,
                "{stem}: {f} of run {tag} differs from run {first_tag} ({} vs {} bytes)",
                bytes.len(),
                want.len()
            );
        }
    }
}

#[test]
fn teapot_renders_are_byte_identical_across_runs_and_thread_counts() {
    renders_are_byte_identical("sgi-teapot");
}

/// An animation's every frame (`frame-00k.png`) and its report's animation section too.
#[test]
fn animations_are_byte_identical_across_runs_and_thread_counts() {
    renders_are_byte_identical("quantized-sphere-orbit");
}

//! Renders are deterministic: the same config gives byte-identical outputs run after run and
//! whatever the number of rayon threads (the float reference renders rows in parallel).

mod common;

use common::*;

const FILES: [&str; 4] = ["image.png", "reference.png", "error.png", "report.json"];

#[test]
fn teapot_renders_are_byte_identical_across_runs_and_thread_counts() {
    let cfg = config("sgi-teapot");
    let scratch = Scratch::new("determinism");
    let runs: [(&str, Option<&str>); 4] = [
        ("a", None),
        ("b", None),
        ("threads1", Some("1")),
        ("threads2", Some("2")),
    ];
    let mut outputs: Vec<(String, Vec<Vec<u8>>)> = Vec::new();
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
        o.expect_code(0, &format!("render run {tag}"));
        let files = FILES
            .iter()
            .map(|f| std::fs::read(out.join(f)).unwrap_or_else(|e| panic!("{tag}/{f}: {e}")))
            .collect();
        outputs.push((tag.to_string(), files));
    }
    let (first_tag, first) = &outputs[0];
    for (tag, files) in &outputs[1..] {
        for (k, f) in FILES.iter().enumerate() {
            assert!(
                files[k] == first[k],
                "{f} of run {tag} differs from run {first_tag} ({} vs {} bytes)",
                files[k].len(),
                first[k].len()
            );
        }
    }
}

//! `--set` override parsing: each line of the input is one `--set path=value`, applied to a
//! bundled config (the first byte picks which). No panic, no stack overflow.
#![no_main]

use bumpsim_pipeline::config::{self, LoadOptions};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

const BASES: &[(&str, &str)] = &[
    (
        "sgi-teapot.ron",
        include_str!("../../configs/sgi-teapot.ron"),
    ),
    ("emboss.ron", include_str!("../../configs/emboss.ron")),
    (
        "quantized-sphere.ron",
        include_str!("../../configs/quantized-sphere.ron"),
    ),
];

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let Ok(text) = std::str::from_utf8(rest) else {
        return;
    };
    let (name, base) = BASES[first as usize % BASES.len()];
    let path = common::scratch_file(name, base.as_bytes());
    let sets: Vec<String> = text.lines().take(8).map(str::to_string).collect();
    if sets.is_empty() {
        return;
    }
    let _ = config::overrides::apply(&config::parse(base, name).unwrap(), &sets);
    let _ = config::load_with(&path, &sets, LoadOptions::default());
});

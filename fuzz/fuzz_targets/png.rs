//! PNG inputs: arbitrary bytes read as a PNG image with the bounded reader
//! (`scene::files::read_png`, sides checked from the header before decoding), and as a
//! height map and a normal map (`BumpSpec::HeightPng`, `BumpSpec::NormalPng`). No panic and
//! no allocation beyond the side limit; errors are values.
#![no_main]

use bumpsim_pipeline::scene::{files, BumpSpec};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let path = common::scratch_file("fuzz.png", data);
    let _ = files::read_png(&path, files::MAX_PNG_SIDE);
    let name = "fuzz.png".to_string();
    let dir = path.parent().unwrap();
    let _ = BumpSpec::HeightPng {
        path: name.clone(),
        depth: 0.05,
    }
    .build(dir);
    let _ = BumpSpec::NormalPng { path: name }.build(dir);
});

//! The PLY reader (ply-rs-bw, ASCII and binary): arbitrary bytes as a `Ply` mesh file, with
//! the file's texture coordinates and with a generated atlas (the first byte's low bit), then
//! the mesh checks. No panic; errors are values.
#![no_main]

use bumpsim_pipeline::scene::MeshSpec;
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let path = common::scratch_file("fuzz.ply", rest);
    let spec = MeshSpec::Ply {
        path: path.file_name().unwrap().to_string_lossy().into_owned(),
        uv_repeat: [1.0, 1.0],
        atlas: first & 1 == 1,
    };
    if let Ok(mesh) = spec.build(path.parent().unwrap()) {
        let _ = mesh.validate("scene.mesh");
    }
});

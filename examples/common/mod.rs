//! What the study generators share: the repository root and a config's framebuffers in
//! both modes.

use bumpsim_hw::Mode;
use bumpsim_pipeline::config;
use bumpsim_pipeline::rop::{self, Framebuffer};
use bumpsim_pipeline::run;
use std::path::PathBuf;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The framebuffers of bundled config `name` (with `--set` overrides `sets`) in bit-accurate
/// and exact mode, rendered without the reference.
pub fn framebuffers(name: &str, sets: &[String]) -> (Framebuffer, Framebuffer) {
    let path = root().join("configs").join(format!("{name}.ron"));
    let l = config::load(&path, sets).unwrap_or_else(|e| panic!("{name} {sets:?}: {e}"));
    let p = run::prepare(&l).unwrap_or_else(|e| panic!("{name}: {e}"));
    let (w, h) = (p.scene.width, p.scene.height);
    let bit = p.simulate_lanes(None);
    let exact = p.evaluate_exact();
    let frags = &p.raster.fragments;
    (
        rop::write(&p.engine.rop, Mode::BitAccurate, w, h, frags, &bit.outputs),
        rop::write(&p.engine.rop, Mode::Exact, w, h, frags, &exact),
    )
}

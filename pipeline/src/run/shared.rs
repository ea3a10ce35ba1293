//! The float reference shared by the runs of this process that render the same frame
//! (`crate::memo`): a sweep's points that differ only in the engine, a study's rows.
//!
//! The reference is a pure function of the scene, the winning fragment of each pixel and
//! the reference options, so it is kept under a digest of exactly those: the scene's key
//! (its config and files), each covered pixel's winner (triangle, depth, barycentrics'
//! bits), the image size and the options. A scene without a key is rendered every time.

use crate::memo::{self, Memo};
use crate::raster::Fragment;
use crate::reference::{self, Coverage, Options, ReferenceImage};
use crate::scene::Scene;
use std::hash::Hash;
use std::sync::Arc;

/// References kept at most, and the pixels they may hold together (8 Mpx: 200 MB of colour
/// and mask, a larger one is not kept).
const CAPACITY: usize = 8;
const BUDGET_PIXELS: usize = 8 << 20;

static REFERENCES: Memo<[u64; 2], Arc<ReferenceImage>> =
    Memo::weighed(CAPACITY, BUDGET_PIXELS, |r| r.mask.len());

/// The reference of `scene` on `coverage` of `frags` with `opts`: kept from an earlier run
/// of the same frame, or rendered now.
pub(super) fn reference(
    scene: &Scene,
    coverage: &Coverage,
    frags: &[Fragment],
    opts: Options,
) -> Arc<ReferenceImage> {
    let render = || Arc::new(reference::render_covered(scene, coverage, frags, opts));
    match scene.key {
        Some(scene_key) => {
            REFERENCES.get_or_build(key(scene_key.scene, coverage, frags, opts), render)
        }
        _ => render(),
    }
}

pub(super) fn key(
    scene: [u64; 2],
    coverage: &Coverage,
    frags: &[Fragment],
    opts: Options,
) -> [u64; 2] {
    memo::digest(|mut h| {
        scene.hash(&mut h);
        (coverage.width, coverage.height).hash(&mut h);
        format!("{opts:?}").hash(&mut h);
        for y in 0..coverage.height {
            for (x, &k) in coverage.row(y).iter().enumerate() {
                if k == Coverage::NONE {
                    continue;
                }
                let f = &frags[k as usize];
                (x as u32, y, f.tri, f.depth).hash(&mut h);
                f.bary.map(f64::to_bits).hash(&mut h);
            }
        }
    })
}

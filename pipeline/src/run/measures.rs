//! The comparisons of a run: the bit-accurate and exact-mode framebuffers against the
//! reference and against each other (error, edge and artifact measures), the error heatmap
//! and the reference's 8-bit image. Each is a pure function of the images, so they run
//! concurrently (rayon) and give the same numbers as one after another.

use crate::artifacts;
use crate::edges;
use crate::metrics::{self, Rgb64};
use crate::report::{Artifacts, Edges, Errors};
use crate::rop::Framebuffer;

/// What [`measure`] gives.
pub(super) struct Measures {
    pub errors: Errors,
    pub edges: Edges,
    pub artifacts: Artifacts,
    /// The reference as 8-bit RGB (reference.png).
    pub reference: image::RgbImage,
    /// The error of the bit-accurate image against the reference (error.png).
    pub heatmap: image::RgbImage,
}

/// Compare the framebuffers `bit` and `exact` (whose triangle map is `exact_tri`: the
/// caller may keep one map for both) with the reference `r` (covered where `r_mask`).
pub(super) fn measure(
    bit: &Framebuffer,
    exact: &Framebuffer,
    exact_tri: &[u32],
    r: &Rgb64,
    r_mask: &[bool],
) -> Measures {
    let (a, am, at) = (&bit.image, &bit.mask[..], &bit.tri[..]);
    let (e, em, et) = (&exact.image, &exact.mask[..], exact_tri);
    // The artifact measures read the images where they lie (a few rows of working memory
    // and a mask each), so the two run concurrently, and beside the rest.
    let (artifacts, (edges, (errors, images))) = rayon::join(
        || {
            let (total, quantization) = rayon::join(
                || artifacts::measure(a, am, r, r_mask),
                || artifacts::measure(a, am, e, em),
            );
            Artifacts {
                total,
                quantization,
            }
        },
        || {
            rayon::join(
                || Edges {
                    total: edges::measure(a, am, at, r, r_mask),
                    algorithm: edges::measure(e, em, et, r, r_mask),
                    quantization: edges::measure(a, am, at, e, em),
                },
                || {
                    let errors = Errors {
                        total: metrics::compare(a, am, r, r_mask),
                        algorithm: metrics::compare(e, em, r, r_mask),
                        quantization: metrics::compare(a, am, e, em),
                    };
                    let images = (r.to_rgb8(), metrics::heatmap(a, am, r, r_mask, 32.0));
                    (errors, images)
                },
            )
        },
    );
    Measures {
        errors,
        edges,
        artifacts,
        reference: images.0,
        heatmap: images.1,
    }
}

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

/// Compare the framebuffers `bit` and `exact` with the reference `r` (covered where `r_mask`).
pub(super) fn measure(
    bit: &Framebuffer,
    exact: &Framebuffer,
    r: &Rgb64,
    r_mask: &[bool],
) -> Measures {
    let (a, am, at) = (&bit.image, &bit.mask[..], &bit.tri[..]);
    let (e, em, et) = (&exact.image, &exact.mask[..], &exact.tri[..]);
    // The two artifact measures run one after the other: each holds working images of about
    // 100 bytes per pixel, the peak of a large frame. The rest runs beside them.
    let (artifacts, (edges, (errors, images))) = rayon::join(
        || Artifacts {
            total: artifacts::measure(a, am, r, r_mask),
            quantization: artifacts::measure(a, am, e, em),
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

//! The error analysis of Wang et al. §5: from 30 views distributed around the model
//! ([`super::views::evaluation`]), the detailed mesh rendered with its (interpolated, exact)
//! vertex normals against the simplified mesh rendered with the normal map as a colour
//! texture; per pixel covered by both, the normal error (length of the difference vector)
//! and the distance error (depth difference).
//!
//! Units: normal errors in 8-bit colour steps, as the paper's Fig. 3 ("quantized to 8 bit,
//! average vector difference"): `|c_o - c_m|` of the two normals as 8-bit colours
//! ([`super::bake::to_colour`]), and unquantised as `127.5 |n_o - n_m|` on the same scale.
//! Distance errors as fractions of the detailed mesh's bounding-sphere radius. The map is
//! read with bilinear filtering (texel centres at `(i + 0.5) / size`, clamped at the map's
//! edge), not renormalised, as a colour texture would be.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::camera::{ItemBuffer, View};
use super::pack::Packing;
use super::Surface;

/// One evaluation view's renders, kept so that maps can be compared without rendering again.
pub struct EvalView {
    pub view: View,
    pub detailed: ItemBuffer,
    pub simplified: ItemBuffer,
}

/// The errors of one view.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ViewError {
    /// Mean normal error in 8-bit colour steps, both normals quantised to 8 bits.
    pub normal8: f64,
    /// Mean normal error on the same scale, unquantised.
    pub normal: f64,
    /// Mean depth difference, as a fraction of the bounding radius.
    pub distance: f64,
    /// Pixels covered by both meshes.
    pub pixels: usize,
    /// Pixels covered by one of the two only (silhouette differences).
    pub one_only: usize,
}

/// The 30 views with both meshes rendered.
pub struct Evaluation {
    pub views: Vec<EvalView>,
    radius: f64,
}

impl Evaluation {
    /// Render `detailed` and `simplified` from the views `dirs` at `size` pixels.
    pub fn new(detailed: &Surface, simplified: &Surface, dirs: &[DVec3], size: u32) -> Self {
        let (centre, radius) = detailed.bounding_sphere();
        let views = dirs
            .iter()
            .map(|&d| {
                let view = View::new(d, centre, radius, size);
                EvalView {
                    view,
                    detailed: ItemBuffer::render(detailed, &view),
                    simplified: ItemBuffer::render(simplified, &view),
                }
            })
            .collect();
        Evaluation { views, radius }
    }

    /// Render another simplified mesh in the same views (the detailed renders are kept).
    pub fn replace_simplified(&mut self, simplified: &Surface) {
        for v in &mut self.views {
            v.simplified = ItemBuffer::render(simplified, &v.view);
        }
    }

    /// The errors of `map` (per texel, object space) on the simplified mesh, per view.
    pub fn errors(&self, detailed: &Surface, packing: &Packing, map: &[DVec3]) -> Vec<ViewError> {
        self.views
            .iter()
            .map(|v| self.view_error(v, detailed, packing, map))
            .collect()
    }

    /// Per pixel of view `v`: the unquantised normal error (or `None` where the meshes do
    /// not both cover it), for error images (Fig. 4b).
    pub fn error_image(
        &self,
        v: &EvalView,
        detailed: &Surface,
        packing: &Packing,
        map: &[DVec3],
    ) -> Vec<Option<f64>> {
        (0..v.detailed.tri.len())
            .into_par_iter()
            .map(|k| {
                pixel(v, k, detailed, packing, map).map(|(no, nm, _)| 127.5 * (no - nm).length())
            })
            .collect()
    }

    fn view_error(
        &self,
        v: &EvalView,
        detailed: &Surface,
        packing: &Packing,
        map: &[DVec3],
    ) -> ViewError {
        let per: Vec<Option<(f64, f64, f64)>> = (0..v.detailed.tri.len())
            .into_par_iter()
            .map(|k| {
                pixel(v, k, detailed, packing, map).map(|(no, nm, dz)| {
                    let (co, cm) = (super::bake::to_colour(no), super::bake::to_colour(nm));
                    let d8 = (0..3)
                        .map(|i| (f64::from(co[i]) - f64::from(cm[i])).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    (d8, 127.5 * (no - nm).length(), dz)
                })
            })
            .collect();
        let mut e = ViewError::default();
        for p in per.iter().flatten() {
            e.normal8 += p.0;
            e.normal += p.1;
            e.distance += p.2;
            e.pixels += 1;
        }
        e.one_only = (0..v.detailed.tri.len())
            .filter(|&k| (v.detailed.tri[k] == u32::MAX) != (v.simplified.tri[k] == u32::MAX))
            .count();
        if e.pixels > 0 {
            let n = e.pixels as f64;
            e.normal8 /= n;
            e.normal /= n;
            e.distance = v.view.depth_to_object(e.distance / n) / self.radius;
        }
        e
    }
}

/// Mean of the views' errors (weighted equally per view).
pub fn mean(errors: &[ViewError]) -> ViewError {
    let n = errors.len().max(1) as f64;
    let mut m = ViewError::default();
    for e in errors {
        m.normal8 += e.normal8 / n;
        m.normal += e.normal / n;
        m.distance += e.distance / n;
        m.pixels += e.pixels;
        m.one_only += e.one_only;
    }
    m
}

/// At pixel `k` of view `v`, covered by both meshes: the detailed normal, the map's normal on
/// the simplified mesh, and the window-depth difference.
fn pixel(
    v: &EvalView,
    k: usize,
    detailed: &Surface,
    packing: &Packing,
    map: &[DVec3],
) -> Option<(DVec3, DVec3, f64)> {
    let (to, ts) = (v.detailed.tri[k], v.simplified.tri[k]);
    if to == u32::MAX || ts == u32::MAX {
        return None;
    }
    let no = detailed.normal_at(to as usize, v.detailed.bary[k]);
    let uv = packing.uv[ts as usize];
    let b = v.simplified.bary[k];
    let at = uv[0] * b[0] + uv[1] * b[1] + uv[2] * b[2];
    let nm = bilinear(map, packing.size, at);
    Some((no, nm, (v.detailed.depth[k] - v.simplified.depth[k]).abs()))
}

/// Bilinear lookup of a `size`-texel map (row-major, row 0 at `v = 0`) at `uv`.
pub fn bilinear(map: &[DVec3], size: u32, uv: DVec2) -> DVec3 {
    let n = f64::from(size);
    let x = (uv.x * n - 0.5).clamp(0.0, n - 1.0);
    let y = (uv.y * n - 0.5).clamp(0.0, n - 1.0);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as usize, y0 as usize);
    let s = size as usize;
    let (x1, y1) = ((x0 + 1).min(s - 1), (y0 + 1).min(s - 1));
    let at = |x: usize, y: usize| map[y * s + x];
    (at(x0, y0) * (1.0 - fx) + at(x1, y0) * fx) * (1.0 - fy)
        + (at(x0, y1) * (1.0 - fx) + at(x1, y1) * fx) * fy
}

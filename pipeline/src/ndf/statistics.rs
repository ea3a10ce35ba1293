//! The report's `synthesis` section (`reference.synthesis`, docs/metrics.md): what the
//! scene's NDF bump synthesis generates, measured on the tables themselves rather than on a
//! render, so that a sweep can tabulate Kautz et al.'s claims about them.
//!
//! * C17 (§4: the generated normals follow the NDF): the normals at `SIDE²` texture
//!   coordinates (the scene's turbulence of all its octaves), through the exact inverse CDFs
//!   and through the engine's lookup table `L` (nearest entry, its f64 normals), binned on a
//!   `BINS²` hemispherical map against the NDF integrated over each bin: KL divergence and
//!   chi-square per degree of freedom ([`crate::ndf::tables::fit`]).
//! * Shading consistency across levels of detail (§5.1): the mean NDF shading `D(h_m) /
//!   max D` of a patch of `SIDE²` texture coordinates at each mip level of the noise, for a
//!   half-way vector tilted by `tilt_deg` from the macro normal, beside the closed form of
//!   the flat surface and the flat level shaded with the far NDF
//!   ([`NdfSurface::patch_shading`], [`NdfSurface::far_shading`]).

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::ndf::Distribution;
use super::surface::NdfSurface;
use super::tables::{binned, fit, histogram};

/// Texture coordinates per side of the measured patch.
pub const SIDE: u32 = 256;
/// Bins per side of the hemispherical histogram.
pub const BINS: u32 = 16;

/// What the config asks to measure (`reference.synthesis`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SynthesisStats {
    /// The half-way vector's tilt from the macro normal, degrees (0 to 90), for the
    /// level-of-detail shading.
    pub tilt_deg: f64,
}

/// A goodness of fit of generated normals to the NDF.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fit {
    /// Kullback-Leibler divergence of the normals' histogram from the NDF, nats.
    pub kl: f64,
    /// Pearson's chi-square per degree of freedom (bins with at least 5 expected).
    pub chi2_dof: f64,
}

/// The fit through the engine's lookup table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LookupFit {
    /// Entries per side of `L` (the engine's first `NdfLookup` of normals).
    pub side: u32,
    pub kl: f64,
    pub chi2_dof: f64,
}

/// The report's `synthesis` section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Synthesis {
    /// Texture coordinates per side of the patch, bins per side of the histogram.
    pub side: u32,
    pub bins: u32,
    /// The normals through the exact inverse CDFs (or uniform, with `normals: Uniform`).
    pub exact: Fit,
    /// The normals through `L`, when the engine reads one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lookup: Option<LookupFit>,
    pub tilt_deg: f64,
    /// The NDF's closed-form shading of the flat surface, `D(θ_h) / max D`.
    pub closed_form: f64,
    /// The patch's mean shading at mip level k (k = 0 to the octaves; the last is flat).
    pub levels: Vec<f64>,
    /// The flat level shaded with the far NDF.
    pub far: f64,
}

/// C17's fit of the normals `surf` generates at `SIDE²` texture coordinates (all its
/// octaves) on `BINS²` bins: through the exact inverse CDFs, or through `L` at `lookup`
/// entries a side (nearest entry, its f64 normals).
pub fn normals_fit(surf: &NdfSurface, lookup: Option<u32>) -> Fit {
    match lookup {
        None => fit_of(surf, |r| surf.normal_of(r)),
        Some(side) => {
            let l = surf.lookup(side);
            fit_of(surf, |r| l.normals[l.nearest(r[0], r[1])])
        }
    }
}

fn fit_of(surf: &NdfSurface, normal: impl Fn([f64; 2]) -> glam::DVec3 + Sync) -> Fit {
    let octaves = f64::from(surf.spec.octaves);
    let normals: Vec<_> = (0..SIDE * SIDE)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % SIDE, k / SIDE);
            let u = (f64::from(i) + 0.5) / f64::from(SIDE);
            let v = (f64::from(j) + 0.5) / f64::from(SIDE);
            normal(surf.indices(u, v, octaves))
        })
        .collect();
    let h = histogram(BINS, normals.into_iter());
    let fine = BINS * 16;
    let (chi2_dof, kl) = fit(
        &h,
        &binned(&surf.ndf.map(fine, Distribution::Ndf), fine, BINS),
    );
    Fit { kl, chi2_dof }
}

/// The section for `surf`, with `L` at `lookup` entries a side if the engine reads one.
pub fn measure(surf: &NdfSurface, lookup: Option<u32>, stats: SynthesisStats) -> Synthesis {
    let theta = stats.tilt_deg.to_radians();
    let exact = normals_fit(surf, None);
    let lookup = lookup.map(|side| {
        let f = normals_fit(surf, Some(side));
        LookupFit {
            side,
            kl: f.kl,
            chi2_dof: f.chi2_dof,
        }
    });
    let levels = (0..=surf.spec.octaves)
        .into_par_iter()
        .map(|k| surf.patch_shading(k, SIDE, theta))
        .collect();
    Synthesis {
        side: SIDE,
        bins: BINS,
        exact,
        lookup,
        tilt_deg: stats.tilt_deg,
        closed_form: surf.ndf.relative_iso(theta.cos()),
        levels,
        far: surf.far_shading(theta),
    }
}

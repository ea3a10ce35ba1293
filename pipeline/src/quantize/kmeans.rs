//! k-means (Lloyd) tables by `linfa-clustering` (rust-ml), on the f64 normals directly.
//!
//! Tarini §4 reuses "standard image processing software" for the palette; NeuQuant
//! (`color_quant`) stops at 256 entries, so this is the crate-backed quantizer for the whole
//! range `s_N = 16 ..= 16K`. Unlike the RGB8 route it needs no byte mapping: the texels are the
//! observations (one row of `x y z` each, every texel counted, so frequent normals weigh
//! more, as in a colour histogram) and the distance is Euclidean, which for unit vectors
//! orders like the angle.
//!
//! * Initialisation ([`KMeansStart`]): `linfa`'s `KMeansInit::Random` (Forgy), `k` texels
//!   drawn by a `Xoshiro256Plus` seeded with `seed`, or `KMeansInit::Precomputed` with the
//!   [`median_cut`](super::median_cut) table; one run. k-means++ / k-means|| are not used: in
//!   `linfa` 0.8 they cost `O(texels * k²)`, minutes at `k = 16384`.
//! * `k = min(s_n, distinct normals)` (Random) or the median-cut table's size: more clusters
//!   than distinct normals would only add empty ones.
//! * Cost: `linfa` assigns by brute force, `texels * k` distances per iteration (rayon):
//!   256x256 texels to 16384 entries take about 2 s per iteration on two cores (release).
//!   From a random start k-means needs tens of iterations; from median cut a few.
//! * Iterations: `linfa`'s m_k-means update (the old centroid counts as one more member, so
//!   an empty cluster stays where it is) until the centroids move less than
//!   [`TOLERANCE`] or after `max_iterations`.
//! * The centroids are renormalised (Tarini §4); duplicates (clusters that ended up empty on
//!   a copy of another centroid) and zero vectors are dropped, so the table may have fewer
//!   than `s_n` entries.
//!
//! Deterministic: the only randomness is the seeded initialisation; the parallel assignment
//! step (rayon) writes each texel's cluster independently and the sums are sequential.

use super::KMeansStart;
use glam::DVec3;
use linfa::prelude::*;
use linfa_clustering::{KMeans, KMeansInit};
use ndarray::Array2;
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;

/// Convergence: total centroid movement (Euclidean, over all centroids) below this stops the
/// iterations early.
pub const TOLERANCE: f64 = 1e-6;

/// At most `s_n` unit entries (`s_n >= 1`, `1 <= max_iterations <=`
/// [`super::MAX_KMEANS_ITERATIONS`],
/// `normals` non-empty, finite, non-zero: checked by the caller).
pub fn kmeans(
    normals: &[DVec3],
    s_n: usize,
    start: KMeansStart,
    max_iterations: u32,
) -> Vec<DVec3> {
    let (k, seed, init) = match start {
        KMeansStart::Random { seed } => {
            let distinct = super::median_cut::histogram(normals).len();
            (s_n.min(distinct), seed, KMeansInit::Random)
        }
        KMeansStart::MedianCut => {
            let t = super::median_cut::median_cut(normals, s_n);
            // one entry per distinct normal already (bit-exact): Lloyd would only re-average
            // each normal with itself and round
            if t.len() == super::median_cut::histogram(normals).len() {
                return t;
            }
            let c = Array2::from_shape_fn((t.len(), 3), |(i, j)| t[i][j]);
            // no randomness left: the seed is unused
            (t.len(), 0, KMeansInit::Precomputed(c))
        }
    };
    let records = Array2::from_shape_fn((normals.len(), 3), |(i, j)| normals[i][j]);
    let data = DatasetBase::from(records);
    let model = KMeans::params_with_rng(k, Xoshiro256Plus::seed_from_u64(seed))
        .init_method(init)
        .n_runs(1)
        .max_n_iterations(u64::from(max_iterations))
        .tolerance(TOLERANCE)
        .fit(&data)
        .expect("k-means parameters are valid (k >= 1, iterations >= 1, tolerance > 0)");
    let mut entries: Vec<DVec3> = Vec::with_capacity(k);
    let mut seen = std::collections::HashSet::new();
    for row in model.centroids().rows() {
        let Some(e) = DVec3::new(row[0], row[1], row[2]).try_normalize() else {
            continue;
        };
        if seen.insert([e.x.to_bits(), e.y.to_bits(), e.z.to_bits()]) {
            entries.push(e);
        }
    }
    // a centroid is a mean of non-zero normals or one of them; if all cancelled (not seen in
    // practice), fall back to the first normal
    if entries.is_empty() {
        entries.push(normals[0].normalize());
    }
    entries
}

//! Baking a mesh's perturbed normals into a texture: object-space normal maps (Tarini et al.
//! §4; Ernst et al. 1998 §5.3 and §5.4.2, Fig. 8: "a bump mapped cylinder for example
//! contains the computed surface normals of the cylinder patch plus the bump-structure"), and
//! the plain tangent-space map for comparison.
//!
//! # Algorithm
//!
//! 1. **Claims** (sequential, in triangle order). Every triangle is rasterised in *uv space*
//!    at its own, unwrapped texture coordinates, snapped to a fixed-point grid of 2^-16 texel
//!    ([`SUB_BITS`]); texel indices are then wrapped into `[0, size)`, so a triangle that
//!    crosses the wrap (`u` from 0.9 to 1.1) covers texels on both sides and a `uv_repeat` of
//!    `n` claims every texel `n` times. A texel centre `((i + 0.5)/size, (j + 0.5)/size)`
//!    (row `j = 0` is `v` in `[0, 1/size)`) is inside a triangle if all three integer edge
//!    functions are positive; a centre exactly on an edge goes to the triangle for which the
//!    centre moved by `(-ε, -ε²)` is inside (the top-left rule mirrored), so triangles that
//!    tile uv space claim every centre exactly once, also on shared edges and vertices. The
//!    first claim wins; later claims of a claimed texel are counted in `overlaps`. Triangles
//!    with zero snapped uv area, out-of-range indices, or non-finite or huge (|u·size| ≥ 2^34)
//!    texture coordinates are skipped and counted in `skipped`.
//! 2. **Evaluation** (per texel, in parallel; every texel is a pure function of its claim, so
//!    the result is bit-identical at any thread count). The barycentrics of the texel centre,
//!    in the claiming copy's unwrapped frame, are computed in f64 from the unsnapped uv; they
//!    interpolate the position, the normal (then renormalised, as in the reference), `Pu` and
//!    `Pv`; [`super::perturb::perturbed_normal`] applies the bump at the texel centre in
//!    `[0, 1)` (bump maps have period 1): Blinn or Lingard's scale-invariant perturbation of
//!    the analytic gradient for height fields, the `(T, B, N)` frame for normal maps.
//! 3. **Gutter**. A texel no triangle covers whose centre lies within [`GUTTER_RADIUS`]
//!    (1.5) texels of a triangle's uv region (Euclidean, in the triangle's unwrapped frame)
//!    belongs to the nearest such triangle (ties: the first in triangle order) and is
//!    evaluated like a covered texel, at the closest point of the triangle (the bump is still
//!    sampled at the texel centre). So nearest sampling anywhere in a triangle (the texel
//!    containing the sample has its centre within √2/2 texel of it) and bilinear sampling
//!    reach only texels of that triangle, provided uv charts are at least 2 · 1.5 texels
//!    apart (see `atlas.rs`) — plain dilation can hand such a texel to a neighbouring
//!    chart near a sharp corner.
//! 4. **Dilation**. The remaining texels take the normal of the nearest covered texel
//!    (Euclidean distance in texels, wrapping at the borders; ties go to one of them
//!    deterministically), computed by an exact two-pass distance transform. With no covered
//!    texel at all the map is `(0, 0, 1)`.
//!
//! # Spaces
//!
//! * [`BakeSpace::Object`]: the perturbed unit normal in the mesh's object coordinates (no
//!   model transform). Because it already contains the surface's own normal, such a map is
//!   tied to the mesh and its uv layout: overlapping uv charts (the teapot's patches, a
//!   `uv_repeat` above 1) cannot share texels, which is what `overlaps` counts.
//! * [`BakeSpace::Tangent`]: the plain tangent-space map, identical to
//!   [`BumpMap::bake_normals`] with [`NormalMethod::Analytic`] at every texel (it does not
//!   depend on the mesh, so it needs no dilation and the perturbation mode does not enter);
//!   `covered` and `overlaps` still describe the mesh's uv layout.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::perturb::{perturb_height, perturbed_normal, Perturbation, SurfacePoint};
use super::{BumpMap, Mesh, NormalMap, NormalMethod};

/// Which frame the baked normals are expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BakeSpace {
    Object,
    Tangent,
}

/// The result of [`bake`].
#[derive(Debug, Clone, PartialEq)]
pub struct BakeOutput {
    /// `size x size` unit normals in the chosen space (row-major, row 0 is `v` in
    /// `[0, 1/size)`). Object space: texels not covered by any triangle hold the nearest
    /// triangle's normal within [`GUTTER_RADIUS`] texels (gutter), else the nearest covered
    /// texel's normal (dilation), or `(0, 0, 1)` if no texel is covered. Tangent
    /// space: [`BumpMap::bake_normals`] with the analytic method at every texel.
    pub map: NormalMap,
    /// Whether a triangle covers the texel centre, row-major like `map`.
    pub covered: Vec<bool>,
    /// Claims of an already claimed texel (overlapping uv charts such as the teapot's
    /// patches, or `uv_repeat` > 1): the first triangle wins, each later claim counts one.
    pub overlaps: u64,
    /// Triangles not rasterised: zero uv area after snapping, a vertex index out of range, or
    /// texture coordinates that are not finite or too large (|u · size| ≥ 2^34).
    pub skipped: u64,
}

/// Sub-texel bits of the fixed-point uv grid the coverage test runs on.
pub const SUB_BITS: u32 = 16;
const ONE: i64 = 1 << SUB_BITS;
const HALF: i64 = ONE / 2;
/// Largest accepted |u · size| (in texels): keeps the bounding-box arithmetic and the edge
/// functions' i128 products far from overflow.
const MAX_TEXELS: f64 = (1u64 << 34) as f64;
/// Uncovered texels whose centre is within this many texels of a triangle take that
/// triangle's normal (step 3 of the module docs).
pub const GUTTER_RADIUS: f64 = 1.5;

/// Bake the mesh's perturbed normals into a `size x size` texture (see the module docs for
/// the rasterisation, evaluation and dilation rules). `size == 0` gives an empty map.
pub fn bake(
    mesh: &Mesh,
    bump: &BumpMap,
    size: u32,
    space: BakeSpace,
    perturbation: Perturbation,
) -> BakeOutput {
    let n = size as usize * size as usize;
    let claims = claim(mesh, size);
    let covered: Vec<bool> = claims
        .winner
        .iter()
        .map(|c| c.is_some_and(|c| !c.gutter))
        .collect();
    let texels = match space {
        BakeSpace::Tangent => bump.bake_normals(size, size, NormalMethod::Analytic).texels,
        BakeSpace::Object => {
            let grads = bump.centre_grads(size, size);
            let values: Vec<Option<DVec3>> = claims
                .winner
                .par_iter()
                .enumerate()
                .map(|(k, c)| {
                    c.map(|c| {
                        let (i, j) = (k % size as usize, k / size as usize);
                        let (i, j) = (i as u32, j as u32);
                        let g = grads.as_ref().and_then(|g| g.at(i, j));
                        object_normal(mesh, bump, size, (i, j), c, (g, perturbation))
                    })
                })
                .collect();
            // only texels no triangle claimed take a neighbour's normal
            let source = if values.iter().all(Option::is_some) {
                Vec::new()
            } else {
                nearest_covered(&covered, size as usize)
            };
            (0..n)
                .into_par_iter()
                .map(|k| {
                    values[k]
                        .or_else(|| source.get(k).copied().flatten().and_then(|s| values[s]))
                        .unwrap_or(DVec3::Z)
                })
                .collect()
        }
    };
    BakeOutput {
        map: NormalMap {
            width: size,
            height: size,
            texels,
        },
        covered,
        overlaps: claims.overlaps,
        skipped: claims.skipped,
    }
}

/// The triangle that claimed a texel first, and the unwrapped texel it claimed it as.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Claim {
    tri: u32,
    /// Unwrapped texel indices: the centre is `(iu + 0.5, ju + 0.5)` texels in the
    /// triangle's own uv frame.
    iu: i64,
    ju: i64,
    /// A gutter texel: not covered, evaluated at the triangle's point nearest the centre.
    gutter: bool,
}

struct Claims {
    winner: Vec<Option<Claim>>,
    overlaps: u64,
    skipped: u64,
}

type Fixed = (i64, i64);

/// Snap a texture coordinate to the fixed-point grid (units of 2^-SUB_BITS texel).
fn snap(uv: DVec2, size: f64) -> Option<Fixed> {
    let t = uv * size;
    if !(t.is_finite() && t.x.abs() < MAX_TEXELS && t.y.abs() < MAX_TEXELS) {
        return None;
    }
    let s = t * ONE as f64;
    Some((s.x.round() as i64, s.y.round() as i64))
}

/// Twice the signed area of `a b p` on the fixed-point grid, exact.
fn edge(a: Fixed, b: Fixed, p: Fixed) -> i128 {
    i128::from(b.0 - a.0) * i128::from(p.1 - a.1) - i128::from(b.1 - a.1) * i128::from(p.0 - a.0)
}

/// Whether a centre with edge function `e` on the counter-clockwise edge `a → b` is inside:
/// `e > 0`, or `e == 0` and the centre moved by `(-ε, -ε²)` would be (`dy > 0`, or
/// `dy == 0` and `dx < 0`). Exactly one of the two triangles sharing an edge includes it.
fn inside(e: i128, a: Fixed, b: Fixed) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    e > 0 || (e == 0 && (dy > 0 || (dy == 0 && dx < 0)))
}

/// Step 1: rasterise every triangle in uv space, first claim wins.
fn claim(mesh: &Mesh, size: u32) -> Claims {
    let s = size as usize;
    let mut out = Claims {
        winner: vec![None; s * s],
        overlaps: 0,
        skipped: 0,
    };
    if size == 0 {
        return out;
    }
    let sz = f64::from(size);
    let mut rasterised = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let verts = tri.map(|k| mesh.vertices.get(k as usize));
        let snapped = match verts {
            [Some(a), Some(b), Some(c)] => [snap(a.uv, sz), snap(b.uv, sz), snap(c.uv, sz)],
            _ => [None; 3],
        };
        let [Some(a), Some(mut b), Some(mut c)] = snapped else {
            out.skipped += 1;
            continue;
        };
        let area = edge(a, b, c);
        if area == 0 {
            out.skipped += 1;
            continue;
        }
        if area < 0 {
            std::mem::swap(&mut b, &mut c);
        }
        let (lo_x, hi_x) = (a.0.min(b.0).min(c.0), a.0.max(b.0).max(c.0));
        let (lo_y, hi_y) = (a.1.min(b.1).min(c.1), a.1.max(b.1).max(c.1));
        // Texel centres at `i * ONE + HALF` inside the bounding box.
        let first = |lo: i64| (lo - HALF + ONE - 1).div_euclid(ONE);
        let last = |hi: i64| (hi - HALF).div_euclid(ONE);
        for ju in first(lo_y)..=last(hi_y) {
            let py = ju * ONE + HALF;
            let j = ju.rem_euclid(i64::from(size)) as usize;
            for iu in first(lo_x)..=last(hi_x) {
                let p = (iu * ONE + HALF, py);
                if inside(edge(a, b, p), a, b)
                    && inside(edge(b, c, p), b, c)
                    && inside(edge(c, a, p), c, a)
                {
                    let slot = &mut out.winner[j * s + iu.rem_euclid(i64::from(size)) as usize];
                    if slot.is_some() {
                        out.overlaps += 1;
                    } else {
                        *slot = Some(Claim {
                            tri: t as u32,
                            iu,
                            ju,
                            gutter: false,
                        });
                    }
                }
            }
        }
        rasterised.push(t);
    }
    gutter(mesh, size, &rasterised, &mut out.winner);
    out
}

/// Step 3: give every uncovered texel whose centre is within [`GUTTER_RADIUS`] texels of a
/// rasterised triangle (in its unwrapped frame) to the nearest one, first in triangle order
/// on ties.
fn gutter(mesh: &Mesh, size: u32, rasterised: &[usize], winner: &mut [Option<Claim>]) {
    let s = size as usize;
    let sz = f64::from(size);
    let mut best = vec![f64::INFINITY; s * s];
    let r2 = GUTTER_RADIUS * GUTTER_RADIUS;
    for &t in rasterised {
        let [a, b, c] = mesh.triangles[t].map(|k| mesh.vertices[k as usize].uv * sz);
        let lo = a.min(b).min(c) - DVec2::splat(GUTTER_RADIUS + 0.5);
        let hi = a.max(b).max(c) + DVec2::splat(GUTTER_RADIUS - 0.5);
        for ju in lo.y.ceil() as i64..=hi.y.floor() as i64 {
            let j = ju.rem_euclid(i64::from(size)) as usize;
            for iu in lo.x.ceil() as i64..=hi.x.floor() as i64 {
                let k = j * s + iu.rem_euclid(i64::from(size)) as usize;
                if winner[k].is_some_and(|w| !w.gutter) {
                    continue;
                }
                let p = DVec2::new(iu as f64 + 0.5, ju as f64 + 0.5);
                let d2 = (closest_on_triangle(p, a, b, c) - p).length_squared();
                if d2 <= r2 && d2 < best[k] {
                    best[k] = d2;
                    winner[k] = Some(Claim {
                        tri: t as u32,
                        iu,
                        ju,
                        gutter: true,
                    });
                }
            }
        }
    }
}

/// The point of triangle `abc` (either orientation) nearest to `p` (Ericson, *Real-Time
/// Collision Detection*, §5.1.5).
fn closest_on_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> DVec2 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Step 2: the object-space perturbed normal of texel `(i, j)` claimed by `c`, with the
/// height field's gradient at the texel centre if it was computed beforehand
/// ([`BumpMap::centre_grads`]).
fn object_normal(
    mesh: &Mesh,
    bump: &BumpMap,
    size: u32,
    (i, j): (u32, u32),
    c: Claim,
    (grad, perturbation): (Option<DVec2>, Perturbation),
) -> DVec3 {
    let sz = f64::from(size);
    let v = mesh.triangles[c.tri as usize].map(|k| mesh.vertices[k as usize]);
    // Barycentrics of the unwrapped centre, in texel units, from the unsnapped uv; for a
    // gutter texel, of the triangle's point nearest the centre.
    let [a, b, cc] = v.map(|x| x.uv * sz);
    let centre = DVec2::new(c.iu as f64 + 0.5, c.ju as f64 + 0.5);
    let p = if c.gutter {
        Some(closest_on_triangle(centre, a, b, cc))
            .filter(|q| q.is_finite())
            .unwrap_or(centre)
    } else {
        centre
    };
    let e = |from: DVec2, to: DVec2| (to - from).perp_dot(p - from);
    let w = DVec3::new(e(b, cc), e(cc, a), e(a, b));
    let sum = w.x + w.y + w.z;
    let w = if sum.is_finite() && sum != 0.0 {
        w / sum
    } else {
        DVec3::splat(1.0 / 3.0)
    };
    let mix = |f: fn(&super::Vertex) -> DVec3| f(&v[0]) * w.x + f(&v[1]) * w.y + f(&v[2]) * w.z;
    let sp = SurfacePoint {
        p: mix(|x| x.pos),
        n: mix(|x| x.normal).normalize_or_zero(),
        pu: mix(|x| x.pu),
        pv: mix(|x| x.pv),
        // The texel centre itself (bump maps have period 1), as `bake_normals` samples it.
        uv: DVec2::new((f64::from(i) + 0.5) / sz, (f64::from(j) + 0.5) / sz),
    };
    let n = match grad {
        Some(g) => perturb_height(sp.n, sp.pu, sp.pv, g, perturbation),
        None => perturbed_normal(bump, &sp, perturbation),
    };
    if n.is_finite() && n.length() > 0.5 {
        return n;
    }
    // The interpolated normal vanished (opposite vertex normals): the face normal.
    (v[1].pos - v[0].pos)
        .cross(v[2].pos - v[0].pos)
        .try_normalize()
        .unwrap_or(DVec3::Z)
}

/// Step 4: for every texel of a `size x size` wrapping grid, the index of a nearest covered
/// texel (squared Euclidean distance in texels, the shorter way round at the borders), or
/// None if nothing is covered. Exact: a circular 1-D pass along the rows, then the lower
/// envelope of parabolas (Felzenszwalb & Huttenlocher) down the columns, each column laid
/// out three times so that distances wrap.
fn nearest_covered(covered: &[bool], size: usize) -> Vec<Option<usize>> {
    let n = size * size;
    if !covered.iter().take(n).any(|&c| c) {
        return vec![None; n];
    }
    // Row pass: the nearest covered column in the same row and its distance (rows apart).
    let mut row_near: Vec<Option<(usize, i64)>> = vec![None; n];
    row_near
        .par_chunks_mut(size)
        .zip(covered.par_chunks(size))
        .for_each(|(near, row)| nearest_in_row(row, near));
    // Column pass: h(j) = min over rows r and copies q = r + k size, k in {-1, 0, 1}, of
    // f(r) + (j - q)², f(r) = (row distance in row r)². Columns apart, then transposed.
    let cols: Vec<Vec<Option<usize>>> = (0..size)
        .into_par_iter()
        .map(|i| nearest_in_column(&row_near, size, i))
        .collect();
    let mut out = vec![None; n];
    for (i, col) in cols.iter().enumerate() {
        for (j, &c) in col.iter().enumerate() {
            out[j * size + i] = c;
        }
    }
    out
}

/// Per texel of a wrapping row, the nearest covered column and its distance (None if the
/// row has no covered texel).
fn nearest_in_row(row: &[bool], near: &mut [Option<(usize, i64)>]) {
    let size = row.len();
    if !row.iter().any(|&c| c) {
        return;
    }
    let mut left = vec![0i64; size];
    let mut last = None;
    for k in 0..2 * size {
        let i = k % size;
        if row[i] {
            last = Some(k);
        }
        if let Some(l) = last {
            left[i] = (k - l) as i64;
        }
    }
    let mut right = vec![0i64; size];
    let mut next = None;
    for k in (0..2 * size).rev() {
        let i = k % size;
        if row[i] {
            next = Some(k);
        }
        if let Some(r) = next {
            right[i] = (r - k) as i64;
        }
    }
    for i in 0..size {
        let (d, col) = if left[i] <= right[i] {
            (left[i], (i + size - left[i] as usize) % size)
        } else {
            (right[i], (i + right[i] as usize) % size)
        };
        near[i] = Some((col, d));
    }
}

/// Column `i` of [`nearest_covered`]: per row `j`, the nearest covered texel.
fn nearest_in_column(
    row_near: &[Option<(usize, i64)>],
    size: usize,
    i: usize,
) -> Vec<Option<usize>> {
    let mut hull: Vec<(i64, i64)> = Vec::with_capacity(3 * size);
    let mut bounds: Vec<f64> = Vec::with_capacity(3 * size + 1);
    let sz = size as i64;
    bounds.push(f64::NEG_INFINITY);
    for q in -sz..2 * sz {
        let r = q.rem_euclid(sz) as usize;
        let Some((_, d)) = row_near[r * size + i] else {
            continue;
        };
        let fq = d * d;
        loop {
            let Some(&(p, fp)) = hull.last() else {
                hull.push((q, fq));
                break;
            };
            let s = ((fq + q * q) - (fp + p * p)) as f64 / (2 * (q - p)) as f64;
            if s <= bounds[hull.len() - 1] {
                hull.pop();
                bounds.pop();
            } else {
                bounds.push(s);
                hull.push((q, fq));
                break;
            }
        }
    }
    bounds.push(f64::INFINITY);
    let mut out = vec![None; size];
    let mut k = 0;
    for (j, o) in out.iter_mut().enumerate() {
        while bounds[k + 1] < j as f64 {
            k += 1;
        }
        let r = hull[k].0.rem_euclid(sz) as usize;
        if let Some((col, _)) = row_near[r * size + i] {
            *o = Some(r * size + col);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;
    use std::path::Path;

    use super::*;
    use crate::scene::{BumpSpec, MeshSpec, Vertex};

    fn mesh(spec: MeshSpec) -> Mesh {
        spec.build(Path::new(".")).unwrap()
    }
    fn flat() -> BumpMap {
        BumpSpec::Flat.build(Path::new(".")).unwrap()
    }
    fn hat() -> BumpMap {
        BumpSpec::MexicanHat {
            cells: 4,
            sigma: 0.2,
            depth: 0.02,
        }
        .build(Path::new("."))
        .unwrap()
    }
    fn quad() -> Mesh {
        mesh(MeshSpec::Quad {
            size: 2.0,
            uv_repeat: [1.0, 1.0],
            subdivisions: 1,
        })
    }
    fn cylinder(slices: u32, stacks: u32) -> Mesh {
        mesh(MeshSpec::Cylinder {
            radius: 1.5,
            height: 3.0,
            slices,
            stacks,
            uv_repeat: [1.0, 1.0],
        })
    }
    fn centre(size: u32, k: usize) -> (f64, f64) {
        let (i, j) = (k % size as usize, k / size as usize);
        (
            (i as f64 + 0.5) / f64::from(size),
            (j as f64 + 0.5) / f64::from(size),
        )
    }
    /// The cylinder's analytic normal at parameter `s` (mesh.rs: θ = 2π s, the normal is
    /// `(cos θ, 0, -sin θ)`; `u = s * uv_repeat.x`).
    fn cylinder_normal(s: f64) -> DVec3 {
        let (st, ct) = (TAU * s).sin_cos();
        DVec3::new(ct, 0.0, -st)
    }

    #[test]
    fn quad_flat_covers_every_texel_once() {
        for space in [BakeSpace::Object, BakeSpace::Tangent] {
            // 32 x 32: the quad's diagonal passes through all 32 texel centres (i+½, i+½),
            // which the tie rule gives to exactly one of the two triangles.
            let out = bake(&quad(), &flat(), 32, space, Perturbation::Blinn);
            assert_eq!(out.overlaps, 0);
            assert_eq!(out.skipped, 0);
            assert_eq!(out.covered.len(), 1024);
            assert!(out.covered.iter().all(|&c| c));
            assert_eq!((out.map.width, out.map.height), (32, 32));
            assert!(out.map.texels.iter().all(|&t| t == DVec3::Z), "{space:?}");
        }
        // Which triangle wins the diagonal: its 32 centres lie on the edge c → a of triangle
        // 0 = (a, b, c) (below-right), running down-left, so they go to triangle 1:
        // triangle 0 keeps the 31·32/2 = 496 centres strictly below.
        let c = claim(&quad(), 32);
        let t0 = c.winner.iter().filter(|w| w.unwrap().tri == 0).count();
        assert_eq!(t0, 496);
        let out = bake(&quad(), &flat(), 0, BakeSpace::Object, Perturbation::Blinn);
        assert!(out.map.texels.is_empty() && out.covered.is_empty());
    }

    #[test]
    fn cylinder_object_space_is_the_analytic_normal() {
        let size = 16u32;
        // Vertex columns on the texel centres: the interpolated normal is the vertex
        // normal, the analytic one.
        let check = |m: &Mesh, s_of_u: &dyn Fn(f64) -> f64, tol: f64| {
            let out = bake(m, &flat(), size, BakeSpace::Object, Perturbation::Blinn);
            assert_eq!(out.overlaps, 0);
            assert!(out.covered.iter().all(|&c| c));
            let mut worst = 0.0f64;
            for (k, n) in out.map.texels.iter().enumerate() {
                let (u, _) = centre(size, k);
                worst = worst.max((*n - cylinder_normal(s_of_u(u))).length());
            }
            assert!(worst <= tol, "{worst}");
            worst
        };
        // slices = 2 size: centres on every other vertex column.
        check(&cylinder(32, 4), &|u| u, 1e-12);
        // Shift uv by ½ + ½ texel: the columns still pass through centres, and triangle
        // strips cross u = 1 (and u = 0 for the negative shift) and wrap.
        for shift in [0.5 + 0.5 / 16.0, -0.75 - 0.5 / 16.0] {
            let mut m = cylinder(16, 4);
            for v in &mut m.vertices {
                v.uv.x += shift;
            }
            let crossing = m.triangles.iter().any(|t| {
                let us = t.map(|k| m.vertices[k as usize].uv.x);
                us.iter().any(|u| u.floor() != us[0].floor())
            });
            assert!(crossing);
            check(&m, &|u| (u - shift).rem_euclid(1.0), 1e-12);
        }
        // Generic texel positions: the mesh is a polygon, and the renormalised linear
        // interpolation of two normals Δ = 2π/slices apart deviates from the true angle by at
        // most Δ³/(36√3). With 2048 slices that is 4.6e-10.
        let fine = check(&cylinder(2048, 2), &|u| u, 1e-9);
        assert!(fine > 0.0);
        let delta = TAU / 12.0;
        let coarse = check(
            &cylinder(12, 2),
            &|u| u,
            delta.powi(3) / (36.0 * 3f64.sqrt()),
        );
        assert!(coarse > 1e-3, "{coarse}");
    }

    #[test]
    fn quad_mexican_hat_object_equals_tangent() {
        let (q, b) = (quad(), hat());
        let tangent = bake(&q, &b, 32, BakeSpace::Tangent, Perturbation::ScaleInvariant);
        assert_eq!(
            tangent.map,
            b.bake_normals(32, 32, NormalMethod::Analytic),
            "the tangent map is bake_normals"
        );
        // The quad's frame is the identity (Pu = 2x, Pv = 2y, n = z): scale-invariant
        // perturbation gives exactly the tangent-space normal.
        let object = bake(&q, &b, 32, BakeSpace::Object, Perturbation::ScaleInvariant);
        let mut tilted = 0;
        for (o, t) in object.map.texels.iter().zip(&tangent.map.texels) {
            assert!((*o - *t).length() < 1e-12, "{o} vs {t}");
            tilted += usize::from(t.z < 0.999);
        }
        assert!(tilted > 100, "{tilted}");
        // Blinn on a quad of edge 2: |Pu × Pv| = 4 but D = -2 (Fu, Fv, 0), so the slopes halve.
        let blinn = bake(&q, &b, 32, BakeSpace::Object, Perturbation::Blinn);
        for (k, o) in blinn.map.texels.iter().enumerate() {
            let (u, v) = centre(32, k);
            let g = b.grad(u, v).unwrap();
            let want = DVec3::new(-g.x / 2.0, -g.y / 2.0, 1.0).normalize();
            assert!((*o - want).length() < 1e-12, "{o} vs {want}");
        }
    }

    #[test]
    fn quad_with_normal_map_bump_bakes_the_map() {
        let ts = hat().bake_normals(16, 16, NormalMethod::CentralDifference);
        let b = BumpMap::Normals(ts.clone());
        let out = bake(&quad(), &b, 16, BakeSpace::Object, Perturbation::Blinn);
        for (o, t) in out.map.texels.iter().zip(&ts.texels) {
            assert!((*o - *t).length() < 1e-12, "{o} vs {t}");
        }
    }

    #[test]
    fn sphere_uv_repeat_counts_overlaps() {
        let sphere = |rep: f64| {
            mesh(MeshSpec::Sphere {
                radius: 1.0,
                slices: 16,
                stacks: 8,
                uv_repeat: [rep, 1.0],
            })
        };
        // 32 x 32 texels, 8 stacks of 4 rows. Rows 4..28 are full (768 texels). In a pole
        // band each slice is one triangle from the pole (at the slice's centre u) to the
        // ring; at the 4 rows' centres (1/8, 3/8, 5/8, 7/8 of the way from the pole) it is
        // 1/8 .. 7/8 of the slice wide.
        let rows = |out: &BakeOutput| -> Vec<usize> {
            (0..32)
                .map(|j| {
                    out.covered[j * 32..(j + 1) * 32]
                        .iter()
                        .filter(|&&c| c)
                        .count()
                })
                .collect()
        };
        let band = |pole: [usize; 4]| -> Vec<usize> {
            let mut r = pole.to_vec();
            r.extend([32; 24]);
            r.extend(pole.iter().rev());
            r
        };
        // uv_repeat (1, 1): slices 2 texels wide, centres ½ texel from the slice's centre:
        // covered from 5/8 on, 0, 0, 32, 32 per row. 1024 - 4 * 32 = 896 covered.
        let single = bake(
            &sphere(1.0),
            &flat(),
            32,
            BakeSpace::Object,
            Perturbation::Blinn,
        );
        assert_eq!(rows(&single), band([0, 0, 32, 32]));
        let covered = single.covered.iter().filter(|&&c| c).count();
        assert_eq!((covered, single.overlaps, single.skipped), (896, 0, 0));
        // uv_repeat (2, 1): slices 4 texels wide (centres ½ and 1½ from the slice's centre):
        // 0, 2, 2, 4 texels per slice and row, 8 distinct slices per row: 0, 16, 16, 32.
        // Again 768 + 2 * 64 = 896 covered, and slices i and i + 8 land on exactly the same
        // texels (every coordinate is dyadic): each covered texel is claimed twice.
        let double = bake(
            &sphere(2.0),
            &flat(),
            32,
            BakeSpace::Object,
            Perturbation::Blinn,
        );
        assert_eq!(rows(&double), band([0, 16, 16, 32]));
        let covered2 = double.covered.iter().filter(|&&c| c).count();
        assert_eq!((covered2, double.overlaps, double.skipped), (896, 896, 0));
        // The teapot's 32 patches all use [0, 1]².
        let teapot = mesh(MeshSpec::Teapot {
            subdivisions: 2,
            uv_repeat: [1.0, 1.0],
        });
        let out = bake(&teapot, &flat(), 16, BakeSpace::Object, Perturbation::Blinn);
        assert!(out.covered.iter().all(|&c| c));
        assert!(out.overlaps >= 256 * 20, "{}", out.overlaps);
        assert!(out
            .map
            .texels
            .iter()
            .all(|n| (n.length() - 1.0).abs() < 1e-12));
    }

    fn vertex(pos: DVec3, normal: DVec3, uv: [f64; 2], pu: DVec3, pv: DVec3) -> Vertex {
        Vertex {
            pos,
            normal,
            uv: DVec2::from(uv),
            pu,
            pv,
        }
    }

    /// Two small triangles: one in z = 0 (normal +z) at uv (0.1..0.4)², one in x = 0
    /// (normal +x) at uv (0.6..0.9)².
    fn two_islands() -> Mesh {
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let a = |u: f64, v: f64| vertex(DVec3::new(u, v, 0.0), z, [u, v], x, y);
        let b = |u: f64, v: f64| vertex(DVec3::new(0.0, u, v), x, [u, v], y, z);
        Mesh {
            vertices: vec![
                a(0.1, 0.1),
                a(0.4, 0.1),
                a(0.1, 0.4),
                b(0.6, 0.6),
                b(0.9, 0.6),
                b(0.6, 0.9),
            ],
            triangles: vec![[0, 1, 2], [3, 4, 5]],
        }
    }

    fn torus_d2(size: usize, a: usize, b: usize) -> usize {
        let d = |p: usize, q: usize| {
            let d = p.abs_diff(q);
            d.min(size - d)
        };
        let (dx, dy) = (d(a % size, b % size), d(a / size, b / size));
        dx * dx + dy * dy
    }

    #[test]
    fn uncovered_texels_are_dilated() {
        let size = 16;
        let out = bake(
            &two_islands(),
            &flat(),
            size,
            BakeSpace::Object,
            Perturbation::Blinn,
        );
        // Each right triangle has legs of 4.8 texels from (1.6, 1.6) (or (9.6, 9.6)); its
        // hypotenuse u + v = 0.5 (1.5) runs through 4 centres, and runs up-left, so the tie
        // rule includes them: 1 + 2 + 3 + 4 centres per triangle.
        let covered: Vec<usize> = (0..256).filter(|&k| out.covered[k]).collect();
        assert_eq!(covered.len(), 20);
        for &k in &covered {
            let (u, v) = centre(size, k);
            let want = if u < 0.5 { DVec3::Z } else { DVec3::X };
            assert!(u + v <= 0.5 || u + v >= 1.2, "{u} {v}");
            assert_eq!(out.map.texels[k], want);
        }
        // Every other texel holds the value of a nearest covered texel.
        let (mut from_z, mut from_x) = (0, 0);
        for k in (0..256).filter(|&k| !out.covered[k]) {
            let best = covered.iter().map(|&c| torus_d2(16, k, c)).min().unwrap();
            let ok = covered
                .iter()
                .any(|&c| torus_d2(16, k, c) == best && out.map.texels[c] == out.map.texels[k]);
            assert!(ok, "texel {k}");
            if out.map.texels[k] == DVec3::Z {
                from_z += 1;
            } else {
                from_x += 1;
            }
        }
        assert!(from_z > 50 && from_x > 50, "{from_z} {from_x}");
        // Nothing covered: (0, 0, 1) everywhere.
        let empty = Mesh::default();
        let out = bake(&empty, &hat(), 8, BakeSpace::Object, Perturbation::Blinn);
        assert!(out.covered.iter().all(|&c| !c));
        assert!(out.map.texels.iter().all(|&t| t == DVec3::Z));
    }

    #[test]
    fn gutter_texels_take_the_nearest_triangle() {
        let size = 16u32;
        let m = two_islands();
        let c = claim(&m, size);
        let sz = f64::from(size);
        for (k, w) in c.winner.iter().enumerate() {
            let p = DVec2::new((k % 16) as f64 + 0.5, (k / 16) as f64 + 0.5);
            let dist = |t: usize| {
                let [a, b, cc] = m.triangles[t].map(|i| m.vertices[i as usize].uv * sz);
                (closest_on_triangle(p, a, b, cc) - p).length()
            };
            let (d0, d1) = (dist(0), dist(1));
            match w {
                Some(w) if w.gutter => {
                    let d = dist(w.tri as usize);
                    assert!(d > 0.0 && d <= GUTTER_RADIUS && d <= d0.min(d1), "{k}");
                }
                Some(w) => assert!(dist(w.tri as usize) < 1e-12, "{k}"),
                None => assert!(d0.min(d1) > GUTTER_RADIUS, "{k}"),
            }
        }
        // Brute-force check of the closest point on a triangle of either orientation.
        let tri = [
            DVec2::new(0.0, 0.0),
            DVec2::new(3.0, 0.5),
            DVec2::new(1.0, 2.0),
        ];
        for j in -10..=30 {
            for i in -10..=40 {
                let p = DVec2::new(f64::from(i), f64::from(j)) * 0.125;
                let mut best = f64::INFINITY;
                for a in 0..=200 {
                    for b in 0..=200 - a {
                        let (wa, wb) = (f64::from(a) / 200.0, f64::from(b) / 200.0);
                        let q = tri[0] * (1.0 - wa - wb) + tri[1] * wa + tri[2] * wb;
                        best = best.min((q - p).length());
                    }
                }
                for [a, b, c] in [tri, [tri[0], tri[2], tri[1]]] {
                    let d = (closest_on_triangle(p, a, b, c) - p).length();
                    assert!(d <= best + 1e-12 && d >= best - 0.02, "{p}: {d} vs {best}");
                }
            }
        }
    }

    #[test]
    fn dilation_matches_brute_force() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for size in [1usize, 2, 3, 7, 16, 23] {
            for density in [1u64, 5, 30, 70] {
                let covered: Vec<bool> = (0..size * size).map(|_| next() % 100 < density).collect();
                let near = nearest_covered(&covered, size);
                let sources: Vec<usize> = (0..size * size).filter(|&k| covered[k]).collect();
                for (k, &near) in near.iter().enumerate() {
                    match near {
                        None => assert!(sources.is_empty()),
                        Some(s) => {
                            assert!(covered[s]);
                            let best = sources.iter().map(|&c| torus_d2(size, k, c)).min();
                            assert_eq!(Some(torus_d2(size, k, s)), best, "size {size} texel {k}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn skips_degenerate_and_invalid_triangles() {
        let mut m = two_islands();
        m.vertices
            .push(vertex(DVec3::ONE, DVec3::Z, [0.5, 0.5], DVec3::X, DVec3::Y));
        m.vertices.push(vertex(
            DVec3::ONE,
            DVec3::Z,
            [f64::NAN, 0.5],
            DVec3::X,
            DVec3::Y,
        ));
        // Zero uv area (collinear in uv), an index out of range, a NaN uv.
        m.triangles.push([0, 6, 3]);
        m.triangles.push([0, 1, 99]);
        m.triangles.push([0, 1, 7]);
        let out = bake(&m, &flat(), 16, BakeSpace::Object, Perturbation::Blinn);
        assert_eq!(out.skipped, 3);
        assert_eq!(
            out,
            bake(
                &two_islands(),
                &flat(),
                16,
                BakeSpace::Object,
                Perturbation::Blinn
            )
            .with_skipped(3)
        );
    }

    impl BakeOutput {
        fn with_skipped(mut self, skipped: u64) -> Self {
            self.skipped = skipped;
            self
        }
    }

    #[test]
    fn bit_identical_at_any_thread_count() {
        let m = mesh(MeshSpec::Torus {
            major: 2.0,
            minor: 0.5,
            slices: 24,
            rings: 12,
            uv_repeat: [3.0, 1.0],
        });
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| bake(&m, &hat(), 48, BakeSpace::Object, Perturbation::Blinn))
        };
        let (one, two) = (run(1), run(2));
        assert_eq!(one, two);
        assert_eq!(one.overlaps, 2 * 48 * 48);
        let bits = |o: &BakeOutput| -> Vec<u64> {
            o.map
                .texels
                .iter()
                .flat_map(|t| t.to_array().map(f64::to_bits))
                .collect()
        };
        assert_eq!(bits(&one), bits(&two));
    }
}

//! Homogeneous-space clipping (Sutherland–Hodgman) of one triangle against the near and
//! far planes, the `w > epsilon` plane and a guard band of ±[`GUARD_BAND_PIXELS`] around the
//! viewport in x and y.
//!
//! Every output vertex carries its barycentrics with respect to the ORIGINAL triangle, so
//! fragments of the sub-triangles can report barycentrics of the triangle that was submitted.
//! Intersections are computed from the edge's end points in a canonical order (independent
//! of which triangle the edge belongs to and of the direction it is walked), so two triangles
//! that share a clipped edge get bit-identical new vertices and the fill rule still holds.

use glam::{DVec3, DVec4};
use std::cmp::Ordering;

/// Smallest `w` kept: the clipper removes everything with `w < W_EPSILON`.
pub const W_EPSILON: f64 = 1e-6;

/// Width of the guard band around the viewport, in pixels, on each side. Geometry beyond it
/// is clipped so that snapped window coordinates (and so the integer edge functions) stay
/// bounded: |x|, |y| <= 16384 + 2 * 16384 pixels for images up to 16384 pixels wide.
pub const GUARD_BAND_PIXELS: f64 = 16384.0;

/// A polygon vertex in clip space with its barycentrics w.r.t. the original triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipVertex {
    pub pos: DVec4,
    pub bary: DVec3,
}

/// A clip plane: a point `p` is inside when `n · p - c >= 0`.
#[derive(Debug, Clone, Copy)]
struct Plane {
    n: DVec4,
    c: f64,
}

impl Plane {
    fn dist(&self, p: DVec4) -> f64 {
        self.n.dot(p) - self.c
    }
}

/// Why a triangle produced no polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClipReject {
    /// Entirely outside one of the planes (or clipped away to nothing).
    Outside,
    /// A plane distance or a new vertex overflowed f64 (coordinates beyond ~1e307).
    Overflow,
}

/// The seven planes, in the order they are applied: near (z >= -w), w >= epsilon, far
/// (z <= w), then the guard band left, right, bottom, top. `kx`, `ky` are the guard band
/// half-extents in NDC units (`1 + 2 * GUARD_BAND_PIXELS / size`).
fn planes(kx: f64, ky: f64) -> [Plane; 7] {
    let p = |x, y, z, w, c| Plane {
        n: DVec4::new(x, y, z, w),
        c,
    };
    [
        p(0.0, 0.0, 1.0, 1.0, 0.0),
        p(0.0, 0.0, 0.0, 1.0, W_EPSILON),
        p(0.0, 0.0, -1.0, 1.0, 0.0),
        p(1.0, 0.0, 0.0, kx, 0.0),
        p(-1.0, 0.0, 0.0, kx, 0.0),
        p(0.0, 1.0, 0.0, ky, 0.0),
        p(0.0, -1.0, 0.0, ky, 0.0),
    ]
}

/// Guard band half-extent in NDC for a viewport dimension of `size` pixels.
pub fn guard_band_ndc(size: u32) -> f64 {
    1.0 + 2.0 * GUARD_BAND_PIXELS / f64::from(size.max(1))
}

/// Total order on vertices used to orient an edge canonically before intersecting it.
fn canonical(a: &ClipVertex, b: &ClipVertex) -> Ordering {
    let ka = [
        a.pos.x, a.pos.y, a.pos.z, a.pos.w, a.bary.x, a.bary.y, a.bary.z,
    ];
    let kb = [
        b.pos.x, b.pos.y, b.pos.z, b.pos.w, b.bary.x, b.bary.y, b.bary.z,
    ];
    for (x, y) in ka.iter().zip(kb.iter()) {
        match x.total_cmp(y) {
            Ordering::Equal => continue,
            o => return o,
        }
    }
    Ordering::Equal
}

fn intersect(a: &ClipVertex, da: f64, b: &ClipVertex, db: f64) -> ClipVertex {
    let ((lo, dlo), (hi, dhi)) = if canonical(a, b) == Ordering::Greater {
        ((b, db), (a, da))
    } else {
        ((a, da), (b, db))
    };
    // dlo and dhi have opposite signs (one >= 0, the other < 0): the denominator is non-zero.
    let t = dlo / (dlo - dhi);
    ClipVertex {
        pos: lo.pos + (hi.pos - lo.pos) * t,
        bary: lo.bary + (hi.bary - lo.bary) * t,
    }
}

/// Clip triangle `v` (clip-space positions, all finite) against all seven planes for a
/// `width` x `height` viewport. Returns the convex polygon (3 to 10 vertices) in the original
/// winding order, or why there is none. A triangle entirely inside is returned unchanged
/// (bit-exact), with barycentrics (1,0,0), (0,1,0), (0,0,1).
pub fn clip_triangle(
    v: [DVec4; 3],
    width: u32,
    height: u32,
) -> Result<Vec<ClipVertex>, ClipReject> {
    let mut poly: Vec<ClipVertex> = vec![
        ClipVertex {
            pos: v[0],
            bary: DVec3::X,
        },
        ClipVertex {
            pos: v[1],
            bary: DVec3::Y,
        },
        ClipVertex {
            pos: v[2],
            bary: DVec3::Z,
        },
    ];
    let mut next = Vec::with_capacity(10);
    for plane in planes(guard_band_ndc(width), guard_band_ndc(height)) {
        let d: Vec<f64> = poly.iter().map(|p| plane.dist(p.pos)).collect();
        if d.iter().any(|x| !x.is_finite()) {
            return Err(ClipReject::Overflow);
        }
        if d.iter().all(|&x| x >= 0.0) {
            continue;
        }
        if d.iter().all(|&x| x < 0.0) {
            return Err(ClipReject::Outside);
        }
        next.clear();
        let n = poly.len();
        for i in 0..n {
            let j = (i + 1) % n;
            let (ci, cj) = (d[i] >= 0.0, d[j] >= 0.0);
            if ci {
                next.push(poly[i]);
            }
            if ci != cj {
                let p = intersect(&poly[i], d[i], &poly[j], d[j]);
                if !p.pos.is_finite() || !p.bary.is_finite() {
                    return Err(ClipReject::Overflow);
                }
                next.push(p);
            }
        }
        if next.len() < 3 {
            return Err(ClipReject::Outside);
        }
        std::mem::swap(&mut poly, &mut next);
    }
    Ok(poly)
}

//! Scan conversion of one set-up triangle: the bounding box is walked row by row from the
//! top of the image down (image y increasing) and, within a row, x increasing. Every pixel
//! centre is tested against the three exact integer edge functions (top-left rule). A covered
//! sample yields its quantised depth (window z interpolated linearly in screen space, which
//! is exact for z/w) and perspective-correct barycentrics w.r.t. the original triangle.

use super::setup::TriangleSetup;
use glam::DVec3;

/// A covered sample before the depth test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub x: u32,
    /// Image row (0 = top).
    pub y: u32,
    pub depth: u32,
    pub bary: [f64; 3],
}

/// Quantise window depth `z` (clamped to [0, 1]) to `bits` bits: round(z * (2^bits - 1)),
/// rounding half up.
pub fn quantise_depth(z: f64, bits: u32) -> u32 {
    let max = depth_max(bits);
    let q = (z.clamp(0.0, 1.0) * f64::from(max) + 0.5).floor();
    if q.is_nan() {
        return max;
    }
    q.min(f64::from(max)) as u32
}

/// Largest depth code for `bits` bits (1..=32), the value the depth buffer is cleared to.
pub fn depth_max(bits: u32) -> u32 {
    let b = bits.clamp(1, 32);
    (u64::MAX >> (64 - b)) as u32
}

/// Walk the bounding box of `t` and call `emit` for each covered sample, in scan order.
pub fn scan(t: &TriangleSetup, depth_bits: u32, mut emit: impl FnMut(Sample)) {
    let half = t.unit / 2;
    let area = t.area2 as f64;
    let v = &t.v;
    for py in t.y0..=t.y1 {
        let cy = py * t.unit + half;
        for px in t.x0..=t.x1 {
            let cx = px * t.unit + half;
            let e = [
                t.edges[0].eval(cx, cy),
                t.edges[1].eval(cx, cy),
                t.edges[2].eval(cx, cy),
            ];
            if !(0..3).all(|i| t.edges[i].covers(e[i])) {
                continue;
            }
            // Screen-space barycentrics from the exact edge values (all >= 0, sum = area).
            let b = [e[0] as f64 / area, e[1] as f64 / area, e[2] as f64 / area];
            let z = b[0] * v[0].z + b[1] * v[1].z + b[2] * v[2].z;
            // Perspective correction with 1/w, then composition with the sub-vertex
            // barycentrics of the original triangle.
            let p = [b[0] * v[0].inv_w, b[1] * v[1].inv_w, b[2] * v[2].inv_w];
            let s = p[0] + p[1] + p[2];
            let bary: DVec3 = if s > 0.0 && s.is_finite() {
                (v[0].bary * p[0] + v[1].bary * p[1] + v[2].bary * p[2]) / s
            } else {
                v[0].bary * b[0] + v[1].bary * b[1] + v[2].bary * b[2]
            };
            emit(Sample {
                x: px as u32,
                y: py as u32,
                depth: quantise_depth(z, depth_bits),
                bary: bary.to_array(),
            });
        }
    }
}

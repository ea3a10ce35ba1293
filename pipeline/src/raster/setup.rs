//! Triangle setup: viewport transform, sub-pixel snapping, integer edge functions with the
//! top-left fill rule, facing, and the pixel bounding box (scissored to the viewport).
//!
//! Coordinates from here on are in IMAGE space (y down, y = 0 the top row) in fixed-point
//! units of 1/2^(subpixel_bits + 1) pixel: one extra bit so that pixel centres (x + 0.5)
//! are exact grid points even at 0 sub-pixel bits.

use super::clip::{ClipVertex, GUARD_BAND_PIXELS};
use super::Cull;
use glam::DVec3;

/// A vertex after the viewport transform and snapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapVertex {
    /// Image-space x, y in units of 1/2^(subpixel_bits + 1) pixel.
    pub x: i64,
    pub y: i64,
    /// Window depth in [0, 1] (unquantised; interpolated linearly in screen space).
    pub z: f64,
    /// 1 / clip w (w > 0 after clipping).
    pub inv_w: f64,
    /// Barycentrics w.r.t. the original triangle.
    pub bary: DVec3,
}

/// One edge function `E(p) = dx * (p.y - y0) - dy * (p.x - x0)` of an edge (x0, y0) → (x0 +
/// dx, y0 + dy), positive inside a triangle of positive (normalised) orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    pub x0: i64,
    pub y0: i64,
    pub dx: i64,
    pub dy: i64,
    /// Top or left edge: pixel centres exactly on it are covered.
    pub top_left: bool,
}

impl Edge {
    fn new(a: &SnapVertex, b: &SnapVertex) -> Edge {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        Edge {
            x0: a.x,
            y0: a.y,
            dx,
            dy,
            // With positive orientation in y-down coordinates the interior lies to the
            // right of the direction of travel: a top edge runs in +x, a left edge runs up.
            top_left: dy < 0 || (dy == 0 && dx > 0),
        }
    }
    /// Exact value at (px, py) (same fixed-point units).
    pub fn eval(&self, px: i64, py: i64) -> i128 {
        i128::from(self.dx) * i128::from(py - self.y0)
            - i128::from(self.dy) * i128::from(px - self.x0)
    }
    /// Whether a sample with edge value `e` is covered by this edge (top-left rule).
    pub fn covers(&self, e: i128) -> bool {
        e > 0 || (e == 0 && self.top_left)
    }
}

/// Result of setting up one (sub-)triangle (a short-lived value: not boxed).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Setup {
    /// Zero area after snapping.
    Degenerate,
    /// Removed by the cull mode.
    Culled,
    /// Bounding box entirely outside the viewport.
    Scissored,
    Ready(TriangleSetup),
}

/// A triangle ready for scan conversion.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleSetup {
    /// Vertices in positive orientation (image space); `edges[i]` is opposite `v[i]`.
    pub v: [SnapVertex; 3],
    pub edges: [Edge; 3],
    /// Twice the signed area (> 0) in fixed-point units squared.
    pub area2: i128,
    /// Inclusive pixel bounds, within the viewport; empty (x0 > x1 or y0 > y1) when no pixel
    /// centre lies in the bounding box.
    pub x0: i64,
    pub x1: i64,
    pub y0: i64,
    pub y1: i64,
    /// Fixed-point units per pixel (2^(subpixel_bits + 1)).
    pub unit: i64,
}

/// Viewport transform and snap of one clipped vertex. Window x, y are snapped to 1/2^bits
/// pixel rounding half up, then converted to image space (y flipped) exactly on the grid.
pub fn snap(v: &ClipVertex, width: u32, height: u32, subpixel_bits: u32) -> SnapVertex {
    let inv_w = 1.0 / v.pos.w;
    let ndc = v.pos.truncate() * inv_w;
    let scale = f64::from(1u32 << subpixel_bits);
    // The clipper guarantees the guard band up to rounding; clamp so that the conversion to
    // integers is bounded whatever happens.
    let lim = |size: u32| {
        (
            -GUARD_BAND_PIXELS - 1.0,
            f64::from(size) + GUARD_BAND_PIXELS + 1.0,
        )
    };
    let (lx, hx) = lim(width);
    let (ly, hy) = lim(height);
    let wx = ((ndc.x + 1.0) * 0.5 * f64::from(width)).clamp(lx, hx);
    let wy = ((ndc.y + 1.0) * 0.5 * f64::from(height)).clamp(ly, hy);
    let sx = (wx * scale + 0.5).floor() as i64;
    let sy = (wy * scale + 0.5).floor() as i64;
    let h = i64::from(height) << subpixel_bits;
    SnapVertex {
        x: sx * 2,
        y: (h - sy) * 2,
        z: (ndc.z + 1.0) * 0.5,
        inv_w,
        bary: v.bary,
    }
}

/// Set up a snapped triangle: area, facing, edges, scissored bounding box.
/// Front-facing = counter-clockwise in window coordinates (y up), i.e. clockwise (negative
/// area) in image coordinates.
pub fn setup(
    tri: [SnapVertex; 3],
    cull: Cull,
    width: u32,
    height: u32,
    subpixel_bits: u32,
) -> Setup {
    let [a, b, c] = tri;
    let area_img = i128::from(b.x - a.x) * i128::from(c.y - a.y)
        - i128::from(b.y - a.y) * i128::from(c.x - a.x);
    if area_img == 0 {
        return Setup::Degenerate;
    }
    let front = area_img < 0;
    match (cull, front) {
        (Cull::Back, false) | (Cull::Front, true) => return Setup::Culled,
        _ => {}
    }
    // Normalise to positive orientation (each vertex keeps its own data).
    let v = if area_img > 0 { [a, b, c] } else { [a, c, b] };
    let area2 = area_img.abs();
    let edges = [
        Edge::new(&v[1], &v[2]),
        Edge::new(&v[2], &v[0]),
        Edge::new(&v[0], &v[1]),
    ];
    let unit = 2i64 << subpixel_bits;
    let half = 1i64 << subpixel_bits;
    let xmin = v.iter().map(|p| p.x).min().unwrap_or(0);
    let xmax = v.iter().map(|p| p.x).max().unwrap_or(0);
    let ymin = v.iter().map(|p| p.y).min().unwrap_or(0);
    let ymax = v.iter().map(|p| p.y).max().unwrap_or(0);
    // Scissor: the snapped bounding box must overlap the viewport.
    let (vw, vh) = (i64::from(width) * unit, i64::from(height) * unit);
    if xmax <= 0 || ymax <= 0 || xmin >= vw || ymin >= vh {
        return Setup::Scissored;
    }
    // Pixel p has its centre at p * unit + half; it may be covered if min <= centre <= max.
    // The range may be empty (a small triangle between pixel centres).
    let lo = |m: i64| (m - half + unit - 1).div_euclid(unit);
    let hi = |m: i64| (m - half).div_euclid(unit);
    Setup::Ready(TriangleSetup {
        v,
        edges,
        area2,
        x0: lo(xmin).max(0),
        x1: hi(xmax).min(i64::from(width) - 1),
        y0: lo(ymin).max(0),
        y1: hi(ymax).min(i64::from(height) - 1),
        unit,
    })
}

//! The rasterizer front end, modelled as hardware: near/far/guard-band clipping in
//! homogeneous space, viewport transform with sub-pixel snapping, exact integer edge
//! functions with the top-left fill rule, scan conversion in a fixed order, early depth test
//! (LESS) and perspective-correct barycentrics w.r.t. the submitted triangle.
//! Conventions are in docs/rasterizer.md.
//!
//! No input panics: non-finite positions and out-of-range indices give [`TriStatus::Invalid`],
//! zero-area triangles [`TriStatus::Degenerate`], and so on; each triangle gets a
//! [`TriangleStats`].

pub mod clip;
pub mod depth;
pub mod packet;
pub mod scan;
pub mod setup;

#[cfg(test)]
mod tests;

use glam::DVec4;
use serde::{Deserialize, Serialize};

pub use clip::{ClipReject, ClipVertex, GUARD_BAND_PIXELS, W_EPSILON};
pub use depth::DepthBuffer;
pub use packet::{Field, PacketLayout};
pub use setup::{Setup, SnapVertex, TriangleSetup};

/// Face culling. Front faces are counter-clockwise in window coordinates (y up), as in OpenGL.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Cull {
    #[default]
    None,
    Back,
    Front,
}

/// Rasterizer configuration (the hardware parameters of the front end).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RasterConfig {
    /// Vertex window x, y are snapped to 1/2^subpixel_bits pixel (round half up). 0..=8.
    #[serde(default = "default_subpixel_bits")]
    pub subpixel_bits: u32,
    /// Window z in [0, 1] is quantised to this many bits (unsigned, scale 2^n - 1). 16..=32.
    #[serde(default = "default_depth_bits")]
    pub depth_bits: u32,
    #[serde(default)]
    pub cull: Cull,
    /// Clock cycles of triangle setup per (sub-)triangle. 1..=1024.
    #[serde(default = "default_setup_cycles")]
    pub setup_cycles: u32,
}

fn default_subpixel_bits() -> u32 {
    4
}
fn default_depth_bits() -> u32 {
    24
}
fn default_setup_cycles() -> u32 {
    8
}

impl Default for RasterConfig {
    fn default() -> Self {
        RasterConfig {
            subpixel_bits: default_subpixel_bits(),
            depth_bits: default_depth_bits(),
            cull: Cull::None,
            setup_cycles: default_setup_cycles(),
        }
    }
}

impl RasterConfig {
    /// Check the ranges; `field` is the config path of this struct (e.g. "raster"), used as
    /// the prefix of the message: "raster.subpixel_bits: expected 0 to 8, found 9".
    pub fn validate(&self, field: &str) -> Result<(), String> {
        let check = |name: &str, v: u32, lo: u32, hi: u32| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(format!("{field}.{name}: expected {lo} to {hi}, found {v}"))
            }
        };
        check("subpixel_bits", self.subpixel_bits, 0, 8)?;
        check("depth_bits", self.depth_bits, 16, 32)?;
        check("setup_cycles", self.setup_cycles, 1, 1024)
    }
}

/// One fragment that passed the early depth test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fragment {
    /// Pixel column.
    pub x: u32,
    /// Pixel row; 0 is the TOP row of the image.
    pub y: u32,
    /// Index into the input triangle list.
    pub tri: u32,
    /// Quantised window depth.
    pub depth: u32,
    /// Perspective-correct barycentrics w.r.t. the original triangle's vertices (sum to 1).
    pub bary: [f64; 3],
}

/// What happened to a submitted triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TriStatus {
    /// Reached the scan converter (it may still cover no pixel centre).
    Drawn,
    /// Removed by the cull mode.
    Culled,
    /// Zero area after snapping.
    Degenerate,
    /// Entirely outside the view volume, the guard band or the viewport.
    Clipped,
    /// Non-finite coordinates (or beyond the f64 range in clipping) or a vertex index out of
    /// range.
    Invalid,
}

/// Per-triangle result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct TriangleStats {
    /// Fragments emitted (passed the depth test).
    pub fragments: u32,
    pub status: TriStatus,
    /// Covered samples that failed the depth test.
    pub depth_rejected: u32,
    /// Sub-triangles that went through setup (1 unless clipping made a polygon; 0 when the
    /// triangle was rejected before setup).
    pub setups: u32,
}

/// Output of [`rasterize`].
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct RasterOutput {
    /// In submission order; within a triangle in scan order.
    pub fragments: Vec<Fragment>,
    /// One per input triangle.
    pub triangles: Vec<TriangleStats>,
    /// Covered samples that failed the depth test.
    pub depth_rejected: u64,
}

impl RasterOutput {
    /// Clock cycles of the modelled front end: `setup_cycles` per sub-triangle set up, plus
    /// one clock per covered sample (emitted or depth-rejected) of the scan converter.
    pub fn cycles(&self, cfg: &RasterConfig) -> u64 {
        self.triangles
            .iter()
            .map(|t| {
                u64::from(t.setups) * u64::from(cfg.setup_cycles)
                    + u64::from(t.fragments)
                    + u64::from(t.depth_rejected)
            })
            .sum()
    }
}

/// Rasterise triangles in order. Early depth test (LESS) against an internal depth buffer
/// cleared to the largest depth code: a fragment that fails is not emitted (counted in
/// `depth_rejected`); one that passes updates the buffer and is emitted, so later triangles
/// may overwrite earlier fragments (overdraw is visible in the list, in submission order).
///
/// Out-of-range config fields are clamped (`validate` rejects them). A zero-sized image gives
/// an empty output with every triangle `Clipped` (or `Invalid`).
pub fn rasterize(
    clip: &[DVec4],
    tris: &[[u32; 3]],
    width: u32,
    height: u32,
    cfg: &RasterConfig,
) -> RasterOutput {
    rasterize_with(clip, tris, width, height, cfg, DepthTest::Early)
}

/// Where the depth test happens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DepthTest {
    /// In the rasterizer, before shading ([`rasterize`]): hidden samples are never shaded.
    Early,
    /// In the ROP, after shading: every covered sample is emitted (none is depth-rejected
    /// here). Needed when the engine may kill fragments, since a killed fragment must not
    /// have updated the depth buffer (hardware turns early Z off for such programs).
    Late,
}

/// [`rasterize`] with the depth test `depth`.
pub fn rasterize_with(
    clip: &[DVec4],
    tris: &[[u32; 3]],
    width: u32,
    height: u32,
    cfg: &RasterConfig,
    depth: DepthTest,
) -> RasterOutput {
    let sub = cfg.subpixel_bits.min(8);
    let depth_bits = cfg.depth_bits.clamp(16, 32);
    let mut out = RasterOutput::default();
    out.triangles.reserve_exact(tris.len());
    // room for half a fragment per pixel up front (pages are only touched when written):
    // most frames need no regrowth, each of which copies the whole list
    out.fragments
        .reserve((width as usize * height as usize / 2).min(1 << 24));
    let mut zbuf = DepthBuffer::new(width, height, scan::depth_max(depth_bits));
    for (ti, tri) in tris.iter().enumerate() {
        let mut stats = TriangleStats {
            fragments: 0,
            status: TriStatus::Invalid,
            depth_rejected: 0,
            setups: 0,
        };
        let verts = tri.map(|i| clip.get(i as usize).copied());
        let [Some(a), Some(b), Some(c)] = verts else {
            out.triangles.push(stats);
            continue;
        };
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            out.triangles.push(stats);
            continue;
        }
        if width == 0 || height == 0 {
            stats.status = TriStatus::Clipped;
            out.triangles.push(stats);
            continue;
        }
        let poly = match clip::clip_triangle([a, b, c], width, height) {
            Ok(p) => p,
            Err(ClipReject::Outside) => {
                stats.status = TriStatus::Clipped;
                out.triangles.push(stats);
                continue;
            }
            Err(ClipReject::Overflow) => {
                out.triangles.push(stats);
                continue;
            }
        };
        let snapped: Vec<SnapVertex> = poly
            .iter()
            .map(|v| setup::snap(v, width, height, sub))
            .collect();
        // Status priority over the fan's sub-triangles: Drawn > Culled > Degenerate > Clipped.
        let mut rank = 0u8;
        for k in 1..snapped.len().saturating_sub(1) {
            stats.setups += 1;
            let t = [snapped[0], snapped[k], snapped[k + 1]];
            let r = match setup::setup(t, cfg.cull, width, height, sub) {
                Setup::Scissored => 0,
                Setup::Degenerate => 1,
                Setup::Culled => 2,
                Setup::Ready(ts) => {
                    scan::scan(&ts, depth_bits, |s| {
                        let pass = match depth {
                            DepthTest::Early => zbuf.test_and_set(s.x, s.y, s.depth),
                            DepthTest::Late => s.x < width && s.y < height,
                        };
                        if pass {
                            stats.fragments = stats.fragments.saturating_add(1);
                            out.fragments.push(Fragment {
                                x: s.x,
                                y: s.y,
                                tri: ti as u32,
                                depth: s.depth,
                                bary: s.bary,
                            });
                        } else {
                            stats.depth_rejected = stats.depth_rejected.saturating_add(1);
                        }
                    });
                    3
                }
            };
            rank = rank.max(r);
        }
        stats.status = match rank {
            3 => TriStatus::Drawn,
            2 => TriStatus::Culled,
            1 => TriStatus::Degenerate,
            _ => TriStatus::Clipped,
        };
        out.depth_rejected += u64::from(stats.depth_rejected);
        out.triangles.push(stats);
    }
    out
}

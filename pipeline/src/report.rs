//! The run report: `report.json` and the readable table of `bumpsim report`.

use crate::artifacts::ArtifactStats;
use crate::edges::EdgeStats;
use crate::engine::memory::TextureStats;
use crate::metrics::ErrorStats;
use crate::raster::packet::PacketLayout;
use crate::sim::CycleReport;
use bumpsim_hw::GateBudget;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write;

/// Version of the report format and of bumpsim.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub version: String,
    pub name: String,
    pub config_hash: String,
    pub image: ImageInfo,
    /// What the bake of a `Baked` mesh did (Wang et al. §2): left out for other meshes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bake: Option<crate::wang::scene::BakeStats>,
    pub cycles: CycleReport,
    pub gates: Gates,
    pub bandwidth: Bandwidth,
    /// Rendering passes: cycles, geometry and framebuffer traffic of each.
    pub passes: crate::passes::Passes,
    pub error: Errors,
    /// Artifact measures (banding, faceting, ringing, low-pass PSNR, half-resolution SSIM;
    /// docs/metrics.md) of the bit-accurate image.
    pub artifacts: Artifacts,
    /// The edge-discontinuity measure (`pipeline/src/edges.rs`, docs/metrics.md).
    pub edges: Edges,
    /// With `reference.highlight_luma`: the error and artifact figures over the pixels where
    /// the reference is bright (`crate::highlight`, docs/metrics.md); left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub highlight: Option<crate::highlight::Highlight>,
    /// With `reference.synthesis`: the NDF bump synthesis measured on its tables
    /// (`crate::ndf::statistics`, docs/metrics.md); left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub synthesis: Option<crate::ndf::statistics::Synthesis>,
    /// Each quantized normal map of the engine (`QuantizedNormals` units, config order) and
    /// its index mipmaps against the true normals, in texel space (docs/metrics.md,
    /// `normal_maps`); left out when the engine has none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub normal_maps: Vec<crate::quantize::NormalMapError>,
    /// A config with `frames`: every frame's cycles, per-frame work, traffic, error and
    /// flicker (`crate::animation`); left out for a single frame. The rest of the report is
    /// frame 0's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub animation: Option<crate::animation::AnimationReport>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Edges {
    /// Bit-accurate mode against the float reference.
    pub total: EdgeStats,
    /// Exact mode against the reference: the discontinuity of the algorithm.
    pub algorithm: EdgeStats,
    /// Bit-accurate against exact mode.
    pub quantization: EdgeStats,
}

#[derive(Debug, Clone, Serialize)]
pub struct Artifacts {
    /// Bit-accurate mode against the float reference.
    pub total: ArtifactStats,
    /// Bit-accurate against exact mode: the artifacts of quantization alone.
    pub quantization: ArtifactStats,
}

#[derive(Debug, Clone, Serialize)]
pub struct ImageInfo {
    pub width: u32,
    pub height: u32,
    /// Pixels covered by the engine's render.
    pub covered_pixels: u64,
    /// Pixels covered by the engine but not the reference, or the other way round.
    pub coverage_mismatch: u64,
    /// Pixels of the bit-accurate 8-bit image that are not black (any channel above 0).
    pub lit_pixels: u64,
    /// The mean of `(R + G + B) / 3` (8-bit levels, 0 to 255) over those pixels: the image's
    /// mean lit intensity (e.g. how a surface's brightness holds over distance, Kautz et al.
    /// Fig. 1), 0 when none is lit.
    pub mean_lit_level: f64,
}

impl ImageInfo {
    /// The lit pixels and mean lit level of an 8-bit image ([`ImageInfo::mean_lit_level`]).
    pub fn lit(img: &image::RgbImage) -> (u64, f64) {
        let (mut n, mut sum) = (0u64, 0u64);
        for p in img.pixels() {
            let v = u64::from(p[0]) + u64::from(p[1]) + u64::from(p[2]);
            if v > 0 {
                n += 1;
                sum += v;
            }
        }
        let mean = if n == 0 {
            0.0
        } else {
            sum as f64 / (3.0 * n as f64)
        };
        (n, mean)
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct UnitGates {
    pub kind: String,
    pub total: f64,
    /// The tables' storage in `total` (items marked `memory`; `cost.tables` says how they
    /// are built).
    pub memory: f64,
    /// What this unit's loadable tables are built as, when the unit's config says so apart
    /// from `cost.tables` (the unit's `tables`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tables: Option<&'static str>,
    /// What each table of a role in the unit's `table_kinds` is built as (role -> kind).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub table_kinds: BTreeMap<&'static str, &'static str>,
    pub items: Vec<bumpsim_hw::gates::GateItem>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Gates {
    /// What the figures are: always `"model"`, the itemised estimate of `docs/gates.md`
    /// (`bumpsim gates CONFIG --synth` puts yosys's synthesis beside it).
    pub estimate: &'static str,
    /// Gate equivalents of all engine units (2-input NAND = 1).
    pub total: f64,
    /// The tables' storage in `total`, built as `tables` says.
    pub memory: f64,
    /// What the loadable tables are built as (`cost.tables`): SRAM, latch RAM, flip-flop RAM
    /// or ROM.
    pub tables: &'static str,
    pub per_unit: BTreeMap<String, UnitGates>,
    /// The raster operations (depth and alpha tests, blending, colour write): beside the
    /// engine's total, not in it, as the papers' budgets leave the raster back end out.
    pub rop: UnitGates,
    /// The texture caches (`engine.texture_cache`), beside the total as the ROP: the papers'
    /// budgets leave the texture memory system out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture_cache: Option<UnitGates>,
}

impl Gates {
    pub fn new(
        units: &[(String, String, GateBudget)],
        rop: &GateBudget,
        tables: bumpsim_hw::gates::MemoryKind,
    ) -> Gates {
        let per_unit: BTreeMap<String, UnitGates> = units
            .iter()
            .map(|(name, kind, b)| {
                (
                    name.clone(),
                    UnitGates {
                        kind: kind.clone(),
                        total: round2(b.total()),
                        memory: round2(b.memory()),
                        tables: None,
                        table_kinds: BTreeMap::new(),
                        items: b.items.clone(),
                    },
                )
            })
            .collect();
        Gates {
            estimate: "model",
            total: round2(per_unit.values().map(|u| u.total).sum()),
            memory: round2(per_unit.values().map(|u| u.memory).sum::<f64>() + 0.0),
            tables: tables.name(),
            per_unit,
            rop: UnitGates::beside("rop", rop),
            texture_cache: None,
        }
    }
}

impl UnitGates {
    /// A budget beside the engine's units (the ROP, the texture caches).
    pub fn beside(kind: &str, b: &GateBudget) -> UnitGates {
        UnitGates {
            kind: kind.into(),
            total: round2(b.total()),
            memory: round2(b.memory()),
            tables: None,
            table_kinds: BTreeMap::new(),
            items: b.items.clone(),
        }
    }
}

fn round2(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

#[derive(Debug, Clone, Serialize)]
pub struct Bandwidth {
    /// Bits of one triangle from geometry to rasterizer, as packed.
    pub bits_per_triangle: u64,
    /// A plain textured Gouraud triangle (docs/rasterizer.md).
    pub baseline_bits_per_triangle: u64,
    /// `(bits_per_triangle - baseline) / baseline`, in percent.
    pub extra_percent: f64,
    /// Bits per triangle of the bump extras: every attribute a plain textured Gouraud
    /// triangle does not carry (all but texture coordinates and the Gouraud colour).
    pub bump_extra_bits_per_triangle: u64,
    /// The bump extras against the baseline, in percent (Ernst et al. §4.2: "three 16-bit
    /// words per triangle, or about less than 5% of a typical textured Gouraud triangle").
    pub bump_extra_percent: f64,
    /// Stored bits per texel of the engine's bump texture (0 when it has none).
    pub bits_per_texel: u32,
    /// Every texture the units hold: unit name and bits per texel.
    pub textures: BTreeMap<String, u32>,
    /// The engine's texture memory: each texture (named after its first reader), its
    /// readers, stored bits and texel traffic per frame.
    pub texture_memory: BTreeMap<String, TextureStats>,
    /// The texel traffic through `engine.texture_cache` (absent without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture_cache: Option<crate::texcache::CacheReport>,
    pub packet: PacketLayout,
}

#[derive(Debug, Clone, Serialize)]
pub struct Errors {
    /// Engine in bit-accurate mode against the float reference.
    pub total: ErrorStats,
    /// Engine in exact mode against the float reference: the algorithm's error.
    pub algorithm: ErrorStats,
    /// Bit-accurate against exact mode: the quantization error.
    pub quantization: ErrorStats,
}

impl Report {
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a report serialises") + "\n"
    }

    /// The readable table printed by `bumpsim report`.
    pub fn to_table(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "bumpsim {}  config {}  hash {}",
            self.version,
            self.name,
            &self.config_hash[..16.min(self.config_hash.len())]
        );
        let _ = writeln!(
            s,
            "image {}x{}, {} pixels covered, {} coverage mismatches, {} lit (mean level {:.2})",
            self.image.width,
            self.image.height,
            self.image.covered_pixels,
            self.image.coverage_mismatch,
            self.image.lit_pixels,
            self.image.mean_lit_level
        );
        if let Some(b) = &self.bake {
            let _ = writeln!(
                s,
                "bake: {} faces simplified to {}, {} samples, {} ({:.1}%) set by a view, {} below their face",
                b.detailed_faces,
                b.faces,
                b.samples,
                b.updated,
                100.0 * b.updated as f64 / b.samples.max(1) as f64,
                b.below
            );
            if let Some(e) = &b.evaluation {
                let _ = writeln!(
                    s,
                    "  against the detailed mesh ({} views of {}x{}): normal error {:.3} (8-bit) \
                     {:.3} (unquantised) colour steps, distance error {:.5} of the radius",
                    e.views, e.size, e.size, e.normal8, e.normal, e.distance
                );
            }
        }
        let c = &self.cycles;
        let _ = writeln!(
            s,
            "\ncycles {} (frame work {}, {} triangles, {} fragments, {} killed, {:.3} cycles/fragment)",
            c.total, c.frame, c.triangles, c.fragments, c.killed, c.per_fragment
        );
        let _ = writeln!(
            s,
            "  {:<14} {:>10} {:>10} {:>10} {:>7}",
            "unit", "busy", "idle", "stall", "util%"
        );
        for (name, k) in &c.per_unit {
            let util = 100.0 * k.busy as f64 / k.total().max(1) as f64;
            let _ = writeln!(
                s,
                "  {:<14} {:>10} {:>10} {:>10} {:>7.1}",
                name, k.busy, k.idle, k.stall, util
            );
        }
        let _ = writeln!(
            s,
            "\ngates {:.0} GE (model estimate, docs/gates.md; `bumpsim gates --synth` for yosys), \
             tables {:.0} GE of it as {}",
            self.gates.total, self.gates.memory, self.gates.tables
        );
        for (name, u) in &self.gates.per_unit {
            let _ = write!(s, "  {:<14} {:<14} {:>10.0}", name, u.kind, u.total);
            if u.memory > 0.0 {
                let _ = write!(s, "  (tables {:.0})", u.memory);
            }
            s.push('\n');
        }
        let _ = write!(s, "  (beside the total: rop {:.0} GE", self.gates.rop.total);
        if let Some(c) = &self.gates.texture_cache {
            let _ = write!(
                s,
                ", texture cache {:.0} GE, storage {:.0} of it",
                c.total, c.memory
            );
        }
        s.push_str(")\n");
        let b = &self.bandwidth;
        let _ = writeln!(
            s,
            "\nbandwidth {} bits/triangle (baseline {}, {:+.1} %), bump extras {} bits ({:.1} % of the baseline), {} bits/texel",
            b.bits_per_triangle,
            b.baseline_bits_per_triangle,
            b.extra_percent,
            b.bump_extra_bits_per_triangle,
            b.bump_extra_percent,
            b.bits_per_texel
        );
        for (name, t) in &b.texture_memory {
            let reads = match t.texels_per_frame_work {
                0 => format!("{} texels/fragment", t.texels_per_fragment),
                n => format!("{n} texels/frame of frame work"),
            };
            let _ = writeln!(
                s,
                "  texture {:<12} {} {}x{}, {} levels, {} bits/texel, {} bits stored, {reads}, {} bits/frame (read by {})",
                name,
                t.shape,
                t.size[0],
                t.size[1],
                t.levels,
                t.bits_per_texel,
                t.stored_bits,
                t.bits_per_frame,
                t.readers.join(", ")
            );
        }
        if let Some(c) = &b.texture_cache {
            let k = &c.config;
            // the memory behind several caches: one bus or a channel each
            let bus = match (c.caches.len() > 1, k.bus) {
                (false, _) => "",
                (true, crate::config::TextureBus::Shared) => " on one bus",
                (true, crate::config::TextureBus::PerCache) => " on a channel per cache",
            };
            let plural = if k.fill_cycles == 1 { "" } else { "s" };
            let fills = format!("{} cycle{plural} a fill{bus}", k.fill_cycles);
            let timing = match (k.miss_cycles, k.prefetch) {
                (0, _) => "traffic only".to_string(),
                (m, 0) => format!("blocking, {m}-cycle misses, {fills}"),
                (m, d) => format!("prefetching, {d}-deep FIFO, {m}-cycle misses, {fills}"),
            };
            let _ = writeln!(
                s,
                "  texture cache {} lines x {}x{} texels, {}-way{} ({timing}): fills {} bits for {} uncached ({:.3}x)",
                k.lines,
                k.block,
                k.block,
                k.ways,
                if k.shared { ", shared" } else { "" },
                c.fill_bits,
                c.uncached_bits,
                c.traffic_ratio
            );
            for q in &c.caches {
                let _ = writeln!(
                    s,
                    "    {:<18} {} reads, {} misses, {:.1} % hits",
                    q.readers.join(", "),
                    q.reads,
                    q.misses,
                    100.0 * q.hit_rate
                );
            }
            // how much of the frame the memory spends on fills (bandwidth-bound near 100 %)
            let total = self.cycles.total.max(1) as f64;
            let busy: Vec<String> = c
                .memory_busy_cycles
                .iter()
                .map(|&b| format!("{b} ({:.1} %)", 100.0 * b as f64 / total))
                .collect();
            let _ = writeln!(
                s,
                "    memory busy with fills {} of the frame's {} cycles",
                busy.join(", "),
                self.cycles.total
            );
        }
        let p = &self.passes;
        let _ = writeln!(
            s,
            "\npasses {} ({} cycles in all, framebuffer {} bits, geometry {} bits)",
            p.passes.len(),
            p.total_cycles,
            p.fb_bits,
            p.geometry_bits
        );
        for q in &p.passes {
            let _ = writeln!(
                s,
                "  {:<42} {:>10} cycles {:>12} fb read {:>12} fb write",
                q.name, q.cycles, q.fb_read_bits, q.fb_write_bits
            );
        }
        let _ = writeln!(
            s,
            "\nerror          {:>9} {:>9} {:>9} {:>9}",
            "PSNR dB", "RMSE", "max LSB", "mean LSB"
        );
        for (name, e) in [
            ("total", &self.error.total),
            ("algorithm", &self.error.algorithm),
            ("quantization", &self.error.quantization),
        ] {
            let _ = writeln!(
                s,
                "  {:<12} {:>9.2} {:>9.5} {:>9.2} {:>9.3}",
                name, e.psnr_db, e.rmse, e.max_abs_lsb, e.mean_abs_lsb
            );
        }
        let _ = writeln!(
            s,
            "\nartifacts      {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
            "banding", "facet LSB", "ring LSB", "LP PSNR", "SSIM/2", "MS-SSIM"
        );
        for (name, a) in [
            ("total", &self.artifacts.total),
            ("quantization", &self.artifacts.quantization),
        ] {
            let _ = writeln!(
                s,
                "  {:<12} {:>9.5} {:>9.3} {:>9.3} {:>9.2} {:>9.5} {:>9.5}",
                name,
                a.banding,
                a.faceting_lsb,
                a.ringing_lsb,
                a.lowpass_psnr_db,
                a.half_ssim,
                a.ms_ssim
            );
        }
        let _ = writeln!(
            s,
            "\nedges          {:>9} {:>9} {:>9} {:>9} {:>9}",
            "edge LSB", "inner LSB", "excess", "edge p99", "seam LSB"
        );
        for (name, e) in [
            ("total", &self.edges.total),
            ("algorithm", &self.edges.algorithm),
            ("quantization", &self.edges.quantization),
        ] {
            let _ = writeln!(
                s,
                "  {:<12} {:>9.3} {:>9.3} {:>9.3} {:>9.2} {:>9.3}",
                name,
                e.edge_step_lsb,
                e.interior_step_lsb,
                e.excess_lsb,
                e.edge_p99_lsb,
                e.worst_seam_lsb
            );
        }
        if let Some(h) = &self.highlight {
            let _ = writeln!(
                s,
                "\nhighlight, {} pixels of reference luma >= {}\n               {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
                h.pixels, h.luma, "PSNR dB", "max LSB", "mean LSB", "bias LSB", "blocky", "facet LSB"
            );
            for (name, x) in [
                ("total", &h.total),
                ("algorithm", &h.algorithm),
                ("quantization", &h.quantization),
            ] {
                let _ = writeln!(
                    s,
                    "  {:<12} {:>9.2} {:>9.2} {:>9.3} {:>+9.3} {:>9.5} {:>9.3}",
                    name,
                    x.error.psnr_db,
                    x.error.max_abs_lsb,
                    x.error.mean_abs_lsb,
                    x.mean_signed_lsb,
                    x.artifacts.blockiness,
                    x.artifacts.faceting_lsb
                );
            }
        }
        if let Some(y) = &self.synthesis {
            let _ = writeln!(
                s,
                "\nNDF synthesis, normals at {0}x{0} texture coordinates on {1}x{1} bins: exact \
                 inverse CDFs KL {2:.4} chi2/dof {3:.2}",
                y.side, y.bins, y.exact.kl, y.exact.chi2_dof
            );
            if let Some(l) = &y.lookup {
                let _ = writeln!(
                    s,
                    "  through L {0}x{0}: KL {1:.4} chi2/dof {2:.2}",
                    l.side, l.kl, l.chi2_dof
                );
            }
            let levels: Vec<String> = y.levels.iter().map(|x| format!("{x:.4}")).collect();
            let _ = writeln!(
                s,
                "  mean shading at {} deg: closed form {:.4}, levels {}, far NDF {:.4}",
                y.tilt_deg,
                y.closed_form,
                levels.join(" "),
                y.far
            );
        }
        if let Some(a) = &self.animation {
            let _ = writeln!(
                s,
                "\nanimation {} frames ({} cycles in all, {} of them per-frame work; the \
                 report above is frame 0's)",
                a.frames, a.total_cycles, a.frame_work_cycles
            );
            let _ = writeln!(
                s,
                "  {:>5} {:>10} {:>10} {:>10} {:>12} {:>9} {:>8} {:>11}",
                "frame",
                "cycles",
                "frame work",
                "fragments",
                "texel bits",
                "PSNR dB",
                "max LSB",
                "flicker LSB"
            );
            for r in &a.per_frame {
                let flicker = r.flicker_lsb.map_or("-".to_string(), |f| format!("{f:.3}"));
                let _ = writeln!(
                    s,
                    "  {:>5} {:>10} {:>10} {:>10} {:>12} {:>9.2} {:>8.0} {:>11}",
                    r.frame,
                    r.cycles,
                    r.frame_work,
                    r.fragments,
                    r.texture_bits,
                    r.total_psnr_db,
                    r.total_max_lsb,
                    flicker
                );
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::ImageInfo;

    #[test]
    fn mean_lit_level_averages_the_pixels_that_are_not_black() {
        let mut img = image::RgbImage::new(4, 1);
        img.put_pixel(0, 0, image::Rgb([30, 60, 90])); // 60
        img.put_pixel(1, 0, image::Rgb([0, 0, 3])); // 1
        img.put_pixel(3, 0, image::Rgb([255, 255, 255])); // 255
        let (n, mean) = ImageInfo::lit(&img);
        assert_eq!(n, 3);
        assert_eq!(mean, (60.0 + 1.0 + 255.0) / 3.0);
        assert_eq!(ImageInfo::lit(&image::RgbImage::new(2, 2)), (0, 0.0));
    }
}

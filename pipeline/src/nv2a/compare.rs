//! The model against the hardware's frame: per quad and per frame, the pixels compared, the
//! exact ones, the largest difference and where the mismatches sit.

use super::{Loaded, QuadModel};
use bumpsim_hw::Mode;
use serde::Serialize;

/// The host's text colour in the frames: opaque white glyphs are written with alpha 0.
const TEXT: [u8; 4] = [255, 255, 255, 0];

/// One quad's comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuadResult {
    pub label: String,
    pub compared: u64,
    pub exact: u64,
    /// Largest channel difference over the quad's pixels, against the nearest of the model's
    /// colours (one per colour that may lie under it).
    pub max_diff: u8,
    /// The model's colours (RGBA) at the quad's first compared pixel, one per colour under
    /// the quad.
    pub model: Vec<[u8; 4]>,
    /// Bounding box of the mismatches, (x0, y0, x1, y1) inclusive; none when exact.
    pub misses_at: Option<[u32; 4]>,
    /// The first mismatch in raster order: (x, y), the frame's RGBA and the model's there.
    pub first_miss: Option<([u32; 2], [u8; 4], [u8; 4])>,
}

/// A frame's comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    pub frame: String,
    /// `bit-accurate` or `exact`.
    pub mode: String,
    pub combiner_width: u32,
    pub compared: u64,
    pub exact: u64,
    /// `exact / compared` (1 when nothing is compared).
    pub share: f64,
    pub max_diff: u8,
    /// Compared pixels that hold the host's text colour: a text cell the config leaves out
    /// (0 in a correct config).
    pub text_pixels: u64,
    pub quads: Vec<QuadResult>,
}

/// Compare the model of a frame in `mode` with the frame the hardware rendered.
pub fn compare(l: &Loaded, mode: Mode) -> Result<Comparison, String> {
    let (f, golden) = (&l.frame, &l.golden);
    let mut quads = Vec::with_capacity(f.quads.len());
    let mut text_pixels = 0;
    for q in &f.quads {
        let m = QuadModel::new(f, q, &l.textures, mode).map_err(|(_, m)| m)?;
        let mut r = QuadResult {
            label: q.label.clone(),
            compared: 0,
            exact: 0,
            max_diff: 0,
            model: Vec::new(),
            misses_at: None,
            first_miss: None,
        };
        let (x0, y0, x1, y1) = q.region.bounds();
        for y in y0..y1 {
            for x in x0..x1 {
                if !q.region.compares(x, y) || f.text.iter().any(|t| t.covers(x, y)) {
                    continue;
                }
                let px = golden.get_pixel(x, y).0;
                if px == TEXT {
                    text_pixels += 1;
                }
                r.compared += 1;
                let model = m.colours_at(x, y);
                if r.model.is_empty() {
                    r.model = model.clone();
                }
                let diff = model
                    .iter()
                    .map(|c| (0..4).map(|i| c[i].abs_diff(px[i])).max().unwrap_or(0))
                    .min()
                    .unwrap_or(255);
                if diff == 0 {
                    r.exact += 1;
                    continue;
                }
                r.max_diff = r.max_diff.max(diff);
                r.first_miss.get_or_insert(([x, y], px, model[0]));
                let b = r.misses_at.get_or_insert([x, y, x, y]);
                *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            }
        }
        quads.push(r);
    }
    let compared = quads.iter().map(|q| q.compared).sum::<u64>();
    let exact = quads.iter().map(|q| q.exact).sum::<u64>();
    Ok(Comparison {
        frame: f.name.clone(),
        mode: match mode {
            Mode::Exact => "exact",
            Mode::BitAccurate => "bit-accurate",
        }
        .into(),
        combiner_width: f.combiner_width,
        compared,
        exact,
        share: if compared == 0 {
            1.0
        } else {
            exact as f64 / compared as f64
        },
        max_diff: quads.iter().map(|q| q.max_diff).max().unwrap_or(0),
        text_pixels,
        quads,
    })
}

impl Comparison {
    /// One line: frame, compared, exact, share, largest difference, and the mismatching quads
    /// with their pixel counts and bounding boxes.
    pub fn line(&self) -> String {
        const SHOWN: usize = 4;
        let missing = self.quads.iter().filter(|q| q.exact < q.compared).count();
        let mut bad: Vec<String> = self
            .quads
            .iter()
            .filter(|q| q.exact < q.compared)
            .take(SHOWN)
            .map(|q| {
                let [x0, y0, x1, y1] = q.misses_at.unwrap_or_default();
                format!(
                    "{} ({} px in x {x0}..={x1}, y {y0}..={y1})",
                    q.label,
                    q.compared - q.exact
                )
            })
            .collect();
        if missing > SHOWN {
            bad.push(format!("{} more quads (--json)", missing - SHOWN));
        }
        format!(
            "{:<24} {:>9} {:>9} {:>8.3}% {:>4}  {}",
            self.frame,
            self.compared,
            self.exact,
            100.0 * self.share,
            self.max_diff,
            bad.join("; ")
        )
    }

    /// The header of [`Comparison::line`].
    pub fn header() -> String {
        format!(
            "{:<24} {:>9} {:>9} {:>9} {:>4}  mismatching quads",
            "frame", "compared", "exact", "share", "max"
        )
    }
}

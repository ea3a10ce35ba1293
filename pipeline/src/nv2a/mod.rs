//! NV2A conformance: frames of real-hardware test suites as configs (`configs/nv2a/`),
//! rendered by the model's units and compared pixel for pixel with the frames the hardware
//! rendered (`bumpsim nv2a`, `docs/nv2a.md`).
//!
//! A frame config ([`Frame`]) lists the quads a test draws: where each lies (a screen
//! rectangle or a world-space quad seen by the host's default camera), what lies under it (the
//! cleared colour or the checkerboard background) and the passes drawn over it, each a
//! register-combiner program ([`bumpsim_hw::units::combiner`]) with the register values it
//! reads. The model runs each pass's program once through the combiner unit in the chosen
//! mode and blends it as the ROP does ([`blend`]); the comparison ([`compare`]) visits every
//! compared pixel of every quad, minus the host's text cells.
//!
//! This covers the `Combiner` suite, whose programs read constants, flat vertex colours and
//! unbound textures only. The texture-shader suites (`Pixel_shader`, `Bump_map`), which need
//! the rasterizer's per-pixel coordinates and generated textures, are checked by the unit
//! library's tests (`hw/tests/nv2a_*.rs`) and are not configs yet.

mod compare;
mod frame;

pub use compare::{compare, Comparison, QuadResult};
pub use frame::{Frame, Pass, Quad, Region, Text, Under, HEIGHT, WIDTH, WORLD_INSET};

use crate::config::{overrides, parse_as, read_config, InputError};
use bumpsim_hw::units::combiner::{
    Combiner, CombinerParams, FinalCombiner, GeneralStage, MuxSelect, Program,
};
use bumpsim_hw::{Codec, Encoding, Mode, Unit, Word};
use std::path::{Path, PathBuf};

/// A frame config read, overridden and checked, with its golden frame.
pub struct Loaded {
    pub frame: Frame,
    pub path: PathBuf,
    /// The frame the hardware rendered.
    pub golden: image::RgbaImage,
}

/// Read a frame config, apply `--set` overrides, check every field and read its golden
/// frame. Errors name the file and the field.
pub fn load(path: &Path, sets: &[String]) -> Result<Loaded, InputError> {
    let file = path.display().to_string();
    let text = read_config(path, &file)?;
    let mut frame: Frame = parse_as(&text, &file)?;
    if !sets.is_empty() {
        frame = overrides::apply_to(&frame, sets)?;
    }
    check(&frame).map_err(|(field, m)| InputError::new(&file, field, m))?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let gpath = base.join(&frame.golden);
    let max = crate::scene::files::MAX_PNG_SIDE;
    let golden = crate::scene::files::read_png(&gpath, max)
        .map_err(|e| InputError::new(&file, "golden", e.to_string()))?
        .to_rgba8();
    if golden.dimensions() != (WIDTH, HEIGHT) {
        return Err(InputError::new(
            &file,
            "golden",
            format!(
                "{} is {} x {}: expected the {WIDTH} x {HEIGHT} frame",
                gpath.display(),
                golden.width(),
                golden.height()
            ),
        ));
    }
    Ok(Loaded {
        frame,
        path: path.to_path_buf(),
        golden,
    })
}

/// Check every field that parsing does not: (field, message) of the first error.
fn check(f: &Frame) -> Result<(), (String, String)> {
    let width_error = |m: String| {
        let m = m.strip_prefix("width: ").map(str::to_string).unwrap_or(m);
        ("combiner_width".to_string(), m)
    };
    params(f.combiner_width).map_err(width_error)?;
    let params = |w| params(w).map_err(width_error);
    if f.quads.is_empty() || f.quads.len() > frame::MAX_QUADS {
        return Err((
            "quads".into(),
            format!(
                "{} quads: expected 1 to {}",
                f.quads.len(),
                frame::MAX_QUADS
            ),
        ));
    }
    for (i, t) in f.text.iter().enumerate() {
        let m = frame::MAX_TEXT_CELL;
        if t.row > m || t.col > m || t.text.chars().count() as u32 > m {
            return Err((
                format!("text[{i}]"),
                format!("row, column and length up to {m} (the frame holds 18 rows of 62)"),
            ));
        }
    }
    for (i, q) in f.quads.iter().enumerate() {
        q.region
            .check()
            .map_err(|m| (format!("quads[{i}].region"), m))?;
        if q.passes.is_empty() || q.passes.len() > frame::MAX_PASSES {
            return Err((
                format!("quads[{i}].passes"),
                format!(
                    "{} passes: expected 1 to {}",
                    q.passes.len(),
                    frame::MAX_PASSES
                ),
            ));
        }
        for (j, p) in q.passes.iter().enumerate() {
            // the program's errors start with its field ("stages[0].rgb.a.source: ...")
            Combiner::new(params(f.combiner_width)?, p.program.clone()).map_err(|m| {
                let at = format!("quads[{i}].passes[{j}].program");
                match m.split_once(": ") {
                    Some((sub, rest)) if !sub.contains(' ') => {
                        (format!("{at}.{sub}"), rest.to_string())
                    }
                    _ => (at, m),
                }
            })?;
        }
    }
    Ok(())
}

fn params(width: u32) -> Result<CombinerParams, String> {
    let p = CombinerParams {
        width,
        ..CombinerParams::default()
    };
    // the part itself checks the width, here on a program that does nothing
    let nop = Program {
        stages: vec![GeneralStage::nop()],
        final_combiner: FinalCombiner::default(),
        mux_select: MuxSelect::default(),
    };
    Combiner::new(p, nop).map(|_| p)
}

/// The ROP's blend of the NV2A frames: SRC_ALPHA, ONE_MINUS_SRC_ALPHA on all four channels,
/// `(s a + d (255 - a)) / 255` rounded to nearest (what the Combiner frames settle).
pub fn blend(s: [u8; 4], d: [u8; 4]) -> [u8; 4] {
    let a = s[3] as u32;
    std::array::from_fn(|c| {
        let t = s[c] as u32 * a + d[c] as u32 * (255 - a);
        ((2 * t + 255) / 510) as u8
    })
}

/// The colour one pass's program computes, in `mode`.
pub fn shade(width: u32, pass: &Pass, mode: Mode) -> Result<[u8; 4], String> {
    let u = Combiner::new(params(width)?, pass.program.clone())?;
    let e8 = Encoding::texel(Codec::UnitUnsigned, false, 8);
    let w = |c: [u8; 4]| Word::from_raw(&e8, &c.map(i64::from));
    let t = w(pass.texture);
    let ins = [w(pass.primary), w(pass.secondary), w(pass.fog), t, t, t, t];
    let mut o = [Word::default()];
    u.eval(mode, &ins, &mut o);
    Ok(o[0].raws::<4>().map(|r| r.clamp(0, 255) as u8))
}

/// The colours a quad may end as, one per colour that may lie under it: its passes blended
/// in order.
pub fn quad_colours(f: &Frame, q: &Quad, mode: Mode) -> Result<Vec<[u8; 4]>, String> {
    let shaded = q
        .passes
        .iter()
        .map(|p| shade(f.combiner_width, p, mode))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(q.under
        .colours()
        .into_iter()
        .map(|mut d| {
            for s in &shaded {
                d = blend(*s, d);
            }
            d
        })
        .collect())
}

/// The model's picture of the frame: each quad's covered pixels in its colour over the first
/// colour under it, in order; the rest transparent black.
pub fn render(f: &Frame, mode: Mode) -> Result<image::RgbaImage, String> {
    let mut img = image::RgbaImage::new(WIDTH, HEIGHT);
    for q in &f.quads {
        let c = quad_colours(f, q, mode)?[0];
        let (x0, y0, x1, y1) = q.region.bounds();
        for y in y0..y1 {
            for x in x0..x1 {
                if q.region.covers(x, y) {
                    img.put_pixel(x, y, image::Rgba(c));
                }
            }
        }
    }
    Ok(img)
}

/// [`render`] encoded as PNG.
pub fn render_png(f: &Frame, mode: Mode) -> Result<Vec<u8>, String> {
    let mut png = Vec::new();
    render(f, mode)?
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    Ok(png)
}

#[cfg(test)]
mod tests;

//! NV2A conformance: frames of real-hardware test suites as configs (`configs/nv2a/`),
//! rendered by the model's units and compared pixel for pixel with the frames the hardware
//! rendered (`bumpsim nv2a`, `docs/nv2a.md`).
//!
//! A frame config ([`Frame`]) lists the quads a test draws: where each lies (a screen
//! rectangle or a world-space quad seen by the host's default camera), what lies under it (the
//! cleared colour or the checkerboard background), its texture coordinates per shader stage at
//! its four vertices, and the passes drawn over it: each an optional texture-shader program
//! ([`bumpsim_hw::units::texture_shader`], reading the frame's textures by name) and a
//! register-combiner program ([`bumpsim_hw::units::combiner`]) with the register values it
//! reads. [`QuadModel`] builds each pass's units once; a pass without a shader has one colour
//! over the quad, a shaded one runs per pixel on the coordinates interpolated at the frame's
//! [`Sample`] point; each is blended as the ROP does ([`blend`]), a culled fragment leaves the
//! pixel. The comparison ([`compare`]) visits every compared pixel of every quad, minus the
//! host's text cells.
//!
//! Every shared frame is a config: the `Combiner` suite (`configs/nv2a/combiner/`: constants,
//! flat vertex colours, unbound textures), the `Pixel_shader` suite
//! (`configs/nv2a/pixel-shader/`) and the `Bump_map` suite (`configs/nv2a/bump-map/`). The
//! unit library's tests (`hw/tests/nv2a_*.rs`) keep the hypotheses' alternatives that are not
//! config fields.

mod compare;
mod frame;
mod model;

pub use compare::{compare, Comparison, QuadResult};
pub use frame::{
    Frame, Pass, Quad, Reading, Region, Sample, Shader, ShaderStage, Text, TextureDef,
    TextureSource, Under, HEIGHT, WIDTH, WORLD_INSET,
};
pub use model::{blend, QuadModel};

use crate::config::{overrides, parse_as, read_config, InputError};
use bumpsim_hw::units::combiner::{
    Combiner, CombinerParams, FinalCombiner, GeneralStage, MuxSelect, Program,
};
use bumpsim_hw::{Mode, Texture};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A frame config read, overridden and checked, with its golden frame and textures.
pub struct Loaded {
    pub frame: Frame,
    pub path: PathBuf,
    /// The frame the hardware rendered.
    pub golden: image::RgbaImage,
    /// The frame's textures by name.
    pub textures: BTreeMap<String, Arc<Texture>>,
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
    let textures = model::textures(&frame, &base).map_err(|m| {
        let (field, m) = m.split_once(": ").unwrap_or(("textures", &m));
        InputError::new(&file, field, m)
    })?;
    // every pass builds (its texture names, its shader and combiner programs)
    for (i, q) in frame.quads.iter().enumerate() {
        QuadModel::new(&frame, q, &textures, Mode::BitAccurate).map_err(|(j, m)| {
            let at = format!("quads[{i}].passes[{j}]");
            match m.split_once(": ") {
                Some((sub, rest)) if !sub.contains(' ') => {
                    InputError::new(&file, format!("{at}.{sub}"), rest)
                }
                _ => InputError::new(&file, at, m),
            }
        })?;
    }
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
        textures,
    })
}

/// Check every field that parsing does not: (field, message) of the first error.
fn check(f: &Frame) -> Result<(), (String, String)> {
    let width_error = |m: String| {
        let m = m.strip_prefix("width: ").map(str::to_string).unwrap_or(m);
        ("combiner_width".to_string(), m)
    };
    params(f.combiner_width).map_err(width_error)?;
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
    if f.text.len() > frame::MAX_TEXTS {
        return Err((
            "text".into(),
            format!(
                "{} cells: expected at most {}",
                f.text.len(),
                frame::MAX_TEXTS
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
    if f.textures.len() > frame::MAX_TEXTURES {
        return Err((
            "textures".into(),
            format!(
                "{} textures: expected at most {}",
                f.textures.len(),
                frame::MAX_TEXTURES
            ),
        ));
    }
    for (i, t) in f.textures.iter().enumerate() {
        if f.textures[..i].iter().any(|u| u.name == t.name) {
            return Err((
                format!("textures[{i}].name"),
                format!("{:?} is named twice: expected distinct names", t.name),
            ));
        }
        if let TextureSource::Checkerboard { cell: 0, .. } = t.source {
            return Err((
                format!("textures[{i}].source.cell"),
                "0: expected cells of at least 1 texel".into(),
            ));
        }
        if let TextureSource::Quadrants { size, split, .. } = t.source {
            let max = frame::MAX_TEXTURE_SIDE;
            if !(1..=max).contains(&size) || split > size {
                return Err((
                    format!("textures[{i}].source"),
                    format!(
                        "size {size}, split {split}: expected 1 <= size <= {max}, split <= size"
                    ),
                ));
            }
        }
        if let TextureSource::RadialPattern { width, height }
        | TextureSource::RgbaPattern { width, height }
        | TextureSource::Checkerboard { width, height, .. } = t.source
        {
            let max = frame::MAX_TEXTURE_SIDE;
            let even = matches!(t.source, TextureSource::RadialPattern { .. });
            if !(2..=max).contains(&width)
                || !(2..=max).contains(&height)
                || (even && (width % 2 == 1 || height % 2 == 1))
            {
                return Err((
                    format!("textures[{i}].source"),
                    format!(
                        "{width} x {height}: expected 2 to {max} texels a side{}",
                        if even {
                            ", even (the radial pattern halves them)"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        }
    }
    for (i, q) in f.quads.iter().enumerate() {
        q.region
            .check()
            .map_err(|m| (format!("quads[{i}].region"), m))?;
        if q.texcoords.len() > 4 {
            return Err((
                format!("quads[{i}].texcoords"),
                format!("{} stages: expected at most 4", q.texcoords.len()),
            ));
        }
        let in_range = |v: &&f32| v.is_finite() && v.abs() <= 16777216.0;
        if let Some(v) = q
            .texcoords
            .iter()
            .flatten()
            .flatten()
            .find(|v| !in_range(v))
        {
            return Err((
                format!("quads[{i}].texcoords"),
                format!("{v}: expected finite coordinates of at most 2^24 = 16777216"),
            ));
        }
        if let Some(j) = q
            .passes
            .iter()
            .position(|p| p.show_depth && p.shader.is_none())
        {
            return Err((
                format!("quads[{i}].passes[{j}].show_depth"),
                "true on a pass without a shader: expected a shader whose last stage replaces \
                 the depth (DotProductDepthReplace)"
                    .into(),
            ));
        }
        let shaded = q.passes.iter().any(|p| p.shader.is_some());
        if shaded && !matches!(q.region, Region::Screen { .. }) {
            return Err((
                format!("quads[{i}].region"),
                "a World quad with a shader pass: expected a Screen region (texture coordinates \
                 are interpolated over screen rectangles only)"
                    .into(),
            ));
        }
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
    }
    let shaded = shaded_pixels(f);
    if shaded > frame::MAX_SHADED {
        return Err((
            "quads".into(),
            format!(
                "the quads shade {shaded} pixels with a texture shader (pixels times shaded \
                 passes): expected at most {} (about ten seconds)",
                frame::MAX_SHADED
            ),
        ));
    }
    Ok(())
}

/// The work of a frame: every pixel of each quad's bounds, once per pass with a shader (at
/// most `frame::MAX_SHADED` in a frame that loads).
pub fn shaded_pixels(f: &Frame) -> u64 {
    f.quads
        .iter()
        .map(|q| {
            let (x0, y0, x1, y1) = q.region.bounds();
            let passes = q.passes.iter().filter(|p| p.shader.is_some()).count() as u64;
            (x1 - x0) as u64 * (y1 - y0) as u64 * passes
        })
        .sum()
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

/// The model's picture of the frame: each quad's covered pixels over the first colour under
/// it, in order; the rest transparent black.
pub fn render(l: &Loaded, mode: Mode) -> Result<image::RgbaImage, String> {
    let mut img = image::RgbaImage::new(WIDTH, HEIGHT);
    for q in &l.frame.quads {
        let m = QuadModel::new(&l.frame, q, &l.textures, mode).map_err(|(_, m)| m)?;
        let (x0, y0, x1, y1) = q.region.bounds();
        for y in y0..y1 {
            for x in x0..x1 {
                if q.region.covers(x, y) {
                    img.put_pixel(x, y, image::Rgba(m.colours_at(x, y)[0]));
                }
            }
        }
    }
    Ok(img)
}

/// Where the model and the frame differ: the frame dimmed to a quarter outside the compared
/// pixels, at full brightness where the model matches it exactly, and magenta
/// (255, 0, 255) where it does not; opaque.
pub fn diff(l: &Loaded, mode: Mode) -> Result<image::RgbaImage, String> {
    let mut img = image::RgbaImage::from_fn(WIDTH, HEIGHT, |x, y| {
        let [r, g, b, _] = l.golden.get_pixel(x, y).0;
        image::Rgba([r / 4, g / 4, b / 4, 255])
    });
    for q in &l.frame.quads {
        let m = QuadModel::new(&l.frame, q, &l.textures, mode).map_err(|(_, m)| m)?;
        let (x0, y0, x1, y1) = q.region.bounds();
        for y in y0..y1 {
            for x in x0..x1 {
                if !q.region.compares(x, y) || l.frame.text.iter().any(|t| t.covers(x, y)) {
                    continue;
                }
                let got = l.golden.get_pixel(x, y).0;
                let c = if m.colours_at(x, y).contains(&got) {
                    [got[0], got[1], got[2], 255]
                } else {
                    [255, 0, 255, 255]
                };
                img.put_pixel(x, y, image::Rgba(c));
            }
        }
    }
    Ok(img)
}

/// An image encoded as PNG.
pub fn png(img: &image::RgbaImage) -> Result<Vec<u8>, String> {
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    Ok(png)
}

/// [`render`] encoded as PNG.
pub fn render_png(l: &Loaded, mode: Mode) -> Result<Vec<u8>, String> {
    png(&render(l, mode)?)
}

#[cfg(test)]
mod tests;

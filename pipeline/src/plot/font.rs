//! The plots' text, laid out and drawn from the bundled DejaVu Sans itself (`assets/fonts/`)
//! through `ab_glyph` (the font's tables: glyph ids, advances, side bearings, `kern` pairs and
//! glyph outlines; and its anti-aliased rasterizer): each glyph placed at its pen position
//! with its side bearing and on the baseline, then either filled into pixels (PNG) or written
//! as SVG path data (so an SVG depends on no installed font). plotters' own text drawing
//! (also through ab_glyph) drops the glyphs' left side bearings and rounds each glyph's
//! baseline on its own, which set the decimal point of "18000.0" raised against the digits;
//! this module lays the glyphs out itself instead.
//!
//! Sizes are plotters' font sizes: a font of size `s` maps the font's ascent to descent
//! (`hhea`) onto `s` pixels, as ab_glyph's `PxScale` does.

use std::sync::OnceLock;

use ab_glyph::{Font as _, FontRef, GlyphId, OutlineCurve};

/// DejaVu Sans (fonts-dejavu-core 2.37, Bitstream Vera licence; `docs/assets.md`).
pub static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// A point of a laid-out text in pixels (x right, y down).
pub type P = (f64, f64);

/// One step of a glyph outline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Seg {
    Move(P),
    Line(P),
    /// A quadratic Bézier: control point, end point.
    Quad(P, P),
    /// A cubic Bézier: two control points, end point (CFF outlines; TrueType has none).
    Cubic(P, P, P),
    Close,
}

/// A TrueType font (ab_glyph's) and its vertical metrics in font units.
#[derive(Debug)]
pub struct Font {
    font: FontRef<'static>,
    /// Font units: ascent (positive), descent (negative), line gap.
    ascent: f64,
    descent: f64,
    line_gap: f64,
}

/// The bundled font, parsed once.
pub fn font() -> &'static Font {
    static F: OnceLock<Font> = OnceLock::new();
    F.get_or_init(|| {
        Font::parse(FONT_BYTES).expect("the bundled font assets/fonts/DejaVuSans.ttf parses")
    })
}

impl Font {
    /// Read a TrueType font (None: it does not parse).
    pub fn parse(data: &'static [u8]) -> Option<Font> {
        let font = FontRef::try_from_slice(data).ok()?;
        Some(Font {
            ascent: font.ascent_unscaled() as f64,
            descent: font.descent_unscaled() as f64,
            line_gap: font.line_gap_unscaled() as f64,
            font,
        })
    }

    /// Pixels per font unit at plotters' font size `size`.
    pub fn scale(&self, size: f64) -> f64 {
        size / (self.ascent - self.descent)
    }

    /// The height of one line at `size`, in pixels (ascent to descent and the line gap).
    pub fn line_height(&self, size: f64) -> f64 {
        (self.ascent - self.descent + self.line_gap) * self.scale(size)
    }

    /// The glyph of a character (0, the missing glyph, outside the map).
    pub fn glyph(&self, c: char) -> u16 {
        self.font.glyph_id(c).0
    }

    /// The advance width of a glyph, in font units.
    pub fn advance(&self, g: u16) -> f64 {
        self.font.h_advance_unscaled(GlyphId(g)) as f64
    }

    /// The kerning between two glyphs (the `kern` table), in font units.
    pub fn kern(&self, left: u16, right: u16) -> f64 {
        self.font.kern_unscaled(GlyphId(left), GlyphId(right)) as f64
    }

    /// The outline of a glyph in font units (y up), relative to its pen position (so with
    /// its left side bearing): empty for a glyph without ink.
    pub fn outline(&self, g: u16) -> Vec<OutlineCurve> {
        self.font
            .outline(GlyphId(g))
            .map_or_else(Vec::new, |o| o.curves)
    }

    /// The width of one line of text at `size`, in pixels.
    pub fn width(&self, text: &str, size: f64) -> f64 {
        let mut pen = 0.0;
        let mut prev = None;
        for c in text.chars() {
            let g = self.glyph(c);
            if let Some(p) = prev {
                pen += self.kern(p, g);
            }
            pen += self.advance(g);
            prev = Some(g);
        }
        pen * self.scale(size)
    }

    /// The size of a text's box at `size` (lines split at `\n`): the widest line, and the
    /// lines' height.
    pub fn text_size(&self, text: &str, size: f64) -> (f64, f64) {
        let w = text
            .split('\n')
            .map(|l| self.width(l, size))
            .fold(0.0, f64::max);
        (w, text.split('\n').count() as f64 * self.line_height(size))
    }
}

/// Where a text's box sits against its anchor point, and its rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// 0: the anchor is the box's left, 0.5 its centre, 1 its right (each line on its own).
    pub h: f64,
    /// 0: the anchor is the box's top, 0.5 its middle, 1 its bottom.
    pub v: f64,
    /// Quarter turns clockwise (0 to 3), about the anchor.
    pub quarter_turns: u8,
}

/// The outline of `text` (lines split at `\n`) at `size`, placed at `pos`, in pixels.
pub fn text_path(text: &str, size: f64, at: Placement, pos: P) -> Vec<Seg> {
    let f = font();
    let s = f.scale(size);
    let lh = f.line_height(size);
    let (_, h) = f.text_size(text, size);
    let turn = |(x, y): P| -> P {
        let (x, y) = match at.quarter_turns % 4 {
            0 => (x, y),
            1 => (-y, x),
            2 => (-x, -y),
            _ => (y, -x),
        };
        (pos.0 + x, pos.1 + y)
    };
    let mut out = Vec::new();
    for (k, line) in text.split('\n').enumerate() {
        let x0 = -at.h * f.width(line, size);
        let baseline = -at.v * h + k as f64 * lh + f.ascent * s;
        let mut pen = 0.0;
        let mut prev = None;
        for c in line.chars() {
            let g = f.glyph(c);
            if let Some(p) = prev {
                pen += f.kern(p, g);
            }
            prev = Some(g);
            let dev =
                |p: ab_glyph::Point| turn((x0 + (pen + p.x as f64) * s, baseline - p.y as f64 * s));
            curve_segs(&f.outline(g), &dev, &mut out);
            pen += f.advance(g);
        }
    }
    out
}

/// A glyph's outline curves (its contours one after another, each closed by a line back to
/// its start) as segments, mapped by `dev`.
fn curve_segs(curves: &[OutlineCurve], dev: &dyn Fn(ab_glyph::Point) -> P, out: &mut Vec<Seg>) {
    let mut open: Option<(ab_glyph::Point, ab_glyph::Point)> = None; // (start, current)
    for curve in curves {
        let (a, b) = match *curve {
            OutlineCurve::Line(a, b) | OutlineCurve::Quad(a, _, b) => (a, b),
            OutlineCurve::Cubic(a, _, _, b) => (a, b),
        };
        match open {
            Some((_, cur)) if cur == a => {}
            _ => {
                if open.is_some() {
                    out.push(Seg::Close);
                }
                out.push(Seg::Move(dev(a)));
                open = Some((a, a));
            }
        }
        let start = open.map_or(a, |o| o.0);
        match *curve {
            // the line closing a contour is the `Close`
            OutlineCurve::Line(..) if b == start => {}
            OutlineCurve::Line(_, b) => out.push(Seg::Line(dev(b))),
            OutlineCurve::Quad(_, c, b) => out.push(Seg::Quad(dev(c), dev(b))),
            OutlineCurve::Cubic(_, c, d, b) => out.push(Seg::Cubic(dev(c), dev(d), dev(b))),
        }
        open = Some((start, b));
    }
    if open.is_some() {
        out.push(Seg::Close);
    }
}

/// SVG path data of segments (coordinates to 1/100 pixel).
pub fn svg_path(segs: &[Seg]) -> String {
    let mut s = String::new();
    let n = |v: f64| {
        let r = (v * 100.0).round() / 100.0;
        let t = format!("{r:.2}");
        let t = t.trim_end_matches('0').trim_end_matches('.');
        if t == "-0" {
            "0".to_string()
        } else {
            t.to_string()
        }
    };
    for seg in segs {
        match *seg {
            Seg::Move(p) => s += &format!("M{} {}", n(p.0), n(p.1)),
            Seg::Line(p) => s += &format!("L{} {}", n(p.0), n(p.1)),
            Seg::Quad(c, p) => s += &format!("Q{} {} {} {}", n(c.0), n(c.1), n(p.0), n(p.1)),
            Seg::Cubic(c, d, p) => {
                s += &format!(
                    "C{} {} {} {} {} {}",
                    n(c.0),
                    n(c.1),
                    n(d.0),
                    n(d.1),
                    n(p.0),
                    n(p.1)
                )
            }
            Seg::Close => s += "Z",
        }
    }
    s
}

/// The pixels a path covers within a `w` x `h` canvas, anti-aliased by ab_glyph's rasterizer
/// (the area of each pixel the path's contours enclose): `(x, y, coverage in 0..=1)`, in row
/// order.
pub fn raster(segs: &[Seg], (w, h): (u32, u32)) -> Vec<(i32, i32, f64)> {
    use ab_glyph::{point, Glyph, Outline, OutlinedGlyph, PxScaleFactor, Rect};
    // the path as ab_glyph outline curves at one unit a pixel, y up as a font's
    let pt = |(x, y): P| point(x as f32, -y as f32);
    let mut curves = Vec::new();
    let (mut cur, mut start) = ((0.0, 0.0), (0.0, 0.0));
    for seg in segs {
        match *seg {
            Seg::Move(_) | Seg::Close => {
                if cur != start {
                    curves.push(OutlineCurve::Line(pt(cur), pt(start)));
                }
                if let Seg::Move(p) = *seg {
                    start = p;
                }
                cur = start;
            }
            Seg::Line(p) => {
                curves.push(OutlineCurve::Line(pt(cur), pt(p)));
                cur = p;
            }
            Seg::Quad(c, p) => {
                curves.push(OutlineCurve::Quad(pt(cur), pt(c), pt(p)));
                cur = p;
            }
            Seg::Cubic(c, d, p) => {
                curves.push(OutlineCurve::Cubic(pt(cur), pt(c), pt(d), pt(p)));
                cur = p;
            }
        }
    }
    if cur != start {
        curves.push(OutlineCurve::Line(pt(cur), pt(start)));
    }
    let finite = |p: &ab_glyph::Point| p.x.is_finite() && p.y.is_finite();
    let points = |c: &OutlineCurve| match c {
        OutlineCurve::Line(a, b) => vec![*a, *b],
        OutlineCurve::Quad(a, b, c) => vec![*a, *b, *c],
        OutlineCurve::Cubic(a, b, c, d) => vec![*a, *b, *c, *d],
    };
    if curves.iter().flat_map(points).any(|p| !finite(&p)) {
        return Vec::new();
    }
    // bounds as ab_glyph keeps a glyph's: min the left top, max the right bottom (y up)
    let (mut x0, mut x1, mut y0, mut y1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
    for p in curves.iter().flat_map(points) {
        (x0, x1, y0, y1) = (x0.min(p.x), x1.max(p.x), y0.min(p.y), y1.max(p.y));
    }
    if curves.is_empty() || x0 >= x1 || y0 >= y1 {
        return Vec::new();
    }
    // the canvas (the path's pixels beyond it are dropped, not drawn)
    if x1 <= 0.0 || x0 >= w as f32 || -y0 <= 0.0 || -y1 >= h as f32 {
        return Vec::new();
    }
    let outline = Outline {
        bounds: Rect {
            min: point(x0, y1),
            max: point(x1, y0),
        },
        curves,
    };
    let glyph = Glyph {
        id: GlyphId(0),
        scale: 1.0.into(),
        position: point(0.0, 0.0),
    };
    let one = PxScaleFactor {
        horizontal: 1.0,
        vertical: 1.0,
    };
    let g = OutlinedGlyph::new(glyph, outline, one);
    let b = g.px_bounds();
    let (bx, by) = (b.min.x as i32, b.min.y as i32);
    let mut out = Vec::new();
    g.draw(|x, y, c| {
        let (x, y) = (bx + x as i32, by + y as i32);
        if c > 1e-6 && x >= 0 && y >= 0 && x < w as i32 && y < h as i32 {
            out.push((x, y, (c as f64).min(1.0)));
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_font_maps_characters_and_measures_them() {
        let f = font();
        let (zero, dot) = (f.glyph('0'), f.glyph('.'));
        assert!(zero != 0 && dot != 0 && zero != dot);
        assert_eq!(f.glyph('\u{10FFFF}'), 0);
        // DejaVu Sans: digits 1303 units wide, the full stop 651, in 2048 units per em
        assert_eq!(f.advance(zero), 1303.0);
        assert_eq!(f.advance(dot), 651.0);
        // ascent 1901 to descent -483: 2384 units make a font size
        assert!((f.scale(2384.0) - 1.0).abs() < 1e-12);
        assert!((f.width("00", 2384.0) - 2606.0).abs() < 1e-9);
        // "AV" kerns closer than its two advances
        let (a, v) = (f.glyph('A'), f.glyph('V'));
        assert!(f.kern(a, v) < 0.0, "{}", f.kern(a, v));
        assert_eq!(f.kern(zero, zero), 0.0);
        // a composite glyph (é) has the curves of e and of the accent
        assert!(f.outline(f.glyph('é')).len() > f.outline(f.glyph('e')).len());
        assert!(f.outline(f.glyph(' ')).is_empty());
    }

    /// The full stop of "0.0" sits on the digits' baseline and after its side bearing: the
    /// bug plotters' text drawing had ("18000·0").
    #[test]
    fn the_decimal_point_sits_on_the_baseline() {
        let at = Placement {
            h: 0.0,
            v: 0.0,
            quarter_turns: 0,
        };
        let f = font();
        let s = f.scale(13.0);
        // the baseline on a pixel boundary (y = 30)
        let px = raster(
            &text_path("0.0", 13.0, at, (10.0, 30.0 - f.ascent * s)),
            (100, 100),
        );
        let inked = |x0: i32, x1: i32| {
            let ys: Vec<i32> = px
                .iter()
                .filter(|p| p.0 >= x0 && p.0 < x1 && p.2 > 0.5)
                .map(|p| p.1)
                .collect();
            (*ys.iter().min().unwrap(), *ys.iter().max().unwrap())
        };
        let d0 = 10.0 + f.advance(f.glyph('0')) * s; // the full stop's pen position
        let d1 = d0 + f.advance(f.glyph('.')) * s;
        let (digit_top, digit_bottom) = inked(10, d0.floor() as i32);
        let (dot_top, dot_bottom) = inked(d0.ceil() as i32, d1.floor() as i32);
        assert_eq!(dot_bottom, digit_bottom, "the full stop on the baseline");
        assert_eq!(dot_bottom, 29);
        assert!(
            dot_top > digit_top + 5,
            "the full stop is low: {dot_top} {digit_top}"
        );
        // the full stop's ink is centred in its advance, not against the first digit
        let xs: Vec<i32> = px
            .iter()
            .filter(|p| p.1 == dot_bottom && p.2 > 0.5 && p.0 as f64 >= d0)
            .map(|p| p.0)
            .filter(|&x| x as f64 + 1.0 <= d1)
            .collect();
        let centre = (xs[0] + xs[xs.len() - 1]) as f64 / 2.0 + 0.5;
        assert!((centre - (d0 + d1) / 2.0).abs() < 1.0, "{xs:?} {d0} {d1}");
    }

    #[test]
    fn placement_and_rotation_move_the_box() {
        let f = font();
        let (w, h) = f.text_size("ab\nc", 20.0);
        assert!((h - 2.0 * f.line_height(20.0)).abs() < 1e-9);
        assert!((w - f.width("ab", 20.0)).abs() < 1e-9);
        let bounds = |segs: &[Seg]| {
            let mut b = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
            for s in segs {
                if let Seg::Move(p) | Seg::Line(p) | Seg::Quad(_, p) = *s {
                    b = (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1));
                }
            }
            b
        };
        let centred = Placement {
            h: 0.5,
            v: 0.5,
            quarter_turns: 0,
        };
        let b = bounds(&text_path("H", 20.0, centred, (100.0, 50.0)));
        assert!((b.0 + b.2 - 200.0).abs() < 1.0, "{b:?}");
        // turned a quarter back (plotters' Rotate270, the y axis' label): it reads upwards
        let up = Placement {
            quarter_turns: 3,
            ..centred
        };
        let r = bounds(&text_path("HHHH", 20.0, up, (100.0, 50.0)));
        assert!(r.3 - r.1 > r.2 - r.0, "taller than wide: {r:?}");
        assert!((r.1 + r.3 - 100.0).abs() < 1.0, "{r:?}");
        assert!(svg_path(&text_path("H", 20.0, centred, (0.0, 0.0))).starts_with('M'));
    }
}

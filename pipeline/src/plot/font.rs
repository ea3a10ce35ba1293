//! The plots' text, laid out and drawn from the bundled DejaVu Sans itself (`assets/fonts/`):
//! the TrueType tables a left-to-right line of text needs (`cmap` format 4, `hmtx`, `kern`
//! format 0, `glyf` with composite glyphs) read here, each glyph placed at its pen position
//! with its side bearing and on the baseline, then either filled into pixels with an
//! anti-aliased coverage rasterizer (PNG) or written as SVG path data (so an SVG depends on
//! no installed font). plotters' own text drawing (through ab_glyph) drops the glyphs' left
//! side bearings and rounds each glyph's baseline on its own, which set the decimal point of
//! "18000.0" raised against the digits; this module replaces it.
//!
//! Sizes are plotters' font sizes: a font of size `s` maps the font's ascent to descent
//! (`hhea`) onto `s` pixels, as ab_glyph's `PxScale` does.

use std::sync::OnceLock;

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
    Close,
}

/// The tables of a TrueType font that text layout and outlines need.
#[derive(Debug)]
pub struct Font {
    data: &'static [u8],
    /// Font units: ascent (positive), descent (negative), line gap.
    ascent: f64,
    descent: f64,
    line_gap: f64,
    num_glyphs: u16,
    n_hmetrics: u16,
    hmtx: usize,
    loca: usize,
    long_loca: bool,
    glyf: usize,
    glyf_len: usize,
    /// The `cmap` format 4 subtable.
    cmap4: usize,
    /// `kern` format 0: the pairs' offset and count.
    kern: Option<(usize, usize)>,
}

fn u16_at(d: &[u8], o: usize) -> Option<u16> {
    Some(u16::from_be_bytes([*d.get(o)?, *d.get(o + 1)?]))
}

fn i16_at(d: &[u8], o: usize) -> Option<i16> {
    u16_at(d, o).map(|v| v as i16)
}

fn u32_at(d: &[u8], o: usize) -> Option<u32> {
    Some(u32::from_be_bytes([
        *d.get(o)?,
        *d.get(o + 1)?,
        *d.get(o + 2)?,
        *d.get(o + 3)?,
    ]))
}

/// The bundled font, parsed once.
pub fn font() -> &'static Font {
    static F: OnceLock<Font> = OnceLock::new();
    F.get_or_init(|| {
        Font::parse(FONT_BYTES).expect("the bundled font assets/fonts/DejaVuSans.ttf parses")
    })
}

impl Font {
    /// Read the tables of a TrueType font (None: a table is missing or malformed).
    pub fn parse(data: &'static [u8]) -> Option<Font> {
        let n = u16_at(data, 4)? as usize;
        let table = |tag: &[u8; 4]| -> Option<(usize, usize)> {
            (0..n).find_map(|i| {
                let r = 12 + 16 * i;
                (data.get(r..r + 4)? == tag)
                    .then(|| {
                        Some((
                            u32_at(data, r + 8)? as usize,
                            u32_at(data, r + 12)? as usize,
                        ))
                    })
                    .flatten()
            })
        };
        let (head, _) = table(b"head")?;
        let (hhea, _) = table(b"hhea")?;
        let (maxp, _) = table(b"maxp")?;
        let (hmtx, _) = table(b"hmtx")?;
        let (loca, _) = table(b"loca")?;
        let (glyf, glyf_len) = table(b"glyf")?;
        let (cmap, _) = table(b"cmap")?;
        // the Windows Unicode BMP subtable (3, 1), else any Unicode (0, _), in format 4
        let subtables = u16_at(data, cmap + 2)? as usize;
        let mut cmap4 = None;
        for want in [(3u16, Some(1u16)), (0, None)] {
            for i in 0..subtables {
                let r = cmap + 4 + 8 * i;
                let (pid, eid) = (u16_at(data, r)?, u16_at(data, r + 2)?);
                let off = cmap + u32_at(data, r + 4)? as usize;
                if pid == want.0
                    && (want.1.is_none() || want.1 == Some(eid))
                    && u16_at(data, off)? == 4
                {
                    cmap4.get_or_insert(off);
                }
            }
        }
        let kern = table(b"kern").and_then(|(k, _)| {
            // version 0, the first subtable if horizontal kerning values in format 0
            let (version, count) = (u16_at(data, k)?, u16_at(data, k + 2)?);
            let coverage = u16_at(data, k + 8)?;
            (version == 0 && count > 0 && coverage >> 8 == 0 && coverage & 0x7 == 1)
                .then(|| Some((k + 18, u16_at(data, k + 10)? as usize)))
                .flatten()
        });
        Some(Font {
            data,
            ascent: i16_at(data, hhea + 4)? as f64,
            descent: i16_at(data, hhea + 6)? as f64,
            line_gap: i16_at(data, hhea + 8)? as f64,
            num_glyphs: u16_at(data, maxp + 4)?,
            n_hmetrics: u16_at(data, hhea + 34)?,
            hmtx,
            loca,
            long_loca: i16_at(data, head + 50)? == 1,
            glyf,
            glyf_len,
            cmap4: cmap4?,
            kern,
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
        self.glyph_of(c as u32).unwrap_or(0)
    }

    fn glyph_of(&self, c: u32) -> Option<u16> {
        if c > 0xFFFF {
            return None;
        }
        let (d, t) = (self.data, self.cmap4);
        let segs = u16_at(d, t + 6)? as usize / 2;
        let ends = t + 14;
        let starts = ends + 2 * segs + 2;
        let deltas = starts + 2 * segs;
        let ranges = deltas + 2 * segs;
        // the first segment whose end is >= c (ends are sorted)
        let (mut lo, mut hi) = (0, segs);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if (u16_at(d, ends + 2 * mid)? as u32) < c {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        let i = lo;
        if i >= segs || (u16_at(d, starts + 2 * i)? as u32) > c {
            return None;
        }
        let delta = u16_at(d, deltas + 2 * i)?;
        let ro = u16_at(d, ranges + 2 * i)? as usize;
        if ro == 0 {
            return Some((c as u16).wrapping_add(delta));
        }
        let start = u16_at(d, starts + 2 * i)? as usize;
        let g = u16_at(d, ranges + 2 * i + ro + 2 * (c as usize - start))?;
        (g != 0).then(|| g.wrapping_add(delta))
    }

    /// The advance width of a glyph, in font units.
    pub fn advance(&self, g: u16) -> f64 {
        let i = g.min(self.n_hmetrics.saturating_sub(1)) as usize;
        u16_at(self.data, self.hmtx + 4 * i).unwrap_or(0) as f64
    }

    /// The kerning between two glyphs, in font units.
    pub fn kern(&self, left: u16, right: u16) -> f64 {
        let Some((pairs, n)) = self.kern else {
            return 0.0;
        };
        let key = ((left as u32) << 16) | right as u32;
        let (mut lo, mut hi) = (0, n);
        while lo < hi {
            let mid = (lo + hi) / 2;
            let Some(k) = u32_at(self.data, pairs + 6 * mid) else {
                return 0.0;
            };
            match k.cmp(&key) {
                std::cmp::Ordering::Less => lo = mid + 1,
                std::cmp::Ordering::Greater => hi = mid,
                std::cmp::Ordering::Equal => {
                    return i16_at(self.data, pairs + 6 * mid + 4).unwrap_or(0) as f64
                }
            }
        }
        0.0
    }

    /// The bytes of a glyph in `glyf` (empty for a glyph without outline).
    fn glyph_data(&self, g: u16) -> Option<&'static [u8]> {
        if g >= self.num_glyphs {
            return None;
        }
        let (d, i) = (self.data, g as usize);
        let (a, b) = if self.long_loca {
            (
                u32_at(d, self.loca + 4 * i)? as usize,
                u32_at(d, self.loca + 4 * i + 4)? as usize,
            )
        } else {
            (
                u16_at(d, self.loca + 2 * i)? as usize * 2,
                u16_at(d, self.loca + 2 * i + 2)? as usize * 2,
            )
        };
        if a > b || b > self.glyf_len {
            return None;
        }
        d.get(self.glyf + a..self.glyf + b)
    }

    /// The outline of a glyph in font units (y up): contours of points `(x, y, on curve)`.
    pub fn outline(&self, g: u16) -> Vec<Vec<(f64, f64, bool)>> {
        let mut out = Vec::new();
        self.outline_into(g, [1.0, 0.0, 0.0, 1.0, 0.0, 0.0], 0, &mut out);
        out
    }

    /// Append glyph `g`'s contours mapped by `m` (`x' = a x + c y + e`, `y' = b x + d y + f`).
    fn outline_into(
        &self,
        g: u16,
        m: [f64; 6],
        depth: u32,
        out: &mut Vec<Vec<(f64, f64, bool)>>,
    ) -> Option<()> {
        let d = self.glyph_data(g)?;
        if d.is_empty() || depth > 8 {
            return Some(());
        }
        let n = i16_at(d, 0)?;
        let map = |x: f64, y: f64| (m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5]);
        if n < 0 {
            // a composite: components each moved (and scaled) by their own matrix
            let mut o = 10;
            loop {
                let flags = u16_at(d, o)?;
                let sub = u16_at(d, o + 2)?;
                o += 4;
                let (dx, dy) = if flags & 1 != 0 {
                    o += 4;
                    (i16_at(d, o - 4)? as f64, i16_at(d, o - 2)? as f64)
                } else {
                    o += 2;
                    (*d.get(o - 2)? as i8 as f64, *d.get(o - 1)? as i8 as f64)
                };
                // point-matched components (flag 2 clear) are placed without an offset
                let (dx, dy) = if flags & 2 != 0 { (dx, dy) } else { (0.0, 0.0) };
                let f2 = |o: usize| i16_at(d, o).map(|v| v as f64 / 16384.0);
                let (a, b, c, dd) = if flags & 0x8 != 0 {
                    o += 2;
                    let s = f2(o - 2)?;
                    (s, 0.0, 0.0, s)
                } else if flags & 0x40 != 0 {
                    o += 4;
                    (f2(o - 4)?, 0.0, 0.0, f2(o - 2)?)
                } else if flags & 0x80 != 0 {
                    o += 8;
                    (f2(o - 8)?, f2(o - 6)?, f2(o - 4)?, f2(o - 2)?)
                } else {
                    (1.0, 0.0, 0.0, 1.0)
                };
                // component matrix, then this glyph's
                let (e, f) = map(dx, dy);
                let sm = [
                    m[0] * a + m[2] * b,
                    m[1] * a + m[3] * b,
                    m[0] * c + m[2] * dd,
                    m[1] * c + m[3] * dd,
                    e,
                    f,
                ];
                self.outline_into(sub, sm, depth + 1, out);
                if flags & 0x20 == 0 {
                    return Some(());
                }
            }
        }
        let n = n as usize;
        let mut ends = Vec::with_capacity(n);
        for i in 0..n {
            ends.push(u16_at(d, 10 + 2 * i)? as usize);
        }
        let points = ends.last().map_or(0, |e| e + 1);
        let mut o = 10 + 2 * n;
        o += 2 + u16_at(d, o)? as usize;
        let mut flags = Vec::with_capacity(points);
        while flags.len() < points {
            let f = *d.get(o)?;
            o += 1;
            flags.push(f);
            if f & 8 != 0 {
                let r = *d.get(o)?;
                o += 1;
                for _ in 0..r {
                    flags.push(f);
                }
            }
        }
        flags.truncate(points);
        let mut coords = |short: u8, same: u8| -> Option<Vec<f64>> {
            let mut v = 0i32;
            let mut out = Vec::with_capacity(points);
            for &f in &flags {
                if f & short != 0 {
                    let b = *d.get(o)? as i32;
                    o += 1;
                    v += if f & same != 0 { b } else { -b };
                } else if f & same == 0 {
                    v += i16_at(d, o)? as i32;
                    o += 2;
                }
                out.push(v as f64);
            }
            Some(out)
        };
        let xs = coords(2, 16)?;
        let ys = coords(4, 32)?;
        let mut start = 0;
        for &e in &ends {
            if e < start || e >= points {
                return None;
            }
            out.push(
                (start..=e)
                    .map(|i| {
                        let (x, y) = map(xs[i], ys[i]);
                        (x, y, flags[i] & 1 != 0)
                    })
                    .collect(),
            );
            start = e + 1;
        }
        Some(())
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
            let dev = |(x, y): (f64, f64)| turn((x0 + (pen + x) * s, baseline - y * s));
            for contour in f.outline(g) {
                contour_segs(&contour, &dev, &mut out);
            }
            pen += f.advance(g);
        }
    }
    out
}

/// A TrueType contour (on- and off-curve points) as segments, mapped by `dev`.
fn contour_segs(c: &[(f64, f64, bool)], dev: &dyn Fn((f64, f64)) -> P, out: &mut Vec<Seg>) {
    let n = c.len();
    if n == 0 {
        return;
    }
    let mid = |a: (f64, f64, bool), b: (f64, f64, bool)| ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
    // start at an on-curve point (or between two off-curve ones)
    let first = c.iter().position(|p| p.2);
    let (start, from) = match first {
        Some(i) => ((c[i].0, c[i].1), i),
        None => (mid(c[n - 1], c[0]), 0),
    };
    out.push(Seg::Move(dev(start)));
    let mut ctrl: Option<(f64, f64)> = None;
    let steps = if first.is_some() { n } else { n + 1 };
    for k in 1..=steps {
        let p = c[(from + k) % n];
        let xy = (p.0, p.1);
        match (p.2, ctrl) {
            (true, None) => out.push(Seg::Line(dev(xy))),
            (true, Some(q)) => {
                out.push(Seg::Quad(dev(q), dev(xy)));
                ctrl = None;
            }
            (false, None) => ctrl = Some(xy),
            (false, Some(q)) => {
                let m = ((q.0 + xy.0) / 2.0, (q.1 + xy.1) / 2.0);
                out.push(Seg::Quad(dev(q), dev(m)));
                ctrl = Some(xy);
            }
        }
    }
    if let Some(q) = ctrl {
        out.push(Seg::Quad(dev(q), dev(start)));
    }
    out.push(Seg::Close);
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
            Seg::Close => s += "Z",
        }
    }
    s
}

/// The pixels a path covers, filled with the non-zero rule and anti-aliased (16 rows of
/// samples per pixel, exact coverage along each row), within a `w` x `h` canvas: `(x, y,
/// coverage in 0..=1)`, in row order.
pub fn raster(segs: &[Seg], (w, h): (u32, u32)) -> Vec<(i32, i32, f64)> {
    // flatten into edges
    let mut edges: Vec<(P, P)> = Vec::new();
    let (mut cur, mut start) = ((0.0, 0.0), (0.0, 0.0));
    for seg in segs {
        match *seg {
            Seg::Move(p) => {
                if cur != start {
                    edges.push((cur, start));
                }
                (cur, start) = (p, p);
            }
            Seg::Line(p) => {
                edges.push((cur, p));
                cur = p;
            }
            Seg::Quad(c, p) => {
                const N: usize = 8;
                let mut a = cur;
                for i in 1..=N {
                    let t = i as f64 / N as f64;
                    let u = 1.0 - t;
                    let b = (
                        u * u * cur.0 + 2.0 * u * t * c.0 + t * t * p.0,
                        u * u * cur.1 + 2.0 * u * t * c.1 + t * t * p.1,
                    );
                    edges.push((a, b));
                    a = b;
                }
                cur = p;
            }
            Seg::Close => {
                if cur != start {
                    edges.push((cur, start));
                }
                cur = start;
            }
        }
    }
    edges.retain(|(a, b)| a.1 != b.1 && [a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()));
    if edges.is_empty() {
        return Vec::new();
    }
    let (mut y0, mut y1, mut x0, mut x1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (a, b) in &edges {
        y0 = y0.min(a.1).min(b.1);
        y1 = y1.max(a.1).max(b.1);
        x0 = x0.min(a.0).min(b.0);
        x1 = x1.max(a.0).max(b.0);
    }
    let clamp = |v: f64, hi: u32| v.clamp(0.0, hi as f64) as i32;
    let (ry0, ry1) = (clamp(y0.floor(), h), clamp(y1.ceil(), h));
    let (cx0, cx1) = (clamp(x0.floor(), w), clamp(x1.ceil(), w));
    if ry0 >= ry1 || cx0 >= cx1 {
        return Vec::new();
    }
    const S: usize = 16;
    let mut out = Vec::new();
    let mut cov = vec![0.0f64; (cx1 - cx0) as usize];
    let mut cross: Vec<(f64, i32)> = Vec::new();
    for py in ry0..ry1 {
        cov.iter_mut().for_each(|c| *c = 0.0);
        for j in 0..S {
            let sy = py as f64 + (j as f64 + 0.5) / S as f64;
            cross.clear();
            for &(a, b) in &edges {
                let (lo, hi, dir) = if a.1 < b.1 { (a, b, 1) } else { (b, a, -1) };
                if lo.1 <= sy && sy < hi.1 {
                    let x = lo.0 + (sy - lo.1) / (hi.1 - lo.1) * (hi.0 - lo.0);
                    cross.push((x, dir));
                }
            }
            cross.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut wind = 0;
            for k in 0..cross.len() {
                wind += cross[k].1;
                if wind == 0 || k + 1 == cross.len() {
                    continue;
                }
                let xa = cross[k].0.max(cx0 as f64);
                let xb = cross[k + 1].0.min(cx1 as f64);
                if xb <= xa {
                    continue;
                }
                let (pa, pb) = (xa.floor() as i32, (xb.ceil() as i32).min(cx1));
                for px in pa..pb {
                    let o = xb.min(px as f64 + 1.0) - xa.max(px as f64);
                    if o > 0.0 {
                        cov[(px - cx0) as usize] += o / S as f64;
                    }
                }
            }
        }
        for (i, &c) in cov.iter().enumerate() {
            if c > 1e-9 {
                out.push((cx0 + i as i32, py, c.min(1.0)));
            }
        }
    }
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
        // a composite glyph (é) has the contours of e and of the accent
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

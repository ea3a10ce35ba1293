//! Drawing a plot with plotters: PNG (the bitmap backend into a buffer, encoded by
//! `output::encode_png`) or SVG. plotters draws the grid, axes and points; every text (title,
//! tick labels, axis names, legend) is laid out here and drawn afterwards from the bundled
//! DejaVu Sans ([`super::font`], `assets/fonts/`, `docs/assets.md`): filled into the PNG's
//! pixels, written into the SVG as paths (no `<text>`, no font family), so the bytes depend on
//! nothing installed and are the same every run. Axes and ticks are [`Axis`]: bounded for any
//! finite data.

use super::axis::{Axis, Scale};
use super::font::{self, Placement};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The family the plots' text styles name: the bundled font, registered with plotters for
/// the layout of its legend.
const FAMILY: &str = "sans-serif";

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (800, 600);

/// The chart's margin, in pixels.
const MARGIN: u32 = 15;

/// From a tick to its label, in pixels.
const TICK_GAP: f64 = 8.0;

/// The title's largest font size (it shrinks, to [`TITLE_MIN`], and wraps to fit).
const TITLE_SIZE: f64 = 20.0;
const TITLE_MIN: f64 = 12.0;
/// Most lines of a title.
const TITLE_LINES: usize = 3;

/// The widest a title's line may be: the canvas within the margins, less a little air.
pub const TITLE_WIDTH: f64 = (SIZE.0 - 2 * MARGIN) as f64 - 10.0;

/// PNG or SVG.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Svg,
}

impl Format {
    /// From a file name's extension (`.png`, `.svg`).
    pub fn of(path: &std::path::Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "png" => Some(Format::Png),
            "svg" => Some(Format::Svg),
            _ => None,
        }
    }
}

/// What to draw: labelled points, those on a Pareto front highlighted.
#[derive(Debug, Clone)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// `(x, y, on the front)`.
    pub points: Vec<(f64, f64, bool)>,
    /// Join the points in x order.
    pub line: bool,
    /// A front was asked for (draw its legend).
    pub pareto: bool,
    /// A value of x or y that stands for "beyond the axis" (the PSNR of identical images,
    /// `metrics::PSNR_CAP_DB`): points at it (or at its negative) are left out of the axis'
    /// range and drawn at its edge as triangles pointing out, when other points are not.
    pub x_cap: Option<f64>,
    pub y_cap: Option<f64>,
    /// The axes' ranges and log scales (points beyond a range drawn at its edge).
    pub x_scale: Scale,
    pub y_scale: Scale,
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FAMILY, FontStyle::Normal, font::FONT_BYTES).is_err() {
            panic!("the bundled font assets/fonts/DejaVuSans.ttf does not parse");
        }
    });
}

/// The figure as PNG or SVG bytes.
pub fn render(fig: &Figure, format: Format) -> Result<Vec<u8>, String> {
    register_font();
    let (w, h) = SIZE;
    match format {
        Format::Png => {
            let mut buf = vec![0u8; (w * h * 3) as usize];
            let texts = {
                let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
                draw(&root, fig)?
            };
            for t in &texts {
                t.fill(&mut buf);
            }
            let img = image::RgbImage::from_raw(w, h, buf).ok_or("a plot buffer of wrong size")?;
            crate::output::encode_png(&img).map_err(|e| format!("cannot encode the PNG: {e}"))
        }
        Format::Svg => {
            let mut s = String::new();
            let texts = {
                let root = SVGBackend::with_string(&mut s, SIZE).into_drawing_area();
                draw(&root, fig)?
            };
            let paths: String = texts.iter().map(Text::svg).collect();
            match s.rfind("</svg>") {
                Some(i) => s.insert_str(i, &paths),
                None => return Err("cannot draw the plot: an SVG without its end".into()),
            }
            Ok(s.into_bytes())
        }
    }
}

/// A text drawn over the chart (after plotters, whose own text is not drawn): in the
/// bundled font's glyphs ([`font`]), filled into the PNG's pixels or as SVG paths.
#[derive(Debug, Clone)]
pub struct Text {
    pub text: String,
    pub size: f64,
    pub at: Placement,
    pub pos: (f64, f64),
    pub rgb: (u8, u8, u8),
}

impl Text {
    fn new(text: &str, size: f64, at: Placement, pos: (f64, f64)) -> Text {
        Text {
            text: text.to_string(),
            size,
            at,
            pos,
            rgb: (0, 0, 0),
        }
    }

    /// The glyphs blended into an RGB buffer of [`SIZE`].
    fn fill(&self, buf: &mut [u8]) {
        let segs = font::text_path(&self.text, self.size, self.at, self.pos);
        for (x, y, c) in font::raster(&segs, SIZE) {
            let i = 3 * (y as usize * SIZE.0 as usize + x as usize);
            for (k, v) in [self.rgb.0, self.rgb.1, self.rgb.2].into_iter().enumerate() {
                let old = buf[i + k] as f64;
                buf[i + k] = (old + (v as f64 - old) * c).round().clamp(0.0, 255.0) as u8;
            }
        }
    }

    /// The glyphs as an SVG `<path>` (nothing for a text without ink).
    fn svg(&self) -> String {
        let segs = font::text_path(&self.text, self.size, self.at, self.pos);
        if segs.is_empty() {
            return String::new();
        }
        let (r, g, b) = self.rgb;
        // the text itself, for search and screen readers
        let label: String = self
            .text
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let label = label
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;");
        format!(
            "<path aria-label=\"{label}\" d=\"{}\" fill=\"#{r:02X}{g:02X}{b:02X}\"/>\n",
            font::svg_path(&segs)
        )
    }
}

/// A title fitted to [`TITLE_WIDTH`]: wrapped at spaces (a word too long for a line broken
/// where it must), at the largest size from `TITLE_SIZE` down to `TITLE_MIN` that needs
/// at most `TITLE_LINES` lines; beyond that, cut with "…". The lines joined by `\n`, and
/// the size.
pub fn fit_title(title: &str) -> (String, f64) {
    let f = font::font();
    let mut size = TITLE_SIZE;
    loop {
        let lines = wrap(title, size, TITLE_WIDTH, TITLE_LINES + 1);
        if lines.len() <= TITLE_LINES {
            return (lines.join("\n"), size);
        }
        if size <= TITLE_MIN {
            let mut lines = lines;
            lines.truncate(TITLE_LINES);
            let last = lines.pop().unwrap_or_default();
            lines.push(cut(&format!("{last} …"), size, TITLE_WIDTH));
            debug_assert!(lines.iter().all(|l| f.width(l, size) <= TITLE_WIDTH));
            return (lines.join("\n"), size);
        }
        size -= 2.0;
    }
}

/// The longest prefix of `s` (in characters) that fits `max_w`, with "…" if cut.
fn cut(s: &str, size: f64, max_w: f64) -> String {
    let f = font::font();
    if f.width(s, size) <= max_w {
        return s.to_string();
    }
    let chars: Vec<char> = s.chars().collect();
    let fits = |n: usize| f.width(&(chars[..n].iter().collect::<String>() + "…"), size) <= max_w;
    let (mut lo, mut hi) = (0, chars.len());
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    chars[..lo].iter().collect::<String>() + "…"
}

/// Greedy line breaking of `s` at spaces to `max_w`, a word wider than a line split at the
/// longest prefix that fits (at least one character); stops after `most` lines.
fn wrap(s: &str, size: f64, max_w: f64, most: usize) -> Vec<String> {
    let f = font::font();
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    for word in s.split(' ').filter(|w| !w.is_empty()) {
        if lines.len() >= most {
            break;
        }
        let joined = if cur.is_empty() {
            word.to_string()
        } else {
            format!("{cur} {word}")
        };
        if f.width(&joined, size) <= max_w {
            cur = joined;
            continue;
        }
        if !cur.is_empty() {
            lines.push(std::mem::take(&mut cur));
        }
        let mut rest: Vec<char> = word.chars().collect();
        while f.width(&rest.iter().collect::<String>(), size) > max_w && lines.len() < most {
            // the longest prefix that fits, by bisection
            let (mut lo, mut hi) = (1, rest.len());
            while lo < hi {
                let mid = (lo + hi).div_ceil(2);
                if f.width(&rest[..mid].iter().collect::<String>(), size) <= max_w {
                    lo = mid;
                } else {
                    hi = mid - 1;
                }
            }
            lines.push(rest[..lo].iter().collect());
            rest.drain(..lo);
        }
        cur = rest.into_iter().collect();
    }
    if !cur.is_empty() && lines.len() < most {
        lines.push(cur);
    }
    lines
}

/// A font size at most `size` at which `text` fits `max_w` (not below 6 px; "…"-cut there).
fn fit_line(text: &str, size: f64, max_w: f64) -> (String, f64) {
    let w = font::font().width(text, size);
    if w <= max_w {
        return (text.to_string(), size);
    }
    let s = (size * max_w / w).floor().max(6.0);
    (cut(text, s, max_w), s)
}

/// How many points are at a cap the axes leave out, or beyond a range (drawn at their
/// edge): `(capped, beyond)`.
pub fn edge_points(fig: &Figure) -> (usize, usize) {
    let (xa, x_out) = axis_of(fig.points.iter().map(|p| p.0), fig.x_cap, fig.x_scale);
    let (ya, y_out) = axis_of(fig.points.iter().map(|p| p.1), fig.y_cap, fig.y_scale);
    let capped = |p: &&(f64, f64, bool)| {
        (x_out && capped(p.0, fig.x_cap)) || (y_out && capped(p.1, fig.y_cap))
    };
    let n_capped = fig.points.iter().filter(capped).count();
    let beyond = fig
        .points
        .iter()
        .filter(|p| !capped(p))
        .filter(|p| place(p.0, &xa, false, None).1 != 0 || place(p.1, &ya, false, None).1 != 0)
        .count();
    (n_capped, beyond)
}

/// Whether `v` is at the cap (or its negative).
fn capped(v: f64, cap: Option<f64>) -> bool {
    cap.is_some_and(|c| v.abs() == c)
}

/// The axis of values `vs` laid out by `scale`, those at `cap` left out when others are not;
/// and whether any was left out.
fn axis_of(vs: impl Iterator<Item = f64> + Clone, cap: Option<f64>, scale: Scale) -> (Axis, bool) {
    let range = |it: &mut dyn Iterator<Item = f64>| {
        it.fold(None, |r: Option<(f64, f64)>, v| {
            Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
        })
    };
    let uncapped = range(&mut vs.clone().filter(|v| !capped(*v, cap)));
    let left_out = uncapped.is_some() && vs.clone().any(|v| capped(v, cap));
    let (lo, hi) = uncapped
        .or_else(|| range(&mut vs.clone()))
        .unwrap_or((1.0, 10.0));
    (Axis::of(scale, lo, hi), left_out)
}

/// A point's place on the axis: `v`, or for a capped one or one beyond the axis' range the
/// end it is beyond, and the way out (-1 below, +1 above, 0 on the axis).
fn place(v: f64, axis: &Axis, left_out: bool, cap: Option<f64>) -> (f64, i32) {
    let (lo, hi) = axis.ends();
    match left_out && capped(v, cap) {
        true if v > 0.0 => (hi, 1),
        true => (lo, -1),
        false if v > hi => (hi, 1),
        false if v < lo => (lo, -1),
        false => (v, 0),
    }
}

/// A triangle of radius `r` pointing along `(dx, dy)` (pixels, y down).
fn triangle(dx: i32, dy: i32, r: i32) -> Vec<(i32, i32)> {
    let (dx, dy) = (dx as f64, dy as f64);
    let r = r as f64;
    let tip = (dx * r * 1.2, dy * r * 1.2);
    let base = (-dx * r * 0.6, -dy * r * 0.6);
    let side = (-dy * r, dx * r);
    [
        tip,
        (base.0 + side.0, base.1 + side.1),
        (base.0 - side.0, base.1 - side.1),
    ]
    .iter()
    .map(|p| (p.0.round() as i32, p.1.round() as i32))
    .collect()
}

/// A point as drawn: where, its way out of the axes (for a capped one), on the front.
type Shown = ((f64, f64), (i32, i32), bool);

/// A legend entry's marker.
#[derive(Debug, Clone, Copy)]
enum Marker {
    Dot(u32, RGBColor),
    Up(RGBColor),
}

/// Draw the chart (no text) into `root`; the texts to draw over it.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
) -> Result<Vec<Text>, String> {
    let err = |e: &dyn std::fmt::Display| format!("cannot draw the plot: {e}");
    let f = font::font();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (xa, x_out) = axis_of(fig.points.iter().map(|p| p.0), fig.x_cap, fig.x_scale);
    let (ya, y_out) = axis_of(fig.points.iter().map(|p| p.1), fig.y_cap, fig.y_scale);
    // each point where it is drawn, its way out (for a capped one) and whether on the front
    let shown: Vec<Shown> = fig
        .points
        .iter()
        .map(|&(x, y, f)| {
            let (px, ox) = place(x, &xa, x_out, fig.x_cap);
            let (py, oy) = place(y, &ya, y_out, fig.y_cap);
            ((px, py), (ox, oy), f)
        })
        .collect();

    // the layout: title, then the chart with room for the labels and the axes' names
    let top = |h: f64, v: f64| Placement {
        h,
        v,
        quarter_turns: 0,
    };
    let mut texts = Vec::new();
    let (title, title_size) = fit_title(&fig.title);
    let title_h = f.text_size(&title, title_size).1;
    texts.push(Text::new(
        &title,
        title_size,
        top(0.5, 0.0),
        (SIZE.0 as f64 / 2.0, 8.0),
    ));
    let (label_size, desc_size) = (13.0, 15.0);
    let y_labels: Vec<String> = ya.ticks().iter().map(|t| ya.label(*t)).collect();
    let widest = y_labels
        .iter()
        .map(|l| f.width(l, label_size))
        .fold(0.0, f64::max);
    let desc_h = f.line_height(desc_size);
    // y label area: the name, a gap, the widest tick label, the tick's gap
    let y_area = (desc_h + 6.0 + widest + TICK_GAP).ceil().clamp(40.0, 300.0) as u32;
    let x_area = 45u32;
    let mut chart = ChartBuilder::on(root)
        .margin(MARGIN)
        .margin_top(MARGIN + title_h.ceil() as u32 + 6)
        .x_label_area_size(x_area)
        .y_label_area_size(y_area)
        .build_cartesian_2d(xa.clone(), ya.clone())
        .map_err(|e| err(&e))?;
    let hidden = (FAMILY, label_size).into_font().color(&TRANSPARENT);
    chart
        .configure_mesh()
        .x_labels(xa.ticks().len())
        .y_labels(ya.ticks().len())
        .label_style(hidden)
        .draw()
        .map_err(|e| err(&e))?;
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (x0, x1, y0, y1) = (
        xr.start as f64,
        xr.end as f64,
        yr.start as f64,
        yr.end as f64,
    );
    let (xlo, _) = xa.ends();
    let (ylo, _) = ya.ends();
    // every k-th x label, the smallest k at which neighbours keep a gap between them (long
    // labels such as "1.2345e-5" would overlap at every tick)
    let x_labels: Vec<(f64, String)> = xa
        .ticks()
        .iter()
        .map(|t| (chart.backend_coord(&(*t, ylo)).0 as f64, xa.label(*t)))
        .collect();
    let fits = |k: usize| {
        let kept: Vec<&(f64, String)> = x_labels.iter().step_by(k).collect();
        kept.windows(2).all(|w| {
            let half = |l: &str| f.width(l, label_size) / 2.0;
            w[1].0 - w[0].0 >= half(&w[0].1) + half(&w[1].1) + 8.0
        })
    };
    let every = (1..=x_labels.len().max(1)).find(|&k| fits(k)).unwrap_or(1);
    for (px, label) in x_labels.iter().step_by(every) {
        texts.push(Text::new(
            label,
            label_size,
            top(0.5, 0.0),
            (*px, y1 + TICK_GAP),
        ));
    }
    for (t, l) in ya.ticks().iter().zip(&y_labels) {
        let (_, py) = chart.backend_coord(&(xlo, *t));
        let pos = (x0 - TICK_GAP, py as f64);
        texts.push(Text::new(l, label_size, top(1.0, 0.5), pos));
    }
    let (x_desc, xs) = fit_line(&fig.x_label, desc_size, x1 - x0);
    let pos = ((x0 + x1) / 2.0, y1 + x_area as f64 - 2.0);
    texts.push(Text::new(&x_desc, xs, top(0.5, 1.0), pos));
    let (y_desc, ys) = fit_line(&fig.y_label, desc_size, y1 - y0);
    let up = Placement {
        h: 0.5,
        v: 0.0,
        quarter_turns: 3,
    };
    let pos = (x0 - y_area as f64 + 2.0, (y0 + y1) / 2.0);
    texts.push(Text::new(&y_desc, ys, up, pos));

    // the points
    let blue = RGBColor(31, 119, 180);
    let red = RGBColor(214, 39, 40);
    if fig.line {
        let mut line: Vec<(f64, f64)> = shown.iter().map(|s| s.0).collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        chart
            .draw_series(LineSeries::new(line, blue.stroke_width(2)))
            .map_err(|e| err(&e))?;
    }
    // a capped point's triangle points out along y if it is beyond y, else along x
    let out_dir = |o: (i32, i32)| if o.1 != 0 { (0, -o.1) } else { (o.0, 0) };
    chart
        .draw_series(
            shown
                .iter()
                .filter(|s| s.1 == (0, 0))
                .map(|s| Circle::new(s.0, 3, blue.filled())),
        )
        .map_err(|e| err(&e))?;
    chart
        .draw_series(shown.iter().filter(|s| s.1 != (0, 0)).map(|s| {
            let (dx, dy) = out_dir(s.1);
            EmptyElement::at(s.0) + Polygon::new(triangle(dx, dy, 5), blue.filled())
        }))
        .map_err(|e| err(&e))?;
    let mut legend: Vec<(Marker, String)> = Vec::new();
    if fig.pareto {
        legend.push((Marker::Dot(3, blue), "dominated".into()));
        let mut front: Vec<(f64, f64)> = shown.iter().filter(|s| s.2).map(|s| s.0).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        chart
            .draw_series(LineSeries::new(front, red.stroke_width(1)))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                shown
                    .iter()
                    .filter(|s| s.2 && s.1 == (0, 0))
                    .map(|s| Circle::new(s.0, 5, red.filled())),
            )
            .map_err(|e| err(&e))?;
        chart
            .draw_series(shown.iter().filter(|s| s.2 && s.1 != (0, 0)).map(|s| {
                let (dx, dy) = out_dir(s.1);
                EmptyElement::at(s.0) + Polygon::new(triangle(dx, dy, 7), red.filled())
            }))
            .map_err(|e| err(&e))?;
        legend.push((Marker::Dot(5, red), "Pareto front".into()));
    }
    let (capped_n, beyond_n) = edge_points(fig);
    if capped_n > 0 {
        let cap = match y_out {
            true => fig.y_cap,
            false => fig.x_cap,
        };
        let cap = cap.map_or(String::new(), |c| format!("{c}"));
        legend.push((
            Marker::Up(blue),
            format!("{capped_n} at the PSNR cap {cap} dB (identical images), at the edge"),
        ));
    }
    if beyond_n > 0 {
        legend.push((
            Marker::Up(blue),
            format!("{beyond_n} beyond the axis' range, at the edge"),
        ));
    }

    // the legend, in the corner of the plot with the fewest points under it
    if !legend.is_empty() {
        let row = 20.0;
        let tw = legend
            .iter()
            .map(|(_, t)| f.width(t, label_size))
            .fold(0.0, f64::max);
        let (bw, bh) = (
            (8.0 + 20.0 + 6.0 + tw + 8.0).ceil(),
            (legend.len() as f64 * row + 8.0).ceil(),
        );
        let pix: Vec<(f64, f64)> = shown
            .iter()
            .map(|s| {
                let (px, py) = chart.backend_coord(&s.0);
                (px as f64, py as f64)
            })
            .collect();
        let corners = [
            (x1 - 10.0 - bw, y0 + 10.0),
            (x0 + 10.0, y0 + 10.0),
            (x1 - 10.0 - bw, y1 - 10.0 - bh),
            (x0 + 10.0, y1 - 10.0 - bh),
        ];
        let under = |&(l, t): &(f64, f64)| {
            pix.iter()
                .filter(|p| {
                    p.0 >= l - 6.0 && p.0 <= l + bw + 6.0 && p.1 >= t - 6.0 && p.1 <= t + bh + 6.0
                })
                .count()
        };
        let (l, t) = corners
            .iter()
            .min_by_key(|c| under(c))
            .copied()
            .unwrap_or(corners[0]);
        let (li, ti) = (l.round() as i32, t.round() as i32);
        let (ri, bi) = (li + bw as i32, ti + bh as i32);
        root.draw(&Rectangle::new(
            [(li, ti), (ri, bi)],
            WHITE.mix(0.8).filled(),
        ))
        .map_err(|e| err(&e))?;
        root.draw(&Rectangle::new([(li, ti), (ri, bi)], BLACK))
            .map_err(|e| err(&e))?;
        for (k, (m, text)) in legend.iter().enumerate() {
            let cy = t + 4.0 + row * (k as f64 + 0.5);
            let c = (li + 18, cy.round() as i32);
            match *m {
                Marker::Dot(r, col) => root.draw(&Circle::new(c, r, col.filled())),
                Marker::Up(col) => root
                    .draw(&(EmptyElement::at(c) + Polygon::new(triangle(0, -1, 5), col.filled()))),
            }
            .map_err(|e| err(&e))?;
            texts.push(Text::new(text, label_size, top(0.0, 0.5), (l + 34.0, cy)));
        }
    }
    root.present().map_err(|e| err(&e))?;
    Ok(texts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_titles_wrap_within_the_canvas() {
        let f = font::font();
        let t = "quantization_psnr_db vs gates_total (front of gates_total:min, \
                 quantization_psnr_db:max, cycles:min)";
        assert!(f.width(t, TITLE_SIZE) > TITLE_WIDTH, "needs wrapping");
        let (lines, size) = fit_title(t);
        assert_eq!(size, TITLE_SIZE);
        let lines: Vec<&str> = lines.split('\n').collect();
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert_eq!(lines.join(" "), t);
        for l in &lines {
            assert!(f.width(l, size) <= TITLE_WIDTH, "{l}: {}", f.width(l, size));
        }
        // a short one stays on one line, at full size
        assert_eq!(fit_title("y vs x"), ("y vs x".to_string(), TITLE_SIZE));
        // one long word is broken; a huge title shrinks, then is cut with "…"
        let word = "x".repeat(300);
        let (w, s) = fit_title(&word);
        assert!(w.split('\n').all(|l| f.width(l, s) <= TITLE_WIDTH), "{w}");
        assert_eq!(w.replace('\n', ""), word);
        let huge = "column_name ".repeat(2000);
        let (h, s) = fit_title(&huge);
        assert_eq!(s, TITLE_MIN);
        let hl: Vec<&str> = h.split('\n').collect();
        assert_eq!(hl.len(), TITLE_LINES);
        assert!(hl[2].ends_with('…'), "{}", hl[2]);
        assert!(hl.iter().all(|l| f.width(l, s) <= TITLE_WIDTH));
    }

    #[test]
    fn capped_values_are_left_out_of_the_range() {
        let ys = [20.0, 30.0, 999.0, 40.0, -999.0];
        let (a, out) = axis_of(ys.iter().copied(), Some(999.0), Scale::default());
        assert!(out);
        let (lo, hi) = a.ends();
        assert!(
            lo < 20.0 && lo > 15.0 && hi > 40.0 && hi < 45.0,
            "{lo} {hi}"
        );
        assert_eq!(place(999.0, &a, out, Some(999.0)), (hi, 1));
        assert_eq!(place(-999.0, &a, out, Some(999.0)), (lo, -1));
        assert_eq!(place(30.0, &a, out, Some(999.0)), (30.0, 0));
        // all at the cap, or no cap: nothing is left out
        let (a, out) = axis_of([999.0, 999.0].into_iter(), Some(999.0), Scale::default());
        assert!(!out && a.ends().0 < 999.0 && a.ends().1 > 999.0);
        let (a, out) = axis_of(ys.iter().copied(), None, Scale::default());
        assert!(!out && a.ends().1 > 999.0);
        assert_eq!(triangle(0, -1, 5), [(0, -6), (5, 3), (-5, 3)]);
        assert_eq!(triangle(1, 0, 5), [(6, 0), (-3, 5), (-3, -5)]);
    }
}

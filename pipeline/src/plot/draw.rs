//! Drawing a plot with plotters: PNG (the bitmap backend into a buffer, encoded by
//! `output::encode_png`) or SVG, text in the bundled DejaVu Sans (`assets/fonts/`,
//! `docs/assets.md`), so the bytes depend on nothing installed and are the same every run.

use plotters::coord::Shift;
use plotters::prelude::*;

/// DejaVu Sans (fonts-dejavu-core 2.37, Bitstream Vera licence; `docs/assets.md`).
static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// The family every text of a plot uses.
const FAMILY: &str = "sans-serif";

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (800, 600);

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
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_err() {
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
            {
                let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
                draw(&root, fig)?;
            }
            let img = image::RgbImage::from_raw(w, h, buf).ok_or("a plot buffer of wrong size")?;
            crate::output::encode_png(&img).map_err(|e| format!("cannot encode the PNG: {e}"))
        }
        Format::Svg => {
            let mut s = String::new();
            {
                let root = SVGBackend::with_string(&mut s, SIZE).into_drawing_area();
                draw(&root, fig)?;
            }
            Ok(s.into_bytes())
        }
    }
}

/// A range around `lo..hi` with a margin (a unit around a single value).
fn padded(lo: f64, hi: f64) -> std::ops::Range<f64> {
    if lo == hi {
        let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.05 };
        return lo - d..hi + d;
    }
    let d = (hi - lo) * 0.05;
    lo - d..hi + d
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("cannot draw the plot: {e}");
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y, _) in &fig.points {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if fig.points.is_empty() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let mut chart = ChartBuilder::on(root)
        .caption(&fig.title, (FAMILY, 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(padded(x0, x1), padded(y0, y1))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(&fig.x_label)
        .y_desc(&fig.y_label)
        .label_style((FAMILY, 13))
        .axis_desc_style((FAMILY, 15))
        .draw()
        .map_err(|e| err(&e))?;
    let blue = RGBColor(31, 119, 180);
    let red = RGBColor(214, 39, 40);
    if fig.line {
        let mut line: Vec<(f64, f64)> = fig.points.iter().map(|&(x, y, _)| (x, y)).collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        chart
            .draw_series(LineSeries::new(line, blue.stroke_width(2)))
            .map_err(|e| err(&e))?;
    }
    let all = chart
        .draw_series(
            fig.points
                .iter()
                .map(|&(x, y, _)| Circle::new((x, y), 3, blue.filled())),
        )
        .map_err(|e| err(&e))?;
    if fig.pareto {
        all.label("dominated")
            .legend(move |(x, y)| Circle::new((x, y), 3, blue.filled()));
        let mut front: Vec<(f64, f64)> = fig
            .points
            .iter()
            .filter(|p| p.2)
            .map(|&(x, y, _)| (x, y))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        chart
            .draw_series(LineSeries::new(front.clone(), red.stroke_width(1)))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                front
                    .iter()
                    .map(|&(x, y)| Circle::new((x, y), 5, red.filled())),
            )
            .map_err(|e| err(&e))?
            .label("Pareto front")
            .legend(move |(x, y)| Circle::new((x, y), 5, red.filled()));
        chart
            .configure_series_labels()
            .label_font((FAMILY, 13))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))
}

//! A plot's axis: its range (the data's with a margin) and its ticks, computed here rather
//! than by plotters' own `f64` ranges, whose tick search never ends on a range that
//! overflows to infinity (1e308 and -1e308 in one column) and can loop on ones narrower than
//! the values' precision. Every step here is bounded: at most [`MAX_TICKS`] ticks at 1, 2 or
//! 5 times a power of ten, each formatted with the decimals its step needs (no ".0" on
//! whole numbers), in scientific notation beyond 1e7 or below 1e-3.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};

/// Most ticks on an axis (and light grid lines between two ticks).
pub const MAX_TICKS: usize = 12;

/// How an axis is laid out: its range (default: the data's, with a margin) and whether it
/// is logarithmic (a sweep file's plot `x_scale`, `y_scale`; `bumpsim plot --x-range`,
/// `--x-log`, ...).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scale {
    /// The axis' ends, exactly (finite, `lo < hi`, both above 0 on a log axis); points
    /// beyond them are drawn at the edge as triangles pointing out.
    #[serde(default)]
    pub range: Option<(f64, f64)>,
    /// Logarithmic (base 10): rows whose value is not above 0 are left out and counted.
    #[serde(default)]
    pub log: bool,
}

impl Scale {
    /// Check the range (`what`: the field in messages is the caller's).
    pub fn check(&self) -> Result<(), String> {
        if let Some((lo, hi)) = self.range {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(format!(
                    "({lo}, {hi}): expected finite ends, the first below the second"
                ));
            }
            if self.log && lo <= 0.0 {
                return Err(format!("({lo}, {hi}): a log axis' ends must be above 0"));
            }
        }
        Ok(())
    }
}

/// An axis from `lo` to `hi` (finite, `lo < hi`; their log10 on a log axis) with its ticks.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    lo: f64,
    hi: f64,
    /// The labelled ticks and the grid's light lines, as data values.
    ticks: Vec<f64>,
    minor: Vec<f64>,
    /// The ticks' step as `m 10^e` (None: the ticks are the range's ends, or decades).
    step: Option<(f64, i32)>,
    log: bool,
}

/// `m 10^e` with `m` 1, 2 or 5, the smallest at least `raw` (> 0, finite).
fn nice(raw: f64) -> Option<(f64, i32)> {
    let e = raw.log10().floor();
    if !e.is_finite() {
        return None;
    }
    let e = e as i32;
    let p = 10f64.powi(e);
    let f = raw / p;
    let (m, e) = if f <= 1.0 {
        (1.0, e)
    } else if f <= 2.0 {
        (2.0, e)
    } else if f <= 5.0 {
        (5.0, e)
    } else {
        (1.0, e + 1)
    };
    let step = m * 10f64.powi(e);
    (step.is_finite() && step > 0.0).then_some((m, e))
}

/// The multiples of `step` in `lo..=hi` (None if more than `most`).
fn multiples(lo: f64, hi: f64, step: f64, most: usize) -> Option<Vec<f64>> {
    let (k0, k1) = ((lo / step).ceil(), (hi / step).floor());
    let n = k1 - k0;
    if !(n >= 0.0 && n < most as f64) {
        return None;
    }
    let mut v: Vec<f64> = (0..=n as usize)
        .map(|i| {
            let t = (k0 + i as f64) * step;
            if t == 0.0 {
                0.0
            } else {
                t
            }
        })
        .filter(|t| *t >= lo && *t <= hi)
        .collect();
    v.dedup();
    Some(v)
}

impl Axis {
    /// The axis of data from `min` to `max` (finite, `min <= max`): 5% of the span added on
    /// each side (5% of the value around a single value, 1 around zero), within ±`f64::MAX`.
    pub fn new(min: f64, max: f64) -> Axis {
        let (min, max) = match min.is_finite() && max.is_finite() {
            true => (min.min(max), max.max(min)),
            false => (0.0, 1.0),
        };
        let clamp = |v: f64| v.clamp(-f64::MAX, f64::MAX);
        let (mut lo, mut hi) = if min < max {
            // in halves: the span of ±1e308 is beyond f64
            let d = (max / 2.0 - min / 2.0) * 0.1;
            (clamp(min - d), clamp(max + d))
        } else {
            let d = min.abs() * 0.05;
            (clamp(min - d), clamp(max + d))
        };
        if lo >= hi {
            (lo, hi) = (min - 1.0, max + 1.0);
        }
        Axis::linear(lo, hi)
    }

    /// The axis of `scale` for data from `min` to `max` (finite; above 0 on a log axis).
    pub fn of(scale: Scale, min: f64, max: f64) -> Axis {
        match (scale.range, scale.log) {
            (Some((lo, hi)), false) => Axis::linear(lo, hi),
            (Some((lo, hi)), true) => Axis::decades(lo.log10(), hi.log10()),
            (None, false) => Axis::new(min, max),
            (None, true) => {
                let pos = |v: f64| if v > 0.0 { v } else { f64::MIN_POSITIVE };
                let l = Axis::new(pos(min).log10(), pos(max).log10());
                Axis::decades(l.lo, l.hi)
            }
        }
    }

    /// A log axis from `10^lo` to `10^hi`: ticks at the decades if two or more fall in it
    /// (every k-th when more than [`MAX_TICKS`]), light lines at 2..9 times them; else at 1,
    /// 2 and 5 times the powers of ten in it; else the ends.
    fn decades(lo: f64, hi: f64) -> Axis {
        let lo = lo.clamp(-307.0, 308.0);
        let hi = hi.clamp(lo, 308.0);
        let hi = if hi > lo { hi } else { lo + 1.0 };
        let (k0, k1) = (lo.ceil() as i32, hi.floor() as i32);
        let inside = |v: f64| {
            let l = v.log10();
            l >= lo - 1e-12 && l <= hi + 1e-12
        };
        let mut a = Axis {
            lo,
            hi,
            ticks: vec![10f64.powf(lo), 10f64.powf(hi)],
            minor: vec![10f64.powf(lo), 10f64.powf(hi)],
            step: None,
            log: true,
        };
        let n = k1 - k0 + 1;
        if n >= 2 {
            let every = (n as usize).div_ceil(MAX_TICKS - 1).max(1);
            a.ticks = (k0..=k1).step_by(every).map(|k| 10f64.powi(k)).collect();
            if every == 1 && n as usize <= MAX_TICKS {
                a.minor = (k0 - 1..=k1)
                    .flat_map(|k| (1..10).map(move |m| m as f64 * 10f64.powi(k)))
                    .filter(|v| inside(*v))
                    .collect();
            } else {
                a.minor = a.ticks.clone();
            }
            return a;
        }
        let nice: Vec<f64> = (k0 - 1..=k1)
            .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
            .filter(|v| inside(*v))
            .collect();
        if nice.len() >= 2 {
            a.ticks = nice.clone();
            a.minor = nice;
        }
        a
    }

    /// A linear axis from `lo` to `hi` exactly, with its ticks.
    fn linear(lo: f64, hi: f64) -> Axis {
        let mut a = Axis {
            lo,
            hi,
            ticks: vec![lo, hi],
            minor: vec![lo, hi],
            step: None,
            log: false,
        };
        // a step of at least a tenth of the span: 11 ticks at most
        let Some((m, e)) = nice((hi / 2.0 - lo / 2.0) / 5.0) else {
            return a;
        };
        let step = m * 10f64.powi(e);
        let Some(ticks) = multiples(lo, hi, step, MAX_TICKS) else {
            return a;
        };
        if ticks.len() < 2 {
            // the span is below the values' precision
            return a;
        }
        let sub = if m == 2.0 { 4.0 } else { 5.0 };
        a.minor = multiples(lo, hi, step / sub, MAX_TICKS * 6).unwrap_or_else(|| ticks.clone());
        a.ticks = ticks;
        a.step = Some((m, e));
        a
    }

    /// The axis' ends (data values).
    pub fn ends(&self) -> (f64, f64) {
        match self.log {
            true => (10f64.powf(self.lo), 10f64.powf(self.hi)),
            false => (self.lo, self.hi),
        }
    }

    /// Whether the axis is logarithmic.
    pub fn is_log(&self) -> bool {
        self.log
    }

    /// The values of the labelled ticks, in order.
    pub fn ticks(&self) -> &[f64] {
        &self.ticks
    }

    /// A tick's label: the decimals the step needs, trailing zeros dropped ("18000", "0.25",
    /// "1.5e9").
    pub fn label(&self, v: f64) -> String {
        if self.log {
            // a tick of a log axis: its significant digits (1, 2, 5 times a power of ten)
            let e = v.log10().floor() as i32;
            return match (-3..7).contains(&e) {
                true => {
                    let d = (-e).clamp(0, 17) as usize;
                    let s = format!("{v:.d$}");
                    match s.contains('.') {
                        true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
                        false => s,
                    }
                }
                false => {
                    let m = (v / 10f64.powi(e)).round();
                    format!("{m}e{e}")
                }
            };
        }
        let big = self.lo.abs().max(self.hi.abs());
        let Some((_, e)) = self.step else {
            // the range's ends: the shortest decimal that reads back
            return match (1e-3..1e7).contains(&big) {
                true => format!("{v}"),
                false => format!("{v:e}"),
            };
        };
        let trim = |s: String| -> String {
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            }
        };
        if v == 0.0 {
            return "0".to_string();
        }
        let s = if !(1e-3..1e7).contains(&big) {
            // digits enough to tell ticks apart at this magnitude
            let digits = (big.log10().floor() as i32 - e).clamp(0, 16) as usize;
            let s = format!("{v:.digits$e}");
            match s.split_once('e') {
                Some((mant, exp)) => format!("{}e{exp}", trim(mant.to_string())),
                None => s,
            }
        } else {
            let d = (-e).clamp(0, 17) as usize;
            trim(format!("{v:.d$}"))
        };
        if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
            s[1..].to_string()
        } else {
            s
        }
    }

    /// Where `v` falls in `0..=1` along the axis (outside for values beyond its ends).
    pub fn fraction(&self, v: f64) -> f64 {
        let v = match self.log {
            true => v.max(f64::MIN_POSITIVE).log10(),
            false => v,
        };
        (v / 2.0 - self.lo / 2.0) / (self.hi / 2.0 - self.lo / 2.0)
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let px = limit.0 as f64 + self.fraction(*v) * (limit.1 as f64 - limit.0 as f64);
        // saturating; a NaN (never passed) is 0
        px.round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let v = if hint.weight().allow_light_points() {
            &self.minor
        } else {
            &self.ticks
        };
        v.iter()
            .take(hint.max_num_points().max(2))
            .copied()
            .collect()
    }

    fn range(&self) -> std::ops::Range<f64> {
        let (lo, hi) = self.ends();
        lo..hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, v: &f64) -> String {
        self.label(*v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(a: &Axis) -> Vec<String> {
        a.ticks().iter().map(|t| a.label(*t)).collect()
    }

    #[test]
    fn whole_ticks_have_no_decimal_point() {
        let a = Axis::new(16.0, 16384.0);
        assert_eq!(
            labels(&a),
            ["0", "2000", "4000", "6000", "8000", "10000", "12000", "14000", "16000"]
        );
        let a = Axis::new(0.0, 1.0);
        assert_eq!(
            labels(&a),
            ["0", "0.2", "0.4", "0.6", "0.8", "1"],
            "{:?}",
            a.ticks()
        );
        let a = Axis::new(-3.0, 3.0);
        assert_eq!(labels(&a), ["-3", "-2", "-1", "0", "1", "2", "3"]);
        let a = Axis::new(1.5e9, 2.5e9);
        assert_eq!(labels(&a), ["1.6e9", "1.8e9", "2e9", "2.2e9", "2.4e9"]);
        assert!(
            labels(&a).contains(&"1.6e9".to_string()),
            "{:?}",
            labels(&a)
        );
        let a = Axis::new(0.0001, 0.0004);
        assert_eq!(
            labels(&a),
            ["1e-4", "1.5e-4", "2e-4", "2.5e-4", "3e-4", "3.5e-4", "4e-4"]
        );
    }

    /// Ranges that plotters' own search never finished or that have no width: each gives a
    /// finite axis with at most MAX_TICKS distinct ticks.
    #[test]
    fn extreme_ranges_give_bounded_axes() {
        for (min, max) in [
            (-1e308, 1e308),
            (-f64::MAX, f64::MAX),
            (f64::MAX, f64::MAX),
            (-f64::MAX, -f64::MAX),
            (0.0, 0.0),
            (5.0, 5.0),
            (-7.5, -7.5),
            (1e15, 1e15 + 0.125),
            (1e300, 1e300),
            (5e-324, 5e-324),
            (5e-324, 1e-323),
            (0.0, f64::MIN_POSITIVE),
            (1.0, 1.0 + f64::EPSILON),
        ] {
            let a = Axis::new(min, max);
            let (lo, hi) = a.ends();
            assert!(
                lo.is_finite() && hi.is_finite() && lo < hi,
                "{min} {max}: {lo} {hi}"
            );
            assert!(lo <= min && hi >= max, "{min} {max}: {lo} {hi}");
            let t = a.ticks();
            assert!(t.len() >= 2 && t.len() <= MAX_TICKS, "{min} {max}: {t:?}");
            assert!(t.windows(2).all(|w| w[0] < w[1]), "{t:?}");
            assert!(t.iter().all(|v| *v >= lo && *v <= hi));
            let f = a.fraction(min);
            assert!((0.0..=1.0).contains(&f), "{min} {max}: {f}");
            assert!(a.map(&max, (0, 700)) <= 700 && a.map(&min, (0, 700)) >= 0);
            for v in t {
                assert!(!a.label(*v).is_empty());
            }
        }
        let a = Axis::new(-1e308, 1e308);
        assert_eq!(labels(&a)[0], "-1e308", "{:?}", labels(&a));
        assert!(labels(&a).contains(&"0".to_string()), "{:?}", labels(&a));
        // a single value sits in the middle
        let a = Axis::new(5.0, 5.0);
        assert_eq!(a.ends(), (4.75, 5.25));
        assert_eq!(Axis::new(0.0, 0.0).ends(), (-1.0, 1.0));
    }

    #[test]
    fn log_axes_tick_decades_or_one_two_five() {
        let log = Scale {
            range: None,
            log: true,
        };
        let a = Axis::of(log, 16.0, 16384.0);
        assert_eq!(labels(&a), ["100", "1000", "10000"]);
        assert!(a.minor.contains(&20.0) && a.minor.contains(&9000.0));
        let a = Axis::of(log, 0.002, 0.009);
        assert_eq!(labels(&a), ["0.002", "0.005"], "{:?}", a.ends());
        let a = Axis::of(log, 1e-30, 1e30);
        assert!(a.ticks().len() <= MAX_TICKS, "{:?}", labels(&a));
        assert!(
            labels(&a).iter().all(|l| l.starts_with("1e") || l == "100"),
            "{:?}",
            labels(&a)
        );
        // a point's place: decades equally spaced
        let a = Axis::of(
            Scale {
                range: Some((1.0, 1000.0)),
                log: true,
            },
            5.0,
            6.0,
        );
        assert_eq!(a.ends(), (1.0, 1000.0));
        assert!((a.fraction(10.0) - 1.0 / 3.0).abs() < 1e-12);
        assert!((a.fraction(100.0) - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(labels(&a), ["1", "10", "100", "1000"]);
        // a fixed linear range is kept exactly, whatever the data
        let lin = Scale {
            range: Some((0.0, 50.0)),
            log: false,
        };
        let a = Axis::of(lin, -1e9, 1e9);
        assert_eq!(a.ends(), (0.0, 50.0));
        assert_eq!(labels(&a)[..3], ["0", "5", "10"]);
        assert_eq!(labels(&a).last().map(String::as_str), Some("50"));
        // bad ranges are refused
        assert!(Scale {
            range: Some((2.0, 1.0)),
            log: false
        }
        .check()
        .is_err());
        assert!(Scale {
            range: Some((0.0, 1.0)),
            log: true
        }
        .check()
        .is_err());
        assert!(Scale {
            range: Some((f64::NAN, 1.0)),
            log: false
        }
        .check()
        .is_err());
        assert!(lin.check().is_ok());
    }
}

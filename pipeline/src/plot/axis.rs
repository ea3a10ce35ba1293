//! A plot's axis: its range (the data's with a margin) and its ticks, computed here rather
//! than by plotters' own `f64` ranges, whose tick search never ends on a range that
//! overflows to infinity (1e308 and -1e308 in one column) and can loop on ones narrower than
//! the values' precision. Every step here is bounded: at most [`MAX_TICKS`] ticks at 1, 2 or
//! 5 times a power of ten, each formatted with the decimals its step needs (no ".0" on
//! whole numbers), in scientific notation beyond 1e7 or below 1e-3.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};

/// Most ticks on an axis (and light grid lines between two ticks).
pub const MAX_TICKS: usize = 12;

/// An axis from `lo` to `hi` (finite, `lo < hi`) with its ticks.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    lo: f64,
    hi: f64,
    ticks: Vec<f64>,
    minor: Vec<f64>,
    /// The ticks' step as `m 10^e` (None: the ticks are the range's ends).
    step: Option<(f64, i32)>,
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
        let mut a = Axis {
            lo,
            hi,
            ticks: vec![lo, hi],
            minor: vec![lo, hi],
            step: None,
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

    /// The axis' ends.
    pub fn ends(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }

    /// The values of the labelled ticks, in order.
    pub fn ticks(&self) -> &[f64] {
        &self.ticks
    }

    /// A tick's label: the decimals the step needs, trailing zeros dropped ("18000", "0.25",
    /// "1.5e9").
    pub fn label(&self, v: f64) -> String {
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
        self.lo..self.hi
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
}

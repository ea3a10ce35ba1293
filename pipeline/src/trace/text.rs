//! The text rendering of a [`Trace`]: a header naming the units, their ports and formats,
//! then one line per unit per cycle in fixed-width columns.
//!
//! ```text
//! # bumpsim trace: 2 units, cycles 0..=5, 12 records
//! # unit dot0 (dot3): in n[3]:s1.15 -> out d0[1]:u1.15
//! # columns: cycle unit state [in#id port=(hex:value,...) ...] [out#id port=(hex:value,...) ...]
//!       0 dot0     busy  in#0 n=(7fff:0.999969,0000:0,c000:-0.5)
//!       2 dot0     busy                                           out#0 d0=(6a0c:0.828491)
//!       3 dot0     stall
//! ```
//!
//! * the cycle is right-aligned in 7 columns, the unit name left-aligned to the longest name
//!   (at least 8 columns), the state (`idle`, `busy`, `stall`) in 5 columns;
//! * the input column (`in#<fragment id>` and the accepted input ports) is padded to its
//!   widest entry for that unit, so the output column lines up per unit; trailing blanks are
//!   trimmed;
//! * a lane is `hex:value`: the raw bits ([`Format::bits`](bumpsim_hw::Format::bits)) zero-padded to
//!   [`Format::hex_digits`](bumpsim_hw::Format::hex_digits), and the lane's real value rounded to 6 significant digits and
//!   printed with `{}` (`-0` prints as `0`); only the port's `lanes` lanes are shown;
//! * a port without a word in the probe prints `name=?`; a record naming a unit the trace
//!   does not have prints as unit `?<index>` with its word counts.
//!
//! The output depends only on the trace (no timestamps, no hash-map order), so it is fit for
//! snapshot tests.

use super::{raw_bits, shown_lanes, Trace, TraceUnit};
use bumpsim_hw::{CycleState, PortSpec, Word};
use std::fmt::Write as _;

/// `x` rounded to `digits` significant decimal digits (non-finite values and zero unchanged).
pub fn round_sig(x: f64, digits: usize) -> f64 {
    if !x.is_finite() || x == 0.0 || digits == 0 {
        return x;
    }
    let s = format!("{:.*e}", digits - 1, x);
    s.parse().unwrap_or(x)
}

/// A lane value as the text trace prints it: 6 significant digits, `{}` formatting, and `0`
/// for both zeros.
pub fn fmt_value(x: f64) -> String {
    let r = round_sig(x, 6);
    if r == 0.0 {
        "0".to_string()
    } else {
        format!("{r}")
    }
}

/// The name of a cycle state as traces print it.
pub fn state_name(s: CycleState) -> &'static str {
    match s {
        CycleState::Idle => "idle",
        CycleState::Busy => "busy",
        CycleState::Stall => "stall",
    }
}

pub(crate) fn port_header(ports: &[PortSpec]) -> String {
    if ports.is_empty() {
        return " -".to_string();
    }
    let mut s = String::new();
    for p in ports {
        let _ = write!(s, " {}[{}]:{}", p.name, p.lanes, p.enc);
    }
    s
}

/// `name=(hex:value,...)` for each port; `name=?` where the probe has no word.
fn port_values(ports: &[PortSpec], words: &[Word]) -> String {
    let mut s = String::new();
    for (i, p) in ports.iter().enumerate() {
        s.push(' ');
        s.push_str(&p.name);
        s.push('=');
        let Some(w) = words.get(i) else {
            s.push('?');
            continue;
        };
        let digits = p.enc.format.hex_digits().max(1);
        s.push('(');
        for (l, lane) in w.lanes.iter().take(shown_lanes(p)).enumerate() {
            if l > 0 {
                s.push(',');
            }
            let bits = raw_bits(&p.enc.format, lane.raw);
            let _ = write!(s, "{bits:0digits$x}:{}", fmt_value(lane.x));
        }
        s.push(')');
    }
    s
}

/// One side of a record: `in#id ports...` or `out#id ports...`, empty when nothing moved.
fn side(
    tag: &str,
    unit: Option<&TraceUnit>,
    moved: &Option<(u64, Vec<Word>)>,
    input: bool,
) -> String {
    let Some((id, words)) = moved else {
        return String::new();
    };
    match unit {
        Some(u) => {
            let ports = if input { &u.inputs } else { &u.outputs };
            format!("{tag}#{id}{}", port_values(ports, words))
        }
        None => format!("{tag}#{id} [{} words]", words.len()),
    }
}

impl Trace {
    /// The text rendering described in the module documentation.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let span = match self.cycle_span() {
            Some((lo, hi)) => format!("cycles {lo}..={hi}"),
            None => "no cycles".to_string(),
        };
        let _ = writeln!(
            out,
            "# bumpsim trace: {} units, {span}, {} records",
            self.units.len(),
            self.records.len()
        );
        for u in &self.units {
            let _ = writeln!(
                out,
                "# unit {} ({}): in{} -> out{}",
                u.name,
                u.kind,
                port_header(&u.inputs),
                port_header(&u.outputs)
            );
        }
        out.push_str(
            "# columns: cycle unit state [in#id port=(hex:value,...) ...] \
             [out#id port=(hex:value,...) ...]\n",
        );

        let order = self.ordered();
        let lines: Vec<(usize, String, String, String)> = order
            .iter()
            .map(|&i| {
                let (u, p) = &self.records[i];
                let unit = self.units.get(*u);
                let name = match unit {
                    Some(t) => t.name.clone(),
                    None => format!("?{u}"),
                };
                let ins = side("in", unit, &p.accepted, true);
                let outs = side("out", unit, &p.emitted, false);
                (*u, name, ins, outs)
            })
            .collect();
        let name_w = lines
            .iter()
            .map(|l| l.1.chars().count())
            .chain([8])
            .max()
            .unwrap_or(8);
        // Input column width per unit index (records may name unknown indices: use a map
        // keyed by index, ordered, so the result never depends on hashing).
        let mut in_w = std::collections::BTreeMap::<usize, usize>::new();
        for (u, _, ins, _) in &lines {
            let w = in_w.entry(*u).or_insert(0);
            *w = (*w).max(ins.chars().count());
        }
        for (k, &i) in order.iter().enumerate() {
            let (u, name, ins, outs) = &lines[k];
            let p = &self.records[i].1;
            let iw = in_w.get(u).copied().unwrap_or(0);
            let line = format!(
                "{:>7} {:<name_w$} {:<5} {:<iw$}  {}",
                p.cycle,
                name,
                state_name(p.state),
                ins,
                outs
            );
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::tests::sample_trace;

    #[test]
    fn values_are_rounded_to_six_significant_digits() {
        assert_eq!(fmt_value(32767.0 / 32768.0), "0.999969");
        assert_eq!(fmt_value(27148.0 / 32768.0), "0.828491");
        assert_eq!(fmt_value(180.0 / 255.0), "0.705882");
        assert_eq!(fmt_value(-0.5), "-0.5");
        assert_eq!(fmt_value(-0.0), "0");
        assert_eq!(fmt_value(1.0), "1");
        assert_eq!(fmt_value(1234567.0), "1234570");
        assert_eq!(fmt_value(-3.0517578125e-5), "-0.0000305176");
        assert_eq!(fmt_value(f64::NAN), "NaN");
        assert_eq!(round_sig(0.1 + 0.2, 6), 0.3);
    }

    #[test]
    fn text_trace_matches_the_expected_lines() {
        let t = sample_trace();
        let expected = "\
# bumpsim trace: 2 units, cycles 0..=5, 12 records
# unit dot0 (dot3): in n[3]:s1.15 -> out d0[1]:u1.15
# unit spec0 (pow): in d0[1]:u1.15 -> out s[1]:UnitUnsigned8
# columns: cycle unit state [in#id port=(hex:value,...) ...] [out#id port=(hex:value,...) ...]
      0 dot0     busy  in#0 n=(7fff:0.999969,0000:0,c000:-0.5)
      0 spec0    idle
      1 dot0     busy  in#1 n=(0000:0,4000:0.5,8000:-1)
      1 spec0    idle
      2 dot0     busy                                           out#0 d0=(6a0c:0.828491)
      2 spec0    idle
      3 dot0     stall
      3 spec0    busy  in#0 d0=(6a0c:0.828491)
      4 dot0     busy                                           out#1 d0=(8000:1)
      4 spec0    busy                           out#0 s=(b4:0.705882)
      5 dot0     idle
      5 spec0    busy  in#1 d0=(8000:1)
";
        assert_eq!(t.to_text(), expected);
    }

    #[test]
    fn text_does_not_depend_on_record_order() {
        let t = sample_trace();
        let mut r = t.clone();
        r.records.reverse();
        assert_eq!(r.to_text(), t.to_text());
    }

    #[test]
    fn malformed_records_render_without_panicking() {
        let mut t = sample_trace();
        // a record for a unit that does not exist, and one with a missing port word
        let mut p = t.records[0].1.clone();
        p.cycle = 9;
        t.records.push((7, p.clone()));
        p.accepted.as_mut().unwrap().1.clear();
        t.records.push((0, p));
        let text = t.to_text();
        assert!(text.contains("      9 dot0     busy  in#0 n=?\n"), "{text}");
        assert!(
            text.contains("      9 ?7       busy  in#0 [1 words]\n"),
            "{text}"
        );
    }
}

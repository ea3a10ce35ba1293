//! Cycle traces: what every probed stage did in every cycle, as text and as VCD.
//!
//! A [`Trace`] is a list of units (name, kind and port specs) and one [`Probe`] per unit per
//! cycle: the stage state (idle, busy, stall) and the port values of the token accepted and
//! of the token emitted in that cycle. [`Trace::to_text`] renders it as a stable, diffable
//! text table (used by the snapshot tests) and [`Trace::write_vcd`] as a value change dump
//! for a waveform viewer such as GTKWave. The formats are described in `docs/traces.md`.
//!
//! Rendering never panics: a record that names a unit the trace does not have, or that
//! carries fewer words than the unit has ports, is shown as far as it can be (see the
//! renderers).

pub mod text;
pub mod vcd;

use bumpsim_hw::unit::MAX_LANES;
use bumpsim_hw::{Format, PortSpec, Probe, Stage};
use std::ops::RangeInclusive;

/// A probed unit: its instance name, its kind and its ports.
#[derive(Debug, Clone, PartialEq)]
pub struct TraceUnit {
    /// Instance name in the pipeline, e.g. `dot0`.
    pub name: String,
    /// Unit kind, e.g. `dot3`.
    pub kind: String,
    pub inputs: Vec<PortSpec>,
    pub outputs: Vec<PortSpec>,
}

impl TraceUnit {
    pub fn new(name: &str, kind: &str, inputs: Vec<PortSpec>, outputs: Vec<PortSpec>) -> Self {
        TraceUnit {
            name: name.to_string(),
            kind: kind.to_string(),
            inputs,
            outputs,
        }
    }

    /// The trace description of a stage: its name, its unit's kind and ports.
    pub fn of_stage(stage: &Stage) -> Self {
        let unit = stage.unit();
        TraceUnit {
            name: stage.name.clone(),
            kind: unit.kind().to_string(),
            inputs: unit.inputs().to_vec(),
            outputs: unit.outputs().to_vec(),
        }
    }
}

/// Probes of a set of units over a span of cycles.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    pub units: Vec<TraceUnit>,
    /// `(unit index, probe)`, sorted by cycle then unit index (see [`Trace::sort`]).
    pub records: Vec<(usize, Probe)>,
}

impl Trace {
    /// An empty trace of `units`.
    pub fn new(units: Vec<TraceUnit>) -> Self {
        Trace {
            units,
            records: Vec::new(),
        }
    }

    /// Append the probe of unit `unit`. Call [`Trace::sort`] when the probes were not pushed
    /// in cycle-then-unit order (the simulator ticks stages last to first).
    pub fn push(&mut self, unit: usize, probe: Probe) {
        self.records.push((unit, probe));
    }

    /// Sort the records by cycle, then unit index (stable: equal keys keep their order).
    pub fn sort(&mut self) {
        self.records.sort_by_key(|(u, p)| (p.cycle, *u));
    }

    /// The first and last cycle recorded, if any.
    pub fn cycle_span(&self) -> Option<(u64, u64)> {
        let lo = self.records.iter().map(|(_, p)| p.cycle).min()?;
        let hi = self.records.iter().map(|(_, p)| p.cycle).max()?;
        Some((lo, hi))
    }

    /// Keep only units whose name is in `names` (in the trace's own unit order), with their
    /// records re-indexed. Errors on the first name that is not a unit of the trace, listing
    /// the known ones.
    pub fn select_units(&self, names: &[String]) -> Result<Trace, String> {
        if let Some(bad) = names
            .iter()
            .find(|n| !self.units.iter().any(|u| &u.name == *n))
        {
            let known: Vec<&str> = self.units.iter().map(|u| u.name.as_str()).collect();
            let known = if known.is_empty() {
                "(none)".to_string()
            } else {
                known.join(", ")
            };
            return Err(format!(
                "unknown unit `{bad}` in trace: the known units are {known}"
            ));
        }
        let mut remap = vec![None; self.units.len()];
        let mut units = Vec::new();
        for (i, u) in self.units.iter().enumerate() {
            if names.contains(&u.name) {
                remap[i] = Some(units.len());
                units.push(u.clone());
            }
        }
        let records = self
            .records
            .iter()
            .filter_map(|(u, p)| remap.get(*u).copied().flatten().map(|nu| (nu, p.clone())))
            .collect();
        Ok(Trace { units, records })
    }

    /// Keep only the records whose cycle lies in `cycles`; all units are kept.
    pub fn select_cycles(&self, cycles: RangeInclusive<u64>) -> Trace {
        Trace {
            units: self.units.clone(),
            records: self
                .records
                .iter()
                .filter(|(_, p)| cycles.contains(&p.cycle))
                .cloned()
                .collect(),
        }
    }

    /// Record indices in cycle-then-unit order (stable), whatever order `records` is in.
    pub(crate) fn ordered(&self) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..self.records.len()).collect();
        idx.sort_by_key(|&i| (self.records[i].1.cycle, self.records[i].0));
        idx
    }
}

/// The bits of a raw word as an unsigned pattern of the format's width: `Format::bits` for
/// a valid format, and never a panic for a malformed one (width 0 counts as 1, widths above
/// 64 as 64).
pub(crate) fn raw_bits(f: &Format, raw: i64) -> u64 {
    if (1..=64).contains(&f.width) {
        f.bits(raw)
    } else {
        let w = (f.width as u32).clamp(1, 64);
        (raw as u64) & (u64::MAX >> (64 - w))
    }
}

/// Width of a port lane in bits, clamped to 1..=64.
pub(crate) fn lane_width(p: &PortSpec) -> u32 {
    (p.enc.format.width as u32).clamp(1, 64)
}

/// Number of lanes of a port that are shown: its `lanes`, clamped to 1..=4.
pub(crate) fn shown_lanes(p: &PortSpec) -> usize {
    (p.lanes as usize).clamp(1, MAX_LANES)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use bumpsim_hw::{Codec, CycleState, Encoding, Word};

    /// Two units over cycles 0..=5: `dot0` (dot3, latency 2) takes a signed s1.15 normal and
    /// emits an unsigned u1.15 dot product; `spec0` (pow) takes that and emits an 8-bit
    /// unsigned texel. `dot0` stalls in cycle 3 (its second result is blocked for a cycle).
    pub(crate) fn sample_trace() -> Trace {
        let s115 = Encoding::fixed(Format::s(16, 15));
        let u115 = Encoding::fixed(Format::u(16, 15));
        let u8t = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let dot = TraceUnit::new(
            "dot0",
            "dot3",
            vec![PortSpec::new("n", 3, s115)],
            vec![PortSpec::new("d0", 1, u115)],
        );
        let spec = TraceUnit::new(
            "spec0",
            "pow",
            vec![PortSpec::new("d0", 1, u115)],
            vec![PortSpec::new("s", 1, u8t)],
        );
        let n0 = Word::from_raw(&s115, &[0x7fff, 0, -0x4000]);
        let n1 = Word::from_raw(&s115, &[0, 0x4000, -0x8000]);
        let d_a = Word::from_raw(&u115, &[0x6a0c]);
        let d_b = Word::from_raw(&u115, &[0x8000]);
        let s_a = Word::from_raw(&u8t, &[0xb4]);
        use CycleState::*;
        let probe = |cycle, state, acc: Option<(u64, Word)>, emi: Option<(u64, Word)>| Probe {
            cycle,
            state,
            accepted: acc.map(|(i, w)| (i, vec![w])),
            emitted: emi.map(|(i, w)| (i, vec![w])),
        };
        let mut t = Trace::new(vec![dot, spec]);
        // pushed in simulator order (last stage first), then sorted
        for (d, s) in [
            (
                probe(0, Busy, Some((0, n0)), None),
                probe(0, Idle, None, None),
            ),
            (
                probe(1, Busy, Some((1, n1)), None),
                probe(1, Idle, None, None),
            ),
            (
                probe(2, Busy, None, Some((0, d_a))),
                probe(2, Idle, None, None),
            ),
            (
                probe(3, Stall, None, None),
                probe(3, Busy, Some((0, d_a)), None),
            ),
            (
                probe(4, Busy, None, Some((1, d_b))),
                probe(4, Busy, None, Some((0, s_a))),
            ),
            (
                probe(5, Idle, None, None),
                probe(5, Busy, Some((1, d_b)), None),
            ),
        ] {
            t.push(1, s);
            t.push(0, d);
        }
        t.sort();
        t
    }

    #[test]
    fn sample_trace_is_sorted_by_cycle_then_unit() {
        let t = sample_trace();
        let keys: Vec<(u64, usize)> = t.records.iter().map(|(u, p)| (p.cycle, *u)).collect();
        let mut sorted = keys.clone();
        sorted.sort();
        assert_eq!(keys, sorted);
        assert_eq!(keys.len(), 12);
        assert_eq!(t.cycle_span(), Some((0, 5)));
        // the decoded values are what the text trace prints
        let n = &t.records[0].1.accepted.as_ref().unwrap().1[0];
        assert_eq!(n.lanes[2].x, -0.5);
        assert_eq!(n.lanes[0].x, 32767.0 / 32768.0);
    }

    #[test]
    fn select_units_keeps_the_named_units_and_reindexes() {
        let t = sample_trace();
        let s = t.select_units(&["spec0".to_string()]).unwrap();
        assert_eq!(s.units.len(), 1);
        assert_eq!(s.units[0].name, "spec0");
        assert_eq!(s.records.len(), 6);
        assert!(s.records.iter().all(|(u, _)| *u == 0));
        assert_eq!(s.records[4].1.emitted.as_ref().unwrap().0, 0);
        assert_eq!(
            s.records[4].1.emitted.as_ref().unwrap().1[0].lanes[0].raw,
            0xb4
        );
        // order follows the trace, not the request
        let both = t
            .select_units(&["spec0".to_string(), "dot0".to_string()])
            .unwrap();
        assert_eq!(both, t);
    }

    #[test]
    fn select_units_names_the_unknown_unit() {
        let t = sample_trace();
        let err = t
            .select_units(&["dot0".to_string(), "dot9".to_string()])
            .unwrap_err();
        assert_eq!(
            err,
            "unknown unit `dot9` in trace: the known units are dot0, spec0"
        );
        let err = Trace::default()
            .select_units(&["x".to_string()])
            .unwrap_err();
        assert_eq!(err, "unknown unit `x` in trace: the known units are (none)");
    }

    #[test]
    fn select_cycles_keeps_a_window() {
        let t = sample_trace().select_cycles(2..=3);
        assert_eq!(t.records.len(), 4);
        assert_eq!(t.cycle_span(), Some((2, 3)));
        assert_eq!(t.units.len(), 2);
    }

    #[test]
    fn malformed_formats_do_not_panic() {
        let bad = Format {
            signed: true,
            width: 0,
            frac: 0,
        };
        assert_eq!(raw_bits(&bad, -1), 1);
        let wide = Format {
            signed: true,
            width: 70,
            frac: 0,
        };
        assert_eq!(raw_bits(&wide, -1), u64::MAX);
        assert_eq!(raw_bits(&Format::s(16, 15), -0x4000), 0xc000);
    }
}

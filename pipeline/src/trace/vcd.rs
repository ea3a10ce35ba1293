//! The VCD (value change dump) rendering of a [`Trace`], for GTKWave and other waveform
//! viewers.
//!
//! Layout (timescale 1 ns, one clock period = 2 ns):
//!
//! ```text
//! bumpsim                 top scope
//!   clk                   1 bit: rises at 2*cycle, falls at 2*cycle + 1
//!   cycle                 32 bits: the cycle number (low 32 bits)
//!   <unit>                one scope per unit, named after the unit
//!     state               2 bits: 0 idle, 1 busy, 2 stall
//!     in_valid  in_id     1 bit / 32 bits: a token was accepted, its fragment id
//!     out_valid out_id    1 bit / 32 bits: a token was emitted, its fragment id
//!     <port>_<lane>       port width: raw bits of each lane of each input, then output port
//! ```
//!
//! Every value changes at the rising edge (time `2*cycle`) of the cycle it belongs to.
//! Port lanes change when a token is accepted (inputs) or emitted (outputs) and hold their
//! value in between; they are `x` until the first transfer, ids likewise. `in_valid` and
//! `out_valid` are 1 only in the cycle of the transfer. Clock edges are written only for
//! cycles that have at least one record, so a trace with gaps stays small; in a cycle where a
//! unit has no record its valids are 0 and its state holds.
//!
//! Names are made VCD-safe: any character other than ASCII letters, digits and `_` becomes
//! `_`. A unit scope name already taken gets a suffix `_2`, `_3`, ... A port whose lane
//! wires would clash with wires already in the scope gets the prefix `in_` or `out_` (then
//! a number after the port name if it still clashes): a unit whose output port has the same
//! name as an input port `v` shows `v_0` (input) and `out_v_0`, `out_v_1` (output).

use super::text::port_header;
use super::{lane_width, raw_bits, shown_lanes, Trace};
use ::vcd::{IdCode, SimulationCommand, TimescaleUnit, Value, Writer};
use bumpsim_hw::CycleState;
use std::collections::BTreeSet;
use std::io;

/// Name of the top-level scope.
pub const TOP_SCOPE: &str = "bumpsim";

/// Replace every character that is not an ASCII letter, digit or `_` by `_`.
pub fn vcd_ident(s: &str) -> String {
    let out: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if out.is_empty() {
        "_".to_string()
    } else {
        out
    }
}

/// `name`, or `name_k` for k = 2, 3, ...: the first not yet in `used`, which is marked used.
fn unique(name: String, used: &mut BTreeSet<String>) -> String {
    let mut cand = name.clone();
    let mut k = 2;
    while used.contains(&cand) {
        cand = format!("{name}_{k}");
        k += 1;
    }
    used.insert(cand.clone());
    cand
}

/// Wire names `<base>_<lane>` of a port's lanes; if any is taken, `<prefix><base>_<lane>`,
/// then `<prefix><base><k>_<lane>` for k = 2, 3, ... All are marked used.
fn lane_names(base: &str, lanes: usize, prefix: &str, used: &mut BTreeSet<String>) -> Vec<String> {
    let names = |b: &str| (0..lanes).map(|l| format!("{b}_{l}")).collect::<Vec<_>>();
    let free = |v: &Vec<String>, used: &BTreeSet<String>| v.iter().all(|n| !used.contains(n));
    let mut v = names(base);
    if !free(&v, used) {
        v = names(&format!("{prefix}{base}"));
        let mut k = 2;
        while !free(&v, used) {
            v = names(&format!("{prefix}{base}{k}"));
            k += 1;
        }
    }
    used.extend(v.iter().cloned());
    v
}

/// The 2-bit code of a cycle state.
pub fn state_code(s: CycleState) -> u64 {
    match s {
        CycleState::Idle => 0,
        CycleState::Busy => 1,
        CycleState::Stall => 2,
    }
}

struct VarSlot {
    id: IdCode,
    width: u32,
}

struct UnitVars {
    state: usize,
    in_valid: usize,
    in_id: usize,
    out_valid: usize,
    out_id: usize,
    /// Variable index per input port, per lane.
    ins: Vec<Vec<usize>>,
    outs: Vec<Vec<usize>>,
}

/// Variables and their current values (`None` = `x`).
struct Vars {
    slots: Vec<VarSlot>,
}

impl Vars {
    fn add<W: io::Write>(
        &mut self,
        w: &mut Writer<W>,
        width: u32,
        name: &str,
    ) -> io::Result<usize> {
        let id = w.add_wire(width, name)?;
        self.slots.push(VarSlot { id, width });
        Ok(self.slots.len() - 1)
    }
}

fn write_value<W: io::Write>(w: &mut Writer<W>, slot: &VarSlot, v: Option<u64>) -> io::Result<()> {
    if slot.width == 1 {
        let bit = match v {
            None => Value::X,
            Some(b) => (b & 1 == 1).into(),
        };
        return w.change_scalar(slot.id, bit);
    }
    let bits = (0..slot.width).rev().map(|b| match v {
        None => Value::X,
        Some(x) => (b < 64 && (x >> b) & 1 == 1).into(),
    });
    w.change_vector(slot.id, bits)
}

impl Trace {
    /// Write the trace as VCD (see the module documentation for the layout).
    pub fn write_vcd(&self, out: &mut impl io::Write) -> io::Result<()> {
        let mut w = Writer::new(out);
        w.comment("bumpsim cycle trace: clk rises at 2*cycle ns and falls at 2*cycle+1 ns")?;
        for u in &self.units {
            w.comment(&format!(
                "unit {} ({}): in{} -> out{}",
                u.name,
                u.kind,
                port_header(&u.inputs),
                port_header(&u.outputs)
            ))?;
        }
        w.timescale(1, TimescaleUnit::NS)?;
        w.add_module(TOP_SCOPE)?;
        let mut vars = Vars { slots: Vec::new() };
        let clk = vars.add(&mut w, 1, "clk")?;
        let cycle = vars.add(&mut w, 32, "cycle")?;
        let mut top_used: BTreeSet<String> =
            ["clk", "cycle"].iter().map(|s| s.to_string()).collect();
        let mut units = Vec::with_capacity(self.units.len());
        for u in &self.units {
            let scope = unique(vcd_ident(&u.name), &mut top_used);
            w.add_module(&scope)?;
            let mut used: BTreeSet<String> = BTreeSet::new();
            let mut fixed = |w: &mut Writer<_>, vars: &mut Vars, width, name: &str| {
                used.insert(name.to_string());
                vars.add(w, width, name)
            };
            let state = fixed(&mut w, &mut vars, 2, "state")?;
            let in_valid = fixed(&mut w, &mut vars, 1, "in_valid")?;
            let in_id = fixed(&mut w, &mut vars, 32, "in_id")?;
            let out_valid = fixed(&mut w, &mut vars, 1, "out_valid")?;
            let out_id = fixed(&mut w, &mut vars, 32, "out_id")?;
            let mut ports = |w: &mut Writer<_>,
                             vars: &mut Vars,
                             specs: &[bumpsim_hw::PortSpec],
                             prefix| {
                let mut per_port = Vec::with_capacity(specs.len());
                for p in specs {
                    let mut lanes = Vec::new();
                    for name in lane_names(&vcd_ident(&p.name), shown_lanes(p), prefix, &mut used) {
                        lanes.push(vars.add(w, lane_width(p), &name)?);
                    }
                    per_port.push(lanes);
                }
                io::Result::Ok(per_port)
            };
            let ins = ports(&mut w, &mut vars, &u.inputs, "in_")?;
            let outs = ports(&mut w, &mut vars, &u.outputs, "out_")?;
            w.upscope()?;
            units.push(UnitVars {
                state,
                in_valid,
                in_id,
                out_valid,
                out_id,
                ins,
                outs,
            });
        }
        w.upscope()?;
        w.enddefinitions()?;

        let n = vars.slots.len();
        let mut cur: Vec<Option<u64>> = vec![None; n];
        let mut written: Vec<Option<Option<u64>>> = vec![None; n];
        for uv in &units {
            cur[uv.in_valid] = Some(0);
            cur[uv.out_valid] = Some(0);
        }
        let order = self.ordered();
        let mut k = 0;
        let mut first = true;
        while k < order.len() {
            let c = self.records[order[k]].1.cycle;
            cur[clk] = Some(1);
            cur[cycle] = Some(c & 0xffff_ffff);
            for uv in &units {
                cur[uv.in_valid] = Some(0);
                cur[uv.out_valid] = Some(0);
            }
            while k < order.len() && self.records[order[k]].1.cycle == c {
                let (ui, p) = &self.records[order[k]];
                k += 1;
                let (Some(uv), Some(tu)) = (units.get(*ui), self.units.get(*ui)) else {
                    continue; // a record of a unit the trace does not describe
                };
                cur[uv.state] = Some(state_code(p.state));
                if let Some((id, words)) = &p.accepted {
                    cur[uv.in_valid] = Some(1);
                    cur[uv.in_id] = Some(id & 0xffff_ffff);
                    for ((spec, lanes), word) in tu.inputs.iter().zip(&uv.ins).zip(words) {
                        for (&var, s) in lanes.iter().zip(&word.lanes) {
                            cur[var] = Some(raw_bits(&spec.enc.format, s.raw));
                        }
                    }
                }
                if let Some((id, words)) = &p.emitted {
                    cur[uv.out_valid] = Some(1);
                    cur[uv.out_id] = Some(id & 0xffff_ffff);
                    for ((spec, lanes), word) in tu.outputs.iter().zip(&uv.outs).zip(words) {
                        for (&var, s) in lanes.iter().zip(&word.lanes) {
                            cur[var] = Some(raw_bits(&spec.enc.format, s.raw));
                        }
                    }
                }
            }
            w.timestamp(c.saturating_mul(2))?;
            if first {
                w.begin(SimulationCommand::Dumpvars)?;
            }
            for i in 0..n {
                if written[i] != Some(cur[i]) {
                    write_value(&mut w, &vars.slots[i], cur[i])?;
                    written[i] = Some(cur[i]);
                }
            }
            if first {
                w.end()?;
                first = false;
            }
            w.timestamp(c.saturating_mul(2).saturating_add(1))?;
            cur[clk] = Some(0);
            write_value(&mut w, &vars.slots[clk], Some(0))?;
            written[clk] = Some(Some(0));
        }
        w.flush()
    }
}

/// One value change read back from a VCD file: time, variable id, and the bits (`None` for x or z).
pub type VcdChange = (u64, ::vcd::IdCode, Option<u64>);

/// Read a VCD file back: its header and every value change in file order. Used to check traces
/// (a waveform viewer must be able to open them) and to compare two traces value by value.
pub fn read_vcd(bytes: &[u8]) -> Result<(::vcd::Header, Vec<VcdChange>), String> {
    let bit = |v: ::vcd::Value| match v {
        ::vcd::Value::V0 => Some(0u64),
        ::vcd::Value::V1 => Some(1),
        _ => None,
    };
    let mut p = ::vcd::Parser::new(bytes);
    let header = p.parse_header().map_err(|e| format!("VCD header: {e}"))?;
    let mut t = 0;
    let mut changes = Vec::new();
    for cmd in p {
        match cmd.map_err(|e| format!("VCD command: {e}"))? {
            ::vcd::Command::Timestamp(ts) => t = ts,
            ::vcd::Command::ChangeScalar(id, v) => changes.push((t, id, bit(v))),
            ::vcd::Command::ChangeVector(id, v) => {
                let mut acc = Some(0u64);
                for b in v.iter() {
                    acc = match (acc, bit(b)) {
                        (Some(a), Some(b)) => Some(a << 1 | b),
                        _ => None,
                    };
                }
                changes.push((t, id, acc));
            }
            ::vcd::Command::Begin(_) | ::vcd::Command::End(_) => {}
            other => return Err(format!("unexpected VCD command {other:?}")),
        }
    }
    Ok((header, changes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::tests::sample_trace;
    use ::vcd::{Header, ScopeItem};
    use std::collections::HashMap;

    /// Value of `id` at time `t`: the last change at or before `t` (`None` = x or never).
    fn at(changes: &[(u64, IdCode, Option<u64>)], id: IdCode, t: u64) -> Option<u64> {
        changes
            .iter()
            .rfind(|c| c.1 == id && c.0 <= t)
            .and_then(|c| c.2)
    }

    fn vars_of(header: &Header, scope: &[&str]) -> Vec<(String, u32)> {
        let s = header.find_scope(scope).expect("scope exists");
        s.items
            .iter()
            .filter_map(|i| match i {
                ScopeItem::Var(v) => Some((v.reference.clone(), v.size)),
                _ => None,
            })
            .collect()
    }

    fn vcd_bytes() -> Vec<u8> {
        let mut buf = Vec::new();
        sample_trace().write_vcd(&mut buf).unwrap();
        buf
    }

    #[test]
    fn vcd_header_has_the_scopes_wires_and_widths() {
        let (h, _) = read_vcd(&vcd_bytes()).unwrap();
        assert_eq!(h.timescale, Some((1, TimescaleUnit::NS)));
        let top = vars_of(&h, &["bumpsim"]);
        assert_eq!(top, vec![("clk".to_string(), 1), ("cycle".to_string(), 32)]);
        let names = |v: Vec<(String, u32)>| {
            v.into_iter()
                .map(|(n, w)| format!("{n}:{w}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        assert_eq!(
            names(vars_of(&h, &["bumpsim", "dot0"])),
            "state:2 in_valid:1 in_id:32 out_valid:1 out_id:32 n_0:16 n_1:16 n_2:16 d0_0:16"
        );
        assert_eq!(
            names(vars_of(&h, &["bumpsim", "spec0"])),
            "state:2 in_valid:1 in_id:32 out_valid:1 out_id:32 d0_0:16 s_0:8"
        );
        let scopes: Vec<&str> = h
            .find_scope(&["bumpsim"])
            .unwrap()
            .items
            .iter()
            .filter_map(|i| match i {
                ScopeItem::Scope(s) => Some(s.identifier.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(scopes, vec!["dot0", "spec0"]);
    }

    #[test]
    fn vcd_values_replay_to_the_probed_raw_bits() {
        let (h, ch) = read_vcd(&vcd_bytes()).unwrap();
        let id = |path: &[&str]| h.find_var(path).unwrap_or_else(|| panic!("{path:?}")).code;
        let clk = id(&["bumpsim", "clk"]);
        let cyc = id(&["bumpsim", "cycle"]);
        // clock: high at 2c, low at 2c + 1, for c = 0..=5
        for c in 0..=5u64 {
            assert_eq!(at(&ch, clk, 2 * c), Some(1), "clk at {}", 2 * c);
            assert_eq!(at(&ch, clk, 2 * c + 1), Some(0), "clk at {}", 2 * c + 1);
            assert_eq!(at(&ch, cyc, 2 * c + 1), Some(c));
        }
        assert_eq!(ch.iter().map(|c| c.0).max(), Some(11));
        let n2 = id(&["bumpsim", "dot0", "n_2"]);
        assert_eq!(at(&ch, n2, 0), Some(0xc000)); // -0.5 in s1.15, accepted in cycle 0
        assert_eq!(at(&ch, n2, 1), Some(0xc000));
        assert_eq!(at(&ch, n2, 2), Some(0x8000)); // -1.0, accepted in cycle 1
        assert_eq!(at(&ch, n2, 11), Some(0x8000)); // holds
        let n0 = id(&["bumpsim", "dot0", "n_0"]);
        assert_eq!(at(&ch, n0, 0), Some(0x7fff));
        assert_eq!(at(&ch, n0, 3), Some(0));
        let d0 = id(&["bumpsim", "dot0", "d0_0"]);
        assert_eq!(at(&ch, d0, 3), None); // x before the first emit
        assert_eq!(at(&ch, d0, 4), Some(0x6a0c));
        assert_eq!(at(&ch, d0, 7), Some(0x6a0c));
        assert_eq!(at(&ch, d0, 8), Some(0x8000));
        let s = id(&["bumpsim", "spec0", "s_0"]);
        assert_eq!(at(&ch, s, 7), None);
        assert_eq!(at(&ch, s, 8), Some(0xb4));
        let sd0 = id(&["bumpsim", "spec0", "d0_0"]);
        assert_eq!(at(&ch, sd0, 6), Some(0x6a0c));
        assert_eq!(at(&ch, sd0, 10), Some(0x8000));

        let state = id(&["bumpsim", "dot0", "state"]);
        let states: Vec<_> = (0..=5).map(|c| at(&ch, state, 2 * c).unwrap()).collect();
        assert_eq!(states, vec![1, 1, 1, 2, 1, 0]);
        let in_valid = id(&["bumpsim", "dot0", "in_valid"]);
        let iv: Vec<_> = (0..=5)
            .map(|c| at(&ch, in_valid, 2 * c + 1).unwrap())
            .collect();
        assert_eq!(iv, vec![1, 1, 0, 0, 0, 0]);
        let out_valid = id(&["bumpsim", "dot0", "out_valid"]);
        let ov: Vec<_> = (0..=5)
            .map(|c| at(&ch, out_valid, 2 * c).unwrap())
            .collect();
        assert_eq!(ov, vec![0, 0, 1, 0, 1, 0]);
        let out_id = id(&["bumpsim", "dot0", "out_id"]);
        assert_eq!(at(&ch, out_id, 3), None);
        assert_eq!(at(&ch, out_id, 4), Some(0));
        assert_eq!(at(&ch, out_id, 8), Some(1));
        let in_id = id(&["bumpsim", "spec0", "in_id"]);
        assert_eq!(at(&ch, in_id, 10), Some(1));

        // each variable changes at most once per timestamp, and only when its value changes
        let mut seen: HashMap<(u64, IdCode), usize> = HashMap::new();
        for c in &ch {
            *seen.entry((c.0, c.1)).or_default() += 1;
        }
        assert!(seen.values().all(|&k| k == 1));
    }

    #[test]
    fn colliding_and_unsafe_names_are_made_unique() {
        use bumpsim_hw::{Encoding, Format, PortSpec};
        let enc = Encoding::fixed(Format::u(4, 0));
        let u = crate::trace::TraceUnit::new(
            "a b",
            "inc",
            vec![PortSpec::new("v", 1, enc)],
            vec![PortSpec::new("v", 2, enc)],
        );
        let t = Trace::new(vec![u.clone(), u]);
        let mut buf = Vec::new();
        t.write_vcd(&mut buf).unwrap();
        let (h, ch) = read_vcd(&buf).unwrap();
        assert!(ch.is_empty());
        let v: Vec<String> = vars_of(&h, &["bumpsim", "a_b_2"])
            .into_iter()
            .skip(5)
            .map(|(n, _)| n)
            .collect();
        assert_eq!(v, vec!["v_0", "out_v_0", "out_v_1"]);
        assert!(h.find_scope(&["bumpsim", "a_b"]).is_some());
    }
}

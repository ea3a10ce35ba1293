//! The engine's top module for `bumpsim rtl` (`DIR/engine.v`, `bumpsim_hw::rtl::top`): the
//! generated units wired as the engine's signals wire them, and its co-simulation on the
//! frame's own fragments (`--cosim N`: N fragments spread evenly over the frame, each with the
//! attribute words the interpolator gives it and the engine's output word, both from the
//! bit-accurate simulator).

use bumpsim_hw::rtl::top::{self, Part, Source};
use bumpsim_hw::rtl::{Lane, RtlUnit};
use bumpsim_hw::{Mode, PortSpec, Wire, Word};
use bumpsim_pipeline::engine::Engine;
use bumpsim_pipeline::run::Prepared;
use std::collections::BTreeMap;

/// A generated unit: its config name, its Verilog, and the names of the ports its lanes index
/// (the ports of the unit it was generated from).
pub(crate) struct UnitRtl {
    pub(crate) name: String,
    pub(crate) rtl: RtlUnit,
    pub(crate) inputs: Vec<String>,
    pub(crate) outputs: Vec<String>,
}

/// The module name of the engine's top.
pub(crate) const TOP: &str = "bumpsim_engine";

fn ident(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// What a token slot holds: attribute `a`, or output port `q` of stage `k`.
#[derive(Clone, Copy)]
enum Origin {
    Attr(usize),
    Unit(usize, usize),
}

/// The top over `units` (every unit of `eng`, by name). `Err` names what is missing.
pub(crate) fn build(eng: &Engine, units: &[UnitRtl]) -> Result<RtlUnit, String> {
    let mut origin: BTreeMap<usize, Origin> = (0..eng.attributes.len())
        .map(|a| (eng.signals[a].slot, Origin::Attr(a)))
        .collect();
    let mut parts_of = Vec::new();
    for (k, st) in eng.stages.iter().enumerate() {
        let u = units
            .iter()
            .find(|u| u.name == st.name)
            .ok_or_else(|| format!("unit {} has no Verilog generator", st.name))?;
        parts_of.push(u);
        for (q, &s) in st.out_slots().iter().enumerate() {
            origin.insert(s, Origin::Unit(k, q));
        }
    }
    let mut inputs: Vec<Lane> = Vec::new();
    let mut input_of: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    // the source of lane `lane` of the word `wire` carries
    let mut source = |wire: Wire, lane: usize| -> Result<Source, String> {
        let (slot, k) = match wire {
            Wire::Slot(s) => (s, lane),
            Wire::Gather { lanes, from } => {
                if lane >= lanes as usize {
                    return Err(format!("lane {lane} of a {lanes}-lane wire"));
                }
                (from[lane].0 as usize, from[lane].1 as usize)
            }
        };
        match origin.get(&slot) {
            Some(&Origin::Attr(a)) => {
                let next = inputs.len();
                let i = *input_of.entry((a, k)).or_insert(next);
                if i == next {
                    let at = &eng.attributes[a];
                    inputs.push(Lane {
                        name: format!("attr_{}_{k}", ident(&at.name)),
                        port: a,
                        lane: k,
                        enc: at.enc,
                    });
                }
                Ok(Source::Input(i))
            }
            Some(&Origin::Unit(j, q)) => {
                let st = &eng.stages[j];
                let name = &st.unit().outputs()[q].name;
                let u = parts_of[j];
                let port = u.outputs.iter().position(|n| n == name);
                u.rtl
                    .outputs
                    .iter()
                    .position(|l| Some(l.port) == port && l.lane == k)
                    .map(|lane| Source::Part { part: j, lane })
                    .ok_or_else(|| {
                        format!("{}.{name} lane {k} is not an output of its Verilog", u.name)
                    })
            }
            None => Err(format!("token slot {slot} is no signal")),
        }
    };
    let mut sources = Vec::new();
    for (st, u) in eng.stages.iter().zip(&parts_of) {
        let ports = st.unit().inputs();
        let mut s = Vec::new();
        for l in &u.rtl.inputs {
            let name = &u.inputs[l.port];
            let pos = ports
                .iter()
                .position(|p| &p.name == name)
                .ok_or_else(|| format!("{}: no input port {name}", u.name))?;
            s.push(
                source(st.in_wires()[pos], l.lane)
                    .map_err(|e| format!("{}.{name}: {e}", u.name))?,
            );
        }
        sources.push(s);
    }
    // every signal a pass writes (engine.output, then engine.passes' others), one port each
    let mut outputs = Vec::new();
    for (port, o) in eng.pass_outputs().into_iter().enumerate() {
        let out: &PortSpec = &o.spec;
        for l in 0..out.lanes as usize {
            let s = source(o.wire, l).map_err(|e| format!("output {}: {e}", o.name))?;
            outputs.push((
                Lane {
                    name: format!("out_{}_{l}", ident(&o.name)),
                    port,
                    lane: l,
                    enc: out.enc,
                },
                s,
            ));
        }
    }
    let parts: Vec<Part> = parts_of
        .iter()
        .zip(sources)
        .map(|(u, inputs)| Part {
            name: format!("u_{}", ident(&u.name)),
            rtl: &u.rtl,
            inputs,
        })
        .collect();
    top::top(TOP, inputs, &parts, outputs)
}

/// `n` fragments spread evenly over the frame: the attribute words (one per attribute, in
/// the engine's order) and the engine's output words of each (one per signal a pass writes:
/// `Engine::pass_outputs`), in bit-accurate mode.
pub(crate) fn fragment_vectors(p: &Prepared, n: usize) -> (Vec<Vec<Word>>, Vec<Vec<Word>>) {
    let total = p.raster.fragments.len();
    let n = n.min(total);
    let attrs = p.engine.attributes.len();
    (0..n)
        .map(|i| {
            let t = p.fragment_token(Mode::BitAccurate, i * total / n);
            let ins = (0..attrs)
                .map(|a| t.slots[p.engine.signals[a].slot])
                .collect();
            let outs = p.engine.pass_outputs();
            (ins, outs.iter().map(|o| o.wire.read(&t.slots)).collect())
        })
        .unzip()
}

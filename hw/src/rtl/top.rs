//! The engine's top module: the generated units of an engine instantiated and wired as the
//! engine's signals wire them, one fragment at a time.
//!
//! Every generated unit has the same handshake ([`super::RtlUnit`]: `start`, inputs held until
//! `done`, registered outputs that hold until the unit's next `start`). The top runs the
//! units in the engine's order (a topological order of its signals): the top's `start` starts
//! the first unit, each unit's `done` starts the next, and the last unit's `done` is the top's.
//! A unit's inputs are earlier units' output registers (or the top's inputs, the fragment's
//! attributes), which hold until the next fragment starts, so the top's latency is the sum of
//! the units' and its interval the same (one fragment in flight: the top checks function and
//! wiring, it is not the engine's pipelined timing, which the cycle simulator models).
//!
//! A wire expression of the engine (swizzle, lane select, concatenation) is wires here: each
//! input lane of a unit names the lane it reads. The host registers of all units share one
//! write port: unit `k`'s words at addresses `base_k ..`, in the units' order. Units with
//! per-frame work share the `frame` pulse; `frame_done` is high when every one of them is done.

use super::verilog::unsigned_bits;
use super::{ConfigWord, Lane, RtlUnit};
use std::fmt::Write as _;

/// Where an input lane of a unit, or an output lane of the top, reads its bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The top's input lane (index into its inputs).
    Input(usize),
    /// Output lane `lane` (index into [`RtlUnit::outputs`]) of part `part`.
    Part { part: usize, lane: usize },
}

/// One instance: its instance name, its unit and the source of each of its input lanes (in
/// [`RtlUnit::inputs`] order).
pub struct Part<'a> {
    pub name: String,
    pub rtl: &'a RtlUnit,
    pub inputs: Vec<Source>,
}

fn range(w: u32) -> String {
    if w <= 1 {
        String::new()
    } else {
        format!("[{}:0] ", w - 1)
    }
}

fn plain(name: &str) -> bool {
    let mut c = name.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

/// The top module `top` over `parts` (in dependency order), with input lanes `inputs` and
/// output lanes `outputs` (each with its source). The result holds every part's Verilog and
/// the top's; its host registers are the parts' in order, its latency their sum. Errors: a
/// source that names a later part or a lane that does not exist, a width that differs from
/// its source's, a name that is not a Verilog identifier.
pub fn top(
    top: &str,
    inputs: Vec<Lane>,
    parts: &[Part<'_>],
    outputs: Vec<(Lane, Source)>,
) -> Result<RtlUnit, String> {
    if parts.is_empty() {
        return Err("an engine without units has no top".into());
    }
    for n in std::iter::once(top)
        .chain(inputs.iter().map(|l| l.name.as_str()))
        .chain(outputs.iter().map(|(l, _)| l.name.as_str()))
        .chain(parts.iter().map(|p| p.name.as_str()))
    {
        if !plain(n) {
            return Err(format!("{n:?} is not a Verilog identifier"));
        }
    }
    // the width a source carries, checked against the lane it feeds
    let width = |s: Source, before: usize| -> Result<(u32, String), String> {
        match s {
            Source::Input(i) => inputs
                .get(i)
                .map(|l| (l.enc.width(), l.name.clone()))
                .ok_or_else(|| format!("input lane {i} does not exist")),
            Source::Part { part, lane } => {
                let p = parts
                    .get(part)
                    .filter(|_| part < before)
                    .ok_or_else(|| format!("part {part} is not an earlier unit"))?;
                let l = p
                    .rtl
                    .outputs
                    .get(lane)
                    .ok_or_else(|| format!("{}: output lane {lane} does not exist", p.name))?;
                Ok((l.enc.width(), format!("{}_{}", p.name, l.name)))
            }
        }
    };
    let nc: usize = parts.iter().map(|p| p.rtl.config.len()).sum();
    let ab = unsigned_bits(nc.saturating_sub(1) as u128);
    let db = parts
        .iter()
        .flat_map(|p| p.rtl.config.iter().map(|c| c.width))
        .max()
        .unwrap_or(1);
    let framed: Vec<&Part> = parts.iter().filter(|p| p.rtl.frame.is_some()).collect();

    let mut ports = vec![
        "input wire clk".to_string(),
        "input wire rst".into(),
        "input wire start".into(),
        "output wire done".into(),
    ];
    if nc > 0 {
        ports.push("input wire cfg_we".into());
        ports.push(format!("input wire {}cfg_addr", range(ab)));
        ports.push(format!("input wire {}cfg_data", range(db)));
    }
    if !framed.is_empty() {
        ports.push("input wire frame".into());
        ports.push("output wire frame_done".into());
    }
    for l in &inputs {
        ports.push(format!("input wire {}{}", range(l.enc.width()), l.name));
    }
    for (l, _) in &outputs {
        ports.push(format!("output wire {}{}", range(l.enc.width()), l.name));
    }
    let mut body = String::new();
    let mut config = Vec::new();
    let mut base = 0usize;
    for (k, p) in parts.iter().enumerate() {
        let u = p.rtl;
        if u.inputs.len() != p.inputs.len() {
            return Err(format!(
                "{}: {} input lanes, {} sources",
                p.name,
                u.inputs.len(),
                p.inputs.len()
            ));
        }
        let _ = writeln!(body, "    // {} ({}), latency {}", p.name, u.top, u.latency);
        let _ = writeln!(body, "    wire {}_done;", p.name);
        for l in &u.outputs {
            let _ = writeln!(
                body,
                "    wire {}{}_{};",
                range(l.enc.width()),
                p.name,
                l.name
            );
        }
        let start = if k == 0 {
            "start".to_string()
        } else {
            format!("{}_done", parts[k - 1].name)
        };
        let mut conns = vec![
            ".clk(clk)".to_string(),
            ".rst(rst)".into(),
            format!(".start({start})"),
            format!(".done({}_done)", p.name),
        ];
        let n = u.config.len();
        if n > 0 {
            let kb = u.cfg_addr_bits();
            let _ = writeln!(
                body,
                "    wire {}{}_cfg_addr = cfg_addr - {ab}'d{base};",
                range(kb),
                p.name
            );
            conns.push(format!(
                ".cfg_we(cfg_we && cfg_addr >= {ab}'d{base} && cfg_addr <= {ab}'d{})",
                base + n - 1
            ));
            conns.push(format!(".cfg_addr({}_cfg_addr)", p.name));
            let kd = u.cfg_data_bits();
            conns.push(if db == 1 {
                ".cfg_data(cfg_data)".into()
            } else {
                format!(".cfg_data(cfg_data[{}:0])", kd - 1)
            });
            config.extend(u.config.iter().map(|c| ConfigWord {
                what: format!("{}: {}", p.name, c.what),
                ..c.clone()
            }));
            base += n;
        }
        if u.frame.is_some() {
            let _ = writeln!(body, "    wire {}_frame_done;", p.name);
            conns.push(".frame(frame)".into());
            conns.push(format!(".frame_done({}_frame_done)", p.name));
        }
        for (l, &s) in u.inputs.iter().zip(&p.inputs) {
            let (w, src) = width(s, k).map_err(|e| format!("{}.{}: {e}", p.name, l.name))?;
            if w != l.enc.width() {
                return Err(format!(
                    "{}.{}: {} bits, its source {src} {w}",
                    p.name,
                    l.name,
                    l.enc.width()
                ));
            }
            conns.push(format!(".{}({src})", l.name));
        }
        for l in &u.outputs {
            conns.push(format!(".{0}({1}_{0})", l.name, p.name));
        }
        let _ = writeln!(
            body,
            "    {} {} (\n        {}\n    );",
            u.top,
            p.name,
            conns.join(",\n        ")
        );
    }
    let last = &parts[parts.len() - 1].name;
    let _ = writeln!(body, "    assign done = {last}_done;");
    if !framed.is_empty() {
        let all: Vec<String> = framed
            .iter()
            .map(|p| format!("{}_frame_done", p.name))
            .collect();
        let _ = writeln!(body, "    assign frame_done = {};", all.join(" && "));
    }
    for (l, s) in &outputs {
        let (w, src) = width(*s, parts.len()).map_err(|e| format!("{}: {e}", l.name))?;
        if w != l.enc.width() {
            return Err(format!(
                "{}: {} bits, its source {src} {w}",
                l.name,
                l.enc.width()
            ));
        }
        let _ = writeln!(body, "    assign {} = {src};", l.name);
    }
    let mut verilog = String::new();
    for p in parts {
        verilog += &p.rtl.verilog;
        verilog += "\n";
    }
    let _ = write!(
        verilog,
        "// the engine: its units one fragment at a time, each unit's done starting the next\n\
         module {top} (\n    {}\n);\n{body}endmodule\n",
        ports.join(",\n    ")
    );
    Ok(RtlUnit {
        top: top.to_string(),
        verilog,
        inputs,
        outputs: outputs.into_iter().map(|(l, _)| l).collect(),
        config,
        latency: parts.iter().map(|p| p.rtl.latency).sum(),
        tables: parts.iter().flat_map(|p| p.rtl.tables.clone()).collect(),
        memories: parts.iter().flat_map(|p| p.rtl.memories.clone()).collect(),
        frame: framed.iter().filter_map(|p| p.rtl.frame).max(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Encoding, Format};

    fn lane(name: &str, port: usize, bits: u8) -> Lane {
        Lane {
            name: name.into(),
            port,
            lane: 0,
            enc: Encoding::fixed(Format::u(bits, 0)),
        }
    }

    fn unit(top: &str, ins: u8, outs: u8, regs: usize, frame: Option<u32>) -> RtlUnit {
        RtlUnit {
            top: top.into(),
            verilog: format!("module {top}; endmodule\n"),
            inputs: vec![lane("a", 0, ins)],
            outputs: vec![lane("y", 0, outs)],
            config: (0..regs)
                .map(|i| ConfigWord {
                    what: format!("w{i}"),
                    width: 4,
                    value: i as i64,
                })
                .collect(),
            latency: 3,
            tables: Vec::new(),
            memories: Vec::new(),
            frame,
        }
    }

    #[test]
    fn the_top_chains_the_units_and_shares_the_host_port() {
        let (p, q) = (unit("p", 8, 6, 2, Some(10)), unit("q", 6, 5, 3, Some(7)));
        let parts = [
            Part {
                name: "u_p".into(),
                rtl: &p,
                inputs: vec![Source::Input(0)],
            },
            Part {
                name: "u_q".into(),
                rtl: &q,
                inputs: vec![Source::Part { part: 0, lane: 0 }],
            },
        ];
        let t = top(
            "eng",
            vec![lane("attr_x_0", 0, 8)],
            &parts,
            vec![(lane("out_c_0", 0, 5), Source::Part { part: 1, lane: 0 })],
        )
        .unwrap();
        assert_eq!(t.latency, 6);
        assert_eq!(t.frame, Some(10));
        assert_eq!(t.config.len(), 5);
        assert_eq!(t.config[2].what, "u_q: w0");
        let v = &t.verilog;
        assert!(v.contains(".start(u_p_done)"), "{v}");
        assert!(
            v.contains("wire [1:0] u_q_cfg_addr = cfg_addr - 3'd2;"),
            "{v}"
        );
        assert!(
            v.contains(".cfg_we(cfg_we && cfg_addr >= 3'd2 && cfg_addr <= 3'd4)"),
            "{v}"
        );
        assert!(
            v.contains(".a(u_p_y)") && v.contains("assign out_c_0 = u_q_y;"),
            "{v}"
        );
        assert!(
            v.contains("assign frame_done = u_p_frame_done && u_q_frame_done;"),
            "{v}"
        );
    }

    #[test]
    fn bad_wiring_is_an_error_naming_the_lane() {
        let (p, q) = (unit("p", 8, 6, 0, None), unit("q", 6, 5, 0, None));
        let mk = |src: Source, q_in: Source| {
            let parts = [
                Part {
                    name: "u_p".into(),
                    rtl: &p,
                    inputs: vec![src],
                },
                Part {
                    name: "u_q".into(),
                    rtl: &q,
                    inputs: vec![q_in],
                },
            ];
            top("eng", vec![lane("x", 0, 8)], &parts, vec![])
        };
        let later = mk(Source::Part { part: 1, lane: 0 }, Source::Input(0)).unwrap_err();
        assert!(
            later.contains("u_p.a: part 1 is not an earlier unit"),
            "{later}"
        );
        let width = mk(Source::Input(0), Source::Input(0)).unwrap_err();
        assert!(width.contains("u_q.a: 6 bits, its source x 8"), "{width}");
        let missing = mk(Source::Input(3), Source::Input(0)).unwrap_err();
        assert!(missing.contains("input lane 3 does not exist"), "{missing}");
        let bad = top("eng-1", vec![], &[], vec![]).unwrap_err();
        assert!(bad.contains("without units"), "{bad}");
        let parts = [Part {
            name: "u p".into(),
            rtl: &p,
            inputs: vec![Source::Input(0)],
        }];
        let ident = top("eng", vec![lane("x", 0, 8)], &parts, vec![]).unwrap_err();
        assert!(
            ident.contains("\"u p\" is not a Verilog identifier"),
            "{ident}"
        );
    }
}

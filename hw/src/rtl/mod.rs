//! Verilog from the model: synthesisable Verilog-2005 of units at their configured widths,
//! bit-exact with their bit-accurate mode (`docs/rtl.md`).
//!
//! Each generator takes the parameters that build the unit ([`Dot3Rtl`], [`PowerTableRtl`],
//! [`ShadeRtl`], [`ModulateRtl`]; [`blend::rtl`], [`normalize::rtl`], [`perturb::rtl`],
//! [`fetch::rtl`], [`emboss::rtl`], [`texram::rtl`], [`quat::rtl`] and [`quantized::rtl`]
//! read a built [`crate::units::BumpBlend`], [`crate::units::Normalize`],
//! [`crate::units::Perturb`], [`crate::units::TexFetch`], [`crate::units::EmbossFilter`],
//! [`crate::units::TexramFrame`], [`crate::units::QuatFrame`] or
//! [`crate::units::QuantizedFetch`]; [`texture_shader::rtl`] reads a built
//! [`crate::units::texture_shader::TextureShader`], specialised to its stages' programs) and
//! writes the
//! datapath with the twins of [`crate::arith::Acc`]'s operations in [`fixed`], so the widths,
//! rounding, clamps and casts are those of the model's code. Co-simulation against the model
//! (`hw/tests/rtl_cosim.rs`) checks every output word; [`synth`] prices the result with yosys.
//!
//! Every generated unit has one interface ([`RtlUnit`]): `clk`, `rst` (synchronous, the
//! sequencer only: datapath registers are reset-free as in the gate model), `start` (the
//! fragment's inputs are presented and held until `done`), one input per port lane
//! (`{port}_{lane}`, or `{port}` for a 1-lane port), one registered output per output lane
//! (named the same way, `out_` in front where an input has the name),
//! `done` (the outputs are valid), and for units with host-loaded registers (coefficients,
//! bump state) a write port `cfg_we`, `cfg_addr`, `cfg_data` (one register word per address,
//! [`RtlUnit::config`]). Tables with known contents are separate ROM modules
//! ([`RtlUnit::tables`]) so that synthesis prices them apart; texture memories are modules
//! loaded from a file for co-simulation and black boxes for synthesis ([`RtlUnit::memories`]).

pub mod blend;
pub mod cast;
pub mod combiner;
pub mod cull;
pub mod divide;
pub mod dot3;
pub mod emboss;
pub mod fb_blend;
pub mod fetch;
pub mod fixed;
pub mod modulate;
pub mod ndf_turbulence;
pub mod normalize;
pub mod palette_builder;
pub(crate) mod palette_envmap;
pub mod perturb;
pub mod power;
pub mod quantized;
pub mod quat;
pub mod rop;
pub mod shade;
pub mod synth;
pub mod testbench;
pub mod texram;
pub mod texture_shader;
pub mod top;
pub mod vectors;
pub mod verilog;

pub use dot3::Dot3Rtl;
pub use modulate::ModulateRtl;
pub use power::PowerTableRtl;
pub use shade::ShadeRtl;

use crate::format::Encoding;
use crate::unit::PortSpec;
use verilog::{unsigned_bits, Module};

/// One lane of a port as a Verilog port.
#[derive(Debug, Clone, PartialEq)]
pub struct Lane {
    /// Verilog port name.
    pub name: String,
    /// Index of the unit port and lane it carries.
    pub port: usize,
    pub lane: usize,
    pub enc: Encoding,
}

/// One host-loaded register word, at address = its index in [`RtlUnit::config`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigWord {
    pub what: String,
    pub width: u32,
    /// The raw code the model holds in that register.
    pub value: i64,
}

/// A generated unit: its Verilog and its interface.
#[derive(Debug, Clone)]
pub struct RtlUnit {
    /// Name of the unit's top module.
    pub top: String,
    /// Every module of the unit (ROMs first, then the top).
    pub verilog: String,
    pub inputs: Vec<Lane>,
    pub outputs: Vec<Lane>,
    pub config: Vec<ConfigWord>,
    /// Clocks from the edge that samples `start` to the one after which `done` is high.
    pub latency: u32,
    /// Names of the ROM modules (tables with known contents) the top instantiates, with the
    /// number of instances.
    pub tables: Vec<(String, u32)>,
    /// Texture memories the top instantiates: behavioural models for co-simulation, loaded
    /// from a `$readmemh` file, and black boxes for synthesis (the memory is outside the
    /// unit's budget, as the gate model has it).
    pub memories: Vec<Memory>,
    /// Units with per-frame work (a table the unit builds itself): clocks from the edge that
    /// samples the `frame` pulse to the one after which `frame_done` is high. The testbench
    /// runs the frame after the host registers and before the vectors.
    pub frame: Option<u32>,
}

/// A memory of a generated unit: module `module` with read ports (`a{p}` address, `d{p}`
/// data `latency` clocks later), contents read from `file`; a loadable table written by the
/// unit itself (`we`, `wa`, `wd`) has no file (`file` empty, no words).
#[derive(Debug, Clone, PartialEq)]
pub struct Memory {
    pub module: String,
    /// The `$readmemh` file the module loads (relative to the simulator's directory).
    pub file: String,
    /// Bits per word.
    pub width: u32,
    /// The words, word `k` at address `k`.
    pub words: Vec<u128>,
}

impl Memory {
    /// Whether the memory is loaded from a file (not written by the unit).
    pub fn has_file(&self) -> bool {
        !self.file.is_empty()
    }

    /// The `$readmemh` text of the contents.
    pub fn hex(&self) -> String {
        let digits = self.width.div_ceil(4).max(1) as usize;
        let mut s = String::with_capacity(self.words.len() * (digits + 1));
        for w in &self.words {
            s += &format!("{w:0digits$x}\n");
        }
        s
    }
}

impl RtlUnit {
    pub fn cfg_addr_bits(&self) -> u32 {
        unsigned_bits(self.config.len().saturating_sub(1) as u128)
    }
    pub fn cfg_data_bits(&self) -> u32 {
        self.config.iter().map(|c| c.width).max().unwrap_or(1)
    }
}

/// The clocking of a unit: input capture edge, `interval` datapath edges, a final edge.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plan {
    /// Edge 1 loads input registers; the datapath runs from edge 2.
    pub capture: bool,
    /// Datapath edges (the unit's initiation interval).
    pub interval: u32,
    /// One edge after the datapath that writes the output registers.
    pub finish: bool,
}

impl Plan {
    /// One datapath edge, from `start` into the output registers (inputs held until `done`).
    pub fn single() -> Plan {
        Plan {
            capture: false,
            interval: 1,
            finish: false,
        }
    }

    /// A pipeline of `latency` (>= 2) stages whose last edge writes the output registers
    /// (every stage register loaded on every edge; the inputs held until `done`).
    pub fn pipeline(latency: u32) -> Plan {
        Plan {
            capture: false,
            interval: latency.max(2) - 1,
            finish: true,
        }
    }

    pub fn latency(&self) -> u32 {
        self.capture as u32 + self.interval + self.finish as u32
    }
}

/// The common shell of a generated unit: ports, sequencer, host registers, ROMs.
pub(crate) struct Shell {
    pub m: Module,
    plan: Plan,
    inputs: Vec<Lane>,
    outputs: Vec<Lane>,
    config: Vec<(ConfigWord, String)>,
    roms: Vec<String>,
    tables: Vec<(String, u32)>,
    memories: Vec<Memory>,
    frame: Option<u32>,
    /// Datapath clock index, its width; datapath enable; final-edge enable.
    pub t: String,
    pub t_bits: u32,
    pub comp: String,
    pub fin: String,
}

fn lane_name(port: &PortSpec, lane: usize) -> String {
    if port.lanes == 1 {
        port.name.clone()
    } else {
        format!("{}_{lane}", port.name)
    }
}

impl Shell {
    pub fn new(top: &str, plan: Plan) -> Shell {
        let mut m = Module::new(top);
        m.input("clk", 1);
        m.input("rst", 1);
        m.input("start", 1);
        let l = plan.latency();
        let sb = unsigned_bits(l as u128);
        m.reg("step", sb);
        m.output_wire("done", 1, &format!("step == {sb}'d{l}"));
        m.stmt(format!(
            "// sequencer: step = clocks since start (0 idle)\n\
             always @(posedge clk) begin\n    if (rst) step <= {sb}'d0;\n    \
             else if (start) step <= {sb}'d1;\n    else if (step == {sb}'d{l}) step <= {sb}'d0;\n    \
             else if (step != {sb}'d0) step <= step + {sb}'d1;\nend"
        ));
        let iv = plan.interval;
        let tb = unsigned_bits(iv.saturating_sub(1) as u128);
        let (t, comp) = if plan.capture {
            (
                m.uwire("t", tb, &format!("step - {sb}'d1")),
                m.uwire(
                    "comp",
                    1,
                    &format!("(step >= {sb}'d1) && (step <= {sb}'d{iv})"),
                ),
            )
        } else {
            (
                m.uwire("t", tb, &format!("start ? {sb}'d0 : step")),
                m.uwire(
                    "comp",
                    1,
                    &format!("start || ((step != {sb}'d0) && (step < {sb}'d{iv}))"),
                ),
            )
        };
        let fe = plan.capture as u32 + iv;
        let fin = m.uwire("fin", 1, &format!("step == {sb}'d{fe}"));
        Shell {
            m,
            plan,
            inputs: Vec::new(),
            outputs: Vec::new(),
            config: Vec::new(),
            roms: Vec::new(),
            tables: Vec::new(),
            memories: Vec::new(),
            frame: None,
            t,
            t_bits: tb,
            comp,
            fin,
        }
    }

    /// Input ports of the unit port `index`; with `capture`, registers loaded at `start`.
    /// Returns the names that carry each lane's bits.
    pub fn port(&mut self, index: usize, p: &PortSpec, capture: bool) -> Vec<String> {
        let w = p.enc.width();
        (0..p.lanes as usize)
            .map(|l| {
                let name = lane_name(p, l);
                self.m.input(&name, w);
                self.inputs.push(Lane {
                    name: name.clone(),
                    port: index,
                    lane: l,
                    enc: p.enc,
                });
                if capture {
                    let r = self.m.reg(&format!("in_{name}"), w);
                    self.m
                        .stmt(format!("always @(posedge clk) if (start) {r} <= {name};"));
                    r
                } else {
                    name
                }
            })
            .collect()
    }

    /// A host-loaded register holding the code `value` of `enc`; returns its name.
    pub fn config_reg(&mut self, what: &str, enc: &Encoding, value: i64) -> String {
        let name = format!("cfg_{}", self.config.len());
        self.m.reg(&name, enc.width());
        self.config.push((
            ConfigWord {
                what: what.to_string(),
                width: enc.width(),
                value,
            },
            name.clone(),
        ));
        name
    }

    /// A host-loaded register of `width` bits holding `value` (two's complement when
    /// negative); returns its name.
    pub fn config_raw(&mut self, what: &str, width: u32, value: i64) -> String {
        let name = format!("cfg_{}", self.config.len());
        self.m.reg(&name, width);
        self.config.push((
            ConfigWord {
                what: what.to_string(),
                width,
                value,
            },
            name.clone(),
        ));
        name
    }

    /// Output lanes of the unit port `index` driven by the wires `exprs` (no registers of
    /// their own, e.g. a copy of other outputs).
    pub fn output_wires(&mut self, index: usize, p: &PortSpec, exprs: &[String]) {
        for (l, e) in exprs.iter().enumerate().take(p.lanes as usize) {
            let name = lane_name(p, l);
            self.m.output_wire(&name, p.enc.width(), e);
            self.outputs.push(Lane {
                name,
                port: index,
                lane: l,
                enc: p.enc,
            });
        }
    }

    /// A per-frame phase of `cycles` clocks: the `frame` input (a pulse, sampled by the
    /// first edge) and the `frame_done` output (high after the `cycles`-th edge until the next
    /// `frame`; the caller drives the register `frame_done`). Returns the names.
    pub fn frame(&mut self, cycles: u32) -> (String, String) {
        self.m.input("frame", 1);
        self.m.output_reg("frame_done", 1);
        self.frame = Some(cycles);
        ("frame".into(), "frame_done".into())
    }

    /// Registered output lanes of the unit port `index`; returns their names.
    pub fn output(&mut self, index: usize, p: &PortSpec) -> Vec<String> {
        (0..p.lanes as usize)
            .map(|l| {
                let mut name = lane_name(p, l);
                if self.inputs.iter().any(|i| i.name == name) {
                    name = format!("out_{name}");
                }
                self.m.output_reg(&name, p.enc.width());
                self.outputs.push(Lane {
                    name: name.clone(),
                    port: index,
                    lane: l,
                    enc: p.enc,
                });
                name
            })
            .collect()
    }

    /// Instantiate the ROM `words` (module `name`, emitted once) addressed by `addr`; returns
    /// the wire with the word.
    pub fn rom(&mut self, name: &str, words: &[i64], value_bits: u32, addr: &str) -> String {
        match self.tables.iter_mut().find(|(n, _)| n == name) {
            Some((_, k)) => *k += 1,
            None => {
                self.roms.push(verilog::rom(name, words, value_bits));
                self.tables.push((name.to_string(), 1));
            }
        }
        let y = self.m.net("rom", value_bits);
        let inst = format!("{y}_i");
        self.m.stmt(format!("{name} {inst} (.a({addr}), .y({y}));"));
        y
    }

    /// Instantiate a texture memory (module `{top}_{name}`, its contents in
    /// `{top}_{name}.hex`) with one read port per address in `addrs`: each port's data is
    /// the word at its address `latency` clocks (>= 1) earlier, through a register pipeline.
    /// Returns the data wires.
    pub fn memory(
        &mut self,
        name: &str,
        words: Vec<u128>,
        width: u32,
        addrs: &[(String, u32)],
        latency: u32,
    ) -> Vec<String> {
        let n = words.len();
        self.memory_module(name, words, n, width, addrs, latency, None)
    }

    /// Instantiate a loadable table (module `{top}_{name}`, `entries` words, empty at reset)
    /// with the read ports of [`Shell::memory`] and one write port `write = (enable, address,
    /// data)`: the word is written on the edge that samples the enable.
    pub fn ram(
        &mut self,
        name: &str,
        entries: usize,
        width: u32,
        addrs: &[(String, u32)],
        latency: u32,
        write: (&str, &str, &str),
    ) -> Vec<String> {
        self.memory_module(
            name,
            Vec::new(),
            entries,
            width,
            addrs,
            latency,
            Some(write),
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn memory_module(
        &mut self,
        name: &str,
        words: Vec<u128>,
        entries: usize,
        width: u32,
        addrs: &[(String, u32)],
        latency: u32,
        write: Option<(&str, &str, &str)>,
    ) -> Vec<String> {
        let module = format!("{}_{name}", self.m.name);
        let file = format!("{module}.hex");
        let ab = addrs.iter().map(|a| a.1).max().unwrap_or(1).max(1);
        let lat = latency.max(1);
        let (kind, from) = match write {
            None => ("texture memory", format!(" (contents from {file})")),
            Some(_) => (
                "loadable table",
                " (written through its write port)".to_string(),
            ),
        };
        let mut text = format!(
            "// {kind} {entries}x{width}, {} read ports, {lat} clocks: a behavioural model for\n\
             // co-simulation{from}; a black box in synthesis\n\
             module {module} (\n    input wire clk",
            addrs.len()
        );
        if write.is_some() {
            text += &format!(
                ",\n    input wire we,\n    input wire [{}:0] wa,\n    input wire [{}:0] wd",
                ab - 1,
                width - 1
            );
        }
        for p in 0..addrs.len() {
            text += &format!(
                ",\n    input wire [{}:0] a{p},\n    output wire [{}:0] d{p}",
                ab - 1,
                width - 1
            );
        }
        text += &format!(
            "\n);\n    reg [{}:0] mem [0:{}];\n",
            width - 1,
            entries.max(1) - 1
        );
        if write.is_some() {
            text += "    always @(posedge clk) if (we) mem[wa] <= wd;\n";
        } else {
            text += &format!(
                "    `ifndef SYNTHESIS\n    initial $readmemh(\"{file}\", mem);\n`endif\n"
            );
        }
        for p in 0..addrs.len() {
            for k in 0..lat {
                text += &format!("    reg [{}:0] r{k}_{p};\n", width - 1);
            }
            text += &format!("    always @(posedge clk) r0_{p} <= mem[a{p}];\n");
            for k in 1..lat {
                text += &format!("    always @(posedge clk) r{k}_{p} <= r{}_{p};\n", k - 1);
            }
            text += &format!("    assign d{p} = r{}_{p};\n", lat - 1);
        }
        text += "endmodule\n";
        self.roms.push(text);
        let mut conns = vec![".clk(clk)".to_string()];
        if let Some((we, wa, wd)) = write {
            conns.extend([
                format!(".we({we})"),
                format!(".wa({wa})"),
                format!(".wd({wd})"),
            ]);
        }
        let mut data = Vec::new();
        for (p, (a, w)) in addrs.iter().enumerate() {
            let y = self.m.net("texel", width);
            let a = if *w < ab {
                format!("{{{}'d0, {a}}}", ab - w)
            } else {
                a.clone()
            };
            conns.push(format!(".a{p}({a})"));
            conns.push(format!(".d{p}({y})"));
            data.push(y);
        }
        self.m
            .stmt(format!("{module} {module}_i ({});", conns.join(", ")));
        self.memories.push(Memory {
            module,
            file: if write.is_some() { String::new() } else { file },
            width,
            words,
        });
        data
    }

    pub fn finish(mut self) -> RtlUnit {
        if !self.config.is_empty() {
            let ab = unsigned_bits(self.config.len().saturating_sub(1) as u128);
            let db = self.config.iter().map(|c| c.0.width).max().unwrap();
            self.m.input("cfg_we", 1);
            self.m.input("cfg_addr", ab);
            self.m.input("cfg_data", db);
            for (i, (c, r)) in self.config.iter().enumerate() {
                let sel = if db == 1 {
                    "cfg_data".to_string()
                } else if c.width == 1 {
                    "cfg_data[0]".to_string()
                } else {
                    format!("cfg_data[{}:0]", c.width - 1)
                };
                self.m.stmt(format!(
                    "always @(posedge clk) if (cfg_we && cfg_addr == {ab}'d{i}) {r} <= {sel};"
                ));
            }
        }
        let mut verilog = String::from("// generated by bumpsim_hw::rtl: do not edit\n");
        for r in &self.roms {
            verilog += r;
            verilog += "\n";
        }
        verilog += &self.m.text();
        RtlUnit {
            top: self.m.name.clone(),
            verilog,
            inputs: self.inputs,
            outputs: self.outputs,
            config: self.config.into_iter().map(|c| c.0).collect(),
            latency: self.plan.latency(),
            tables: self.tables,
            memories: self.memories,
            frame: self.frame,
        }
    }
}

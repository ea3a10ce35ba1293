//! A tiny Verilog-2005 writer: one module, its ports, declarations and statements, with
//! fresh names for generated wires. Only what the unit generators need; the text it writes is
//! read by yosys 0.23 and iverilog (`-g2005`).

use std::fmt::Write;

/// One module under construction.
pub struct Module {
    pub name: String,
    ports: Vec<String>,
    decls: Vec<String>,
    body: Vec<String>,
    next: usize,
}

/// Width of a signed two's-complement word that holds every integer of `[lo, hi]` (>= 1).
pub fn signed_bits(lo: i128, hi: i128) -> u32 {
    let mut w = 1;
    while w < 127 && !(lo >= -(1i128 << (w - 1)) && hi < (1i128 << (w - 1))) {
        w += 1;
    }
    w
}

/// Width of an unsigned word that holds `0..=hi` (>= 1).
pub fn unsigned_bits(hi: u128) -> u32 {
    (128 - hi.leading_zeros()).max(1)
}

/// A signed decimal literal wide enough for `v` (a context-sized signed operand).
pub fn lit(v: i128) -> String {
    let w = signed_bits(v.min(0), v.max(0)) + 1;
    if v < 0 {
        format!("(-{w}'sd{})", v.unsigned_abs())
    } else {
        format!("{w}'sd{v}")
    }
}

/// An unsigned literal of exactly `w` bits.
pub fn ulit(w: u32, v: u128) -> String {
    format!("{w}'d{v}")
}

fn range(w: u32) -> String {
    if w == 1 {
        String::new()
    } else {
        format!("[{}:0] ", w - 1)
    }
}

impl Module {
    pub fn new(name: &str) -> Module {
        Module {
            name: name.to_string(),
            ports: Vec::new(),
            decls: Vec::new(),
            body: Vec::new(),
            next: 0,
        }
    }

    /// An input port of `w` bits (unsigned bit vector).
    pub fn input(&mut self, name: &str, w: u32) -> String {
        self.ports.push(format!("input wire {}{name}", range(w)));
        name.to_string()
    }

    /// An output port driven by a register of `w` bits.
    pub fn output_reg(&mut self, name: &str, w: u32) -> String {
        self.ports.push(format!("output reg {}{name}", range(w)));
        name.to_string()
    }

    /// An output port driven by a continuous assignment.
    pub fn output_wire(&mut self, name: &str, w: u32, expr: &str) -> String {
        self.ports.push(format!("output wire {}{name}", range(w)));
        self.body.push(format!("assign {name} = {expr};"));
        name.to_string()
    }

    /// A new name `{hint}_w{n}`: unlike every port name (`{port}_{lane}` ends in a digit
    /// after its last `_`, and unit ports are plain identifiers), so that a unit port named
    /// like a generated wire (Modulate's `t` beside the sequencer's `t`) cannot clash.
    fn fresh(&mut self, hint: &str) -> String {
        self.next += 1;
        format!("{hint}_w{}", self.next)
    }

    /// A signed wire of `w` bits assigned `expr`; returns its name.
    pub fn swire(&mut self, hint: &str, w: u32, expr: &str) -> String {
        let n = self.fresh(hint);
        self.decls
            .push(format!("wire signed {}{n} = {expr};", range(w)));
        n
    }

    /// An unsigned wire of `w` bits assigned `expr`; returns its name.
    pub fn uwire(&mut self, hint: &str, w: u32, expr: &str) -> String {
        let n = self.fresh(hint);
        self.decls.push(format!("wire {}{n} = {expr};", range(w)));
        n
    }

    /// An undriven unsigned wire of `w` bits (driven by an instance); returns its name.
    pub fn net(&mut self, hint: &str, w: u32) -> String {
        let n = self.fresh(hint);
        self.decls.push(format!("wire {}{n};", range(w)));
        n
    }

    /// A signed register declaration of `w` bits with a given name.
    pub fn sreg(&mut self, name: &str, w: u32) -> String {
        self.decls.push(format!("reg signed {}{name};", range(w)));
        name.to_string()
    }

    /// A `k`-way selection of bit vectors of `w` bits by the unsigned `sel` (value `i` picks
    /// `names[i]`, larger values the last); one name is returned as it is.
    pub fn select_bits(&mut self, sel: &str, names: &[String], w: u32) -> String {
        if names.len() == 1 {
            return names[0].clone();
        }
        let mut e = names.last().unwrap().clone();
        for (i, n) in names.iter().enumerate().rev().skip(1) {
            e = format!("({sel} == {i}) ? {n} : ({e})");
        }
        self.uwire("mux", w, &e)
    }

    /// A register declaration (unsigned, `w` bits) with a given name.
    pub fn reg(&mut self, name: &str, w: u32) -> String {
        self.decls.push(format!("reg {}{name};", range(w)));
        name.to_string()
    }

    /// A statement or block in the module body.
    pub fn stmt(&mut self, s: impl Into<String>) {
        self.body.push(s.into());
    }

    /// A comment line.
    pub fn comment(&mut self, s: &str) {
        self.decls.push(format!("// {s}"));
    }

    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "module {} (", self.name);
        let _ = writeln!(s, "    {}", self.ports.join(",\n    "));
        let _ = writeln!(s, ");");
        for d in &self.decls {
            let _ = writeln!(s, "    {d}");
        }
        for b in &self.body {
            for line in b.lines() {
                let _ = writeln!(s, "    {line}");
            }
        }
        let _ = writeln!(s, "endmodule");
        s
    }
}

/// A ROM of known contents as a module `name(a, y)`: a case statement over every entry.
pub fn rom(name: &str, words: &[i64], value_bits: u32) -> String {
    let ab = unsigned_bits(words.len().saturating_sub(1) as u128);
    let mut s = format!(
        "// ROM {}x{value_bits}, contents fixed at generation\n\
         module {name} (\n    input wire {}a,\n    output reg {}y\n);\n    always @* begin\n        case (a)\n",
        words.len(),
        range(ab),
        range(value_bits)
    );
    let mask = if value_bits >= 64 {
        u64::MAX
    } else {
        (1u64 << value_bits) - 1
    };
    for (i, &v) in words.iter().enumerate() {
        let _ = writeln!(
            s,
            "            {}: y = {};",
            ulit(ab, i as u128),
            ulit(value_bits, (v as u64 & mask) as u128)
        );
    }
    let _ = writeln!(
        s,
        "            default: y = {};\n        endcase\n    end\nendmodule",
        ulit(value_bits, 0)
    );
    s
}

//! Synthesis of a generated unit with yosys, priced in gate equivalents.
//!
//! The script is the one `hw/tests/gates_yosys.rs` checks the primitives with ("cell"
//! mapping), on the unit's hierarchy (not flattened, so each ROM module is priced apart):
//!
//! ```text
//! read_verilog unit.v; synth -top TOP
//! dfflegalize -cell $_DFF_P_ x      # enable and reset flops -> plain DFF + gates
//! abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX; opt_clean; stat
//! ```
//!
//! and the cells are priced with [`LIB_GE`], the NAND2-normalised areas of the public 45 nm
//! library (`docs/gates.md`), flip-flops at 5.67 GE. [`Synth::ge`] is the unit's total
//! (every ROM instance counted), [`Synth::table_ge`] the ROMs' share. Texture memories
//! ([`super::RtlUnit::memories`]) are black boxes (`blackbox MODULE` before `synth`) and
//! count nothing: the texel store is outside the unit's budget, as in the gate model.

use super::RtlUnit;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// Cell areas in GE (cell area / NAND2 area) of the public 45 nm library
/// (`shared/facts/hardware-facts.md`), also the yardstick of `hw/tests/gates_yosys.rs`. NOR2, OR2 and XNOR2 are taken equal to their CMOS duals.
pub const LIB_GE: &[(&str, f64)] = &[
    ("$_NOT_", 0.67),
    ("$_NAND_", 1.0),
    ("$_NOR_", 1.0),
    ("$_AND_", 1.33),
    ("$_OR_", 1.33),
    ("$_XOR_", 2.0),
    ("$_XNOR_", 2.0),
    ("$_MUX_", 2.33),
    ("$_DFF_P_", 5.67),
];

/// Counts of cells (and of submodule instances) per module.
pub type Counts = BTreeMap<String, u32>;

/// A unit's synthesis.
#[derive(Debug, Clone)]
pub struct Synth {
    pub modules: BTreeMap<String, Counts>,
    /// GE of the whole unit.
    pub ge: f64,
    /// GE of the ROM instances (included in `ge`).
    pub table_ge: f64,
    /// Flip-flops of the whole unit.
    pub flops: u32,
}

/// The yosys script for `u`, writing `stat` into `stat`.
pub fn script(u: &RtlUnit, stat: &Path) -> String {
    let boxes: String = u
        .memories
        .iter()
        .map(|mem| format!("blackbox {}; ", mem.module))
        .collect();
    format!(
        "read_verilog unit.v; {boxes}synth -top {}; dfflegalize -cell $_DFF_P_ x; \
         abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX; opt_clean; tee -q -o {} stat",
        u.top,
        stat.display()
    )
}

/// Per-module counts from a `stat` report.
pub fn parse_stat(text: &str) -> BTreeMap<String, Counts> {
    let mut mods = BTreeMap::new();
    let mut cur: Option<String> = None;
    for line in text.lines() {
        let l = line.trim();
        if let Some(name) = l.strip_prefix("=== ").and_then(|r| r.strip_suffix(" ===")) {
            cur = Some(name.trim_start_matches('\\').to_string());
            mods.entry(cur.clone().unwrap()).or_insert_with(Counts::new);
            continue;
        }
        if l.starts_with("design hierarchy") {
            cur = None;
        }
        let Some(m) = &cur else { continue };
        let mut it = l.split_whitespace();
        if let (Some(cell), Some(n), None) = (it.next(), it.next(), it.next()) {
            if let Ok(n) = n.parse::<u32>() {
                if cell != "Number" && !cell.ends_with(':') {
                    *mods
                        .get_mut(m)
                        .unwrap()
                        .entry(cell.to_string())
                        .or_insert(0) += n;
                }
            }
        }
    }
    mods
}

fn area(cell: &str) -> Option<f64> {
    LIB_GE.iter().find(|(c, _)| *c == cell).map(|(_, a)| *a)
}

/// GE and flip-flops of module `name`, its instances included; the black boxes `boxes`
/// (texture memories) count nothing.
pub fn price(
    mods: &BTreeMap<String, Counts>,
    name: &str,
    boxes: &[&str],
) -> Result<(f64, u32), String> {
    let counts = mods
        .get(name)
        .ok_or_else(|| format!("module {name} not in the stat report"))?;
    let (mut ge, mut ff) = (0.0, 0);
    for (cell, &n) in counts {
        if let Some(a) = area(cell) {
            ge += a * n as f64;
            if cell == "$_DFF_P_" {
                ff += n;
            }
        } else if boxes.contains(&cell.as_str()) {
            continue;
        } else if mods.contains_key(cell) {
            let (g, f) = price(mods, cell, boxes)?;
            ge += g * n as f64;
            ff += f * n;
        } else {
            return Err(format!("cell {cell} (in {name}) has no area in LIB_GE"));
        }
    }
    Ok((ge, ff))
}

/// The yosys binary: `$YOSYS` or `yosys` on `PATH`.
pub fn yosys_bin() -> String {
    std::env::var("YOSYS").unwrap_or_else(|_| "yosys".into())
}

/// Synthesise `u` in `dir` (its Verilog is written there as `unit.v`).
pub fn synthesise(u: &RtlUnit, dir: &Path) -> Result<Synth, String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("unit.v"), &u.verilog).map_err(|e| e.to_string())?;
    let stat = dir.join("stat.txt");
    let o = Command::new(yosys_bin())
        .current_dir(dir)
        .args(["-q", "-p"])
        .arg(script(u, &stat))
        .output()
        .map_err(|e| format!("running yosys: {e}"))?;
    if !o.status.success() {
        return Err(format!(
            "{}: yosys failed: {}{}",
            u.top,
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let text = std::fs::read_to_string(&stat).map_err(|e| e.to_string())?;
    let modules = parse_stat(&text);
    let boxes: Vec<&str> = u.memories.iter().map(|mem| mem.module.as_str()).collect();
    let (ge, flops) = price(&modules, &u.top, &boxes)?;
    let mut table_ge = 0.0;
    for (t, n) in &u.tables {
        table_ge += price(&modules, t, &boxes)?.0 * *n as f64;
    }
    Ok(Synth {
        modules,
        ge,
        table_ge,
        flops,
    })
}

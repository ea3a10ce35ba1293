//! `bumpsim gates CONFIG [--synth] [--json]`: the engine's gate figures without rendering
//! (`run::gates`: the report's `gates`, the model's estimate of `docs/gates.md`) and, with
//! `--synth`, beside them the yosys synthesis of every unit that has a Verilog generator
//! (`bumpsim_hw::rtl`, `docs/rtl.md`), priced with the same cell areas as `bumpsim rtl
//! --synth`. Synthesis runs in a temporary directory that is removed afterwards; a failing
//! yosys (or none installed) is an error (exit 1) naming the unit, never a silent model-only
//! table.

use crate::rtl_cmd::{engine_unit, generate, module_name};
use crate::Failure;
use bumpsim_hw::rtl::synth::{self, Synth};
use bumpsim_hw::units::RopDatapath;
use bumpsim_hw::Unit;
use bumpsim_pipeline::config::Loaded;
use bumpsim_pipeline::engine;
use bumpsim_pipeline::report::{Gates, VERSION};
use bumpsim_pipeline::run::build_scene;
use serde_json::{json, Value};
use std::fmt::Write as _;

/// One unit's synthesis beside its model figures.
struct Row {
    name: String,
    model: f64,
    /// The model's loadable tables (in `model`).
    model_tables: f64,
    /// The model of the generated hardware where the unit's budget prices other hardware
    /// (`Unit::generated_gates`: the texture shaders' configured programs), total and tables:
    /// synthesis is compared with it.
    generated: Option<(f64, f64)>,
    /// `Err`: no generator for this kind (or its configuration), with the reason.
    synth: Result<Synth, String>,
    /// A pass's ROP (`Engine::rops`), not a config unit.
    rop: bool,
}

/// Synthesise every unit with a generator (one yosys process per unit, concurrently); the
/// others get the reason they are not.
fn synthesise(l: &Loaded) -> Result<Vec<Row>, Failure> {
    let scene = build_scene(l)?;
    let eng = engine::build(l, &scene)?;
    let dir = tempfile::Builder::new()
        .prefix("bumpsim-gates-")
        .tempdir()
        .map_err(|e| Failure::Internal(format!("temporary directory for yosys: {e}")))?;
    let table = &l.config.cost;
    let mut units = Vec::new();
    for uc in &l.config.engine.units {
        let unit = engine_unit(&eng, &uc.name)?;
        let budget = unit.gates(&uc.cost(table));
        let other = unit
            .generated_gates(&uc.cost(table))
            .map(|b| (b.total(), b.tables()));
        let generated = match generate(&uc.unit, unit, &scene, &module_name(&uc.name)) {
            Ok(Some(g)) => Ok(g.rtl),
            Ok(None) => Err("no Verilog generator for this kind".to_string()),
            Err(e) => Err(format!("not generated: {e}")),
        };
        units.push((uc.name.clone(), budget, other, generated, false));
    }
    // every pass's ROP (`rtl::rop`), rows `rop`, `rop.1`, ...: the figures beside the total
    for (label, _, rop) in eng.rops() {
        let u = RopDatapath::new(rop);
        let rtl = bumpsim_hw::rtl::rop::rtl(&u, &module_name(&label));
        units.push((label, u.gates(table), None, Ok(rtl), true));
    }
    let synthesised: Vec<Option<Result<Synth, String>>> = std::thread::scope(|sc| {
        let jobs: Vec<_> = units
            .iter()
            .map(|(name, _, _, g, _)| {
                let d = dir.path().join(name);
                g.as_ref()
                    .ok()
                    .map(|rtl| sc.spawn(move || synth::synthesise(rtl, &d)))
            })
            .collect();
        jobs.into_iter()
            .map(|j| {
                j.map(|h| {
                    h.join()
                        .unwrap_or_else(|_| Err("the synthesis thread panicked".into()))
                })
            })
            .collect()
    });
    let mut rows = Vec::new();
    for ((name, budget, other, generated, rop), s) in units.into_iter().zip(synthesised) {
        let synth = match (generated, s) {
            (Ok(_), Some(Ok(s))) => Ok(s),
            (Ok(_), Some(Err(e))) => {
                return Err(Failure::Internal(format!("unit {name}: {e}")));
            }
            (Err(why), _) => Err(why),
            (Ok(_), None) => Err("not synthesised".to_string()),
        };
        rows.push(Row {
            name,
            model: budget.total(),
            model_tables: budget.tables(),
            generated: other,
            synth,
            rop,
        });
    }
    Ok(rows)
}

fn synth_json(r: &Row) -> Value {
    match &r.synth {
        Ok(s) => {
            let (ml, sl) = (r.logic_model(), s.ge - s.table_ge);
            let mut v = json!({
                "ge": round2(s.ge),
                "rom_ge": round2(s.table_ge),
                "flops": s.flops,
                "logic_model_ge": round2(ml),
                "logic_synth_ge": round2(sl),
                "logic_ratio": round4(ml / sl),
            });
            if let Some((total, _)) = r.generated {
                // the model of the generated hardware, not the unit's budget
                v["generated_model_ge"] = json!(round2(total));
            }
            v
        }
        Err(why) => json!({ "none": why }),
    }
}

impl Row {
    /// The model's logic that synthesis is compared with: of the generated hardware where
    /// the unit's budget prices other hardware, else of the budget.
    fn logic_model(&self) -> f64 {
        match self.generated {
            Some((total, tables)) => total - tables,
            None => self.model - self.model_tables,
        }
    }
}

fn round2(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

fn round4(x: f64) -> f64 {
    (x * 10_000.0).round() / 10_000.0
}

/// The text table: the model per unit and, with synthesis, yosys beside it.
fn text(l: &Loaded, g: &Gates, rows: Option<&[Row]>) -> String {
    let mut s = format!(
        "bumpsim {VERSION}  config {}  hash {}\n\
         gates: the model's estimate (docs/gates.md), no render; tables {:.1} GE of it, \
         built as {} (cost.tables){}\n",
        l.config.name,
        &l.hash[..16.min(l.hash.len())],
        g.memory,
        g.tables,
        g.per_unit
            .iter()
            .flat_map(|(name, u)| {
                let unit = u.tables.map(|t| format!(", {name}'s as {t}"));
                let roles = u
                    .table_kinds
                    .iter()
                    .map(move |(r, k)| format!(", {name}'s {r} table as {k}"));
                unit.into_iter().chain(roles)
            })
            .collect::<String>()
    );
    if rows.is_some() {
        s.push_str(
            "yosys: `synth; abc -g AND,NAND,OR,NOR,XOR,XNOR,MUX` priced with the 45 nm cell \
             areas, flip-flops 5.67 GE (docs/rtl.md)\n\
             logic: the total without the tables (the model's loadable tables and ROMs; yosys's \
             ROM modules of their contents)\n",
        );
    }
    s.push('\n');
    let _ = write!(s, "  {:<14} {:<16} {:>10}", "unit", "kind", "model GE");
    if rows.is_some() {
        let _ = write!(
            s,
            " {:>10} {:>11} {:>11} {:>7}  tables model / yosys ROM",
            "yosys GE", "logic model", "logic yosys", "ratio"
        );
    }
    s.push('\n');
    for (name, u) in &g.per_unit {
        let _ = write!(s, "  {:<14} {:<16} {:>10.1}", name, u.kind, u.total);
        if let Some(rows) = rows {
            match rows
                .iter()
                .find(|r| !r.rop && &r.name == name)
                .map(|r| (r, &r.synth))
            {
                Some((r, Ok(y))) => {
                    let (ml, sl) = (r.logic_model(), y.ge - y.table_ge);
                    let _ = write!(
                        s,
                        " {:>10.1} {:>11.1} {:>11.1} {:>7.3}",
                        y.ge,
                        ml,
                        sl,
                        ml / sl
                    );
                    if r.model_tables > 0.0 || y.table_ge > 0.0 {
                        let _ = write!(s, "  {:.1} / {:.1}", r.model_tables, y.table_ge);
                    }
                    if r.generated.is_some() {
                        s.push_str(
                            "  (logic model: the configured programs' datapath, which the \
                             Verilog is; the unit's budget is the programmable part)",
                        );
                    }
                }
                Some((_, Err(why))) => {
                    let _ = write!(s, "  - ({why})");
                }
                // the interpolator: not a config unit
                None => s.push_str("  - (no Verilog generator)"),
            }
        }
        s.push('\n');
    }
    let _ = writeln!(s, "  {:<31} {:>10.1}", "total", g.total);
    let _ = write!(s, "  (beside the total: rop {:.1} GE", g.rop.total);
    if let Some(c) = &g.texture_cache {
        let _ = write!(
            s,
            ", texture cache {:.1} GE, storage {:.1} of it",
            c.total, c.memory
        );
    }
    s.push_str(")\n");
    if let Some(rows) = rows {
        // each pass's ROP state synthesised (the report's figure is their union)
        for r in rows.iter().filter(|r| r.rop) {
            if let Ok(y) = &r.synth {
                let _ = writeln!(
                    s,
                    "  {:<14} {:<16} {:>10.1} {:>10.1} {:>11.1} {:>11.1} {:>7.3}",
                    r.name,
                    "rop",
                    r.model,
                    y.ge,
                    r.model,
                    y.ge,
                    r.model / y.ge
                );
            }
        }
    }
    if let Some(rows) = rows {
        let done: Vec<&Row> = rows.iter().filter(|r| !r.rop && r.synth.is_ok()).collect();
        let (m, y) = done.iter().fold((0.0, 0.0), |(m, y), r| {
            let s = r.synth.as_ref().map_or(0.0, |s| s.ge);
            (m + r.generated.map_or(r.model, |g| g.0), y + s)
        });
        let _ = writeln!(
            s,
            "  synthesised {} of {} units: model {m:.1} GE, yosys {y:.1} GE",
            done.len(),
            g.per_unit.len()
        );
    }
    s
}

/// Run the command.
pub fn execute(l: &Loaded, synth_on: bool, json_out: bool) -> Result<(), Failure> {
    let g = bumpsim_pipeline::run::gates(l)?;
    let rows = if synth_on { Some(synthesise(l)?) } else { None };
    if json_out {
        let mut v = serde_json::to_value(&g).map_err(|e| Failure::Internal(e.to_string()))?;
        if let (Some(rows), Some(per_unit)) = (&rows, v["per_unit"].as_object_mut()) {
            for r in rows.iter().filter(|r| !r.rop) {
                if let Some(u) = per_unit.get_mut(&r.name) {
                    u["synth"] = synth_json(r);
                }
            }
        }
        if let Some(rows) = &rows {
            // each pass's ROP state: `rop`, `rop1`, ... (the budget above is their union)
            let rops: serde_json::Map<String, Value> = rows
                .iter()
                .filter(|r| r.rop)
                .map(|r| {
                    let mut j = synth_json(r);
                    j["model_ge"] = json!(round2(r.model));
                    (r.name.clone(), j)
                })
                .collect();
            v["rop"]["synth"] = Value::Object(rops);
        }
        let out = json!({
            "version": VERSION,
            "name": l.config.name,
            "config_hash": l.hash,
            "gates": v,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&out).map_err(|e| Failure::Internal(e.to_string()))?
        );
    } else {
        print!("{}", text(l, &g, rows.as_deref()));
    }
    Ok(())
}

//! An engine: hardware units wired by a config into a pipeline.
//!
//! Wiring names signals: attributes by their name, unit outputs as `unit.port`. The units form
//! a DAG; it is checked for cycles and laid out in a topological order (config order among
//! independent units) as a chain of clocked stages. Every signal has a slot in the token a
//! fragment carries down the chain, so a unit may read any earlier unit's output (a dependent
//! lookup, a texture shader stage reading an earlier stage): this is how fixed-function pipes
//! carry values in their pipeline registers. An input may also read a wire expression over
//! earlier signals (swizzles, lane selects, concatenation: [`wire`]). See docs/ARCHITECTURE.md.

pub mod attributes;
pub mod frame_inputs;
pub mod frames;
pub mod memory;
pub mod palette;
pub mod units;
pub mod wire;

use crate::config::{AttributeConfig, InputError, Loaded};
use crate::raster::packet::{Field, PacketLayout};
use crate::scene::Scene;
use bumpsim_hw::units::Rop;
use bumpsim_hw::{GateBudget, PortSpec, Stage, Wire};
use std::collections::{BTreeMap, BTreeSet};
use units::BuildCtx;

/// A signal: where it lives in the token and what it carries.
#[derive(Debug, Clone)]
pub struct Signal {
    pub name: String,
    pub slot: usize,
    pub spec: PortSpec,
}

/// The engine's output: a signal or a wire expression over signals (`cat(shade.color,
/// alpha.t)` for RGBA).
#[derive(Debug, Clone)]
pub struct Output {
    pub name: String,
    pub spec: PortSpec,
    pub wire: Wire,
}

/// A wired engine, ready to simulate.
pub struct Engine {
    pub stages: Vec<Stage>,
    pub signals: Vec<Signal>,
    pub attributes: Vec<AttributeConfig>,
    /// The colour written to the frame buffer.
    pub output: Output,
    /// Bits per texel of each texture the units hold (unit name, bits).
    pub texels: Vec<(String, u32)>,
    pub gates: Vec<(String, GateBudget)>,
    /// The error of each quantized normal map (`QuantizedNormals` units, config order) and
    /// of its mip levels, in texel space: the report's `normal_maps`.
    pub normal_maps: Vec<crate::quantize::NormalMapError>,
    /// The raster operations writing the output to the framebuffer.
    pub rop: Rop,
    /// The passes after the first (`engine.passes`), in order.
    pub passes: Vec<Pass>,
    /// The texture cache the report simulates on the texel reads (`engine.texture_cache`).
    pub texture_cache: Option<crate::config::TextureCacheConfig>,
    /// The textures the host builds from the frame's inputs, built again each frame.
    frame_textures: Vec<memory::FrameTexture>,
    /// Each stage's cost table (the config's, with the unit's table kinds), as `gates` priced it.
    costs: Vec<bumpsim_hw::CostTable>,
}

/// A rendering pass after the first: its output and the ROP state that writes it.
pub struct Pass {
    pub name: String,
    pub output: Output,
    pub rop: Rop,
}

impl Engine {
    /// Take the inputs of the frame of `scene` (the same hardware, another light, camera,
    /// material or model transform), as the hardware does before each frame: every unit takes
    /// the frame's inputs ([`bumpsim_hw::Unit::begin_frame`]), and the host builds again each
    /// texture computed from them and uploads it where its words changed
    /// ([`bumpsim_hw::Unit::upload`]). The engine is then the one [`build`] gives for that
    /// scene. Errors name the unit or the texture.
    pub fn begin_frame(&mut self, scene: &Scene) -> Result<(), String> {
        let frame = frame_inputs::of(scene);
        for s in &mut self.stages {
            s.begin_frame(&frame)
                .map_err(|m| format!("unit {:?}: {m}", s.name))?;
        }
        for f in &mut self.frame_textures {
            let name = f.texture.name().to_string();
            let new = (f.recipe)(scene, &name).map_err(|m| format!("texture {name:?}: {m}"))?;
            if new.same_contents(&f.texture) {
                continue;
            }
            let new = std::sync::Arc::new(new);
            for s in &mut self.stages {
                s.upload(&f.texture, &new);
            }
            f.texture = new;
        }
        // the hardware is the frame's too: a table priced by its contents (a ROM) cannot
        // follow the frame
        for ((s, (_, built)), cost) in self.stages.iter().zip(&self.gates).zip(&self.costs) {
            let now = s.unit().gates(cost);
            if now != *built {
                return Err(format!(
                    "unit {:?}: the frame changes its gate estimate from {:.1} to {:.1} GE: a \
                     table priced by its contents (a ROM, `tables: Rom`) cannot follow the \
                     frame's inputs; expected a loadable table kind, or the same table inputs \
                     (lights, material) in every frame",
                    s.name,
                    built.total(),
                    now.total()
                ));
            }
        }
        Ok(())
    }

    pub fn slots(&self) -> usize {
        self.signals.len()
    }

    /// Whether a unit may kill fragments (then the depth test must follow shading).
    pub fn kills(&self) -> bool {
        self.stages.iter().any(|s| s.unit().can_kill())
    }

    /// Whether the depth test must wait for the ROP: a unit may kill, the ROP tests alpha, or
    /// its depth test is not the rasterizer's early LESS with depth writes.
    pub fn late_depth(&self) -> bool {
        let p = self.rop.params();
        self.kills()
            || p.alpha_test.is_some()
            || p.depth != bumpsim_hw::units::rop::Compare::Less
            || !p.depth_write
    }

    /// The signals the passes write, each once, the first pass's first: what the engine
    /// computes for the ROP.
    pub fn pass_outputs(&self) -> Vec<&Output> {
        let mut out = vec![&self.output];
        for p in &self.passes {
            if !out.iter().any(|o| o.name == p.output.name) {
                out.push(&p.output);
            }
        }
        out
    }

    /// The gate budget of the ROP that runs every pass: the first pass's, and each circuit
    /// that a later pass needs and it lacks (a blender, an alpha test, another colour
    /// conversion), once: the union of the passes' budgets by item, each at its dearest.
    /// Every pass's ROP state with a label and the pass's name: `rop` for the first pass
    /// (`engine.rop`, name `first`), `rop.1`, `rop.2`, ... for `engine.passes` (a unit name
    /// has no dot, so no label is a unit's).
    pub fn rops(&self) -> Vec<(String, &str, &Rop)> {
        std::iter::once(("rop".to_string(), "first", &self.rop))
            .chain(
                self.passes
                    .iter()
                    .enumerate()
                    .map(|(k, p)| (format!("rop.{}", k + 1), p.name.as_str(), &p.rop)),
            )
            .collect()
    }

    pub fn rop_gates(&self, t: &bumpsim_hw::CostTable) -> GateBudget {
        let mut g = self.rop.gates(t);
        for p in &self.passes {
            for item in p.rop.gates(t).items {
                match g.items.iter_mut().find(|i| i.what == item.what) {
                    Some(i) if i.ge < item.ge => *i = item,
                    Some(_) => {}
                    None => g.items.push(item),
                }
            }
        }
        g
    }

    /// Triangle packet from geometry to rasterizer: per vertex x, y, z and 1/w as 32-bit words
    /// (as the baseline) plus every attribute in its encoding.
    pub fn packet(&self) -> PacketLayout {
        let mut per_vertex: Vec<Field> = ["x", "y", "z", "1/w"]
            .iter()
            .map(|n| Field {
                name: n.to_string(),
                lanes: 1,
                bits: 32,
            })
            .collect();
        let field = |a: &AttributeConfig| Field {
            name: a.name.clone(),
            lanes: a.source.lanes() as u32,
            bits: a.enc.width(),
        };
        per_vertex.extend(
            self.attributes
                .iter()
                .filter(|a| !a.source.per_triangle())
                .map(field),
        );
        let per_triangle = self
            .attributes
            .iter()
            .filter(|a| a.source.per_triangle())
            .map(field)
            .collect();
        PacketLayout {
            per_vertex,
            per_triangle,
        }
    }
}

/// Build the engine of a loaded config for `scene`. Units hold their assets (textures,
/// tables) and evaluate in either mode, so one engine serves both.
pub fn build(l: &Loaded, scene: &Scene) -> Result<Engine, InputError> {
    let cfg = &l.config.engine;
    let memory = memory::TextureMemory::default();
    let frame = frame_inputs::of(scene);
    let mut signals: Vec<Signal> = cfg
        .attributes
        .iter()
        .enumerate()
        .map(|(slot, a)| Signal {
            name: a.name.clone(),
            slot,
            spec: PortSpec::new(&a.name, a.source.lanes(), a.enc),
        })
        .collect();
    let unit_names: BTreeMap<&str, usize> = cfg
        .units
        .iter()
        .enumerate()
        .map(|(i, u)| (u.name.as_str(), i))
        .collect();
    for (i, u) in cfg.units.iter().enumerate() {
        let field = format!("engine.units[{i}].name");
        let needle = format!("\"{}\"", u.name);
        // a unit's name also names its files (`bumpsim rtl`, `gates --synth`) and signals
        let plain = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if u.name.is_empty() || !u.name.chars().all(plain) || unit_names[u.name.as_str()] != i {
            return Err(l.error(
                &field,
                &needle,
                format!(
                    "unit name {:?}: expected a unique name of ASCII letters, digits, '_' and '-'",
                    u.name
                ),
            ));
        }
        if crate::sim::FIXED_UNITS.contains(&u.name.as_str()) {
            return Err(l.error(
                &field,
                &needle,
                format!(
                    "unit name {:?} names a unit of the front or back end in reports and traces: \
                     expected another name (reserved: {})",
                    u.name,
                    crate::sim::FIXED_UNITS.join(", ")
                ),
            ));
        }
        if signals.iter().any(|s| s.name == u.name) {
            return Err(l.error(
                &field,
                &needle,
                format!(
                    "unit name {:?} is also an attribute name: expected distinct names",
                    u.name
                ),
            ));
        }
    }
    let order = topo_order(l)?;
    let mut stages = Vec::new();
    let mut texels = Vec::new();
    let mut gates = Vec::new();
    let mut normal_maps = Vec::new();
    let mut costs = Vec::new();
    for i in order {
        let u = &cfg.units[i];
        let field = format!("engine.units[{i}]");
        let needle = format!("\"{}\"", u.name);
        let err = |f: &str, m: String| l.error(&format!("{field}.{f}"), &needle, m);
        let ctx = BuildCtx {
            scene,
            memory: &memory,
            unit: &u.name,
            frame: &frame,
        };
        let names = u.unit.input_names(&ctx);
        for port in u.inputs.keys().chain(u.expect.keys()) {
            if !names.contains(port) {
                return Err(err(
                    "inputs",
                    format!(
                        "unit {:?} has no input port {port:?}: expected {}",
                        u.name,
                        names.join(", ")
                    ),
                ));
            }
        }
        let mut ins = BTreeMap::new();
        let mut wires = BTreeMap::new();
        for port in &names {
            let src = u.inputs.get(port).ok_or_else(|| {
                err(
                    "inputs",
                    format!(
                        "input port {port:?} of unit {:?} is not wired: expected a signal",
                        u.name
                    ),
                )
            })?;
            let r = wire::resolve(src, &signals).map_err(|m| err(&format!("inputs.{port}"), m))?;
            if let Some(&w) = u.expect.get(port) {
                if w != r.spec.enc.width() {
                    return Err(err(&format!("expect.{port}"), format!("port width mismatch: {}.{port} expects {w} bits per lane, {src} carries {}", u.name, r.spec.enc.width())));
                }
            }
            ins.insert(port.clone(), r.spec.clone());
            wires.insert(port.clone(), r);
        }
        let unit = match &u.unit {
            units::UnitSpec::QuantizedNormals(q) => {
                let (unit, m) = q.build_measured(&ins, &ctx).map_err(|m| err("unit", m))?;
                normal_maps.push((i, m));
                unit
            }
            spec => spec.build(&ins, &ctx).map_err(|m| err("unit", m))?,
        };
        let mut in_wires = Vec::new();
        for p in unit.inputs() {
            let src = &u.inputs[&p.name];
            let r = &wires[&p.name];
            if r.spec.lanes != p.lanes {
                return Err(err(
                    &format!("inputs.{}", p.name),
                    format!(
                        "port {} takes {} lanes, {src} carries {}",
                        p.name, p.lanes, r.spec.lanes
                    ),
                ));
            }
            if r.spec.enc != p.enc {
                return Err(err(
                    &format!("inputs.{}", p.name),
                    format!("port width mismatch: {}.{} is {} ({} bits per lane) but {src} carries {} ({} bits); every vector input of one unit must share a format", u.name, p.name, p.enc, p.enc.width(), r.spec.enc, r.spec.enc.width()),
                ));
            }
            in_wires.push(r.wire);
        }
        let mut out_slots = Vec::new();
        for p in unit.outputs() {
            let slot = signals.len();
            signals.push(Signal {
                name: format!("{}.{}", u.name, p.name),
                slot,
                spec: p.clone(),
            });
            out_slots.push(slot);
        }
        if let Some(r) = unit.textures().first() {
            texels.push((u.name.clone(), r.texture.bits_per_texel()));
        }
        check_table_kinds(u, unit.as_ref(), &l.config.cost).map_err(|m| err("table_kinds", m))?;
        let cost = u.cost(&l.config.cost);
        gates.push((u.name.clone(), unit.gates(&cost)));
        costs.push(cost);
        stages.push(Stage::new(u.name.clone(), unit, in_wires, out_slots));
    }
    let (output, rop) = pass_output(l, &signals, "engine", &cfg.output, cfg.rop)?;
    if cfg.passes.len() + 1 > crate::config::MAX_PASSES {
        return Err(l.error(
            "engine.passes",
            "passes",
            format!(
                "{} passes after the first: expected at most {}",
                cfg.passes.len(),
                crate::config::MAX_PASSES - 1
            ),
        ));
    }
    if let Some(c) = &cfg.texture_cache {
        c.check()
            .map_err(|(field, m)| l.error(&format!("engine.texture_cache.{field}"), field, m))?;
    }
    let mut passes = Vec::with_capacity(cfg.passes.len());
    for (i, p) in cfg.passes.iter().enumerate() {
        let field = format!("engine.passes[{i}]");
        let (output, rop) = pass_output(l, &signals, &field, &p.output, p.rop)?;
        if p.rop.color_bits != cfg.rop.color_bits {
            return Err(l.error(
                &format!("{field}.rop.color_bits"),
                "color_bits",
                format!(
                    "{} bits per channel: expected engine.rop's {} (the passes write one framebuffer)",
                    p.rop.color_bits, cfg.rop.color_bits
                ),
            ));
        }
        passes.push(Pass {
            name: p.name.clone(),
            output,
            rop,
        });
    }
    normal_maps.sort_by_key(|m| m.0);
    Ok(Engine {
        rop,
        passes,
        texture_cache: cfg.texture_cache,
        stages,
        signals,
        attributes: cfg.attributes.clone(),
        output,
        texels,
        gates,
        normal_maps: normal_maps.into_iter().map(|m| m.1).collect(),
        frame_textures: memory.into_frame_textures(),
        costs,
    })
}

/// The output of a pass (`field`: `engine` or `engine.passes[i]`) and its ROP: the signal
/// `name` resolved, RGB or, when `rop` tests or blends with alpha, RGBA.
fn pass_output(
    l: &Loaded,
    signals: &[Signal],
    field: &str,
    name: &str,
    rop: bumpsim_hw::units::rop::RopParams,
) -> Result<(Output, Rop), InputError> {
    let needle = format!("\"{name}\"");
    let output = wire::resolve(name, signals)
        .map(|r| Output {
            name: name.to_string(),
            spec: r.spec,
            wire: r.wire,
        })
        .map_err(|m| l.error(&format!("{field}.output"), &needle, m))?;
    let rgba = output.spec.lanes == 4;
    if output.spec.lanes != 3 && !(rgba && rop.reads_alpha()) {
        return Err(l.error(
            &format!("{field}.output"),
            &needle,
            format!(
                "signal {name:?} has {} lanes: expected an RGB signal of 3 (or RGBA of 4 when {field}.rop tests or blends with alpha)",
                output.spec.lanes
            ),
        ));
    }
    let enc = output.spec.enc;
    let rop = Rop::new(rop, enc, rgba.then_some(enc), l.config.raster.depth_bits)
        .map_err(|m| l.error(&format!("{field}.rop"), "rop", m))?;
    Ok((output, rop))
}

/// Units in dependency order (config order among independent ones); a cycle is an error.
fn topo_order(l: &Loaded) -> Result<Vec<usize>, InputError> {
    let units = &l.config.engine.units;
    let index: BTreeMap<&str, usize> = units
        .iter()
        .enumerate()
        .map(|(i, u)| (u.name.as_str(), i))
        .collect();
    let deps: Vec<BTreeSet<usize>> = units
        .iter()
        .map(|u| {
            u.inputs
                .values()
                .flat_map(|e| wire::parts(e))
                .filter_map(|s| {
                    s.split_once('.')
                        .and_then(|(unit, _)| index.get(unit).copied())
                })
                .collect()
        })
        .collect();
    let mut done = vec![false; units.len()];
    let mut order = Vec::new();
    while order.len() < units.len() {
        let next = (0..units.len()).find(|&i| !done[i] && deps[i].iter().all(|&d| done[d]));
        match next {
            Some(i) => {
                done[i] = true;
                order.push(i);
            }
            None => {
                let stuck: Vec<&str> = (0..units.len())
                    .filter(|&i| !done[i])
                    .map(|i| units[i].name.as_str())
                    .collect();
                let first = stuck[0];
                return Err(l.error(
                    "engine.units",
                    &format!("\"{first}\""),
                    format!(
                        "the wiring has a cycle among units {}: expected a DAG",
                        stuck.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(order)
}

/// Every role of a unit's `table_kinds` names a table the unit has: its memory is priced
/// differently as SRAM and as flip-flop RAM (a unit without such a table prices both alike).
fn check_table_kinds(
    u: &crate::config::UnitConfig,
    unit: &dyn bumpsim_hw::Unit,
    cost: &bumpsim_hw::gates::CostTable,
) -> Result<(), String> {
    use bumpsim_hw::gates::{MemoryKind, TableRole};
    for &role in u.table_kinds.keys() {
        let priced = |k: MemoryKind| {
            let mut t = *cost;
            t.by_role[role as usize] = Some(k);
            unit.gates(&t).memory()
        };
        if priced(MemoryKind::Sram) == priced(MemoryKind::FlopRam) {
            let has: Vec<String> = TableRole::ALL
                .iter()
                .filter(|&&r| {
                    let mut a = *cost;
                    let mut b = *cost;
                    a.by_role[r as usize] = Some(MemoryKind::Sram);
                    b.by_role[r as usize] = Some(MemoryKind::FlopRam);
                    unit.gates(&a).memory() != unit.gates(&b).memory()
                })
                .map(|r| format!("{r:?}"))
                .collect();
            return Err(format!(
                "{role:?}: a {} unit has no {} table; the roles of its tables: {}",
                unit.kind(),
                role.name(),
                if has.is_empty() {
                    "none".to_string()
                } else {
                    has.join(", ")
                }
            ));
        }
    }
    Ok(())
}

//! `bumpsim rtl CONFIG --out DIR [--cosim N] [--synth]`: Verilog of the engine's units
//! (`bumpsim_hw::rtl`, `docs/rtl.md`).
//!
//! For every unit with a generator (Dot3, PowerTable, Shade, BumpBlend, Modulate, Normalize, Perturb, Turbulence,
//! TexFetch, EmbossFilter, CullFragment, FbBlend, QuantizedNormals, TexramFrame, QuatFrame)
//! the unit's parameters are taken from its config spec, the encodings of the signals wired to
//! it (the built engine's unit) and the scene (material, bump lights, the emboss filter's
//! heights for its default bevel width), and the unit is rebuilt
//! from them with the hw constructors; the rebuilt unit must have the engine's gate budget (the
//! same structure) and, with `--cosim`, the same outputs as the engine's unit on every vector.
//! The quantized normal maps unit is the exception: its Verilog is generated from the
//! engine's own unit (`Unit::as_any`), whose normal table and index texture the engine baked.
//! Writes `DIR/NAME.v` (the unit and its ROMs) and `DIR/NAME.regs` (the host-loaded register
//! words: address, width, value, what) and, for a unit with a texture memory, `DIR/MODULE.hex` (its
//! `$readmemh` contents); `--cosim N` replays N vectors per unit with iverilog
//! in `DIR/cosim/NAME/`; `--synth` runs yosys and prints the model's GE beside synthesis.

use crate::rtl_top;
use crate::Failure;
use bumpsim_hw::rtl::{
    self, synth, testbench, vectors, Dot3Rtl, ModulateRtl, PowerTableRtl, RtlUnit, ShadeRtl,
};
use bumpsim_hw::units::{
    BlendKind, BumpBlend, BumpBlendParams, CullFragment, EmbossFilter, FbBlend, LightState,
    Normalize, Perturb, QuantizedFetch, QuatFrame, RopDatapath, ShadeInputs, ShadeParams, TexFetch,
    TexramFrame,
};
use bumpsim_hw::{Mode, PortSpec, Sampler, Unit, Word};
use bumpsim_pipeline::config::{InputError, Loaded};
use bumpsim_pipeline::engine::{self, units::UnitSpec};
use bumpsim_pipeline::run::build_scene;
use bumpsim_pipeline::scene::Scene;
use std::fmt::Write as _;
use std::path::Path;

/// A generated unit: the Verilog and the unit rebuilt from the same parameters (`None`: the
/// Verilog is generated from the engine's unit itself, whose assets are baked by the engine).
pub(crate) struct Generated {
    pub(crate) rtl: RtlUnit,
    pub(crate) model: Option<Box<dyn Unit>>,
}

fn enc_of(ports: &[PortSpec], name: &str) -> Option<bumpsim_hw::Encoding> {
    ports.iter().find(|p| p.name == name).map(|p| p.enc)
}

/// The bump lights' indices (as `BuildCtx::bump_lights`).
fn bump_lights(scene: &Scene) -> Vec<usize> {
    (0..scene.lights.len())
        .filter(|&i| scene.lights[i].bump)
        .collect()
}

/// The blend unit's parameters as `BumpBlendSpec::params` computes them.
fn blend_params(s: &engine::units::BumpBlendSpec, scene: &Scene) -> BumpBlendParams {
    let to_object = scene.model.inverse();
    let origin = scene.model.transform_point3(Default::default());
    let v = to_object
        .transform_vector3(scene.camera.view_dir(origin))
        .normalize_or_zero();
    let lights = bump_lights(scene)
        .into_iter()
        .map(|i| {
            let light = &scene.lights[i];
            let l = to_object
                .transform_vector3(light.dir_from(origin))
                .normalize_or_zero();
            let w = match s.kind {
                BlendKind::Diffuse => scene.material.diffuse,
                BlendKind::Specular => scene.material.specular,
                BlendKind::Both => [1.0; 3],
            };
            LightState {
                color: std::array::from_fn(|c| light.color[c] * w[c]),
                l: l.to_array(),
                h: (l + v).normalize_or_zero().to_array(),
                k: 1.0,
            }
        })
        .collect();
    BumpBlendParams {
        kind: s.kind,
        lights,
        l_source: s.l_source,
        h_source: s.h_source,
        spec: s.spec,
        shininess: s.shininess.unwrap_or(scene.material.shininess),
        state: s.state,
        color: s.color,
        dot: s.dot,
        out: s.out,
        selective: s.selective,
        parallel: s.parallel,
    }
}

/// The engine's unit named `name` (every config unit is one).
pub(crate) fn engine_unit<'a>(
    eng: &'a engine::Engine,
    name: &str,
) -> Result<&'a dyn Unit, Failure> {
    eng.stages
        .iter()
        .find(|s| s.name == name)
        .map(|s| s.unit())
        .ok_or_else(|| Failure::Internal(format!("unit {name} not in the engine")))
}

/// Verilog module name for a unit instance.
pub(crate) fn module_name(unit: &str) -> String {
    let s: String = unit
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    format!("bumpsim_{s}")
}

/// The generator for one unit; `Ok(None)` for a kind without one.
pub(crate) fn generate(
    spec: &UnitSpec,
    unit: &dyn Unit,
    scene: &Scene,
    top: &str,
) -> Result<Option<Generated>, String> {
    let ins = unit.inputs();
    let first = || ins.first().map(|p| p.enc).ok_or("no inputs");
    let g = match spec {
        UnitSpec::Dot3(s) => {
            let p = Dot3Rtl {
                a: first()?,
                b: enc_of(ins, "b0").ok_or("no b0")?,
                k: s.count,
                parallel: s.parallel,
                clamp: s.clamp,
                out: s.out,
            };
            Generated {
                rtl: p.rtl(top),
                model: Some(Box::new(p.unit())),
            }
        }
        UnitSpec::PowerTable(s) => {
            let p = PowerTableRtl {
                input: first()?,
                k: s.count,
                index_bits: s.index_bits,
                value_bits: s.value_bits,
                shininess: s.shininess.unwrap_or(scene.material.shininess),
                parallel: s.parallel,
            };
            Generated {
                rtl: p.rtl(top),
                model: Some(Box::new(p.unit())),
            }
        }
        UnitSpec::Shade(s) => {
            let m = &scene.material;
            let p = ShadeRtl {
                intensity: first()?,
                has: ShadeInputs {
                    specular: enc_of(ins, "s0"),
                    base: enc_of(ins, "base"),
                    src: enc_of(ins, "src"),
                },
                params: ShadeParams {
                    ambient: m.ambient,
                    diffuse: m.diffuse,
                    specular: m.specular,
                    light_colors: bump_lights(scene)
                        .into_iter()
                        .map(|i| scene.lights[i].color)
                        .collect(),
                },
                coef: s.coef,
                parallel: s.parallel,
                out: s.out,
            };
            Generated {
                rtl: p.rtl(top),
                model: Some(Box::new(p.unit())),
            }
        }
        UnitSpec::Modulate(s) => {
            let p = ModulateRtl {
                c: enc_of(ins, "c").ok_or("no c")?,
                t: enc_of(ins, "t").ok_or("no t")?,
                out: s.out,
            };
            Generated {
                rtl: p.rtl(top),
                model: Some(Box::new(p.unit())),
            }
        }
        UnitSpec::Normalize(s) => {
            let u = Normalize::new(first()?, s.table_bits, s.value_bits, s.out)?;
            Generated {
                rtl: rtl::normalize::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::Perturb(s) => {
            let enc = |n: &str| enc_of(ins, n).ok_or(format!("no {n}"));
            let u = Perturb::new(enc("base")?, enc("u")?, enc("v")?, enc("d")?, s.out)?;
            Generated {
                rtl: rtl::perturb::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::TexFetch(s) => {
            let tex = unit
                .textures()
                .first()
                .map(|r| r.texture.clone())
                .ok_or("no texture")?;
            let sampler = Sampler::new(s.filter, s.weight_bits)?.with_address(s.address, s.address);
            let u = TexFetch::new(first()?, tex, sampler, s.ports, s.mem_latency, s.out)?;
            Generated {
                rtl: rtl::fetch::rtl(&u, top)?,
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::EmbossFilter(s) => {
            let tex = unit
                .textures()
                .first()
                .map(|r| r.texture.clone())
                .ok_or("no texture")?;
            let u = EmbossFilter::new(
                first()?,
                tex,
                s.bevel(scene)?,
                s.ports,
                s.mem_latency,
                s.out,
            )?;
            Generated {
                rtl: rtl::emboss::rtl(&u, top)?,
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::FbBlend(s) => {
            let enc = |n: &str| enc_of(ins, n).ok_or(format!("no {n}"));
            let u = FbBlend::new(s.equation, enc("base")?, enc("entry")?, s.fb)?;
            Generated {
                rtl: rtl::fb_blend::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::CullFragment(s) => {
            let u = CullFragment::new(first()?, &s.tests)?;
            Generated {
                rtl: rtl::cull::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::BumpBlend(s) => {
            let u = BumpBlend::new(blend_params(s, scene), |n| enc_of(ins, n))?;
            Generated {
                rtl: rtl::blend::rtl(&u, top)?,
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::Turbulence(s) => {
            // as TurbulenceSpec::build: the scene's NDF surface (octaves, frequency, seed, spread)
            let n = bumpsim_pipeline::ndf::sources::surface(scene, "Turbulence")?;
            let t = bumpsim_hw::units::ndf_noise::Turbulence::new(n.spec.frequency, n.spec.seed);
            let enc = |p: &str| enc_of(ins, p).ok_or(format!("no {p}"));
            let u = bumpsim_hw::units::TurbulenceIndex::new(
                t,
                n.spec.octaves,
                1.0 / (2.0 * n.spread),
                s.frac,
                enc("uv")?,
                enc("lod")?,
                s.out,
            )?;
            Generated {
                rtl: rtl::ndf_turbulence::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::QuatFrame(s) => {
            let m = if s.scaled {
                Some(enc_of(ins, "m").ok_or("no m")?)
            } else {
                None
            };
            let u = QuatFrame::new(first()?, m, s.table_bits, s.value_bits, s.out)?;
            Generated {
                rtl: rtl::quat::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::TexramFrame(s) => {
            let enc = |n: &str| enc_of(ins, n).ok_or(format!("no {n}"));
            let u = TexramFrame::new(
                enc("n")?,
                enc("m")?,
                s.form,
                s.table_bits,
                s.value_bits,
                s.out,
            )?;
            Generated {
                rtl: rtl::texram::rtl(&u, top),
                model: Some(Box::new(u)),
            }
        }
        UnitSpec::QuantizedNormals(_) => {
            let u = unit
                .as_any()
                .downcast_ref::<QuantizedFetch>()
                .ok_or("the engine's unit is not a quantized fetch")?;
            Generated {
                rtl: rtl::quantized::rtl(u, top)?,
                model: None,
            }
        }
        UnitSpec::RegisterCombiners(_) => {
            let u = unit
                .as_any()
                .downcast_ref::<bumpsim_hw::units::combiner::Combiner>()
                .ok_or("the engine's unit is not a register combiner")?;
            Generated {
                rtl: rtl::combiner::rtl(u, top),
                model: None,
            }
        }
        UnitSpec::TextureShader(_) => {
            let u = unit
                .as_any()
                .downcast_ref::<bumpsim_hw::units::texture_shader::TextureShader>()
                .ok_or("the engine's unit is not a texture shader")?;
            Generated {
                rtl: rtl::texture_shader::rtl(u, top)?,
                model: None,
            }
        }
        // every kind has a generator today; a new kind answers "not generated" until it has one
        #[allow(unreachable_patterns)]
        _ => return Ok(None),
    };
    Ok(Some(g))
}

/// Co-simulation and synthesis of one generated module, appended to its line of the listing.
struct Check<'a> {
    out: &'a Path,
    /// Vectors to co-simulate (0: none).
    cosim: usize,
    synth: bool,
}

impl Check<'_> {
    /// Check module `name` (`rtl`, of the unit `model` whose estimate is `(total, tables)`
    /// GE), vectors from `seed`; a mismatch or a failing tool is added to `failures`.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        name: &str,
        rtl: &RtlUnit,
        model: &dyn Unit,
        (model_ge, tables): (f64, f64),
        seed: u64,
        line: &mut String,
        failures: &mut Vec<String>,
    ) -> Result<(), Failure> {
        if self.cosim > 0 {
            let (ins, outs) = vectors::vectors(model, self.cosim, seed);
            let dir = self.out.join("cosim").join(name);
            testbench::write(&dir, rtl, &ins, &outs)
                .map_err(|e| Failure::Internal(format!("{}: {e}", dir.display())))?;
            match testbench::run_iverilog(&dir) {
                Ok(r) => {
                    let _ = write!(
                        line,
                        "  cosim {} vectors, {} mismatches",
                        r.vectors, r.mismatches
                    );
                    if r.mismatches > 0 || r.latency_errors > 0 || r.vectors != self.cosim {
                        failures.push(format!("{name}: co-simulation {r:?}"));
                    }
                }
                Err(e) => failures.push(format!("{name}: {e}")),
            }
        }
        if self.synth {
            match synth::synthesise(rtl, &self.out.join("synth").join(name)) {
                Ok(s) => {
                    let _ = write!(
                        line,
                        "  yosys {:.1} GE; logic model {:.1} / yosys {:.1} = {:.3}",
                        s.ge,
                        model_ge - tables,
                        s.ge - s.table_ge,
                        (model_ge - tables) / (s.ge - s.table_ge),
                    );
                    if tables > 0.0 {
                        let _ = write!(
                            line,
                            "; tables model {tables:.1} (loadable) / yosys ROM {:.1}",
                            s.table_ge
                        );
                    }
                }
                Err(e) => failures.push(format!("{name}: {e}")),
            }
        }
        Ok(())
    }
}

/// The ROP datapath's input words for what the ROP read for one fragment of the frame.
fn rop_words(u: &RopDatapath, r: &bumpsim_pipeline::rop::RopInput) -> Vec<Word> {
    let ins = u.inputs();
    let (z, dc) = (ins[1].enc, ins[2].enc);
    vec![
        r.color,
        Word::from_raw(&z, &[i64::from(r.depth)]),
        Word::from_raw(&dc, &r.dst.code),
        Word::from_raw(&z, &[i64::from(r.dst_depth)]),
    ]
}

fn regs_text(u: &RtlUnit) -> String {
    let mut s = String::from("# addr width value what (host-loaded registers, cfg_* port)\n");
    for (i, c) in u.config.iter().enumerate() {
        let _ = writeln!(s, "{i} {} {:#x} {}", c.width, c.value, c.what);
    }
    s
}

fn write(dir: &Path, name: &str, text: &str) -> Result<(), Failure> {
    std::fs::write(dir.join(name), text).map_err(|e| {
        Failure::Input(InputError::new(
            dir.join(name).display().to_string(),
            "--out",
            e.to_string(),
        ))
    })
}

/// Run the command: generate, write, and optionally co-simulate and synthesise.
pub fn execute(l: &Loaded, out: &Path, cosim: usize, synth_on: bool) -> Result<(), Failure> {
    // with --cosim the frame is rasterised too: the top replays its fragments
    let prepared = if cosim > 0 {
        Some(bumpsim_pipeline::run::prepare(l)?)
    } else {
        None
    };
    let built;
    let (scene, eng) = match &prepared {
        Some(p) => (&p.scene, &p.engine),
        None => {
            let scene = build_scene(l)?;
            let eng = engine::build(l, &scene)?;
            built = (scene, eng);
            (&built.0, &built.1)
        }
    };
    std::fs::create_dir_all(out).map_err(|e| {
        Failure::Input(InputError::new(
            out.display().to_string(),
            "--out",
            e.to_string(),
        ))
    })?;
    let table = &l.config.cost;
    let mut lines = Vec::new();
    let mut failures = Vec::new();
    let mut units = Vec::new();
    let check = Check {
        out,
        cosim,
        synth: synth_on,
    };
    for (i, uc) in l.config.engine.units.iter().enumerate() {
        let unit = engine_unit(eng, &uc.name)?;
        let top = module_name(&uc.name);
        let g = match generate(&uc.unit, unit, scene, &top) {
            Ok(Some(g)) => g,
            Ok(None) => {
                lines.push(format!("{:<12} {:<14} not generated", uc.name, unit.kind()));
                continue;
            }
            Err(e) => {
                lines.push(format!(
                    "{:<12} {:<14} not generated: {e}",
                    uc.name,
                    unit.kind()
                ));
                continue;
            }
        };
        let cost = uc.cost(table);
        let model_ge = unit.gates(&cost).total();
        let model: &dyn Unit = g.model.as_deref().unwrap_or(unit);
        if model.gates(&cost) != unit.gates(&cost) {
            failures.push(format!(
                "{}: the unit rebuilt for the RTL has another gate budget than the engine's",
                uc.name
            ));
        }
        write(out, &format!("{}.v", uc.name), &g.rtl.verilog)?;
        write(out, &format!("{}.regs", uc.name), &regs_text(&g.rtl))?;
        for mem in g.rtl.memories.iter().filter(|m| m.has_file()) {
            write(out, &mem.file, &mem.hex())?;
        }
        let mut line = format!(
            "{:<12} {:<14} {}.v  latency {}  registers {}  model {:.1} GE",
            uc.name,
            unit.kind(),
            uc.name,
            g.rtl.latency,
            g.rtl.config.len(),
            model_ge
        );
        if let Some(f) = g.rtl.frame {
            let _ = write!(line, "  frame {f} clocks (model {})", unit.frame_cycles());
        }
        if cosim > 0 {
            // the engine's own unit on the same words
            let (ins, outs) = vectors::vectors(model, cosim, 0x13_0000 + i as u64);
            let differ = ins
                .iter()
                .zip(&outs)
                .filter(|(w, o)| {
                    let mut e = vec![Word::default(); unit.outputs().len()];
                    unit.eval(Mode::BitAccurate, w, &mut e);
                    e != **o
                })
                .count();
            if differ > 0 {
                failures.push(format!(
                    "{}: the rebuilt unit differs from the engine's on {differ} of {cosim} vectors",
                    uc.name
                ));
            }
        }
        check.run(
            &uc.name,
            &g.rtl,
            model,
            (model_ge, unit.gates(&cost).tables()),
            0x13_0000 + i as u64,
            &mut line,
            &mut failures,
        )?;
        let names = |ps: &[PortSpec]| ps.iter().map(|p| p.name.clone()).collect();
        units.push(rtl_top::UnitRtl {
            name: uc.name.clone(),
            inputs: names(model.inputs()),
            outputs: names(model.outputs()),
            rtl: g.rtl,
        });
        lines.push(line);
    }
    // with --cosim the ROP modules also replay what the ROP read in the frame
    let frame_inputs = prepared.as_ref().map(|p| p.rop_inputs(cosim));
    for (k, (label, pass, rop)) in eng.rops().into_iter().enumerate() {
        let file = &label;
        let u = RopDatapath::new(rop);
        let rtl = rtl::rop::rtl(&u, &module_name(&label));
        let ge = u.gates(table).total();
        write(out, &format!("{file}.v"), &rtl.verilog)?;
        write(out, &format!("{file}.regs"), &regs_text(&rtl))?;
        let mut line = format!(
            "{:<12} {:<14} {file}.v  latency {}  registers {}  model {ge:.1} GE  (pass {pass:?}: {} -> {} bits)",
            label,
            u.kind(),
            rtl.latency,
            rtl.config.len(),
            rop.color(),
            rop.params().color_bits,
        );
        check.run(
            &label,
            &rtl,
            &u,
            (ge, 0.0),
            0x13_8000 + k as u64,
            &mut line,
            &mut failures,
        )?;
        if let Some(inputs) = frame_inputs.as_ref().and_then(|f| f.get(k)) {
            let ins: Vec<Vec<Word>> = inputs.iter().map(|r| rop_words(&u, r)).collect();
            let outs: Vec<Vec<Word>> = ins
                .iter()
                .map(|w| {
                    let mut o = vec![Word::default(); u.outputs().len()];
                    u.eval(Mode::BitAccurate, w, &mut o);
                    o
                })
                .collect();
            let dir = out.join("cosim").join(format!("{label}-frame"));
            testbench::write(&dir, &rtl, &ins, &outs)
                .map_err(|e| Failure::Internal(format!("{}: {e}", dir.display())))?;
            match testbench::run_iverilog(&dir) {
                Ok(r) => {
                    let _ = write!(
                        line,
                        "; frame {} fragments, {} mismatches",
                        r.vectors, r.mismatches
                    );
                    if r.mismatches > 0 || r.latency_errors > 0 || r.vectors != ins.len() {
                        failures.push(format!("{label}: frame co-simulation {r:?}"));
                    }
                }
                Err(e) => failures.push(format!("{label}: {e}")),
            }
        }
        lines.push(line);
    }
    let all = l.config.engine.units.len();
    if units.len() < all {
        lines.push(format!(
            "engine top not generated: {} of {all} units have no generator",
            all - units.len()
        ));
    } else {
        match rtl_top::build(eng, &units) {
            Ok(t) => {
                write(out, "engine.v", &t.verilog)?;
                write(out, "engine.regs", &regs_text(&t))?;
                let mut line = format!(
                    "{:<12} {:<14} engine.v  latency {}  registers {}",
                    "engine",
                    rtl_top::TOP,
                    t.latency,
                    t.config.len()
                );
                if let Some(p) = &prepared {
                    let (ins, outs) = rtl_top::fragment_vectors(p, cosim);
                    let dir = out.join("cosim").join("engine");
                    testbench::write(&dir, &t, &ins, &outs)
                        .map_err(|e| Failure::Internal(format!("{}: {e}", dir.display())))?;
                    match testbench::run_iverilog(&dir) {
                        Ok(r) => {
                            let _ = write!(
                                line,
                                "  cosim {} fragments of the frame, {} mismatches",
                                r.vectors, r.mismatches
                            );
                            if r.mismatches > 0 || r.latency_errors > 0 || r.vectors != ins.len() {
                                failures.push(format!("engine: co-simulation {r:?}"));
                            }
                        }
                        Err(e) => failures.push(format!("engine: {e}")),
                    }
                }
                lines.push(line);
            }
            Err(e) => failures.push(format!("engine top: {e}")),
        }
    }
    for l in &lines {
        println!("{l}");
    }
    println!("wrote {}", out.display());
    if failures.is_empty() {
        Ok(())
    } else {
        Err(Failure::Internal(failures.join("\n")))
    }
}

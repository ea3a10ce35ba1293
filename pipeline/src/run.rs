//! One run of a config: scene, geometry, rasterizer, the engine in both modes, the float
//! reference, the comparisons, the report and the pictures.

mod front;
mod measures;
mod shared;
mod timings;

use crate::config::{AttrSource, InputError, Loaded};
use crate::engine::{self, attributes, Engine};
use crate::raster::{self, packet::PacketLayout};
use crate::reference;
use crate::report::{Bandwidth, Gates, ImageInfo, Report, VERSION};
use crate::scene::Scene;
use crate::sim;
use crate::trace::{Trace, TraceUnit};
use bumpsim_hw::{Mode, Token, Word};
use front::{fixed, raster_ranges, Front};
use std::sync::Arc;
pub use timings::Timings;

/// What to trace: a half-open cycle window and optionally a subset of units.
#[derive(Debug, Clone, Default)]
pub struct TraceRequest {
    pub cycles: (u64, u64),
    pub units: Option<Vec<String>>,
}

/// Everything a run produces.
pub struct RunResult {
    pub report: Report,
    pub image: image::RgbImage,
    /// The pixels the engine wrote (row-major, as `image`).
    pub mask: Vec<bool>,
    pub reference: image::RgbImage,
    pub error: image::RgbImage,
    /// The exact-mode framebuffer's 8-bit image (the same algorithm in f64, `image`'s
    /// comparison in `error.quantization`); an animation compares its frames' changes.
    pub exact: image::RgbImage,
    pub trace: Option<Trace>,
    /// Wall time of each phase, in order (for `render --timings`; never in the report, which
    /// stays deterministic).
    pub timings: Timings,
    /// The engine's texture memory by texture name: what an animation compares from frame to
    /// frame (the textures the host uploads again).
    pub textures: Vec<(String, Arc<bumpsim_hw::Texture>)>,
}

/// Build the scene a config describes. Errors name the config file and the field. Its
/// [`Scene::key`] digests the scene's config (and apart, its bump map's and mesh's), the
/// config's directory and every file read.
pub fn build_scene(l: &Loaded) -> Result<Scene, InputError> {
    let (scene, files) = crate::scene::files::recorded(|| build_scene_unkeyed(l));
    let mut scene = scene?;
    let c = &l.config.scene;
    let specs = (
        ron::to_string(c),
        ron::to_string(&c.bump),
        ron::to_string(&c.mesh),
    );
    scene.key = match (files, specs) {
        (Some(files), (Ok(all), Ok(bump), Ok(mesh))) => {
            let key = |parts: &[&str]| {
                crate::memo::digest(|mut h| {
                    use std::hash::Hash;
                    parts.hash(&mut h);
                    l.base_dir.hash(&mut h);
                    files.hash(&mut h);
                })
            };
            Some(crate::scene::SceneKey {
                scene: key(&[&all]),
                // a `Baked` bump map is the mesh's
                bump: key(&[&bump, &mesh]),
            })
        }
        _ => None,
    };
    Ok(scene)
}

fn build_scene_unkeyed(l: &Loaded) -> Result<Scene, InputError> {
    let c = &l.config.scene;
    let (mesh, baked) = c
        .mesh
        .build_with_map(&l.base_dir)
        .map_err(|e| l.scene_error("scene.mesh", "mesh:", e))?;
    mesh.validate("scene.mesh")
        .map_err(|e| l.scene_error("scene.mesh", "mesh:", e))?;
    let (baked, bake) = match baked {
        Some((map, stats)) => (Some(map), Some(stats)),
        None => (None, None),
    };
    let bump = match (&c.bump, baked) {
        (crate::scene::BumpSpec::Baked, Some(map)) => crate::scene::BumpMap::Normals(map),
        (spec, _) => spec
            .build(&l.base_dir)
            .map_err(|e| l.scene_error("scene.bump", "bump:", e))?,
    };
    let color_texture = match &c.color_texture {
        None => None,
        Some(t) => Some(t.build(&l.base_dir).map_err(|(file, m)| {
            if file.is_empty() {
                l.error("scene.color_texture", "color_texture:", m)
            } else {
                InputError::new(file, "scene.color_texture", m)
            }
        })?),
    };
    let looks = build_looks(l)?;
    Ok(Scene {
        mesh,
        model: c.model.matrix(),
        camera: c.camera,
        lights: c.lights.clone(),
        material: c.material.clone(),
        looks,
        bump,
        bake,
        color_texture,
        width: c.width.0,
        height: c.height.0,
        key: None,
    })
}

/// The scene's extra materials and the environment maps of all materials (paths relative to
/// the config file). A missing or unreadable map names the file and the field.
fn build_looks(l: &Loaded) -> Result<crate::scene::Looks, InputError> {
    let c = &l.config.scene;
    let regions = c.regions.clone();
    let mut all = vec![("scene.material".to_string(), &c.material)];
    if let Some(r) = &c.regions {
        for (i, m) in r.materials.iter().enumerate() {
            all.push((format!("scene.regions.materials[{i}]"), m));
        }
    }
    let mut env_maps = Vec::with_capacity(all.len());
    for (field, m) in all {
        env_maps.push(match &m.model {
            crate::scene::Shading::EnvMap { image } => Some(
                crate::scene::EnvImage::load(&l.base_dir.join(image))
                    .map_err(|e| l.scene_error(&format!("{field}.model.image"), "image:", e))?,
            ),
            _ => None,
        });
    }
    Ok(crate::scene::Looks { regions, env_maps })
}

/// A frame ready to simulate: the scene, the geometry engine's output, the rasterizer's
/// fragments, and the engine (built once; it evaluates in both modes).
pub struct Prepared {
    pub scene: Scene,
    pub vertices: attributes::VertexData,
    /// `vertices.values` on the attributes' grids, for the bit-accurate interpolator.
    snapped: Vec<Vec<[f64; 4]>>,
    /// The vertex words of a fixed-point interpolator (empty with `Interpolator::Exact`).
    codes: Vec<Vec<[i64; 4]>>,
    interpolator: crate::config::Interpolator,
    pub raster: raster::RasterOutput,
    /// The engine: units with their assets, evaluated in both modes.
    pub engine: Engine,
    raster_config: raster::RasterConfig,
    fifo_depth: usize,
}

/// Build the scene, wire the engine (its assets built once), run geometry and the rasterizer.
pub fn prepare(l: &Loaded) -> Result<Prepared, InputError> {
    prepare_with(l, None, None).map(|(p, _)| p)
}

/// The reference image of a run and its wall time, when [`prepare_with`] rendered it.
type Early = Option<(Arc<reference::ReferenceImage>, std::time::Duration)>;

/// [`prepare`], the rasterizer running while the engine's assets are built; with
/// `reference`, the reference image is rendered there too (it reads the scene and the
/// fragments, not the engine). Both assume early depth: an engine that needs the depth test
/// after shading (known once it is built) gets its fragments again, and no reference. With
/// `engine` (built for an earlier frame of the same config), that engine takes this frame's
/// inputs ([`Engine::begin_frame`]) instead of a new one being built.
fn prepare_with(
    l: &Loaded,
    reference: Option<crate::config::ReferenceConfig>,
    engine: Option<Engine>,
) -> Result<(Prepared, Early), InputError> {
    let scene = build_scene(l)?;
    let cfg = &l.config;
    let vertices = attributes::compute(&scene, &cfg.engine.attributes);
    let rasterize = |depth| {
        let mut r = raster::rasterize_with(
            &vertices.clip,
            &scene.mesh.triangles,
            scene.width,
            scene.height,
            &cfg.raster,
            depth,
        );
        // the list grew by doubling: up to half of it is spare capacity that the whole run
        // holds
        r.fragments.shrink_to_fit();
        r
    };
    let next_frame = |mut e: Engine| {
        e.begin_frame(&scene)
            .map(|()| e)
            .map_err(|m| InputError::new(l.path.display().to_string(), "scene", m))
    };
    let (engine, (raster, early)) = rayon::join(
        || match engine {
            Some(e) => next_frame(e),
            None => engine::build(l, &scene),
        },
        || {
            let r = rasterize(raster::DepthTest::Early);
            let img = reference.map(|rc| timed_call(|| reference_of(&scene, &r, &cfg.raster, rc)));
            (r, img)
        },
    );
    let engine = engine?;
    // an engine that may kill fragments, or a ROP with other tests, needs the depth test
    // after shading
    let (raster, early) = if engine.late_depth() {
        (rasterize(raster::DepthTest::Late), None)
    } else {
        (raster, early)
    };
    let snapped = vertices.snapped(&cfg.engine.attributes);
    let interpolator = cfg.engine.interpolator;
    let codes = match interpolator {
        crate::config::Interpolator::Exact => Vec::new(),
        crate::config::Interpolator::Fixed { .. } => vertices.codes(&cfg.engine.attributes),
    };
    let p = Prepared {
        scene,
        snapped,
        codes,
        interpolator,
        vertices,
        raster,
        engine,
        raster_config: cfg.raster,
        fifo_depth: cfg.sim.fifo_depth as usize,
    };
    Ok((p, early))
}

/// The f64 reference of `scene` over the coverage of `raster`'s fragments.
fn reference_of(
    scene: &Scene,
    raster: &raster::RasterOutput,
    raster_config: &raster::RasterConfig,
    r: crate::config::ReferenceConfig,
) -> Arc<reference::ReferenceImage> {
    let (w, h) = (scene.width, scene.height);
    let frags = &raster.fragments;
    let coverage = reference::Coverage::of_fragments(frags, w, h, raster_config);
    let opts = reference::Options {
        perturbation: r.perturbation,
        samples: r.samples,
        normals: false,
    };
    shared::reference(scene, &coverage, frags, opts)
}

impl Prepared {
    /// The front end of `mode`: fragments and the vertex values its interpolator reads;
    /// `exact_raw`: whether exact-mode words carry raw words (for traces and tests).
    fn front(&self, mode: Mode, exact_raw: bool) -> Front<'_> {
        Front {
            frags: &self.raster.fragments,
            tris: &self.scene.mesh.triangles,
            vd: &self.vertices,
            values: match mode {
                Mode::BitAccurate => &self.snapped,
                Mode::Exact => &self.vertices.values,
            },
            fixed: fixed(&self.codes, self.interpolator),
            exact_raw,
        }
    }

    /// The simulator's view of the frame: triangles, their setup cycles, the token filler.
    fn workload<'a>(
        &'a self,
        fill: &'a sim::FillToken<'a>,
        stalls: crate::texcache::Timing,
    ) -> sim::Workload<'a> {
        let ranges = raster_ranges(&self.raster, self.scene.mesh.triangles.len());
        let setup = self
            .raster
            .triangles
            .iter()
            .map(|t| t.setups.max(1) * self.raster_config.setup_cycles)
            .collect();
        sim::Workload {
            triangles: ranges,
            setup,
            fill_token: fill,
            slots: self.engine.signals.len(),
            attributes: self.engine.attributes.len(),
            fifo_depth: self.fifo_depth,
            extra: stalls,
        }
    }

    /// The timed, bit-accurate run of the frame, every output as a [`Word`] (for tests of the
    /// engines; a render stores raw lanes: [`Prepared::simulate_lanes`]). The timing model
    /// ticks twins of the stages, so the engine is only read (`&mut` is kept for callers).
    pub fn simulate(&mut self, trace: Option<(u64, u64)>) -> sim::SimResult {
        let front = self.front(Mode::BitAccurate, true);
        let attrs = &self.engine.attributes;
        let fill = |f: usize, t: &mut Token| front.fill(attrs, Mode::BitAccurate, f, t);
        let output = self.engine.output.wire;
        let stalls = self.timed_cache().map(|c| c.1).unwrap_or_default();
        sim::run(
            &self.engine.stages,
            output,
            self.workload(&fill, stalls),
            trace,
        )
    }

    /// The timed, bit-accurate run of the frame as a render takes it: the timing model and the
    /// function concurrently, the outputs as raw lanes of the output port.
    pub fn simulate_lanes(&self, trace: Option<(u64, u64)>) -> sim::Timed {
        let stalls = self.timed_cache().map(|c| c.1).unwrap_or_default();
        self.simulate_lanes_with(trace, stalls)
    }

    /// [`Self::simulate_lanes`] with the texture cache's stalls given.
    fn simulate_lanes_with(
        &self,
        trace: Option<(u64, u64)>,
        stalls: crate::texcache::Timing,
    ) -> sim::Timed {
        let front = self.front(Mode::BitAccurate, true);
        let fill = front::FrontFill {
            front: &front,
            attrs: &self.engine.attributes,
            mode: Mode::BitAccurate,
        };
        let out = &self.engine.output;
        sim::run_lanes(
            &self.engine.stages,
            out.wire,
            &out.spec,
            self.workload(&fill, stalls),
            trace,
        )
    }

    /// The engine in exact mode over every fragment (untimed: its timing is the same), the
    /// outputs as values. No trace reads exact mode, so its attribute words carry no raw
    /// words ([`Prepared::fragment_token`] keeps them).
    pub fn evaluate_exact(&self) -> sim::Outputs {
        let front = self.front(Mode::Exact, false);
        let attrs = &self.engine.attributes;
        let fill = |f: usize, t: &mut Token| front.fill(attrs, Mode::Exact, f, t);
        let out = &self.engine.output;
        sim::evaluate_lanes(
            &self.engine.stages,
            Mode::Exact,
            out.wire,
            &out.spec,
            front.frags.len(),
            self.engine.slots(),
            &fill,
        )
    }

    /// The outputs of every pass after the first in `mode`, in order, without timing (a pass
    /// streams the same fragments through the engine as the first, and its timing is the
    /// first's: `passes.rs`).
    pub fn pass_outputs(&self, mode: Mode) -> Vec<sim::Outputs> {
        let front = self.front(mode, false);
        let fill = front::FrontFill {
            front: &front,
            attrs: &self.engine.attributes,
            mode,
        };
        self.engine
            .passes
            .iter()
            .map(|p| {
                sim::evaluate_lanes(
                    &self.engine.stages,
                    mode,
                    p.output.wire,
                    &p.output.spec,
                    front.frags.len(),
                    self.engine.slots(),
                    &fill,
                )
            })
            .collect()
    }

    /// Up to `n` of every pass's ROP inputs in the bit-accurate frame (`crate::rop::RopInput`:
    /// what the ROP read for a fragment that reached it), evenly spaced over the pass's
    /// fragments: the replay of the ROP's Verilog (`bumpsim rtl --cosim`).
    pub fn rop_inputs(&self, n: usize) -> Vec<Vec<crate::rop::RopInput>> {
        let mode = Mode::BitAccurate;
        let front = self.front(mode, false);
        let fill = front::FrontFill {
            front: &front,
            attrs: &self.engine.attributes,
            mode,
        };
        let out = &self.engine.output;
        let first = sim::evaluate_lanes(
            &self.engine.stages,
            mode,
            out.wire,
            &out.spec,
            front.frags.len(),
            self.engine.slots(),
            &fill,
        );
        let extra = self.pass_outputs(mode);
        let (w, h) = (self.scene.width, self.scene.height);
        let mut list = vec![(&self.engine.rop, &first)];
        list.extend(self.engine.passes.iter().map(|p| &p.rop).zip(&extra));
        let mut all: Vec<Vec<crate::rop::RopInput>> = vec![Vec::new(); list.len()];
        crate::rop::write_passes_observed(&list, mode, w, h, &self.raster.fragments, |r| {
            all[r.pass].push(r)
        });
        all.into_iter()
            .map(|v| {
                let m = n.min(v.len());
                (0..m).map(|k| v[k * v.len() / m]).collect()
            })
            .collect()
    }

    /// The texel reads of the frame through `engine.texture_cache` (`None` without one):
    /// every fragment in rasterization order, bit-accurate (evaluated in parallel chunks, the
    /// reads taken by the caches in rasterization order: `texcache::simulate`).
    pub fn texture_cache(&self) -> Option<(crate::texcache::CacheReport, crate::texcache::Timing)> {
        let c = self.engine.texture_cache.as_ref()?;
        let front = self.front(Mode::BitAccurate, true);
        let fill = front::FrontFill {
            front: &front,
            attrs: &self.engine.attributes,
            mode: Mode::BitAccurate,
        };
        Some(crate::texcache::simulate(
            c,
            &self.engine.stages,
            front.frags.len(),
            self.engine.slots(),
            &fill,
        ))
    }

    /// [`Self::texture_cache`] when its misses stall the units (`miss_cycles > 0`): the timed
    /// run needs it first.
    fn timed_cache(&self) -> Option<(crate::texcache::CacheReport, crate::texcache::Timing)> {
        let timed = self.engine.texture_cache.is_some_and(|c| c.miss_cycles > 0);
        timed.then(|| self.texture_cache()).flatten()
    }

    /// The framebuffer of `mode` after every pass: `first` is the first pass's outputs,
    /// `extra` the others' ([`Self::pass_outputs`]).
    pub fn framebuffer(
        &self,
        mode: Mode,
        first: &sim::Outputs,
        extra: &[sim::Outputs],
        frags: &[impl crate::rop::AsRopFragment],
    ) -> crate::rop::Framebuffer {
        let (w, h) = (self.scene.width, self.scene.height);
        let mut list = vec![(&self.engine.rop, first)];
        list.extend(self.engine.passes.iter().map(|p| &p.rop).zip(extra));
        crate::rop::write_passes(&list, mode, w, h, frags)
    }

    /// The token of fragment `f` after every stage in `mode` (every signal's value, raw words
    /// included): for tests of the units in their configured engines.
    pub fn fragment_token(&self, mode: Mode, f: usize) -> Token {
        let front = self.front(mode, true);
        let mut t = Token {
            id: 0,
            x: 0,
            y: 0,
            live: true,
            slots: vec![Word::default(); self.engine.slots()],
        };
        front.fill(&self.engine.attributes, mode, f, &mut t);
        let mut scratch = bumpsim_hw::Scratch::default();
        for s in &self.engine.stages {
            s.eval_token(&mut t, mode, &mut scratch);
        }
        t
    }

    /// The float reference of the same scene, on the engine's coverage (the winning fragment
    /// of each pixel), without normals.
    pub fn reference(&self, r: crate::config::ReferenceConfig) -> Arc<reference::ReferenceImage> {
        reference_of(&self.scene, &self.raster, &self.raster_config, r)
    }

    /// The three paths of the frame concurrently (rayon): the timed bit-accurate run, exact
    /// mode and the reference. Each only reads the prepared frame and stores its results by
    /// index, so they are the same as one after another.
    pub fn paths(&self, r: crate::config::ReferenceConfig, trace: Option<(u64, u64)>) -> Paths {
        self.paths_with(r, trace, None)
    }

    /// [`Self::paths`] with the reference already rendered (`early`: by [`prepare_with`]).
    fn paths_with(
        &self,
        r: crate::config::ReferenceConfig,
        trace: Option<(u64, u64)>,
        early: Early,
    ) -> Paths {
        // a texture cache whose misses stall the units runs before the timed run, which
        // takes the stalls; one that counts traffic only runs beside the paths
        let (pre, stalls) = match self.timed_cache() {
            Some((report, stalls)) => (Some(report), stalls),
            None => (None, Vec::new()),
        };
        let untimed_cache = pre.is_none();
        let ((sim, t_sim), (((exact, t_exact), (reference, t_ref)), late)) = rayon::join(
            || timed_call(|| self.simulate_lanes_with(trace, stalls)),
            || {
                rayon::join(
                    || {
                        rayon::join(
                            || timed_call(|| self.evaluate_exact()),
                            || match early {
                                Some((img, _)) => (img, None),
                                None => {
                                    let (img, t) = timed_call(|| self.reference(r));
                                    (img, Some(t))
                                }
                            },
                        )
                    },
                    || {
                        untimed_cache
                            .then(|| self.texture_cache().map(|c| c.0))
                            .flatten()
                    },
                )
            },
        );
        let mut walls = vec![("simulation", t_sim), ("exact mode", t_exact)];
        walls.extend(t_ref.map(|t| ("reference", t)));
        Paths {
            sim,
            exact,
            reference,
            cache: pre.or(late),
            walls,
        }
    }
}

/// The results of [`Prepared::paths`].
pub struct Paths {
    pub sim: sim::Timed,
    pub exact: sim::Outputs,
    pub reference: Arc<reference::ReferenceImage>,
    /// The texture cache's report (`engine.texture_cache`).
    pub cache: Option<crate::texcache::CacheReport>,
    /// The wall time of each path run here (they overlap; the reference is missing when it
    /// was rendered beside the assets).
    pub walls: Vec<(&'static str, std::time::Duration)>,
}

/// `f()` and its wall time.
fn timed_call<T>(f: impl FnOnce() -> T) -> (T, std::time::Duration) {
    let t0 = std::time::Instant::now();
    let r = f();
    (r, t0.elapsed())
}

/// Run a loaded config.
/// The gate budgets of `engine` as the report states them: every unit, the fixed-point
/// interpolator if there is one, the ROP (serving every pass).
fn engine_gates(cfg: &crate::config::Config, engine: &Engine) -> Gates {
    let mut units: Vec<(String, String, bumpsim_hw::GateBudget)> = engine
        .stages
        .iter()
        .zip(&engine.gates)
        .map(|(s, (_, g))| (s.name.clone(), s.unit().kind().to_string(), g.clone()))
        .collect();
    if let crate::config::Interpolator::Fixed { weight_bits } = cfg.engine.interpolator {
        let g = attributes::interpolator_gates(&engine.attributes, weight_bits, &cfg.cost);
        units.push(("attribute interpolator".into(), "interpolator".into(), g));
    }
    let mut g = Gates::new(&units, &engine.rop_gates(&cfg.cost), cfg.cost.tables);
    g.texture_cache = engine.texture_cache.as_ref().map(|c| {
        let b = crate::texcache::gates(c, &engine.stages, &cfg.cost);
        crate::report::UnitGates::beside("texture_cache", &b)
    });
    for uc in &cfg.engine.units {
        if let Some(u) = g.per_unit.get_mut(&uc.name) {
            u.tables = uc.tables.map(|k| k.name());
            u.table_kinds = uc
                .table_kinds
                .iter()
                .map(|(r, k)| (r.name(), k.name()))
                .collect();
        }
    }
    g
}

/// The report's `gates` of config `l` without rendering: the scene and the engine are built
/// (assets included, as the units' budgets may depend on them), nothing is rasterised or run.
/// The same figures as `run(l, ..).report.gates`.
pub fn gates(l: &Loaded) -> Result<Gates, InputError> {
    let scene = build_scene(l)?;
    let engine = engine::build(l, &scene)?;
    Ok(engine_gates(&l.config, &engine))
}

pub fn run(l: &Loaded, trace: Option<&TraceRequest>) -> Result<RunResult, InputError> {
    run_frame(l, trace, None).map(|r| r.0)
}

/// [`run`] with the engine of an earlier frame of the same config (`frames`): it takes this
/// frame's inputs ([`Engine::begin_frame`]) rather than being built again. Returns the engine
/// for the next frame.
pub fn run_frame(
    l: &Loaded,
    trace: Option<&TraceRequest>,
    engine: Option<Engine>,
) -> Result<(RunResult, Engine), InputError> {
    let cfg = &l.config;
    let mut timings = Timings::start();
    let (mut p, early) = prepare_with(l, Some(cfg.reference), engine)?;
    timings.lap("scene and assets");
    if let Some((_, d)) = &early {
        timings.part("reference", *d);
    }
    let trace_units = trace_units(&p.engine);
    if let Some(t) = trace {
        if let Some(names) = &t.units {
            for n in names {
                if !trace_units.iter().any(|u| &u.name == n) {
                    let known: Vec<&str> = trace_units.iter().map(|u| u.name.as_str()).collect();
                    return Err(InputError::new(
                        "--units",
                        "",
                        format!("no unit {n:?}: expected one of {}", known.join(", ")),
                    ));
                }
            }
        }
    }
    let paths = p.paths_with(cfg.reference, trace.map(|t| t.cycles), early);
    timings.lap("paths (concurrent)");
    for (name, d) in paths.walls {
        timings.part(name, d);
    }
    let Paths {
        sim: result,
        exact: exact_out,
        reference: refimg,
        cache,
        ..
    } = paths;
    let (w, h) = (p.scene.width, p.scene.height);
    // the passes after the first, in both modes, while the full fragment list is there
    let (extra_exact, extra_bit) = rayon::join(
        || p.pass_outputs(Mode::Exact),
        || p.pass_outputs(Mode::BitAccurate),
    );
    let frags = &p.raster.fragments;
    // The two framebuffers one after the other, each mode's outputs freed once its ROP has
    // read them (a framebuffer being written holds 39 bytes per pixel: two at once were the
    // peak of a large frame).
    // The ROP reads 16 of a fragment's 40 bytes: the list is cut to those before the
    // framebuffers are built, and the full one freed.
    let frags: Vec<crate::rop::RopFragment> = frags.iter().map(Into::into).collect();
    p.raster.fragments = Vec::new();
    let mut fb_exact = p.framebuffer(Mode::Exact, &exact_out, &extra_exact, &frags);
    drop((exact_out, extra_exact));
    let fb = p.framebuffer(Mode::BitAccurate, &result.outputs, &extra_bit, &frags);
    drop((result.outputs, extra_bit, frags));
    let bit = &p.engine;
    // the two modes' triangle maps are one where the same fragments were written (the
    // usual case): keep one
    let shared_tri = fb_exact.tri == fb.tri;
    if shared_tri {
        fb_exact.tri = Vec::new();
    }
    let exact_tri = if shared_tri { &fb.tri } else { &fb_exact.tri };
    timings.lap("ROP");
    let mask = &fb.mask;
    let rimg = &refimg.image;
    let rmask = &refimg.mask;
    let measured = measures::measure(&fb, &fb_exact, exact_tri, rimg, rmask);
    let highlight = cfg.reference.highlight_luma.map(|t| {
        let (a, e) = ((&fb.image, &fb.mask), (&fb_exact.image, &fb_exact.mask));
        crate::highlight::measure(a.0, a.1, e.0, e.1, rimg, rmask, t)
    });
    let synthesis = match (&cfg.reference.synthesis, &p.scene.bump) {
        (Some(st), crate::scene::BumpMap::Ndf(surf)) => Some(crate::ndf::statistics::measure(
            surf,
            ndf_lookup_side(&cfg.engine),
            *st,
        )),
        _ => None,
    };
    let covered = mask.iter().filter(|&&m| m).count() as u64;
    let (lit_pixels, mean_lit_level) = ImageInfo::lit(&fb.rgb8);
    let mismatch = mask.iter().zip(rmask).filter(|(a, b)| a != b).count() as u64;

    let extras: u64 = bit
        .attributes
        .iter()
        .filter(|a| !matches!(a.source, AttrSource::Uv | AttrSource::Gouraud { .. }))
        .map(|a| {
            let bits = a.source.lanes() as u64 * a.enc.width() as u64;
            if a.source.per_triangle() {
                bits
            } else {
                3 * bits
            }
        })
        .sum();
    let packet = bit.packet();
    let baseline = PacketLayout::baseline_textured_gouraud();
    let bits = packet.bits_per_triangle();
    let base_bits = baseline.bits_per_triangle();
    let color_bits = |r: &bumpsim_hw::units::Rop| 3 * u64::from(r.params().color_bits);
    let runs: Vec<crate::passes::PassRun> = std::iter::once((
        if bit.passes.is_empty() {
            "shade".to_string()
        } else {
            bit.output.name.clone()
        },
        &bit.rop,
    ))
    .chain(bit.passes.iter().map(|q| (q.name.clone(), &q.rop)))
    .zip(&fb.passes)
    .map(|((name, rop), &counts)| crate::passes::PassRun {
        name,
        counts,
        blends: rop.params().blend.is_some(),
        depth_write: rop.params().depth_write,
    })
    .collect();
    let passes = crate::passes::passes(
        crate::passes::Frame {
            frame_cycles: result.cycles.frame,
            stream_cycles: result.cycles.total - result.cycles.frame,
            triangles: result.cycles.triangles,
            bits_per_triangle: bits,
            color_bits: color_bits(&bit.rop),
            depth_bits: u64::from(cfg.raster.depth_bits),
        },
        &runs,
    );
    let fragments = result.cycles.fragments;
    let report = Report {
        version: VERSION.to_string(),
        name: cfg.name.clone(),
        config_hash: l.hash.clone(),
        image: ImageInfo {
            width: w,
            height: h,
            covered_pixels: covered,
            coverage_mismatch: mismatch,
            lit_pixels,
            mean_lit_level,
        },
        bake: p.scene.bake,
        cycles: result.cycles,
        gates: engine_gates(cfg, bit),
        bandwidth: Bandwidth {
            bits_per_triangle: bits,
            baseline_bits_per_triangle: base_bits,
            extra_percent: ((bits as f64 - base_bits as f64) / base_bits as f64 * 1000.0).round()
                / 10.0,
            bump_extra_bits_per_triangle: extras,
            bump_extra_percent: (extras as f64 / base_bits as f64 * 1000.0).round() / 10.0,
            bits_per_texel: bit.texels.first().map_or(0, |t| t.1),
            textures: bit.texels.iter().cloned().collect(),
            texture_memory: engine::memory::stats(&bit.stages, fragments),
            texture_cache: cache,
            packet,
        },
        passes,
        error: measured.errors,
        artifacts: measured.artifacts,
        edges: measured.edges,
        highlight,
        synthesis,
        normal_maps: bit.normal_maps.clone(),
        animation: None,
    };
    let trace = trace.map(|t| {
        let full = Trace {
            units: trace_units,
            records: result.probes,
        };
        match &t.units {
            Some(names) => full.select_units(names).expect("unit names checked above"),
            None => full,
        }
    });
    timings.lap("metrics");
    let result = RunResult {
        exact: fb_exact.rgb8,
        image: fb.rgb8,
        mask: fb.mask,
        reference: measured.reference,
        error: measured.heatmap,
        report,
        trace,
        timings,
        textures: engine::memory::textures(&p.engine.stages),
    };
    Ok((result, p.engine))
}

/// The units of a trace, in the order of [`sim::trace_index`]: the scan converter (its
/// outputs the interpolated attributes), the engine's stages, the ROP (its input the engine's
/// output).
fn trace_units(engine: &Engine) -> Vec<TraceUnit> {
    let [_, scan, rop] = sim::FIXED_UNITS;
    let attributes = engine.signals[..engine.attributes.len()]
        .iter()
        .map(|s| s.spec.clone())
        .collect();
    let mut units = vec![TraceUnit::new(scan, "scan", Vec::new(), attributes)];
    units.extend(engine.stages.iter().map(TraceUnit::of_stage));
    units.push(TraceUnit::new(
        rop,
        "rop",
        vec![engine.output.spec.clone()],
        Vec::new(),
    ));
    units
}

#[cfg(test)]
mod tests;

/// The side of the engine's first lookup table `L` of microfacet normals (`NdfLookup` with an
/// entry of normals, in a `TexFetch` or a texture-shader stage), for the report's
/// `synthesis` section.
fn ndf_lookup_side(engine: &crate::config::EngineConfig) -> Option<u32> {
    use crate::engine::units::{TextureSource, UnitSpec};
    use crate::ndf::sources::LookupEntry;
    let normals = |s: &TextureSource| match *s {
        TextureSource::NdfLookup { size, entry } => matches!(
            entry,
            LookupEntry::Rgb8 | LookupEntry::Hilo16 | LookupEntry::Signed
        )
        .then_some(size),
        _ => None,
    };
    engine.units.iter().find_map(|u| match &u.unit {
        UnitSpec::TexFetch(t) => normals(&t.source),
        UnitSpec::TextureShader(t) => t
            .programs
            .iter()
            .find_map(|p| p.texture.as_ref().and_then(|x| normals(&x.source))),
        _ => None,
    })
}

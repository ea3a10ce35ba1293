//! One run of a config: scene, geometry, rasterizer, the engine in both modes, the float
//! reference, the comparisons, the report and the pictures.

use crate::config::{AttrSource, AttributeConfig, InputError, Loaded};
use crate::engine::{self, attributes, Engine};
use crate::metrics::{self, Rgb64};
use crate::raster::{self, packet::PacketLayout, Fragment};
use crate::reference;
use crate::report::{Artifacts, Bandwidth, Edges, Errors, Gates, ImageInfo, Report, VERSION};
use crate::scene::Scene;
use crate::sim;
use crate::trace::{Trace, TraceUnit};
use bumpsim_hw::{Mode, Token, Word};

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
    pub reference: image::RgbImage,
    pub error: image::RgbImage,
    pub trace: Option<Trace>,
    /// Wall time of each phase, in order (for `render --timings`; never in the report, which
    /// stays deterministic).
    pub timings: Timings,
}

/// Wall times of a run's phases.
#[derive(Debug, Clone, Default)]
pub struct Timings {
    pub phases: Vec<(&'static str, std::time::Duration)>,
    last: Option<std::time::Instant>,
}

impl Timings {
    /// Start timing.
    pub fn start() -> Self {
        Timings {
            phases: Vec::new(),
            last: Some(std::time::Instant::now()),
        }
    }
    /// End the phase `name` (it began where the last one ended).
    pub fn lap(&mut self, name: &'static str) {
        let now = std::time::Instant::now();
        let since = self.last.unwrap_or(now);
        self.phases.push((name, now - since));
        self.last = Some(now);
    }
    /// One line per phase and the total, e.g. `  simulation      12.3 ms`.
    pub fn to_text(&self) -> String {
        let total: std::time::Duration = self.phases.iter().map(|p| p.1).sum();
        let mut s = String::new();
        for (name, d) in self.phases.iter().chain([&("total", total)]) {
            s.push_str(&format!(
                "  {name:<18} {:>10.1} ms\n",
                d.as_secs_f64() * 1e3
            ));
        }
        s
    }
}

/// Build the scene a config describes. Errors name the config file and the field.
pub fn build_scene(l: &Loaded) -> Result<Scene, InputError> {
    let c = &l.config.scene;
    let mesh = c
        .mesh
        .build(&l.base_dir)
        .map_err(|e| l.scene_error("scene.mesh", "mesh:", e))?;
    mesh.validate("scene.mesh")
        .map_err(|e| l.scene_error("scene.mesh", "mesh:", e))?;
    let bump = c
        .bump
        .build(&l.base_dir)
        .map_err(|e| l.scene_error("scene.bump", "bump:", e))?;
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
        color_texture,
        width: c.width.0,
        height: c.height.0,
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

/// Fragments grouped by triangle: ranges into the fragment list, one per submitted triangle.
fn triangle_ranges(frags: &[Fragment], ntri: usize) -> Vec<std::ops::Range<usize>> {
    let mut ranges = vec![0..0; ntri];
    let mut start = 0;
    while start < frags.len() {
        let t = frags[start].tri as usize;
        let mut end = start;
        while end < frags.len() && frags[end].tri as usize == t {
            end += 1;
        }
        ranges[t] = start..end;
        start = end;
    }
    // triangles without fragments keep an empty range at their own position
    let mut fixed = Vec::with_capacity(ntri);
    let mut cursor = 0;
    for r in ranges {
        if r.is_empty() {
            fixed.push(cursor..cursor);
        } else {
            cursor = r.end;
            fixed.push(r);
        }
    }
    fixed
}

struct Front<'a> {
    frags: &'a [Fragment],
    tris: &'a [[u32; 3]],
    vd: &'a attributes::VertexData,
    /// The vertex values the interpolator reads: on each attribute's grid in bit-accurate
    /// mode ([`attributes::VertexData::snapped`]), as computed in exact mode.
    values: &'a [Vec<[f64; 4]>],
    /// The fixed-point interpolator's vertex words and weight bits, when the bit-accurate
    /// engine has one.
    fixed: Option<(&'a [Vec<[i64; 4]>], u32)>,
}

impl Front<'_> {
    /// Fill a token with fragment `f`'s interpolated attributes.
    fn fill(&self, attrs: &[AttributeConfig], mode: Mode, f: usize, t: &mut Token) {
        let frag = &self.frags[f];
        let tri = self.tris[frag.tri as usize];
        for (a, attr) in attrs.iter().enumerate() {
            let lanes = attr.source.lanes() as usize;
            t.slots[a] = if self.vd.flat[a] {
                attributes::flat(
                    mode,
                    &attr.enc,
                    lanes,
                    &self.vd.values[a][frag.tri as usize],
                )
            } else if let Some((codes, bits)) = self.fixed.filter(|_| mode == Mode::BitAccurate) {
                let mut c = tri.map(|i| codes[a][i as usize]);
                if let Some(flips) = self.flips(attr, a, tri) {
                    for (v, flip) in c.iter_mut().zip(flips) {
                        if flip {
                            *v = v.map(|x| -x);
                        }
                    }
                }
                attributes::interpolate_fixed(
                    &attr.enc,
                    lanes,
                    [&c[0], &c[1], &c[2]],
                    frag.bary,
                    bits,
                )
            } else {
                let mut v = tri.map(|i| self.values[a][i as usize]);
                if let Some(flips) = self.flips(attr, a, tri) {
                    for (v, flip) in v.iter_mut().zip(flips) {
                        if flip {
                            *v = v.map(|x| -x);
                        }
                    }
                }
                attributes::interpolate_snapped(
                    mode,
                    &attr.enc,
                    lanes,
                    [&v[0], &v[1], &v[2]],
                    frag.bary,
                )
            };
        }
        (t.id, t.x, t.y) = (f as u64, frag.x, frag.y);
    }

    /// Triangle setup's sign choice for quaternion attributes
    /// ([`crate::engine::frames::hemisphere_flips`], decided on the geometry engine's values).
    fn flips(&self, attr: &AttributeConfig, a: usize, tri: [u32; 3]) -> Option<[bool; 3]> {
        matches!(attr.source, AttrSource::Quaternion).then(|| {
            let q = tri.map(|i| &self.vd.values[a][i as usize]);
            crate::engine::frames::hemisphere_flips(q)
        })
    }
}

/// The fixed-point interpolator's vertex words and weight bits, if `i` is one.
fn fixed(
    codes: &[Vec<[i64; 4]>],
    i: crate::config::Interpolator,
) -> Option<(&[Vec<[i64; 4]>], u32)> {
    match i {
        crate::config::Interpolator::Exact => None,
        crate::config::Interpolator::Fixed { weight_bits } => Some((codes, weight_bits)),
    }
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
    let scene = build_scene(l)?;
    let cfg = &l.config;
    let vertices = attributes::compute(&scene, &cfg.engine.attributes);
    let engine = engine::build(l, &scene)?;
    // an engine that may kill fragments, or a ROP with other tests, needs the depth test
    // after shading
    let depth = if engine.late_depth() {
        raster::DepthTest::Late
    } else {
        raster::DepthTest::Early
    };
    let raster = raster::rasterize_with(
        &vertices.clip,
        &scene.mesh.triangles,
        scene.width,
        scene.height,
        &cfg.raster,
        depth,
    );
    let snapped = vertices.snapped(&cfg.engine.attributes);
    let interpolator = cfg.engine.interpolator;
    let codes = match interpolator {
        crate::config::Interpolator::Exact => Vec::new(),
        crate::config::Interpolator::Fixed { .. } => vertices.codes(&cfg.engine.attributes),
    };
    Ok(Prepared {
        scene,
        snapped,
        codes,
        interpolator,
        vertices,
        raster,
        engine,
        raster_config: cfg.raster,
        fifo_depth: cfg.sim.fifo_depth as usize,
    })
}

impl Prepared {
    /// The front end of `mode`: fragments and the vertex values its interpolator reads.
    fn front(&self, mode: Mode) -> Front<'_> {
        Front {
            frags: &self.raster.fragments,
            tris: &self.scene.mesh.triangles,
            vd: &self.vertices,
            values: match mode {
                Mode::BitAccurate => &self.snapped,
                Mode::Exact => &self.vertices.values,
            },
            fixed: fixed(&self.codes, self.interpolator),
        }
    }

    /// The timed, bit-accurate run of the frame.
    pub fn simulate(&mut self, trace: Option<(u64, u64)>) -> sim::SimResult {
        // the fields one by one: the stages are borrowed mutably below
        let front = Front {
            frags: &self.raster.fragments,
            tris: &self.scene.mesh.triangles,
            vd: &self.vertices,
            values: &self.snapped,
            fixed: fixed(&self.codes, self.interpolator),
        };
        let attrs = &self.engine.attributes;
        let fill = |f: usize, t: &mut Token| front.fill(attrs, Mode::BitAccurate, f, t);
        let ranges = triangle_ranges(front.frags, self.scene.mesh.triangles.len());
        let setup = self
            .raster
            .triangles
            .iter()
            .map(|t| t.setups.max(1) * self.raster_config.setup_cycles)
            .collect();
        let workload = sim::Workload {
            triangles: ranges,
            setup,
            fill_token: &fill,
            slots: self.engine.signals.len(),
            fifo_depth: self.fifo_depth,
        };
        let output = self.engine.output.wire;
        sim::run(&mut self.engine.stages, output, workload, trace)
    }

    /// The engine in exact mode over every fragment (untimed: its timing is the same).
    pub fn evaluate_exact(&self) -> Vec<Option<Word>> {
        let front = self.front(Mode::Exact);
        let attrs = &self.engine.attributes;
        let fill = |f: usize, t: &mut Token| front.fill(attrs, Mode::Exact, f, t);
        sim::evaluate(
            &self.engine.stages,
            Mode::Exact,
            self.engine.output.wire,
            front.frags.len(),
            self.engine.slots(),
            &fill,
        )
    }

    /// The token of fragment `f` after every stage in `mode` (every signal's value): for
    /// tests of the units in their configured engines.
    pub fn fragment_token(&self, mode: Mode, f: usize) -> Token {
        let front = self.front(mode);
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

    /// The float reference of the same scene.
    pub fn reference(&self, r: crate::config::ReferenceConfig) -> reference::ReferenceImage {
        reference::render_reference_sampled(
            &self.scene,
            &self.raster_config,
            r.perturbation,
            r.samples,
        )
    }
}

/// Run a loaded config.
pub fn run(l: &Loaded, trace: Option<&TraceRequest>) -> Result<RunResult, InputError> {
    let cfg = &l.config;
    let mut timings = Timings::start();
    let mut p = prepare(l)?;
    timings.lap("scene and assets");
    if let Some(t) = trace {
        if let Some(names) = &t.units {
            for n in names {
                if !p.engine.stages.iter().any(|s| &s.name == n) {
                    let known: Vec<&str> =
                        p.engine.stages.iter().map(|s| s.name.as_str()).collect();
                    return Err(InputError::new(
                        "--units",
                        "",
                        format!("no unit {n:?}: expected one of {}", known.join(", ")),
                    ));
                }
            }
        }
    }
    let result = p.simulate(trace.map(|t| t.cycles));
    timings.lap("simulation");
    let exact_out = p.evaluate_exact();
    timings.lap("exact mode");
    let (w, h) = (p.scene.width, p.scene.height);
    let frags = &p.raster.fragments;
    let bit = &p.engine;
    let fb = crate::rop::write(&bit.rop, Mode::BitAccurate, w, h, frags, &result.outputs);
    let fb_exact = crate::rop::write(&bit.rop, Mode::Exact, w, h, frags, &exact_out);
    let (img_bit, mask) = (&fb.image, &fb.mask);
    let (img_exact, exact_mask) = (&fb_exact.image, &fb_exact.mask);
    let refimg = p.reference(cfg.reference);
    timings.lap("reference");
    let rimg = Rgb64 {
        width: w,
        height: h,
        px: refimg.px.clone(),
    };
    let rmask = &refimg.mask;
    let errors = Errors {
        total: metrics::compare(img_bit, mask, &rimg, rmask),
        algorithm: metrics::compare(img_exact, exact_mask, &rimg, rmask),
        quantization: metrics::compare(img_bit, mask, img_exact, exact_mask),
    };
    let edges = Edges {
        total: crate::edges::measure(img_bit, mask, &fb.tri, &rimg, rmask),
        algorithm: crate::edges::measure(img_exact, exact_mask, &fb_exact.tri, &rimg, rmask),
        quantization: crate::edges::measure(img_bit, mask, &fb.tri, img_exact, exact_mask),
    };
    let artifacts = Artifacts {
        total: crate::artifacts::measure(img_bit, mask, &rimg, rmask),
        quantization: crate::artifacts::measure(img_bit, mask, img_exact, exact_mask),
    };
    let covered = mask.iter().filter(|&&m| m).count() as u64;
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
    let mut units: Vec<(String, String, bumpsim_hw::GateBudget)> = bit
        .stages
        .iter()
        .zip(&bit.gates)
        .map(|(s, (_, g))| (s.name.clone(), s.unit().kind().to_string(), g.clone()))
        .collect();
    if let crate::config::Interpolator::Fixed { weight_bits } = cfg.engine.interpolator {
        let g = attributes::interpolator_gates(&bit.attributes, weight_bits, &cfg.cost);
        units.push(("attribute interpolator".into(), "interpolator".into(), g));
    }
    let blend = cfg.engine.units.iter().find_map(|u| match u.unit {
        engine::units::UnitSpec::FbBlend(ref fb) => Some(fb.equation),
        _ => None,
    });
    let passes = crate::passes::passes(
        crate::passes::Frame {
            frame_cycles: result.cycles.frame,
            stream_cycles: result.cycles.total - result.cycles.frame,
            triangles: result.cycles.triangles,
            fragments: fb.depth_tested,
            written: fb.written,
            bits_per_triangle: bits,
            color_bits: 3 * u64::from(bit.rop.params().color_bits),
            depth_bits: u64::from(cfg.raster.depth_bits),
        },
        blend,
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
        },
        cycles: result.cycles,
        gates: Gates::new(&units, &bit.rop.gates(&cfg.cost)),
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
            packet,
        },
        passes,
        error: errors,
        artifacts,
        edges,
    };
    let trace = trace.map(|t| {
        let units = bit.stages.iter().map(TraceUnit::of_stage).collect();
        let full = Trace {
            units,
            records: result.probes,
        };
        match &t.units {
            Some(names) => full.select_units(names).expect("unit names checked above"),
            None => full,
        }
    });
    let (image, reference) = (fb.rgb8.clone(), rimg.to_rgb8());
    let error = metrics::heatmap(img_bit, mask, &rimg, rmask, 32.0);
    timings.lap("metrics");
    Ok(RunResult {
        image,
        reference,
        error,
        report,
        trace,
        timings,
    })
}

//! The cycle simulator: drives fragments through an engine's stages clock by clock.
//!
//! A frame is:
//! 1. **frame work**: every unit's per-frame cycles (table loads, palette builds), one after
//!    another on the shared load path, before any fragment;
//! 2. **triangles**: the setup unit takes `setup_cycles` per triangle (every submitted
//!    triangle, drawn or not) and hands set-up triangles through a one-entry buffer to the
//!    scan converter, so setup of the next triangle overlaps the scan of this one;
//! 3. **fragments**: the scan converter emits at most one fragment per clock into the first
//!    FIFO; the stages move them on with valid/ready handshakes and bounded FIFOs; the frame
//!    buffer write (ROP) drains one fragment per clock from the last FIFO.
//!
//! Stages are ticked from the last to the first within a clock (see `bumpsim_hw::stage`).
//! The timing model is single-threaded and deterministic. It runs on **timing twins** of the
//! stages (the same latency, interval and frame work in a shell of their own), so it needs no
//! mutable access to the engine and runs concurrently with the function (`function.rs`),
//! which evaluates the engine's own stages: timing does not depend on data.
//!
//! A run without a trace (and without two units' texture-cache misses queued at one memory)
//! gets the same model's report from recurrences on each fragment's entry and exit clocks
//! (`events.rs`), per fragment and unit instead of per clock; `tests.rs` checks the two
//! against each other, misses included.

mod events;
mod function;

use bumpsim_hw::{
    Columns, CostTable, Counters, CycleState, Fifo, GateBudget, Mode, PortSpec, Probe, Scratch,
    Stage, Token, Unit, Wire, Word,
};
use function::eval_one;
pub(crate) use function::new_token;
pub use function::{evaluate, evaluate_lanes, Outputs};
use serde::Serialize;
use std::collections::BTreeMap;

/// The front end's and the back end's units in the cycle report and in traces, beside the
/// engine's own: triangle setup, the scan converter (which hands each fragment's interpolated
/// attributes to the first FIFO) and the ROP (which drains one fragment per clock from the
/// last). Engine units may not take these names.
pub const FIXED_UNITS: [&str; 3] = ["setup", "scan", "rop"];

/// Cycle accounting of one frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CycleReport {
    /// All cycles of the frame: frame work, then triangles and fragments until the pipe drains.
    pub total: u64,
    /// Cycles of per-frame work before the first triangle.
    pub frame: u64,
    pub fragments: u64,
    /// Fragments killed in the pipe (they flow to the ROP, which does not write them).
    pub killed: u64,
    pub triangles: u64,
    /// `(total - frame) / fragments`.
    pub per_fragment: f64,
    /// Counters of the setup unit, the scan converter, every engine unit and the ROP (busy in
    /// a clock that takes a fragment from the last FIFO, idle otherwise), from the end of the
    /// frame work to the end of the frame.
    pub per_unit: BTreeMap<String, Counters>,
}

impl CycleReport {
    /// The report of a frame of `total` clocks whose first `frame` were frame work: the
    /// fixed units' counters (setup, scan, ROP) and the engine units' by name.
    fn new(
        [total, frame, fragments, triangles]: [u64; 4],
        fixed: [Counters; 3],
        units: impl IntoIterator<Item = (String, Counters)>,
    ) -> Self {
        let mut per_unit: BTreeMap<String, Counters> = FIXED_UNITS
            .iter()
            .map(|n| n.to_string())
            .zip(fixed)
            .collect();
        per_unit.extend(units);
        let work = total - frame;
        CycleReport {
            total,
            frame,
            fragments,
            killed: 0,
            triangles,
            per_fragment: if fragments > 0 {
                work as f64 / fragments as f64
            } else {
                0.0
            },
            per_unit,
        }
    }
}

/// What the simulator needs of the front end.
pub struct Workload<'a> {
    /// Fragments of each triangle, in submission order; entries are indices into the frame's
    /// fragment list.
    pub triangles: Vec<std::ops::Range<usize>>,
    /// Setup cycles of each triangle (a clipped triangle may need several setups).
    pub setup: Vec<u32>,
    /// Builds the token of a fragment (interpolated attributes).
    pub fill_token: &'a FillToken<'a>,
    /// Slots of a token.
    pub slots: usize,
    /// The interpolated attributes: the token's first slots, which the scan converter's
    /// probes show.
    pub attributes: usize,
    pub fifo_depth: usize,
    /// Per stage, how its texture-cache misses delay its fragments
    /// ([`bumpsim_hw::Stage::set_misses`]); empty or `None`: not at all.
    pub extra: Vec<Option<bumpsim_hw::stage::MissTiming>>,
}

/// Fills a token with a fragment's interpolated attributes (and id and position); called from
/// any thread.
pub type FillToken<'a> = dyn Fill + 'a;

/// The front end's filling of tokens: one fragment, or a batch of consecutive fragments
/// (the same tokens as one call per fragment; a front end may compute a batch lane by lane).
/// Every `Fn(usize, &mut Token)` is one.
pub trait Fill: Sync {
    /// Fill `t` with fragment `f`.
    fn fill(&self, f: usize, t: &mut Token);
    /// Fill `ts[k]` with fragment `first + k`, as [`Fill::fill`] would.
    fn fill_batch(&self, first: usize, ts: &mut [Token]) {
        for (k, t) in ts.iter_mut().enumerate() {
            self.fill(first + k, t);
        }
    }
    /// Start a batch of fragments `first..first + n` (at most [`bumpsim_hw::BATCH`]) in
    /// `cols` and write their bit-accurate tokens' raw words, as [`Fill::fill`] would.
    fn fill_columns(&self, first: usize, n: usize, cols: &mut Columns) {
        fill_columns_each(self, first, n, cols);
    }
}

/// [`Fill::fill_columns`] by one [`Fill::fill`] per fragment.
pub(crate) fn fill_columns_each<F: Fill + ?Sized>(
    f: &F,
    first: usize,
    n: usize,
    cols: &mut Columns,
) {
    cols.start(n);
    let mut t = new_token(cols.slots.len());
    for k in 0..cols.len() {
        f.fill(first + k, &mut t);
        for (s, w) in t.slots.iter().enumerate() {
            cols.set_word(s, k, w);
        }
    }
}

impl<F: Fn(usize, &mut Token) + Sync> Fill for F {
    fn fill(&self, f: usize, t: &mut Token) {
        self(f, t)
    }
}

/// The result of a timed run.
pub struct SimResult {
    /// Output word of each fragment, by fragment index; `None` for a killed fragment.
    pub outputs: Vec<Option<Word>>,
    pub cycles: CycleReport,
    /// Probes of the traced cycles, by trace unit ([`trace_index`]).
    pub probes: Vec<(usize, Probe)>,
}

/// The index of a probe's unit in a trace: the scan converter first (0), then the engine's
/// stages in order (`1..=stages`), then the ROP (`stages + 1`).
pub mod trace_index {
    pub const SCAN: usize = 0;
    pub fn stage(i: usize) -> usize {
        i + 1
    }
    pub fn rop(stages: usize) -> usize {
        stages + 1
    }
}

/// Probes of the frame work inside the `trace` window: the stages' per-frame work runs one
/// after another on one load path from cycle 0; each of a stage's clocks is busy and a clock
/// that writes a table entry shows it as the emitted token (id = entry index; the first
/// entry when several are written in one clock).
fn frame_probes(stages: &[Stage], trace: Option<(u64, u64)>) -> Vec<(usize, Probe)> {
    let Some((a, b)) = trace else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut start = 0u64;
    for (i, s) in stages.iter().enumerate() {
        let n = s.unit().frame_cycles();
        let (lo, hi) = (a.max(start), b.min(start.saturating_add(n)));
        if lo < hi {
            let writes = s.unit().frame_writes();
            let mut w = writes.iter().peekable();
            for cycle in lo..hi {
                while w.peek().is_some_and(|x| start.saturating_add(x.0) < cycle) {
                    w.next();
                }
                let emitted = w
                    .peek()
                    .filter(|x| start.saturating_add(x.0) == cycle)
                    .map(|x| (x.1, x.2.clone()));
                out.push((
                    trace_index::stage(i),
                    Probe {
                        cycle,
                        state: CycleState::Busy,
                        accepted: None,
                        emitted,
                    },
                ));
            }
        }
        start = start.saturating_add(n);
    }
    out
}

/// Run one frame: the timing model over fragment ids and, concurrently, the function over
/// every fragment (timing does not depend on data), then the traced probes' port values.
/// `trace` is a half-open cycle window to probe.
pub fn run(stages: &[Stage], output: Wire, w: Workload, trace: Option<(u64, u64)>) -> SimResult {
    let nfrag = w.fragments();
    let (mut cycles, probes, outputs) = run_with(stages, output, &w, trace, || {
        evaluate(
            stages,
            Mode::BitAccurate,
            output,
            nfrag,
            w.slots,
            w.fill_token,
        )
    });
    cycles.killed = outputs.iter().filter(|o| o.is_none()).count() as u64;
    SimResult {
        outputs,
        cycles,
        probes,
    }
}

/// A timed run whose outputs are stored as the ROP reads them ([`Outputs`]).
pub struct Timed {
    pub outputs: Outputs,
    pub cycles: CycleReport,
    /// Probes of the traced cycles, by trace unit ([`trace_index`]).
    pub probes: Vec<(usize, Probe)>,
}

/// [`run`] with the outputs stored as raw lanes of the output port `port` ([`Outputs`]).
pub fn run_lanes(
    stages: &[Stage],
    output: Wire,
    port: &PortSpec,
    w: Workload,
    trace: Option<(u64, u64)>,
) -> Timed {
    let nfrag = w.fragments();
    let (mut cycles, probes, outputs) = run_with(stages, output, &w, trace, || {
        evaluate_lanes(
            stages,
            Mode::BitAccurate,
            output,
            port,
            nfrag,
            w.slots,
            w.fill_token,
        )
    });
    cycles.killed = outputs.killed();
    Timed {
        outputs,
        cycles,
        probes,
    }
}

/// The timing model (on the stages' twins) concurrently with `function`, then the port values
/// of the traced probes. The cycle report's `killed` is left to the caller (it is the
/// function's).
fn run_with<O: Send>(
    stages: &[Stage],
    output: Wire,
    w: &Workload,
    trace: Option<(u64, u64)>,
    function: impl FnOnce() -> O + Send,
) -> (CycleReport, Vec<(usize, Probe)>, O) {
    let ((cycles, mut probes, first), outputs) = rayon::join(|| timing(stages, w, trace), function);
    // fragment id -> the probes that show it
    let mut refs: BTreeMap<u64, Vec<usize>> = BTreeMap::new();
    for (k, (_, p)) in probes.iter().enumerate().skip(first) {
        for id in [&p.accepted, &p.emitted].into_iter().flatten().map(|x| x.0) {
            refs.entry(id).or_default().push(k);
        }
    }
    // the traced fragments once more, for their port values
    let (mut t, mut scratch) = (new_token(w.slots), Scratch::default());
    for (&f, ks) in &refs {
        eval_one(
            stages,
            Mode::BitAccurate,
            output,
            f as usize,
            &mut t,
            &mut scratch,
            w.fill_token,
        );
        for &k in ks {
            let (i, p) = &mut probes[k];
            // what the unit took and gave: the scan converter gives the attributes, the ROP
            // takes the engine's output, a stage its ports
            let (ins, outs) = match *i {
                trace_index::SCAN => (Vec::new(), t.slots[..w.attributes].to_vec()),
                i if i == trace_index::rop(stages.len()) => {
                    (vec![output.read(&t.slots)], Vec::new())
                }
                i => {
                    let s = &stages[i - 1];
                    (s.input_words(&t), s.output_words(&t))
                }
            };
            if let Some((id, words)) = &mut p.accepted {
                if *id == f {
                    *words = ins;
                }
            }
            if let Some((id, words)) = &mut p.emitted {
                if *id == f {
                    *words = outs;
                }
            }
        }
    }
    (cycles, probes, outputs)
}

impl Workload<'_> {
    fn fragments(&self) -> usize {
        self.triangles.iter().map(|r| r.len()).sum()
    }
}

/// A stage's shell for the timing model: the latency, interval, kill flag and frame work of
/// a unit, without its function (no ports; never evaluated).
struct TimingTwin {
    kind: &'static str,
    latency: u32,
    interval: u32,
    frame_cycles: u64,
    can_kill: bool,
}

impl Unit for TimingTwin {
    fn kind(&self) -> &'static str {
        self.kind
    }
    fn inputs(&self) -> &[PortSpec] {
        &[]
    }
    fn outputs(&self) -> &[PortSpec] {
        &[]
    }
    fn latency(&self) -> u32 {
        self.latency
    }
    fn interval(&self) -> u32 {
        self.interval
    }
    fn gates(&self, _: &CostTable) -> GateBudget {
        GateBudget::new()
    }
    fn frame_cycles(&self) -> u64 {
        self.frame_cycles
    }
    fn can_kill(&self) -> bool {
        self.can_kill
    }
    fn eval(&self, _: Mode, _: &[Word], _: &mut [Word]) {}
}

/// Stages with the timing of `stages` (same names, latencies, intervals and frame work), in
/// their reset state: what [`timing`] ticks, so the engine's stages are only read.
fn timing_twins(stages: &[Stage]) -> Vec<Stage> {
    stages
        .iter()
        .map(|s| {
            let u = s.unit();
            let twin = TimingTwin {
                kind: u.kind(),
                latency: u.latency(),
                interval: u.interval(),
                frame_cycles: u.frame_cycles(),
                can_kill: u.can_kill(),
            };
            Stage::new(s.name.clone(), Box::new(twin), Vec::new(), Vec::new())
        })
        .collect()
}

/// The timing model of a frame over fragment ids. Returns the cycle report (without
/// `killed`), the probes of the `trace` window without port values, and the index of the first
/// fragment probe (the ones before it are frame work). Without a trace, and when no unit's
/// timing depends on the fragment, on events (`events.rs`, the same report); otherwise clock
/// by clock ([`clocked`]).
fn timing(
    engine: &[Stage],
    w: &Workload,
    trace: Option<(u64, u64)>,
) -> (CycleReport, Vec<(usize, Probe)>, usize) {
    if trace.is_none() {
        if let Some(c) = events::timing(engine, w) {
            return (c, Vec::new(), 0);
        }
    }
    clocked(engine, w, trace)
}

/// The timing model of a frame clock by clock: frame work, setup, scan, the stages and the
/// frame buffer write. Returns what [`timing`] returns.
fn clocked(
    engine: &[Stage],
    w: &Workload,
    trace: Option<(u64, u64)>,
) -> (CycleReport, Vec<(usize, Probe)>, usize) {
    let nfrag = w.fragments();
    let mut stages = timing_twins(engine);
    for (s, e) in stages.iter_mut().zip(&w.extra) {
        if let Some(e) = e {
            s.set_misses(e.clone());
        }
    }
    let nstage = stages.len();
    // the texture memories' fill queues: the cycle each can issue its next fill
    // (one per stage at most: an index beyond them does not queue, `MissTiming::memory`)
    let nmem = w.extra.iter().flatten().map(|m| m.memory.saturating_add(1));
    let nmem = nmem.max().unwrap_or(0).min(w.extra.len());
    let mut memories = vec![0u64; nmem];
    let mut fifos: Vec<Fifo> = (0..=nstage).map(|_| Fifo::new(w.fifo_depth)).collect();
    // saturating sums and additions of the config-derived cycle counts (frame work, setup):
    // a huge value saturates instead of wrapping to a small one
    let frame: u64 = stages
        .iter()
        .map(|s| s.unit().frame_cycles())
        .fold(0, u64::saturating_add);
    let mut probes = frame_probes(engine, trace);
    let first = probes.len();
    let [mut setup_c, mut scan_c, mut rop_c] = [Counters::default(); 3];
    let mut next_tri = 0usize;
    let mut setting_up: Option<(usize, u64)> = None; // (triangle, cycle its setup completes)
    let mut ready: Option<usize> = None;
    let mut scanning: Option<(usize, usize)> = None; // (triangle, next fragment)
    let mut cycle = frame;
    let bump = |c: &mut Counters, busy: bool, stall: bool| {
        if stall {
            c.stall += 1
        } else if busy {
            c.busy += 1
        } else {
            c.idle += 1
        }
    };
    loop {
        let probe = trace.is_some_and(|(a, b)| cycle >= a && cycle < b);
        // frame buffer write
        let drained = fifos[nstage].pop();
        if drained.is_some() {
            rop_c.accepted += 1;
        }
        bump(&mut rop_c, drained.is_some(), false);
        if probe {
            let state = match drained {
                Some(_) => CycleState::Busy,
                None => CycleState::Idle,
            };
            let accepted = drained.map(|id| (id, Vec::new()));
            probes.push((
                trace_index::rop(nstage),
                Probe {
                    cycle,
                    state,
                    accepted,
                    emitted: None,
                },
            ));
        }
        for i in (0..nstage).rev() {
            let (a, b) = fifos.split_at_mut(i + 1);
            if let Some(p) = stages[i].tick(cycle, &mut a[i], &mut b[0], probe, &mut memories) {
                probes.push((trace_index::stage(i), p));
            }
        }
        // scan conversion: one fragment per clock
        let (mut scan_busy, mut scan_stall) = (false, false);
        loop {
            match scanning {
                Some((t, k)) if k < w.triangles[t].len() => break,
                _ => match ready.take() {
                    Some(t) => scanning = Some((t, 0)),
                    None => {
                        scanning = None;
                        break;
                    }
                },
            }
        }
        let mut scanned = None;
        if let Some((t, k)) = scanning {
            if fifos[0].has_room() {
                let id = (w.triangles[t].start + k) as u64;
                fifos[0].push(id);
                scanned = Some(id);
                scanning = Some((t, k + 1));
                scan_busy = true;
            } else {
                scan_stall = true;
            }
        }
        bump(&mut scan_c, scan_busy, scan_stall);
        if probe {
            let state = match (scan_busy, scan_stall) {
                (_, true) => CycleState::Stall,
                (true, _) => CycleState::Busy,
                _ => CycleState::Idle,
            };
            let emitted = scanned.map(|id| (id, Vec::new()));
            probes.push((
                trace_index::SCAN,
                Probe {
                    cycle,
                    state,
                    accepted: None,
                    emitted,
                },
            ));
        }
        // triangle setup
        let (mut setup_busy, mut setup_stall) = (false, false);
        if let Some((t, done)) = setting_up {
            if cycle >= done {
                if ready.is_none() {
                    ready = Some(t);
                    setting_up = None;
                } else {
                    setup_stall = true;
                }
            } else {
                setup_busy = true;
            }
        }
        if setting_up.is_none() && next_tri < w.triangles.len() {
            setting_up = Some((
                next_tri,
                cycle.saturating_add(u64::from(w.setup[next_tri].max(1))),
            ));
            next_tri += 1;
            setup_busy = true;
        }
        bump(&mut setup_c, setup_busy, setup_stall);
        cycle += 1;
        // every fragment written: the ROP has taken them all
        let idle = rop_c.accepted == nfrag as u64
            && next_tri == w.triangles.len()
            && setting_up.is_none()
            && ready.is_none()
            && scanning.is_none()
            && stages.iter().all(|s| s.is_empty())
            && fifos.iter().all(|f| f.is_empty());
        if idle {
            break;
        }
    }
    let cycles = CycleReport::new(
        [cycle, frame, nfrag as u64, w.triangles.len() as u64],
        [setup_c, scan_c, rop_c],
        stages.iter().map(|s| (s.name.clone(), s.counters)),
    );
    (cycles, probes, first)
}

#[cfg(test)]
mod tests;

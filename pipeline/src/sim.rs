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
//! The simulation is single-threaded and deterministic.

use bumpsim_hw::{Counters, CycleState, Fifo, Probe, Stage, Token, Word};
use serde::Serialize;
use std::collections::BTreeMap;

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
    /// Counters of the setup unit, the scan converter and every engine unit, from the end of
    /// the frame work to the end of the frame.
    pub per_unit: BTreeMap<String, Counters>,
}

/// What the simulator needs of the front end.
pub struct Workload<'a> {
    /// Fragments of each triangle, in submission order; entries are indices into the frame's
    /// fragment list.
    pub triangles: Vec<std::ops::Range<usize>>,
    /// Setup cycles of each triangle (a clipped triangle may need several setups).
    pub setup: Vec<u32>,
    /// Builds the token of a fragment (interpolated attributes).
    pub fill_token: &'a mut dyn FnMut(usize, &mut Token),
    /// Slots of a token.
    pub slots: usize,
    pub fifo_depth: usize,
}

/// The result of a timed run.
pub struct SimResult {
    /// Output word of each fragment, by fragment index; `None` for a killed fragment.
    pub outputs: Vec<Option<Word>>,
    pub cycles: CycleReport,
    /// Probes of the stages, by stage index, for the traced cycles.
    pub probes: Vec<(usize, Probe)>,
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
        let (lo, hi) = (a.max(start), b.min(start + n));
        if lo < hi {
            let writes = s.unit().frame_writes();
            let mut w = writes.iter().peekable();
            for cycle in lo..hi {
                while w.peek().is_some_and(|x| start + x.0 < cycle) {
                    w.next();
                }
                let emitted = w
                    .peek()
                    .filter(|x| start + x.0 == cycle)
                    .map(|x| (x.1, x.2.clone()));
                out.push((
                    i,
                    Probe {
                        cycle,
                        state: CycleState::Busy,
                        accepted: None,
                        emitted,
                    },
                ));
            }
        }
        start += n;
    }
    out
}

/// Run one frame with timing. `trace` is a half-open cycle window to probe.
pub fn run(
    stages: &mut [Stage],
    output_slot: usize,
    w: Workload,
    trace: Option<(u64, u64)>,
) -> SimResult {
    let nfrag: usize = w.triangles.iter().map(|r| r.len()).sum();
    let nstage = stages.len();
    let mut fifos: Vec<Fifo> = (0..=nstage).map(|_| Fifo::new(w.fifo_depth)).collect();
    let frame: u64 = stages.iter().map(|s| s.unit().frame_cycles()).sum();
    let mut outputs = vec![None; nfrag];
    let mut probes = frame_probes(stages, trace);
    let (mut setup_c, mut scan_c) = (Counters::default(), Counters::default());
    let mut next_tri = 0usize;
    let mut setting_up: Option<(usize, u64)> = None; // (triangle, cycle its setup completes)
    let mut ready: Option<usize> = None;
    let mut scanning: Option<(usize, usize)> = None; // (triangle, next fragment)
    let mut written = 0usize;
    let mut killed = 0u64;
    // tokens leaving the frame buffer are reused by the scan converter
    let mut pool: Vec<Token> = Vec::new();
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
        if let Some(t) = fifos[nstage].pop() {
            outputs[t.id as usize] = t.live.then(|| t.slots[output_slot]);
            killed += u64::from(!t.live);
            written += 1;
            pool.push(t);
        }
        for i in (0..nstage).rev() {
            let (a, b) = fifos.split_at_mut(i + 1);
            if let Some(p) = stages[i].tick(cycle, &mut a[i], &mut b[0], probe) {
                probes.push((i, p));
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
        if let Some((t, k)) = scanning {
            if fifos[0].has_room() {
                let f = w.triangles[t].start + k;
                let mut token = pool.pop().unwrap_or_else(|| Token {
                    id: 0,
                    x: 0,
                    y: 0,
                    live: true,
                    slots: vec![Word::default(); w.slots],
                });
                token.live = true;
                (w.fill_token)(f, &mut token);
                fifos[0].push(token);
                scanning = Some((t, k + 1));
                scan_busy = true;
            } else {
                scan_stall = true;
            }
        }
        bump(&mut scan_c, scan_busy, scan_stall);
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
            setting_up = Some((next_tri, cycle + w.setup[next_tri].max(1) as u64));
            next_tri += 1;
            setup_busy = true;
        }
        bump(&mut setup_c, setup_busy, setup_stall);
        cycle += 1;
        let idle = written == nfrag
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
    let mut per_unit = BTreeMap::new();
    per_unit.insert("setup".to_string(), setup_c);
    per_unit.insert("scan".to_string(), scan_c);
    for s in stages.iter() {
        per_unit.insert(s.name.clone(), s.counters);
    }
    let work = cycle - frame;
    let cycles = CycleReport {
        total: cycle,
        frame,
        fragments: nfrag as u64,
        killed,
        triangles: w.triangles.len() as u64,
        per_fragment: if nfrag > 0 {
            work as f64 / nfrag as f64
        } else {
            0.0
        },
        per_unit,
    };
    SimResult {
        outputs,
        cycles,
        probes,
    }
}

/// Evaluate every fragment through the stages without timing (used for the exact mode, whose
/// timing is the same as the bit-accurate run's).
pub fn evaluate(
    stages: &mut [Stage],
    output_slot: usize,
    nfrag: usize,
    slots: usize,
    fill_token: &mut dyn FnMut(usize, &mut Token),
) -> Vec<Option<Word>> {
    let mut t = Token {
        id: 0,
        x: 0,
        y: 0,
        live: true,
        slots: vec![Word::default(); slots],
    };
    (0..nfrag)
        .map(|f| {
            t.live = true;
            fill_token(f, &mut t);
            for s in stages.iter_mut() {
                s.eval_token(&mut t);
            }
            t.live.then(|| t.slots[output_slot])
        })
        .collect()
}

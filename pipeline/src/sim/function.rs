//! The function half of the simulator: every fragment through the stages in a mode, chunks
//! of fragments in parallel (rayon), each output stored by fragment index, so the result is
//! the same at any thread count; and [`Outputs`], the outputs as the ROP reads them.

use super::FillToken;
use bumpsim_hw::{
    ColumnScratch, Columns, Encoding, Mode, PortSpec, Scratch, Stage, Token, Wire, Word, MAX_LANES,
};
use rayon::prelude::*;

/// Fragments per task of the parallel function evaluation.
const CHUNK: usize = 2048;

/// Evaluate every fragment through the stages without timing (the exact mode, whose timing
/// is the same as the bit-accurate run's; and the function half of [`super::run`]). Fragments are
/// independent and units do not change when they evaluate, so chunks of fragments run in
/// parallel (rayon) and the result is the same at any thread count.
pub fn evaluate(
    stages: &[Stage],
    mode: Mode,
    output: Wire,
    nfrag: usize,
    slots: usize,
    fill_token: &FillToken<'_>,
) -> Vec<Option<Word>> {
    let mut out = vec![None; nfrag];
    out.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, chunk)| {
            let (mut t, mut scratch) = (new_token(slots), Scratch::default());
            for (k, o) in chunk.iter_mut().enumerate() {
                *o = eval_one(
                    stages,
                    mode,
                    output,
                    c * CHUNK + k,
                    &mut t,
                    &mut scratch,
                    fill_token,
                );
            }
        });
    out
}

/// The engine's output of every fragment, stored as the ROP reads it: the raw words of the
/// output port in bit-accurate mode (the values are their decodings), the real values in
/// exact mode (whose raw words nothing reads), `lanes` per fragment, and whether each
/// fragment is live. A quarter to a half of a [`Word`] per fragment.
#[derive(Debug, Clone, PartialEq)]
pub struct Outputs {
    enc: Encoding,
    lanes: usize,
    values: Lanes,
    live: Vec<bool>,
}

#[derive(Debug, Clone, PartialEq)]
enum Lanes {
    Raw(Vec<i64>),
    Real(Vec<f64>),
}

impl Outputs {
    /// Fragments.
    pub fn len(&self) -> usize {
        self.live.len()
    }
    pub fn is_empty(&self) -> bool {
        self.live.is_empty()
    }
    /// Fragments killed in the pipe.
    pub fn killed(&self) -> u64 {
        self.live.iter().filter(|&&l| !l).count() as u64
    }
    /// The output word of fragment `f` as the ROP reads it, `None` if it was killed: in
    /// bit-accurate mode the raw words and their decodings (a bit-accurate word's value is its
    /// decoding), in exact mode the values (raw words 0).
    pub fn word(&self, f: usize) -> Option<Word> {
        if !self.live[f] {
            return None;
        }
        let lanes = f * self.lanes..(f + 1) * self.lanes;
        Some(match &self.values {
            Lanes::Raw(r) => Word::from_raw(&self.enc, &r[lanes]),
            Lanes::Real(x) => {
                let mut w = Word::default();
                for (l, &x) in w.lanes.iter_mut().zip(&x[lanes]) {
                    l.x = x;
                }
                w
            }
        })
    }
}

/// [`evaluate`], the outputs stored as [`Outputs`] of the output port `port`.
pub fn evaluate_lanes(
    stages: &[Stage],
    mode: Mode,
    output: Wire,
    port: &PortSpec,
    nfrag: usize,
    slots: usize,
    fill_token: &FillToken<'_>,
) -> Outputs {
    // a port has 1 to MAX_LANES lanes
    let lanes = (port.lanes as usize).clamp(1, MAX_LANES);
    let f = Function {
        stages,
        mode,
        output,
        slots,
        fill_token,
    };
    let mut live = vec![false; nfrag];
    let values = match mode {
        Mode::BitAccurate => {
            let mut raw = vec![0i64; nfrag * lanes];
            evaluate_columns(&f, &mut raw, lanes, &mut live);
            Lanes::Raw(raw)
        }
        Mode::Exact => {
            let mut x = vec![0f64; nfrag * lanes];
            evaluate_into(&f, &mut x, lanes, &mut live, |w, l| w.lanes[l].x);
            Lanes::Real(x)
        }
    };
    Outputs {
        enc: port.enc,
        lanes,
        values,
        live,
    }
}

/// Every fragment through `stages` in `mode`, chunks in parallel; lane `l` of a live
/// fragment `f`'s output word goes to `values[f * lanes + l]` through `get`, and its liveness
/// to `live[f]`.
fn evaluate_into<T: Send + Copy>(
    f: &Function<'_>,
    values: &mut [T],
    lanes: usize,
    live: &mut [bool],
    get: impl Fn(&Word, usize) -> T + Sync,
) {
    values
        .par_chunks_mut(CHUNK * lanes)
        .zip(live.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (vals, live))| {
            let mut ts: Vec<Token> = (0..BATCH).map(|_| new_token(f.slots)).collect();
            let mut scratch = Scratch::default();
            for (b, live) in live.chunks_mut(BATCH).enumerate() {
                let first = c * CHUNK + b * BATCH;
                let ts = &mut ts[..live.len()];
                eval_batch(f, first, ts, &mut scratch);
                for (k, (l, t)) in live.iter_mut().zip(ts.iter()).enumerate() {
                    if t.live {
                        *l = true;
                        let w = f.output.read(&t.slots);
                        let k = b * BATCH + k;
                        for (i, v) in vals[k * lanes..(k + 1) * lanes].iter_mut().enumerate() {
                            *v = get(&w, i);
                        }
                    }
                }
            }
        });
}

/// Fragments per batch of [`eval_batch`].
const BATCH: usize = bumpsim_hw::BATCH;

/// [`evaluate_into`] in bit-accurate mode, of the raw words, a batch of fragments at a time
/// as columns ([`bumpsim_hw::columns`]): the front end fills the batch's attribute columns and
/// every stage evaluates the batch ([`Stage::eval_columns`]) before the next.
fn evaluate_columns(f: &Function<'_>, values: &mut [i64], lanes: usize, live: &mut [bool]) {
    values
        .par_chunks_mut(CHUNK * lanes)
        .zip(live.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (vals, live))| {
            let mut cols = Columns::new(f.slots);
            let mut scratch = ColumnScratch::default();
            for (b, live) in live.chunks_mut(BATCH).enumerate() {
                let first = c * CHUNK + b * BATCH;
                f.fill_token.fill_columns(first, live.len(), &mut cols);
                for s in f.stages {
                    s.eval_columns(&mut cols, &mut scratch);
                }
                let out = wire_lanes(&f.output, &cols);
                for (k, l) in live.iter_mut().enumerate() {
                    *l = cols.live[k];
                    if *l {
                        let k0 = (b * BATCH + k) * lanes;
                        for (v, lane) in vals[k0..k0 + lanes].iter_mut().zip(out) {
                            *v = lane[k];
                        }
                    }
                }
            }
        });
}

/// The lanes wire `w` reads of the batch's slot columns.
fn wire_lanes<'a>(w: &Wire, cols: &'a Columns) -> [&'a bumpsim_hw::columns::Lane; MAX_LANES] {
    w.columns(&cols.slots).lanes
}

/// Fragments `first..first + ts.len()` through every stage: their tokens filled as one batch
/// ([`super::Fill::fill_batch`]), then each through the stages. `ts[k].live` tells whether
/// fragment `first + k` survived.
fn eval_batch(f: &Function<'_>, first: usize, ts: &mut [Token], scratch: &mut Scratch) {
    for t in ts.iter_mut() {
        t.live = true;
    }
    f.fill_token.fill_batch(first, ts);
    for t in ts.iter_mut() {
        for s in f.stages {
            s.eval_token(t, f.mode, scratch);
        }
    }
}

/// What the function evaluates: the stages in a mode, read at the output wire, on tokens of
/// `slots` slots filled by the front end.
struct Function<'a> {
    stages: &'a [Stage],
    mode: Mode,
    output: Wire,
    slots: usize,
    fill_token: &'a FillToken<'a>,
}

/// A token of `slots` slots, live, its words zero.
pub(crate) fn new_token(slots: usize) -> Token {
    Token {
        id: 0,
        x: 0,
        y: 0,
        live: true,
        slots: vec![Word::default(); slots],
    }
}

/// Fragment `f` through every stage in `mode`; its output word, or `None` if it was killed.
pub(super) fn eval_one(
    stages: &[Stage],
    mode: Mode,
    output: Wire,
    f: usize,
    t: &mut Token,
    scratch: &mut Scratch,
    fill_token: &FillToken<'_>,
) -> Option<Word> {
    t.live = true;
    fill_token.fill(f, t);
    for s in stages {
        s.eval_token(t, mode, scratch);
    }
    t.live.then(|| output.read(&t.slots))
}

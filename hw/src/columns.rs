//! A batch of fragments in bit-accurate mode as columns (a structure of arrays): for every
//! token slot and lane, the raw words of up to [`BATCH`] consecutive fragments. The
//! simulator's function half evaluates a batch stage by stage ([`crate::Stage::eval_columns`]):
//! a unit with a batch datapath ([`crate::Unit::eval_columns`]) runs its loops over the
//! columns, once per stage and batch, reading raw words only; the other units run fragment by
//! fragment on words decoded from the columns. Either way every raw word is the one
//! [`crate::Stage::eval_token`] computes, which `pipeline`'s tests check on every bundled
//! config.
//!
//! Only raw words are kept: in bit-accurate mode a word's value is its decoding
//! (`x == decode(raw)`, the unit contract), so nothing is lost, and the decoding runs only
//! where a unit without a batch datapath reads it.

use crate::format::Encoding;
use crate::unit::{PortSpec, Word, MAX_LANES};

/// Fragments in a batch.
pub const BATCH: usize = 64;

/// One lane of a port over a batch: the raw word of each fragment.
pub type Lane = [i64; BATCH];

/// One port's (or slot's) words over a batch: [`MAX_LANES`] lanes.
pub type Column = [Lane; MAX_LANES];

/// Lanes of no port: what a wire expression's unused lanes read.
static ZERO: Lane = [0; BATCH];

/// An input port's lanes over a batch, each a lane of some slot (a wire expression gathers
/// lanes of several slots; lanes past its lanes read zeros). Lanes past the port's lanes
/// hold no value.
#[derive(Clone, Copy)]
pub struct ColumnIn<'a> {
    pub lanes: [&'a Lane; MAX_LANES],
}

impl Default for ColumnIn<'_> {
    fn default() -> Self {
        ColumnIn {
            lanes: [&ZERO; MAX_LANES],
        }
    }
}

/// The tokens of a batch as columns: `n` fragments, one [`Column`] per slot, and whether each
/// fragment is live.
#[derive(Clone)]
pub struct Columns {
    n: usize,
    pub slots: Vec<Box<Column>>,
    pub live: [bool; BATCH],
}

impl Columns {
    /// Columns of `slots` slots, all words zero, no fragment.
    pub fn new(slots: usize) -> Self {
        Columns {
            n: 0,
            slots: (0..slots)
                .map(|_| Box::new([[0; BATCH]; MAX_LANES]))
                .collect(),
            live: [true; BATCH],
        }
    }
    /// Fragments in the batch.
    pub fn len(&self) -> usize {
        self.n
    }
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
    /// Start a batch of `n` fragments (at most [`BATCH`]), all live; the words are left as
    /// they are, for the front end and the stages to overwrite.
    pub fn start(&mut self, n: usize) {
        self.n = n.min(BATCH);
        self.live = [true; BATCH];
    }
    /// Fragment `k`'s word of slot `s`, its first `lanes` lanes decoded in `enc` (the others
    /// 0).
    pub fn word(&self, s: usize, k: usize, enc: &Encoding, lanes: usize) -> Word {
        decoded(self.slots[s].each_ref().map(|l| l[k]), enc, lanes)
    }
    /// Write `w`'s raw words as fragment `k`'s word of slot `s`.
    #[inline]
    pub fn set_word(&mut self, s: usize, k: usize, w: &Word) {
        set_raws(&mut self.slots[s], k, w);
    }
}

/// The first `lanes` of `raws` and their decodings in `enc` (the other lanes 0: nothing
/// reads lanes past a port's, and a batch datapath need not write them).
#[inline]
pub(crate) fn decoded(raws: [i64; MAX_LANES], enc: &Encoding, lanes: usize) -> Word {
    Word::from_raw(enc, &raws[..lanes.min(MAX_LANES)])
}

/// Fragment `k`'s word of an input port read through `c`, decoded in `port`'s encoding.
#[inline]
pub(crate) fn input_word(c: &ColumnIn<'_>, k: usize, port: &PortSpec) -> Word {
    decoded(c.lanes.map(|l| l[k]), &port.enc, port.lanes as usize)
}

/// Write `w`'s raw words as fragment `k` of `col`.
#[inline]
pub(crate) fn set_raws(col: &mut Column, k: usize, w: &Word) {
    for (lane, s) in col.iter_mut().zip(&w.lanes) {
        lane[k] = s.raw;
    }
}

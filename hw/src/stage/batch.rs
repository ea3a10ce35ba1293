//! [`Stage::eval_columns`]: a stage's function over a batch of fragments held as columns
//! ([`crate::columns`]), in bit-accurate mode.

use super::{Stage, Wire};
use crate::columns::{input_word, set_raws, Column, ColumnIn, Columns, BATCH};
use crate::unit::{Mode, Word, MAX_LANES};

/// Buffers for [`Stage::eval_columns`], one per thread that evaluates batches.
#[derive(Default)]
pub struct ColumnScratch {
    /// Boxed: a stage's output columns are swapped in and out of the batch (2 KiB each).
    #[allow(clippy::vec_box)]
    outs: Vec<Box<Column>>,
    ins: Vec<Word>,
    words: Vec<Word>,
}

impl Stage {
    /// [`Stage::eval_token`] in bit-accurate mode over the batch `cols`: the unit's batch
    /// datapath ([`crate::Unit::eval_columns`]) when it has one and does not kill, otherwise
    /// [`crate::Unit::eval`] fragment by fragment on words decoded from the columns. The
    /// output slots' raw words and the live bits are the ones `eval_token` gives each token.
    pub fn eval_columns(&self, cols: &mut Columns, scratch: &mut ColumnScratch) {
        let n = cols.len();
        // the output columns move out of the batch while the inputs are read (a stage never
        // reads its own outputs: a wire reads earlier signals)
        let outs = &mut scratch.outs;
        while outs.len() < self.out_slots.len() {
            outs.push(Box::new([[0; BATCH]; MAX_LANES]));
        }
        for (o, &s) in outs.iter_mut().zip(&self.out_slots) {
            std::mem::swap(o, &mut cols.slots[s]);
        }
        let ins: Vec<ColumnIn<'_>> = self
            .in_wires
            .iter()
            .map(|w| w.columns(&cols.slots))
            .collect();
        let no = self.out_slots.len();
        let mut cols_out: Vec<&mut Column> = outs[..no].iter_mut().map(|b| &mut **b).collect();
        let batched = !self.kills && self.unit.eval_columns(n, &ins, &mut cols_out);
        if !batched {
            let ports_in = self.unit.inputs();
            let (words_in, words_out) = (&mut scratch.ins, &mut scratch.words);
            words_in.resize(ins.len(), Word::default());
            words_out.resize(no, Word::default());
            for k in 0..n {
                for ((w, c), p) in words_in.iter_mut().zip(&ins).zip(ports_in) {
                    *w = input_word(c, k, p);
                }
                words_out.fill(Word::default());
                self.unit.eval(Mode::BitAccurate, words_in, words_out);
                if self.kills && !self.unit.live(Mode::BitAccurate, words_in, words_out) {
                    cols.live[k] = false;
                }
                for (c, w) in cols_out.iter_mut().zip(words_out.iter()) {
                    set_raws(c, k, w);
                }
            }
        }
        drop(ins);
        for (o, &s) in outs.iter_mut().zip(&self.out_slots) {
            std::mem::swap(o, &mut cols.slots[s]);
        }
    }
}

impl Wire {
    /// The lanes this wire reads of a batch's slot columns ([`Columns::slots`]).
    pub fn columns<'a>(&self, slots: &'a [Box<Column>]) -> ColumnIn<'a> {
        let mut c = ColumnIn::default();
        match *self {
            Wire::Slot(s) => {
                for (l, lane) in c.lanes.iter_mut().zip(slots[s].iter()) {
                    *l = lane;
                }
            }
            Wire::Gather { lanes, from } => {
                for (l, &(s, k)) in c.lanes.iter_mut().zip(&from).take(lanes as usize) {
                    *l = &slots[s as usize][k as usize];
                }
            }
        }
        c
    }
}

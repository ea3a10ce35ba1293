//! The clocked shell around a unit: valid/ready handshakes, latency, initiation interval,
//! busy/idle/stall counters and per-cycle probes.
//!
//! A [`Stage`] binds a [`Unit`] to slots of a [`Token`] (the values a fragment carries down
//! the pipeline: interpolated attributes and every unit's outputs, like the pipeline
//! registers of a fixed-function pipe). Function and timing are apart, since timing does not
//! depend on data: [`Stage::eval_token`] computes a token's outputs, and [`Stage::tick`]
//! moves fragment ids from an input FIFO to an output FIFO, clock by clock:
//!
//! * **accept**: when the cycle is at least `next_accept`, fewer than
//!   `ceil(latency / interval)` tokens are in flight, and the input FIFO is not empty, the
//!   stage pops a fragment and schedules its result `latency` cycles later. The next accept
//!   is `interval` cycles later.
//! * **emit**: a result whose cycle has come moves to the output FIFO if it has room;
//!   otherwise the stage stalls and, once its pipeline is full, stops accepting, so
//!   back-pressure reaches the units before it.
//!
//! Each cycle is counted once as **stall** (a finished result is blocked downstream),
//! **busy** (an operation is in progress or was accepted), or **idle** (starved).
//! The simulator ticks stages from the last to the first so that a FIFO slot freed in a cycle
//! can be refilled in the same cycle, and a token pushed in cycle c is seen downstream at c+1.

use crate::unit::{Mode, Unit, Word, MAX_LANES};
use std::collections::VecDeque;

mod batch;
pub use batch::ColumnScratch;

/// The values one fragment carries through the pipeline.
#[derive(Debug, Clone)]
pub struct Token {
    /// Sequence number of the fragment in the frame.
    pub id: u64,
    /// Pixel position, for the frame buffer and traces.
    pub x: u32,
    pub y: u32,
    /// The fragment is still alive: a unit that kills fragments (CULL_FRAGMENT, a clip
    /// plane) clears it. A dead token keeps its place in the pipe (its valid bit stays, as in
    /// a fixed-function pipe that does not squash), so timing does not depend on data; the
    /// ROP does not write it.
    pub live: bool,
    /// One word per signal of the pipeline (see the pipeline's wiring).
    pub slots: Vec<Word>,
}

/// Where one input port of a stage reads its word in the token: a whole slot (a plain wire) or
/// lanes gathered from several slots (a wire expression: swizzle, lane select, concatenation;
/// in hardware, wires only: no logic, no delay).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wire {
    /// The whole word of a slot.
    Slot(usize),
    /// `lanes` lanes, lane `i` taken from lane `from[i].1` of slot `from[i].0`.
    Gather {
        lanes: u8,
        from: [(u32, u8); MAX_LANES],
    },
}

impl Wire {
    /// The word this wire carries in `slots`.
    #[inline]
    pub fn read(&self, slots: &[Word]) -> Word {
        match *self {
            Wire::Slot(s) => slots[s],
            Wire::Gather { lanes, from } => {
                let mut w = Word::default();
                for (l, &(s, k)) in w.lanes.iter_mut().zip(&from).take(lanes as usize) {
                    *l = slots[s as usize].lanes[k as usize];
                }
                w
            }
        }
    }
}

/// A bounded FIFO between stages, holding the ids of the fragments in it (their values live
/// in the function model: see [`Stage`]).
#[derive(Debug, Clone)]
pub struct Fifo {
    items: VecDeque<u64>,
    depth: usize,
}

impl Fifo {
    pub fn new(depth: usize) -> Self {
        Fifo {
            items: VecDeque::with_capacity(depth.max(1)),
            depth: depth.max(1),
        }
    }
    pub fn has_room(&self) -> bool {
        self.items.len() < self.depth
    }
    pub fn push(&mut self, id: u64) {
        debug_assert!(self.has_room());
        self.items.push_back(id);
    }
    pub fn pop(&mut self) -> Option<u64> {
        self.items.pop_front()
    }
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
    pub fn len(&self) -> usize {
        self.items.len()
    }
    pub fn depth(&self) -> usize {
        self.depth
    }
}

/// What a stage did in one cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum CycleState {
    Idle,
    Busy,
    Stall,
}

/// Cycle counters of a stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counters {
    pub busy: u64,
    pub idle: u64,
    pub stall: u64,
    /// Tokens accepted.
    pub accepted: u64,
}

impl Counters {
    pub fn total(&self) -> u64 {
        self.busy
            .saturating_add(self.idle)
            .saturating_add(self.stall)
    }
}

/// A probe of one stage in one cycle: its state and the port values that moved.
///
/// [`Stage::tick`] gives the fragment ids with empty word lists; the simulator fills them in
/// from the function model ([`Stage::input_words`], [`Stage::output_words`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    pub cycle: u64,
    pub state: CycleState,
    /// Fragment id and input port values of the token accepted this cycle.
    pub accepted: Option<(u64, Vec<Word>)>,
    /// Fragment id and output port values of the token emitted this cycle.
    pub emitted: Option<(u64, Vec<Word>)>,
}

/// A unit in its clocked shell, bound to token slots.
pub struct Stage {
    pub name: String,
    unit: Box<dyn Unit>,
    in_wires: Vec<Wire>,
    out_slots: Vec<usize>,
    /// `out_slots` as one range of consecutive slots, when they are (the usual case: a
    /// unit's signals are allocated together): the unit then writes the token in place.
    out_range: Option<std::ops::Range<usize>>,
    latency: u64,
    interval: u64,
    max_in_flight: usize,
    /// The unit may kill fragments ([`Unit::can_kill`]).
    kills: bool,
    /// How the unit's texture-cache misses delay its fragments ([`Stage::set_misses`]); none
    /// by default.
    misses: Option<MissTiming>,
    /// (cycle the result is ready, fragment id).
    in_flight: VecDeque<(u64, u64)>,
    next_accept: u64,
    pub counters: Counters,
}

/// How texture-cache misses delay a stage's fragments (the timing of `engine.texture_cache`).
#[derive(Debug, Clone)]
pub struct MissTiming {
    /// Misses of each fragment, by id.
    pub misses: std::sync::Arc<[u32]>,
    /// Cycles from a fill's request to its data.
    pub latency: u32,
    /// Cycles the memory is busy with one fill (fills one after another).
    pub occupancy: u32,
    /// The memory whose fill queue the fills wait in: an index into the `memories` that
    /// [`Stage::tick`] is given (stages with the same index share one texture bus; an index
    /// beyond them: a memory of the fragment's own, free when it arrives).
    pub memory: usize,
    /// `None`: a blocking unit: a fragment's fills go one after another, each requested when
    /// the one before has its data and issued when the memory is free (a fragment with `n`
    /// misses waits `n x latency` when nothing else holds the memory), and the unit takes no
    /// other fragment meanwhile. `Some(d)`: a prefetching unit (Igehy, Eldridge and
    /// Proudfoot 1998) whose fragments wait in a `d`-deep FIFO: the fills are requested when
    /// the fragment arrives, queue at the memory (`occupancy` each), and the fragment leaves
    /// the cycle after its last fill's data or after its own latency, whichever is later.
    pub prefetch: Option<u32>,
}

/// Port buffers for [`Stage::eval_token`], one per thread that evaluates tokens.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    ins: Vec<Word>,
    outs: Vec<Word>,
}

impl Stage {
    /// Bind `unit` to the wires feeding its inputs and the token slots receiving its outputs.
    pub fn new(
        name: impl Into<String>,
        unit: Box<dyn Unit>,
        in_wires: Vec<Wire>,
        out_slots: Vec<usize>,
    ) -> Self {
        assert_eq!(in_wires.len(), unit.inputs().len());
        assert_eq!(out_slots.len(), unit.outputs().len());
        let latency = u64::from(unit.latency().max(1));
        let interval = u64::from(unit.interval().max(1));
        let max_in_flight = latency.div_ceil(interval) as usize;
        let kills = unit.can_kill();
        let out_range = out_slots.first().and_then(|&a| {
            let consecutive = out_slots.iter().enumerate().all(|(k, &s)| s == a + k);
            consecutive.then(|| a..a + out_slots.len())
        });
        Stage {
            name: name.into(),
            unit,
            in_wires,
            out_slots,
            out_range,
            latency,
            interval,
            max_in_flight,
            kills,
            misses: None,
            in_flight: VecDeque::new(),
            next_accept: 0,
            counters: Counters::default(),
        }
    }

    pub fn unit(&self) -> &dyn Unit {
        self.unit.as_ref()
    }

    /// The unit takes the frame's inputs ([`Unit::begin_frame`]). Its timing is hardware: a
    /// unit whose latency or interval would change is an error.
    pub fn begin_frame(&mut self, frame: &crate::frame::FrameInputs) -> Result<(), String> {
        self.unit.begin_frame(frame)?;
        let l = u64::from(self.unit.latency().max(1));
        let i = u64::from(self.unit.interval().max(1));
        if (l, i) != (self.latency, self.interval) {
            return Err(format!(
                "the frame changes the unit's latency and interval from {} and {} to {l} and {i}",
                self.latency, self.interval
            ));
        }
        Ok(())
    }

    /// The host uploaded `new` in place of `old` ([`Unit::upload`]).
    pub fn upload(
        &mut self,
        old: &std::sync::Arc<crate::Texture>,
        new: &std::sync::Arc<crate::Texture>,
    ) {
        self.unit.upload(old, new);
    }

    /// The stage's timing when it is the same for every fragment (no texture-cache misses):
    /// latency, initiation interval and the most tokens in flight, as [`Stage::tick`] applies
    /// them; `None` when misses delay fragments.
    pub fn fixed_timing(&self) -> Option<(u64, u64, usize)> {
        self.misses.is_none().then(|| self.timing())
    }

    /// Latency, initiation interval and the most tokens in flight (with a prefetching
    /// unit's FIFO when misses are set): the numbers [`Stage::schedule`] starts from.
    pub fn timing(&self) -> (u64, u64, usize) {
        (self.latency, self.interval, self.max_in_flight)
    }

    /// The texture-cache misses that delay the stage's fragments, if set.
    pub fn misses(&self) -> Option<&MissTiming> {
        self.misses.as_ref()
    }

    /// Delay each fragment by its texture-cache misses as `m` says (a fragment beyond
    /// `m.misses` has none). A prefetching unit keeps up to its FIFO's depth in flight.
    pub fn set_misses(&mut self, m: MissTiming) {
        if let Some(d) = m.prefetch {
            self.max_in_flight = self.max_in_flight.max(d.max(1) as usize);
        }
        self.misses = Some(m);
    }

    /// The cycle fragment `id`, accepted at `cycle`, is ready and the next cycle the unit may
    /// accept, after its misses; `memories` holds the cycle each memory can issue its next
    /// fill (an index beyond it: a memory of the fragment's own). [`Stage::tick`] calls it on
    /// each accept; a timing model on events may call it in the same order per memory.
    pub fn schedule(&self, cycle: u64, id: u64, memories: &mut [u64]) -> (u64, u64) {
        let plain = (
            cycle.saturating_add(self.latency),
            cycle.saturating_add(self.interval),
        );
        let Some(m) = &self.misses else {
            return plain;
        };
        let n = m.misses.get(id as usize).map_or(0, |&x| u64::from(x));
        if n == 0 {
            return plain;
        }
        let mut unqueued = 0;
        let free = memories.get_mut(m.memory).unwrap_or(&mut unqueued);
        let (latency, occupancy) = (u64::from(m.latency), u64::from(m.occupancy));
        // one fill requested at `at`: issued when the memory is free, its data `latency` later
        let mut fill = |at: u64| {
            let issue = (*free).max(at);
            *free = issue.saturating_add(occupancy);
            issue.saturating_add(latency)
        };
        match m.prefetch {
            // the fragment waits for its fills one after another, the unit with it
            None => {
                let mut data = cycle;
                for _ in 0..n {
                    data = fill(data);
                }
                let extra = data - cycle;
                (plain.0.saturating_add(extra), plain.1.saturating_add(extra))
            }
            // the fills are requested on arrival and queue at the memory; the fragment waits
            // in the FIFO for the last and leaves the cycle after it (or after its latency)
            Some(_) => {
                let mut done = cycle;
                for _ in 0..n {
                    done = fill(cycle);
                }
                (plain.0.max(done.saturating_add(1)), plain.1)
            }
        }
    }

    /// Where each input port reads its word in the token.
    pub fn in_wires(&self) -> &[Wire] {
        &self.in_wires
    }

    /// The token slot each output port writes.
    pub fn out_slots(&self) -> &[usize] {
        &self.out_slots
    }

    /// Clear the timing state (in-flight work, the next accept, the counters) for a new frame.
    pub fn reset(&mut self) {
        self.in_flight.clear();
        self.next_accept = 0;
        self.counters = Counters::default();
    }

    /// Whether the stage holds no work.
    pub fn is_empty(&self) -> bool {
        self.in_flight.is_empty()
    }

    /// The input port values of the unit for `token`.
    pub fn input_words(&self, token: &Token) -> Vec<Word> {
        self.in_wires.iter().map(|w| w.read(&token.slots)).collect()
    }

    /// The output port values of the unit in `token` (after [`Stage::eval_token`]).
    pub fn output_words(&self, token: &Token) -> Vec<Word> {
        self.out_slots.iter().map(|&s| token.slots[s]).collect()
    }

    /// The function: evaluate the unit on a token in `mode`, writing its output slots (and clearing
    /// the live bit if the unit kills the fragment). Timing is [`Stage::tick`]'s. Units do
    /// not change when they evaluate, so tokens may be evaluated in any order, on any thread
    /// (each with its own `scratch`).
    pub fn eval_token(&self, token: &mut Token, mode: Mode, scratch: &mut Scratch) {
        let Scratch { ins, outs } = scratch;
        ins.resize(self.in_wires.len(), Word::default());
        for (w, wire) in ins.iter_mut().zip(&self.in_wires) {
            *w = wire.read(&token.slots);
        }
        if let Some(r) = self
            .out_range
            .clone()
            .filter(|r| r.end <= token.slots.len())
        {
            let outs = &mut token.slots[r];
            self.unit.eval(mode, ins, outs);
            if self.kills && !self.unit.live(mode, ins, outs) {
                token.live = false;
            }
            return;
        }
        outs.resize(self.out_slots.len(), Word::default());
        self.unit.eval(mode, ins, outs);
        if self.kills && !self.unit.live(mode, ins, outs) {
            token.live = false;
        }
        for (w, &s) in outs.iter().zip(&self.out_slots) {
            token.slots[s] = *w;
        }
    }

    /// Advance one clock: emit into `output`, accept from `input` (FIFOs of fragment ids).
    /// Returns a probe, without port values, when `probe` is set. `memories`: the cycle each
    /// texture memory can issue its next fill ([`MissTiming::memory`]; empty when no stage
    /// has misses), shared by the stages ticked with it.
    pub fn tick(
        &mut self,
        cycle: u64,
        input: &mut Fifo,
        output: &mut Fifo,
        probe: bool,
        memories: &mut [u64],
    ) -> Option<Probe> {
        let mut stalled = false;
        let mut emitted = None;
        if let Some(&(ready, id)) = self.in_flight.front() {
            if ready <= cycle {
                if output.has_room() {
                    self.in_flight.pop_front();
                    if probe {
                        emitted = Some((id, Vec::new()));
                    }
                    output.push(id);
                } else {
                    stalled = true;
                }
            }
        }
        let mut accepted = None;
        let mut did_accept = false;
        let can_accept = cycle >= self.next_accept && self.in_flight.len() < self.max_in_flight;
        if can_accept {
            if let Some(id) = input.pop() {
                if probe {
                    accepted = Some((id, Vec::new()));
                }
                // saturating: a latency or interval from a config cannot wrap the clock
                let (ready, next) = self.schedule(cycle, id, memories);
                self.in_flight.push_back((ready, id));
                self.next_accept = next;
                self.counters.accepted += 1;
                did_accept = true;
            }
        }
        let state = if stalled {
            CycleState::Stall
        } else if did_accept || !self.in_flight.is_empty() || cycle < self.next_accept {
            CycleState::Busy
        } else {
            CycleState::Idle
        };
        match state {
            CycleState::Stall => self.counters.stall += 1,
            CycleState::Busy => self.counters.busy += 1,
            CycleState::Idle => self.counters.idle += 1,
        }
        probe.then_some(Probe {
            cycle,
            state,
            accepted,
            emitted,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Encoding, Format};
    use crate::gates::{CostTable, GateBudget};
    use crate::unit::PortSpec;

    /// A test unit: out = in + 1, with a given latency and interval.
    struct Inc {
        ports: Vec<PortSpec>,
        latency: u32,
        interval: u32,
    }

    impl Unit for Inc {
        fn kind(&self) -> &'static str {
            "inc"
        }
        fn inputs(&self) -> &[PortSpec] {
            &self.ports
        }
        fn outputs(&self) -> &[PortSpec] {
            &self.ports
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
        fn eval(&self, _: Mode, ins: &[Word], outs: &mut [Word]) {
            outs[0] = ins[0];
            outs[0].lanes[0].x += 1.0;
        }
    }

    fn inc(latency: u32, interval: u32) -> Box<dyn Unit> {
        let enc = Encoding::fixed(Format::s(16, 0));
        Box::new(Inc {
            ports: vec![PortSpec::new("v", 1, enc)],
            latency,
            interval,
        })
    }

    /// Run `n` tokens through a chain of stages; returns the cycle each token left the last
    /// FIFO (drained one per cycle) and the stages. The function runs apart from the timing:
    /// each drained token is evaluated through every stage and checked.
    fn run(units: Vec<(u32, u32)>, n: u64, fifo: usize) -> (Vec<u64>, Vec<Stage>) {
        let mut stages: Vec<Stage> = units
            .into_iter()
            .enumerate()
            .map(|(i, (l, ii))| {
                Stage::new(format!("s{i}"), inc(l, ii), vec![Wire::Slot(0)], vec![0])
            })
            .collect();
        let mut fifos: Vec<Fifo> = (0..=stages.len()).map(|_| Fifo::new(fifo)).collect();
        let mut next = 0;
        let mut out = vec![];
        let mut cycle = 0;
        while (out.len() as u64) < n {
            if let Some(id) = fifos.last_mut().unwrap().pop() {
                assert_eq!(id, out.len() as u64, "in order");
                let mut t = Token {
                    id,
                    x: 0,
                    y: 0,
                    live: true,
                    slots: vec![Word::default()],
                };
                t.slots[0].lanes[0].x = id as f64;
                let mut scratch = Scratch::default();
                for s in stages.iter() {
                    s.eval_token(&mut t, Mode::Exact, &mut scratch);
                }
                assert_eq!(t.slots[0].lanes[0].x, (id + stages.len() as u64) as f64);
                out.push(cycle);
            }
            for i in (0..stages.len()).rev() {
                let (a, b) = fifos.split_at_mut(i + 1);
                stages[i].tick(cycle, &mut a[i], &mut b[0], false, &mut []);
            }
            if next < n && fifos[0].has_room() {
                fifos[0].push(next);
                next += 1;
            }
            cycle += 1;
            assert!(cycle < 10_000);
        }
        (out, stages)
    }

    #[test]
    fn a_tokens_extra_cycles_delay_it_and_the_tokens_behind_it() {
        // latency 2, interval 1; token 1 waits 3 more cycles (a blocking miss)
        let run = |prefetch: Option<u32>| {
            let mut s = Stage::new("s", inc(2, 1), vec![Wire::Slot(0)], vec![0]);
            s.set_misses(MissTiming {
                misses: std::sync::Arc::from(vec![0u32, 1, 2, 0]),
                latency: 3,
                occupancy: 2,
                memory: 0,
                prefetch,
            });
            let (mut input, mut output) = (Fifo::new(8), Fifo::new(8));
            for id in 0..5 {
                input.push(id);
            }
            let (mut out, mut free) = (Vec::new(), [0u64]);
            for cycle in 0..30 {
                s.tick(cycle, &mut input, &mut output, false, &mut free);
                if let Some(id) = output.pop() {
                    out.push(cycle);
                    assert_eq!(id as usize, out.len() - 1, "in order");
                }
            }
            out
        };
        // blocking, latency 2, interval 1: 0 in at 0, out at 2; 1 (one miss) in at 1, out at
        // 1 + 2 + 3 = 6, next in at 1 + 1 + 3 = 5; 2 (two misses) in at 5, out at 5 + 2 + 6 =
        // 13, next at 12; 3 in at 12, out at 14; 4 (beyond the list: none) in at 13, out 15
        assert_eq!(run(None), [2, 6, 13, 14, 15]);
        // prefetching (a 4-deep FIFO): 1 in at 1 requests a fill (memory busy 1-3, data at 4),
        // leaves at 5; 2 in at 2 requests two (issued at 3 and 5, data at 8), leaves at 9; 3
        // and 4 follow in order
        assert_eq!(run(Some(4)), [2, 5, 9, 10, 11]);
    }

    #[test]
    fn stages_on_one_memory_queue_their_fills_behind_each_others() {
        // two prefetching stages (latency 1, a 4-deep FIFO), fills of 3 cycles' latency that
        // hold the memory 3 cycles; the first stage misses on tokens 1 and 2, the second on 0
        // and 1; the output taken the cycle a token arrives
        let run = |memories: [usize; 2]| {
            let mut stages: Vec<Stage> = [
                (vec![0u32, 1, 1, 0], memories[0]),
                (vec![1, 1, 0, 0], memories[1]),
            ]
            .into_iter()
            .enumerate()
            .map(|(i, (misses, memory))| {
                let mut s = Stage::new(format!("s{i}"), inc(1, 1), vec![Wire::Slot(0)], vec![0]);
                s.set_misses(MissTiming {
                    misses: std::sync::Arc::from(misses),
                    latency: 3,
                    occupancy: 3,
                    memory,
                    prefetch: Some(4),
                });
                s
            })
            .collect();
            let mut fifos: Vec<Fifo> = (0..3).map(|_| Fifo::new(8)).collect();
            for id in 0..4 {
                fifos[0].push(id);
            }
            let (mut free, mut out) = ([0u64; 2], Vec::new());
            for cycle in 0..40 {
                for i in (0..2).rev() {
                    let (a, b) = fifos.split_at_mut(i + 1);
                    stages[i].tick(cycle, &mut a[i], &mut b[0], false, &mut free);
                }
                if let Some(id) = fifos[2].pop() {
                    assert_eq!(id as usize, out.len(), "in order");
                    out.push(cycle);
                }
            }
            out
        };
        // a memory each: s0's fills issue at 1 and 4 (1 leaves s0 at 5, 2 at 8), s1's at 2
        // (token 0 out at 6) and 6 (token 1, in at 6, out at 10); 2 and 3 follow
        assert_eq!(run([0, 1]), [6, 10, 11, 12]);
        // one memory: s1's first fill (requested at 2) waits for s0's (1-4), issues at 4 (out
        // at 8), s0's second at 7 (token 2 leaves s0 at 11), s1's second (requested at 6) at
        // 10 (out at 14)
        assert_eq!(run([0, 0]), [8, 14, 15, 16]);
    }

    #[test]
    fn a_fully_pipelined_chain_delivers_one_token_per_cycle() {
        let (out, stages) = run(vec![(1, 1), (3, 1), (2, 1)], 10, 2);
        // token 0 enters fifo0 at cycle 0, accepted by s0 at 1, out at 2, s1 accepts 3,
        // emits at 6, s2 accepts 7, emits at 9, drained at 10.
        assert_eq!(out[0], 10);
        assert_eq!(
            out.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>(),
            vec![1; 9]
        );
        assert_eq!(stages[1].counters.accepted, 10);
    }

    #[test]
    fn a_multi_cycle_unit_sets_the_rate_and_stalls_the_units_before_it() {
        let (out, stages) = run(vec![(1, 1), (2, 3), (1, 1)], 12, 1);
        let gaps: Vec<u64> = out.windows(2).map(|w| w[1] - w[0]).collect();
        assert_eq!(gaps, vec![3; 11]);
        assert!(
            stages[0].counters.stall > 0,
            "upstream unit must see back-pressure"
        );
        let c = stages[1].counters;
        assert_eq!(c.accepted, 12);
        // the 3-cycle unit is busy 3 cycles per token except for its last token's tail
        assert!(c.busy >= 3 * 11, "busy {}", c.busy);
        for s in &stages {
            assert_eq!(s.counters.total(), out.last().unwrap() + 1);
        }
    }
}

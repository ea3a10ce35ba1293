//! The timing model on events: the clock-by-clock model of [`super::timing`] written as
//! recurrences on the cycle each fragment enters and leaves each unit, computed fragment by
//! fragment (work per fragment and unit, none per idle clock). It gives the same cycle report
//! as the clocked model whenever no two units' texture-cache misses queue at one texture
//! memory: a unit's misses ([`Stage::schedule`]) take its memory's fill queue in its accept
//! order, which is fragment order, as in the clocked model. Traces, which need each clock's
//! state, and misses of several units on one memory, whose queue the clocked model serves in
//! a clock's tick order, run on the clocked model.
//!
//! With `D` the FIFO depth and, for a unit, `L` its latency, `I` its interval and `M` the
//! tokens it may hold (`ceil(L / I)`), fragment `i` in submission order:
//!
//! * **scan**: pushed into FIFO 0 at `S(i) = max(avail(i), A_0(i - D))`, where `avail` is the
//!   clock its triangle was taken (its first fragment) or `S(i - 1) + 1`, and `A_0(i - D)`
//!   frees a place (the unit after the FIFO is ticked first in a clock, so a place freed in a
//!   clock is refilled in it);
//! * **a unit**: accepted at `A(i) = max(P(i) + 1, N(i - 1), X(i - M))` (`P`: pushed into
//!   its input FIFO, seen the next clock; `X`: emitted; `N(i) = A(i) + I`, the next accept),
//!   ready at `R(i) = A(i) + L`, and emitted at `X(i) = max(R(i), X(i - 1) + 1, A'(i - D))`
//!   with `A'` the next unit's accepts. With misses, `R(i)` and `N(i)` are
//!   [`Stage::schedule`]'s (a blocking unit adds the fills' wait to both; a prefetching one
//!   makes `R(i)` at least the clock after its last fill's data), and `M` counts a prefetching
//!   unit's FIFO;
//! * **ROP**: `A(i) = max(P(i) + 1, A(i - 1) + 1)`;
//! * **setup**: triangle `t` starts at `s_t` (the frame work's end for the first), is set up
//!   at `d_t = s_t + setup_t` and handed to the scan converter at `h_t = max(d_t, g_{t-1})`,
//!   the clock the scan converter took the triangle before; the next setup starts then
//!   (`s_{t+1} = h_t`), and the scan converter takes triangle `t` at
//!   `g_t = max(h_t + 1, free_{t-1})`, `free` being the clock after its last fragment (the
//!   clock after it was taken, for a triangle without fragments).
//!
//! Counters follow: a unit stalls while its oldest token is ready and not emitted, is busy in
//! the union of `[A(i), max(X(i), N(i)))` less its stalls, and idle otherwise; the scan
//! converter stalls from `avail(i)` to `S(i)`; setup is busy from `s_t` to `d_t` and stalls
//! from `d_t` to `h_t`.

use super::{CycleReport, Workload};
use bumpsim_hw::{Counters, Stage};

/// The cycle report of [`super::timing`] (without `killed`), computed on events; `None` when
/// texture-cache misses of two stages queue at one texture memory (the clocked model serves
/// that queue in its tick order within a clock).
pub(super) fn timing(engine: &[Stage], w: &Workload) -> Option<CycleReport> {
    let depth = w.fifo_depth.max(1);
    // the stages' timing twins with their misses, and the memories' fill queues as the
    // clocked model has them (`super::clocked`)
    let twins: Vec<Option<Stage>> = (0..engine.len())
        .map(|k| w.extra.get(k).cloned().flatten())
        .zip(super::timing_twins(engine))
        .map(|(m, mut twin)| {
            m.map(|m| {
                twin.set_misses(m);
                twin
            })
        })
        .collect();
    let nmem = w.extra.iter().flatten().map(|m| m.memory.saturating_add(1));
    let nmem = nmem.max().unwrap_or(0).min(w.extra.len());
    let mut users = vec![0usize; nmem];
    for m in twins.iter().flatten().filter_map(Stage::misses) {
        if let Some(u) = users.get_mut(m.memory) {
            *u += 1;
        }
    }
    if users.iter().any(|&u| u > 1) {
        return None;
    }
    let mut memories = vec![0u64; nmem];
    let mut units: Vec<UnitEvents> = engine
        .iter()
        .zip(twins)
        .map(|(s, twin)| {
            let t = twin.as_ref().map_or_else(|| s.timing(), Stage::timing);
            UnitEvents::new(t, depth, twin)
        })
        .collect();
    let frame: u64 = engine
        .iter()
        .map(|s| s.unit().frame_cycles())
        .fold(0, u64::saturating_add);
    // the ROP's accepts, read by the last unit for room in the last FIFO
    let mut rop = Ring::new(depth + 1);
    let mut rop_last = 0u64;
    let [mut setup_c, mut scan_c] = [Counters::default(); 2];
    let mut seq = 0usize; // fragments so far, in submission order
    let mut start = frame; // the setup of the next triangle starts
    let mut taken_before: Option<u64> = None; // g of the triangle before
    let mut scan_free = frame; // the scan converter may take a triangle
    let mut end = frame; // the last clock of the frame
    for (t, frags) in w.triangles.iter().enumerate() {
        let set_up = start.saturating_add(u64::from(w.setup[t].max(1)));
        let handed = set_up.max(taken_before.unwrap_or(0));
        setup_c.busy += set_up - start;
        setup_c.stall += handed - set_up;
        let taken = handed.saturating_add(1).max(scan_free);
        let mut avail = taken;
        let mut last_scan = None;
        for id in frags.clone() {
            let room = units
                .first()
                .map_or(&rop, |u| &u.accepted)
                .before(seq, depth);
            let scanned = avail.max(room);
            scan_c.busy += 1;
            scan_c.stall += scanned - avail;
            let mut pushed = scanned;
            for k in 0..units.len() {
                let down = units.get(k + 1).map_or(&rop, |u| &u.accepted);
                let room = down.before(seq, depth);
                pushed = units[k].take(seq, id as u64, pushed, room, &mut memories);
            }
            rop_last = pushed.saturating_add(1).max(rop_last.saturating_add(1));
            rop.set(seq, rop_last);
            end = end.max(rop_last);
            avail = scanned.saturating_add(1);
            last_scan = Some(scanned);
            seq += 1;
        }
        scan_free = last_scan.map_or(taken, |s| s.saturating_add(1));
        // the frame ends when the scan converter has taken every triangle and the ROP every
        // fragment (a triangle's last fragment reaches the ROP after the scan converter is
        // done with it)
        end = end.max(taken);
        taken_before = Some(taken);
        start = handed;
    }
    let total = end.saturating_add(1);
    let window = total - frame;
    let nfrag = seq as u64;
    scan_c.idle = window - scan_c.busy - scan_c.stall;
    setup_c.idle = window - setup_c.busy - setup_c.stall;
    let rop_c = Counters {
        busy: nfrag,
        idle: window - nfrag,
        stall: 0,
        accepted: nfrag,
    };
    Some(CycleReport::new(
        [total, frame, nfrag, w.triangles.len() as u64],
        [setup_c, scan_c, rop_c],
        engine
            .iter()
            .zip(&units)
            .map(|(s, u)| (s.name.clone(), u.counters(nfrag, total, window))),
    ))
}

/// The last values of a per-fragment clock, by fragment sequence number.
struct Ring {
    v: Vec<u64>,
    mask: usize,
}

impl Ring {
    /// A ring holding at least the last `n` values.
    fn new(n: usize) -> Self {
        let n = n.max(1).next_power_of_two();
        Ring {
            v: vec![0; n],
            mask: n - 1,
        }
    }
    fn set(&mut self, seq: usize, x: u64) {
        self.v[seq & self.mask] = x;
    }
    /// The value of fragment `seq - back`, or 0 (no constraint) before the first fragment.
    fn before(&self, seq: usize, back: usize) -> u64 {
        seq.checked_sub(back).map_or(0, |i| self.v[i & self.mask])
    }
}

/// One unit's recurrences: its accepts and emits, stalls and busy cycles so far.
struct UnitEvents {
    latency: u64,
    interval: u64,
    max_in_flight: usize,
    /// The stage's timing twin when texture-cache misses delay its fragments
    /// ([`Stage::schedule`] gives each fragment's ready clock and the unit's next accept).
    misses: Option<Stage>,
    accepted: Ring,
    emitted: Ring,
    last: Option<(u64, u64)>, // (next accept, emit) after the fragment before
    stall: u64,
    /// The union of the busy-or-stalled spans so far: its length and end.
    occupied: u64,
    occupied_end: u64,
}

impl UnitEvents {
    fn new(
        (latency, interval, max_in_flight): (u64, u64, usize),
        depth: usize,
        misses: Option<Stage>,
    ) -> Self {
        let n = depth.max(max_in_flight) + 1;
        UnitEvents {
            latency,
            interval,
            max_in_flight,
            misses,
            accepted: Ring::new(n),
            emitted: Ring::new(n),
            last: None,
            stall: 0,
            occupied: 0,
            occupied_end: 0,
        }
    }

    /// Fragment `seq` (id `id`), pushed into the unit's input FIFO at `pushed`, with a place
    /// in its output FIFO from `room`: the clock it is emitted. `memories`: the texture
    /// memories' next free clocks, which its misses' fills take.
    fn take(&mut self, seq: usize, id: u64, pushed: u64, room: u64, memories: &mut [u64]) -> u64 {
        let held = self.emitted.before(seq, self.max_in_flight);
        let mut accept = pushed.saturating_add(1).max(held);
        let mut front = 0; // the fragment becomes the oldest in the unit
        if let Some((next, x)) = self.last {
            accept = accept.max(next);
            front = x.saturating_add(1);
        }
        let (ready, next) = match &self.misses {
            Some(twin) => twin.schedule(accept, id, memories),
            None => (
                accept.saturating_add(self.latency),
                accept.saturating_add(self.interval),
            ),
        };
        let ready = ready.max(front);
        let emit = ready.max(room);
        self.stall += emit - ready;
        let (lo, hi) = (accept, emit.max(next));
        let lo = lo.max(self.occupied_end);
        if hi > lo {
            self.occupied += hi - lo;
            self.occupied_end = hi;
        }
        self.accepted.set(seq, accept);
        self.emitted.set(seq, emit);
        self.last = Some((next, emit));
        emit
    }

    /// The counters over the frame's `window` of clocks ending before `total`.
    fn counters(&self, nfrag: u64, total: u64, window: u64) -> Counters {
        // only the last spans can reach past the frame's end (no accept comes after it)
        let occupied = self.occupied - self.occupied_end.saturating_sub(total);
        Counters {
            busy: occupied - self.stall,
            idle: window - occupied,
            stall: self.stall,
            accepted: nfrag,
        }
    }
}

//! Tables already built in this process, found again by their inputs (issue 16: "assets
//! built once per run and shared ... across points with the same inputs").
//!
//! Building the table is the expensive step of a quantized config (k-means at 16,384 entries:
//! seconds per iteration); a render builds it for the engine, and a sweep, a study or a
//! config with and without dithering asks for the same table again and again. The table is a
//! pure function of (normals, `s_n`, quantizer), so [`table`] keeps the last [`CAPACITY`]
//! results keyed by those inputs and hands out copies: the same entries bit for bit as a new
//! build, in any order of calls and at any thread count.
//!
//! * The key: the map's length, a 128-bit digest of its normals' bits (two SipHash passes
//!   with different prefixes), `s_n` and the quantizer with all its parameters.
//! * A thread asking for a table being built on another thread builds it too (no waiting
//!   inside the rayon pool: `crate::memo`); the first is kept.
//! * Bounded memory: at most [`CAPACITY`] tables (each at most 65,536 entries of 24 bytes),
//!   least recently used evicted first. Errors are kept like tables (they are cheap anyway).

use super::{QuantizeError, Quantizer};
use glam::DVec3;
use std::hash::Hash;

/// Tables kept at most.
pub const CAPACITY: usize = 8;

type Built = Result<Vec<DVec3>, QuantizeError>;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    digest: [u64; 2],
    len: usize,
    s_n: usize,
    q: Quantizer,
}

/// Kept tables (`crate::memo`).
pub(crate) struct Memo(crate::memo::Memo<Key, Built>);

/// The tables of this process.
static TABLES: Memo = Memo::new();

fn digest(normals: &[DVec3]) -> [u64; 2] {
    crate::memo::digest(|mut h| {
        for n in normals {
            n.x.to_bits().hash(&mut h);
            n.y.to_bits().hash(&mut h);
            n.z.to_bits().hash(&mut h);
        }
    })
}

/// The table of `(normals, s_n, q)`: kept from an earlier call, or `build()` now (and kept).
pub(crate) fn table(
    normals: &[DVec3],
    s_n: usize,
    q: Quantizer,
    build: impl FnOnce() -> Built,
) -> Built {
    TABLES.table(normals, s_n, q, build)
}

impl Memo {
    const fn new() -> Self {
        Memo(crate::memo::Memo::new(CAPACITY))
    }

    fn table(
        &self,
        normals: &[DVec3],
        s_n: usize,
        q: Quantizer,
        build: impl FnOnce() -> Built,
    ) -> Built {
        let key = Key {
            digest: digest(normals),
            len: normals.len(),
            s_n,
            q,
        };
        self.0.get_or_build(key, build)
    }

    /// How many tables are kept now (tests).
    #[cfg(test)]
    fn kept(&self) -> usize {
        self.0.kept()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn map(k: usize) -> Vec<DVec3> {
        (0..64)
            .map(|i| DVec3::new(i as f64 * 0.01, k as f64 * 0.01, 1.0).normalize())
            .collect()
    }

    #[test]
    fn builds_once_per_input_and_again_for_any_difference() {
        let builds = AtomicUsize::new(0);
        let memo = Memo::new();
        let get = |m: &[DVec3], s_n, q| {
            memo.table(m, s_n, q, || {
                builds.fetch_add(1, Ordering::SeqCst);
                Ok(vec![DVec3::Z; s_n])
            })
        };
        let (a, mut b) = (map(1000), map(1000));
        let mc = Quantizer::MedianCut;
        assert_eq!(get(&a, 3, mc).unwrap().len(), 3);
        assert_eq!(get(&b, 3, mc).unwrap().len(), 3);
        assert_eq!(builds.load(Ordering::SeqCst), 1, "same inputs: one build");
        get(&a, 4, mc).unwrap();
        get(&a, 3, Quantizer::NeuQuant { sample_factor: 1 }).unwrap();
        // one bit of one normal
        b[17].y = f64::from_bits(b[17].y.to_bits() ^ 1);
        get(&b, 3, mc).unwrap();
        assert_eq!(builds.load(Ordering::SeqCst), 4);
        assert_eq!(memo.kept(), 4);
    }

    #[test]
    fn evicts_the_least_recently_used_and_stays_bounded() {
        let builds = AtomicUsize::new(0);
        let memo = Memo::new();
        let get = |m: &[DVec3]| {
            memo.table(m, 2, Quantizer::MedianCut, || {
                builds.fetch_add(1, Ordering::SeqCst);
                Ok(vec![DVec3::X, DVec3::Z])
            })
        };
        let maps: Vec<_> = (0..CAPACITY + 3).map(|k| map(2000 + k)).collect();
        for m in &maps {
            get(m).unwrap();
        }
        assert_eq!(memo.kept(), CAPACITY);
        let n = builds.load(Ordering::SeqCst);
        assert_eq!(n, CAPACITY + 3);
        // the last is kept; a hit makes the oldest kept one (maps[3]) the most recent
        get(&maps[CAPACITY + 2]).unwrap();
        get(&maps[3]).unwrap();
        assert_eq!(builds.load(Ordering::SeqCst), n);
        // the first was evicted; building it again evicts maps[4], not maps[3]
        get(&maps[0]).unwrap();
        get(&maps[3]).unwrap();
        assert_eq!(builds.load(Ordering::SeqCst), n + 1);
        get(&maps[4]).unwrap();
        assert_eq!(builds.load(Ordering::SeqCst), n + 2);
        assert_eq!(memo.kept(), CAPACITY);
    }

    #[test]
    fn concurrent_askers_get_one_table_and_it_is_kept_once() {
        let builds = AtomicUsize::new(0);
        let (m, memo) = (map(3000), Memo::new());
        let got: Vec<_> = std::thread::scope(|s| {
            let hs: Vec<_> = (0..4)
                .map(|_| {
                    s.spawn(|| {
                        memo.table(&m, 5, Quantizer::MedianCut, || {
                            builds.fetch_add(1, Ordering::SeqCst);
                            std::thread::sleep(std::time::Duration::from_millis(20));
                            Ok(vec![DVec3::Y; 5])
                        })
                        .unwrap()
                    })
                })
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert!(got.iter().all(|t| *t == vec![DVec3::Y; 5]));
        assert_eq!(memo.kept(), 1);
        // every later ask is a hit
        let n = builds.load(Ordering::SeqCst);
        memo.table(&m, 5, Quantizer::MedianCut, || unreachable!())
            .unwrap();
        assert_eq!(builds.load(Ordering::SeqCst), n);
    }
}

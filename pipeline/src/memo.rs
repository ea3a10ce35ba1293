//! Results already computed in this process, found again by their inputs (issue 16: "assets
//! built once per run and shared ... across points with the same inputs"; issue 11: "scene,
//! assets and reference are built once per distinct input and shared across points").
//!
//! A [`Memo`] keeps the last few results of a pure function, keyed by everything the result
//! depends on, and hands out clones (an `Arc` for large results: one allocation shared by
//! every holder). What is kept, and under which keys:
//!
//! * the quantizers' tables (`quantize::memo`): the normals' digest, `s_n`, the quantizer;
//! * the normal maps baked from a scene's bump map (`engine::units::textures`): the scene's
//!   key, the size and the method;
//! * the normal maps and simplified meshes baked from detailed meshes (`wang::scene::build`,
//!   Wang et al.): the bake's spec, the mesh file's path and a digest of its bytes (read
//!   once, so a sweep over engines bakes once);
//! * the float reference of a frame (`run::Prepared::reference`): the scene's key, a digest
//!   of the fragments, the raster settings and the reference options.
//!
//! A scene's key ([`crate::scene::Scene::key`]) digests its config and the bytes of every
//! file read to build it; a scene without one (built by hand, or whose files could not all be
//! accounted for) is never looked up, so nothing is shared that might differ.
//!
//! A thread asking for a key whose build is in flight on another thread builds it too
//! (waiting inside the rayon pool can deadlock), and the first build is kept: the results
//! are equal, so who builds first does not show. Memory is bounded: at most `capacity` results per memo, least
//! recently used evicted first, and of those only as many as a budget of weight (pixels,
//! texels) allows.

use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex, OnceLock};

type Slot<K, V> = (K, Arc<OnceLock<V>>);

/// The last `capacity` results of a function, least recently used first, and of those only
/// as many as weigh at most `budget` together.
pub struct Memo<K, V> {
    slots: Mutex<Vec<Slot<K, V>>>,
    capacity: usize,
    budget: usize,
    weight: fn(&V) -> usize,
}

impl<K: PartialEq, V: Clone> Memo<K, V> {
    /// At most `capacity` results.
    pub const fn new(capacity: usize) -> Self {
        Memo::weighed(capacity, usize::MAX, |_| 0)
    }

    /// At most `capacity` results, and only while their weights add up to at most `budget`
    /// (the least recently used go first; a result heavier than the budget is not kept).
    pub const fn weighed(capacity: usize, budget: usize, weight: fn(&V) -> usize) -> Self {
        Memo {
            slots: Mutex::new(Vec::new()),
            capacity,
            budget,
            weight,
        }
    }

    /// The result for `key`: kept from an earlier call, or `build()` now (and kept).
    pub fn get_or_build(&self, key: K, build: impl FnOnce() -> V) -> V {
        let cell = {
            // a panic elsewhere while holding the lock leaves the list itself consistent
            let mut t = self.slots.lock().unwrap_or_else(|p| p.into_inner());
            let cell = match t.iter().position(|(k, _)| *k == key) {
                Some(i) => t.remove(i).1,
                None => Arc::new(OnceLock::new()),
            };
            if t.len() >= self.capacity {
                t.remove(0);
            }
            t.push((key, cell.clone()));
            cell
        };
        if let Some(v) = cell.get() {
            return v.clone();
        }
        // Not `get_or_init`: waiting for a build in flight on another thread can deadlock in
        // the rayon pool (the builder may be waiting for a job the waiting thread holds, or
        // the waiting thread may be the builder, re-entered by work stealing). A concurrent
        // asker builds too; the builds are equal, the first one is kept.
        let v = build();
        let _ = cell.set(v);
        self.trim();
        cell.get().expect("set above").clone()
    }

    /// Evict the least recently used results until the kept ones fit the budget.
    fn trim(&self) {
        let mut t = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let weigh = |c: &OnceLock<V>| c.get().map_or(0, self.weight);
        let mut total: usize = t.iter().map(|(_, c)| weigh(c)).sum();
        while total > self.budget && !t.is_empty() {
            total -= weigh(&t.remove(0).1);
        }
    }

    /// How many results are kept now.
    pub fn kept(&self) -> usize {
        self.slots.lock().unwrap_or_else(|p| p.into_inner()).len()
    }
}

/// A 128-bit digest of what `feed` writes: two SipHash passes with different prefixes.
pub fn digest(feed: impl Fn(&mut dyn Hasher)) -> [u64; 2] {
    std::array::from_fn(|pass| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (pass as u64).hash(&mut h);
        feed(&mut h);
        h.finish()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn builds_once_per_key_and_evicts_the_least_recently_used() {
        let builds = AtomicUsize::new(0);
        let memo: Memo<u32, u32> = Memo::new(3);
        let get = |k: u32| {
            memo.get_or_build(k, || {
                builds.fetch_add(1, Ordering::SeqCst);
                k * 10
            })
        };
        assert_eq!((get(1), get(2), get(1)), (10, 20, 10));
        assert_eq!(builds.load(Ordering::SeqCst), 2);
        get(3);
        get(4); // evicts 2 (1 was used after it)
        assert_eq!(memo.kept(), 3);
        get(1);
        assert_eq!(builds.load(Ordering::SeqCst), 4);
        get(2);
        assert_eq!(builds.load(Ordering::SeqCst), 5);
    }

    #[test]
    fn keeps_older_results_only_within_the_budget() {
        let memo: Memo<u32, Vec<u8>> = Memo::weighed(8, 10, Vec::len);
        let get = |k: u32, n: usize| memo.get_or_build(k, || vec![0; n]);
        get(1, 4);
        get(2, 4);
        assert_eq!(memo.kept(), 2);
        get(3, 4); // 12 > 10: the oldest goes
        assert_eq!(memo.kept(), 2);
        assert_eq!(get(3, 0).len(), 4, "a hit, not a build");
        get(4, 40); // heavier than the budget alone: not kept, and the others go
        assert_eq!(memo.kept(), 0);
        assert_eq!(get(4, 7).len(), 7, "built again");
    }

    #[test]
    fn digest_tells_apart_one_bit() {
        let a = digest(|h| h.write_u64(1 << 40));
        assert_eq!(a, digest(|h| h.write_u64(1 << 40)));
        assert_ne!(a, digest(|h| h.write_u64((1 << 40) | 1)));
        assert_ne!(a[0], a[1]);
    }
}

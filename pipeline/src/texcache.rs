//! A texture cache on the engine's texel reads: how many texel bits the memory must deliver
//! once the units read through a cache (`engine.texture_cache`, `docs/units/texture_memory.md`,
//! "Texture cache").
//!
//! The model is the blocked cache of Hakura and Gupta ("The design and analysis of a cache
//! architecture for texture mapping", ISCA 1997) that texture units of the period built: a
//! line holds a square block of `block x block` texels of one level (and face) of one
//! texture, so the four taps of a bilinear read and the neighbours the next fragment reads
//! fall in one or a few lines; `lines` lines in sets of `ways`, least recently used replaced.
//! The set of a block interleaves its block coordinates in 2D (`Tiled`: `set = (bx mod a) +
//! a (by mod b)`, `a b` = sets), so that a square of neighbouring blocks maps to different
//! sets, or (`Xor`) XORs `bx` with `by a`, so that a row of blocks uses every set too.
//!
//! The address stream is the bit-accurate engine's own: every fragment in rasterization order
//! through every stage, each texel read as the unit makes it (`bumpsim_hw::texture::reads`).
//! A cache per reading unit (each texture unit of the period had its own), or one shared by
//! all (`shared: true`). With `miss_cycles`, misses delay their fragments in the timed run
//! ([`Timing`], `bumpsim_hw::stage::MissTiming`): a blocking unit waits `miss_cycles` per miss
//! and takes no other fragment meanwhile; a prefetching one (`prefetch`: its fragment FIFO's
//! depth) requests the fills on arrival, queues them at the memory (`fill_cycles` each) and
//! lets the fragment wait in the FIFO; by default the cache changes traffic only. The fills of
//! every cache queue at one memory (`bus: Shared`, the default) or at one per cache
//! (`PerCache`): [`bumpsim_hw::stage::MissTiming::memory`].

use crate::config::{TextureBus, TextureCacheConfig};
use crate::sim::{new_token, FillToken};
use bumpsim_hw::texture::reads::{self, Read};
use bumpsim_hw::units::texture_cache::CacheShape;
use bumpsim_hw::{GateBudget, Mode, Scratch, Stage, Texture, Token};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::Arc;

/// One cache's counts over a frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CacheStats {
    /// The units that read through it.
    pub readers: Vec<String>,
    /// Texel reads.
    pub reads: u64,
    /// Reads that missed (each fills a line).
    pub misses: u64,
    /// `1 - misses / reads` (1 without reads).
    pub hit_rate: f64,
    /// Texel bits the reads take without a cache: each read's texel.
    pub uncached_bits: u64,
    /// Texel bits the memory delivers: each miss a line of `block^2` texels.
    pub fill_bits: u64,
}

/// The cache report of a frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CacheReport {
    pub config: TextureCacheConfig,
    /// Bits of one cache's data: `lines x block^2` texels of the widest texel it holds.
    pub data_bits: Vec<u64>,
    /// One per reading unit, or one (`shared`).
    pub caches: Vec<CacheStats>,
    pub uncached_bits: u64,
    pub fill_bits: u64,
    /// `fill_bits / uncached_bits`: the memory traffic the cache leaves.
    pub traffic_ratio: f64,
    /// Cycles each texture memory is busy with the frame's fills (`fill_cycles` a miss): one
    /// entry on one bus (`bus: Shared`), one per cache with `PerCache`. Against the frame's
    /// `cycles.total`: a memory busy most of the frame bounds it.
    pub memory_busy_cycles: Vec<u64>,
}

/// A line's tag: the level's key, face and block coordinates.
type Tag = (usize, u32, u32, u32);

/// One set-associative cache with least-recently-used replacement.
struct Cache {
    ways: usize,
    /// Per set, the tags and their last use, most recent last.
    sets: Vec<Vec<Tag>>,
    split: (u32, u32),
    index: crate::config::SetIndex,
    stats: CacheStats,
    widest: u32,
}

impl Cache {
    fn new(c: &TextureCacheConfig) -> Cache {
        let sets = (c.lines / c.ways) as usize;
        // a = 2^ceil(log2(sets) / 2), b = sets / a
        let log = sets.trailing_zeros();
        let a = 1u32 << log.div_ceil(2);
        Cache {
            ways: c.ways as usize,
            sets: vec![Vec::with_capacity(c.ways as usize); sets],
            split: (a, sets as u32 / a),
            index: c.index,
            stats: CacheStats::default(),
            widest: 0,
        }
    }

    /// Read `tag`: a hit moves it to most recent; a miss fills it, evicting the least recent.
    fn access(&mut self, tag: Tag) -> bool {
        let (a, b) = self.split;
        let set = match self.index {
            crate::config::SetIndex::Tiled => (tag.2 % a + a * (tag.3 % b)) as usize,
            crate::config::SetIndex::Xor => ((tag.2 ^ tag.3.wrapping_mul(a)) % (a * b)) as usize,
        };
        let s = &mut self.sets[set];
        if let Some(p) = s.iter().position(|t| *t == tag) {
            let t = s.remove(p);
            s.push(t);
            return true;
        }
        if s.len() == self.ways {
            s.remove(0);
        }
        s.push(tag);
        false
    }
}

/// What the cache needs of a level: its texture's bits per texel, its width and face size.
struct LevelInfo {
    bits: u32,
    width: u32,
    face: u32,
}

/// Fragments whose reads are held at once (about 16 bytes a texel read).
const WINDOW: usize = 1 << 15;
/// Fragments per parallel task of a window.
const CHUNK: usize = 1 << 11;
/// Tokens filled at once (`Fill::fill_batch`).
const BATCH: usize = 64;

/// The texel reads of a chunk of fragments from `first`: `reads` in order, and for each
/// fragment and stage (fragment-major) the end of its reads in `reads`.
struct ChunkReads {
    first: usize,
    reads: Vec<Read>,
    ends: Vec<u32>,
}

/// The texel reads of the fragments of `window` through every stage (bit-accurate), recorded
/// in parallel chunks, in fragment order: the same reads as one thread recording them all.
fn record_window(
    stages: &[Stage],
    window: std::ops::Range<usize>,
    slots: usize,
    fill: &FillToken<'_>,
) -> Vec<ChunkReads> {
    let chunks: Vec<usize> = window.clone().step_by(CHUNK).collect();
    chunks
        .into_par_iter()
        .map(|first| {
            let end = (first + CHUNK).min(window.end);
            let mut ts: Vec<Token> = (0..BATCH).map(|_| new_token(slots)).collect();
            let mut scratch = Scratch::default();
            let mut out = ChunkReads {
                first,
                reads: Vec::new(),
                ends: Vec::with_capacity((end - first) * stages.len()),
            };
            reads::record(|drain| {
                for b in (first..end).step_by(BATCH) {
                    let ts = &mut ts[..(end - b).min(BATCH)];
                    for t in ts.iter_mut() {
                        t.live = true;
                    }
                    fill.fill_batch(b, ts);
                    for t in ts.iter_mut() {
                        for s in stages {
                            s.eval_token(t, Mode::BitAccurate, &mut scratch);
                            drain(&mut out.reads);
                            // a chunk's reads stay far below 2^32
                            out.ends.push(out.reads.len() as u32);
                        }
                    }
                }
            });
            out
        })
        .collect()
}

/// The misses of each fragment in each stage (`None` for a stage without a miss), for the
/// timing model (`sim::Workload::extra`, with the cache's `miss_cycles`, `fill_cycles` and
/// `prefetch`).
pub type Timing = Vec<Option<bumpsim_hw::stage::MissTiming>>;

/// The texel reads of every fragment through `stages` (bit-accurate mode, rasterization
/// order), through the caches `c` describes, and with `c.miss_cycles` their stalls. `fill`
/// builds the fragments' tokens. The engine runs over windows of fragments in parallel
/// chunks (rayon), each recording its reads; the caches then take the reads in
/// rasterization order, so the result is the same at any thread count.
pub fn simulate(
    c: &TextureCacheConfig,
    stages: &[Stage],
    nfrag: usize,
    slots: usize,
    fill: &FillToken<'_>,
) -> (CacheReport, Timing) {
    let mut stall: Vec<Vec<u32>> = if c.miss_cycles > 0 {
        vec![Vec::new(); stages.len()]
    } else {
        Vec::new()
    };
    let mut levels: BTreeMap<usize, LevelInfo> = BTreeMap::new();
    let mut textures: Vec<Vec<Arc<Texture>>> = Vec::with_capacity(stages.len());
    for s in stages {
        let ts: Vec<Arc<Texture>> = s.unit().textures().into_iter().map(|r| r.texture).collect();
        for t in &ts {
            for k in 0..t.levels() {
                let l = t.level_at(k);
                levels.insert(
                    reads::level_key(l),
                    LevelInfo {
                        bits: t.bits_per_texel(),
                        width: l.width(),
                        face: l.width() * l.height(),
                    },
                );
            }
        }
        textures.push(ts);
    }
    // the readers and their caches: one per unit with textures, or one for all
    let readers: Vec<usize> = (0..stages.len())
        .filter(|&i| !textures[i].is_empty())
        .collect();
    let ncaches = if c.shared { 1 } else { readers.len() };
    let mut caches: Vec<Cache> = (0..ncaches.max(1)).map(|_| Cache::new(c)).collect();
    let mut cache_of = vec![usize::MAX; stages.len()];
    for (k, &i) in readers.iter().enumerate() {
        let slot = if c.shared { 0 } else { k };
        cache_of[i] = slot;
        caches[slot].stats.readers.push(stages[i].name.clone());
        let widest = textures[i].iter().map(|t| t.bits_per_texel()).max();
        caches[slot].widest = caches[slot].widest.max(widest.unwrap_or(0));
    }
    let shift = c.block.trailing_zeros();
    let line_texels = u64::from(c.block) * u64::from(c.block);
    // the reads of a window of fragments, recorded in parallel chunks, then through the
    // caches in rasterization order
    let mut window_start = 0;
    while window_start < nfrag {
        let window = window_start..(window_start + WINDOW).min(nfrag);
        for chunk in record_window(stages, window.clone(), slots, fill) {
            let mut start = 0;
            // (an engine without stages reads nothing: no chunk of ends)
            for (k, ends) in chunk.ends.chunks(stages.len().max(1)).enumerate() {
                let f = chunk.first + k;
                for (i, &end) in ends.iter().enumerate() {
                    let got = &chunk.reads[start..end as usize];
                    start = end as usize;
                    let Some(cache) = caches.get_mut(cache_of[i]) else {
                        continue;
                    };
                    let mut missed = 0u32;
                    for r in got {
                        let Some(l) = levels.get(&r.level_key()) else {
                            continue;
                        };
                        let face = r.index / l.face;
                        let within = r.index % l.face;
                        let (x, y) = (within % l.width, within / l.width);
                        let hit = cache.access((r.level_key(), face, x >> shift, y >> shift));
                        let st = &mut cache.stats;
                        st.reads += 1;
                        st.uncached_bits += u64::from(l.bits);
                        if !hit {
                            st.misses += 1;
                            st.fill_bits += line_texels * u64::from(l.bits);
                            missed = missed.saturating_add(1);
                        }
                    }
                    if let Some(s) = stall.get_mut(i) {
                        if missed > 0 {
                            s.resize(nfrag, 0);
                            s[f] = missed;
                        }
                    }
                }
            }
        }
        window_start = window.end;
    }
    let caches: Vec<Cache> = caches
        .into_iter()
        .filter(|k| !k.stats.readers.is_empty())
        .collect();
    let data_bits = caches
        .iter()
        .map(|k| u64::from(c.lines) * line_texels * u64::from(k.widest))
        .collect();
    let stats: Vec<CacheStats> = caches
        .into_iter()
        .map(|k| {
            let mut s = k.stats;
            s.hit_rate = if s.reads == 0 {
                1.0
            } else {
                1.0 - s.misses as f64 / s.reads as f64
            };
            s
        })
        .collect();
    let busy: Vec<u64> = stats
        .iter()
        .map(|s| s.misses.saturating_mul(u64::from(c.fill_cycles)))
        .collect();
    let memory_busy_cycles = match c.bus {
        TextureBus::Shared => vec![busy.iter().fold(0u64, |a, &b| a.saturating_add(b))],
        TextureBus::PerCache => busy,
    };
    let uncached_bits = stats.iter().map(|s| s.uncached_bits).sum();
    let fill_bits = stats.iter().map(|s| s.fill_bits).sum();
    // the fill queue of each stage's misses: its cache's, or the one bus's
    let timing = stall
        .into_iter()
        .enumerate()
        .map(|(i, s)| {
            (!s.is_empty()).then(|| bumpsim_hw::stage::MissTiming {
                misses: Arc::from(s),
                latency: c.miss_cycles,
                occupancy: c.fill_cycles,
                memory: match c.bus {
                    TextureBus::Shared => 0,
                    TextureBus::PerCache => cache_of[i],
                },
                prefetch: (c.prefetch > 0).then_some(c.prefetch),
            })
        })
        .collect();
    let report = CacheReport {
        config: *c,
        data_bits,
        caches: stats,
        uncached_bits,
        fill_bits,
        memory_busy_cycles,
        traffic_ratio: if uncached_bits == 0 {
            0.0
        } else {
            fill_bits as f64 / uncached_bits as f64
        },
    };
    (report, timing)
}

/// The gate estimate of the caches `c` puts on the texel reads of `stages`
/// (`bumpsim_hw::units::texture_cache`): one per reading unit, each item prefixed by its
/// reader, or one shared (`shared:`). A cache's texel is the widest texel it holds and its
/// block address spans every level and face of the textures it holds.
pub fn gates(c: &TextureCacheConfig, stages: &[Stage], t: &bumpsim_hw::CostTable) -> GateBudget {
    let readers: Vec<(&str, Vec<Arc<Texture>>)> = stages
        .iter()
        .map(|s| {
            let ts = s.unit().textures().into_iter().map(|r| r.texture).collect();
            (s.name.as_str(), ts)
        })
        .filter(|(_, ts): &(&str, Vec<Arc<Texture>>)| !ts.is_empty())
        .collect();
    let groups: Vec<(String, Vec<&Arc<Texture>>)> = if c.shared {
        vec![(
            "shared".to_string(),
            readers.iter().flat_map(|(_, ts)| ts.iter()).collect(),
        )]
    } else {
        readers
            .iter()
            .map(|(n, ts)| (n.to_string(), ts.iter().collect()))
            .collect()
    };
    let mut g = GateBudget::new();
    for (name, ts) in groups {
        let blocks: u64 = ts
            .iter()
            .flat_map(|t| (0..t.levels()).map(move |k| t.level_at(k)))
            .map(|l| {
                let faces = l.len() as u64 / (u64::from(l.width()) * u64::from(l.height())).max(1);
                faces
                    * u64::from(l.width().div_ceil(c.block))
                    * u64::from(l.height().div_ceil(c.block))
            })
            .sum();
        let shape = CacheShape {
            lines: c.lines,
            ways: c.ways,
            block: c.block,
            texel_bits: ts.iter().map(|t| t.bits_per_texel()).max().unwrap_or(0),
            block_address_bits: 64 - blocks.max(2).saturating_sub(1).leading_zeros(),
            xor_index: c.index == crate::config::SetIndex::Xor,
            prefetch: c.prefetch,
        };
        g.add_part(&format!("{name}: "), 1, shape.gates(t));
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cache(lines: u32, ways: u32) -> Cache {
        Cache::new(&TextureCacheConfig {
            lines,
            ways,
            block: 4,
            shared: false,
            index: crate::config::SetIndex::Tiled,
            miss_cycles: 0,
            fill_cycles: 1,
            prefetch: 0,
            bus: TextureBus::Shared,
        })
    }

    #[test]
    fn least_recently_used_is_evicted_within_a_set() {
        // one set of two ways
        let mut c = cache(2, 2);
        let (a, b, d) = ((0, 0, 0, 0), (0, 0, 1, 0), (0, 0, 2, 0));
        assert!(!c.access(a));
        assert!(!c.access(b));
        assert!(c.access(a)); // a is now the most recent
        assert!(!c.access(d)); // evicts b
        assert!(c.access(a));
        assert!(!c.access(b));
        // direct-mapped: 4 sets in a 2 x 2 tiling of blocks
        let mut c = cache(4, 1);
        assert_eq!(c.split, (2, 2));
        for (bx, by) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            assert!(!c.access((0, 0, bx, by)));
        }
        // the four neighbours sit in four sets: all hit
        for (bx, by) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            assert!(c.access((0, 0, bx, by)));
        }
        // (2, 0) maps onto (0, 0)'s set and evicts it
        assert!(!c.access((0, 0, 2, 0)));
        assert!(!c.access((0, 0, 0, 0)));
        assert!(c.access((0, 0, 1, 1)));
        // another level's block at the same coordinates is another line
        assert!(!c.access((1, 0, 1, 1)));
    }

    #[test]
    fn sets_tile_the_blocks_for_every_power_of_two() {
        for log in 0..12 {
            let c = cache(1 << log, 1);
            assert_eq!(c.split.0 * c.split.1, 1 << log);
            assert!(c.split.0 >= c.split.1 && c.split.0 <= 2 * c.split.1);
        }
    }
}

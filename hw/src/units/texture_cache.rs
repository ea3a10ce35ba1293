//! The texture cache's hardware, priced: its behaviour (hits, misses, the fills' timing) is
//! simulated on the engine's own texel reads by `pipeline/src/texcache.rs`
//! (`docs/units/texture_memory.md`, "Texture cache"); this is what it costs.
//!
//! The organisation is Hakura and Gupta's (ISCA 1997, §4): `lines` lines of `block x block`
//! texels in sets of `ways`, each line's tag the block's address above the set index; a read
//! compares the set's tags (one equality a way, with the valid bit), picks the hit way's texel
//! and updates the set's LRU order; a miss latches its block address for the fill. The
//! prefetching unit (Igehy, Eldridge and Proudfoot, Graphics Hardware 1998) adds the fragment
//! FIFO in which fragments wait for their fills, each entry the texel's line address and its
//! place in the line. The storage (data, tags, LRU state, the FIFO) is priced by the memory
//! model (`CostTable::table`: the config's `cost.tables`, SRAM macros by default) and shown as
//! memory; the logic beside it. One read port a clock is priced (a unit reading several taps
//! a clock needs as many ports or banks: not modelled).

use crate::gates::{CostTable, GateBudget};

/// One cache's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CacheShape {
    /// Lines (a power of two).
    pub lines: u32,
    /// Lines of a set (a power of two, at most `lines`).
    pub ways: u32,
    /// Texels a side of a line's block.
    pub block: u32,
    /// Bits of the widest texel the cache holds.
    pub texel_bits: u32,
    /// Bits of a block's address over every texture, level and face the cache holds.
    pub block_address_bits: u32,
    /// The set index XORs the block row into the column (`SetIndex::Xor`).
    pub xor_index: bool,
    /// The fragment FIFO's depth of a prefetching unit (0: blocking).
    pub prefetch: u32,
}

fn log2(n: u32) -> u32 {
    n.max(1).next_power_of_two().trailing_zeros()
}

impl CacheShape {
    /// Tag bits: the block address above the set index.
    pub fn tag_bits(&self) -> u32 {
        self.block_address_bits
            .saturating_sub(log2(self.lines / self.ways.max(1)))
    }

    /// The gate estimate (see the module documentation).
    pub fn gates(&self, t: &CostTable) -> GateBudget {
        let mut g = GateBudget::new();
        let (lines, ways) = (self.lines.max(1), self.ways.max(1));
        let sets = lines / ways;
        let texels = u64::from(lines) * u64::from(self.block) * u64::from(self.block);
        let tag = self.tag_bits();
        g.add_memory(
            format!("data store {texels} x {}", self.texel_bits),
            1,
            t.table(texels, self.texel_bits),
        );
        g.add_memory(
            format!("tag store {lines} x {} (tag, valid)", tag + 1),
            1,
            t.table(u64::from(lines), tag + 1),
        );
        g.add(
            format!("tag compare {tag} and valid"),
            ways,
            t.xor2 * f64::from(tag) + t.and2 * f64::from(tag),
        );
        if ways > 1 {
            let age = log2(ways);
            g.add_memory(
                format!("LRU state {sets} x {}", ways * age),
                1,
                t.table(u64::from(sets), ways * age),
            );
            // the hit way's age against every other way's, each older one incremented
            g.add(
                format!("LRU update {age}"),
                ways,
                t.comparator(age) + t.adder(age) + t.mux(age, 2),
            );
            g.add("hit way encoder", 1, t.and2 * f64::from(ways * age));
            g.add(
                format!("way select {}", self.texel_bits),
                1,
                t.mux(self.texel_bits, ways),
            );
        }
        if self.xor_index {
            g.add("set index XOR", 1, t.xor2 * f64::from(log2(sets)));
        }
        g.add(
            format!("fill address register {}", self.block_address_bits),
            1,
            t.register(self.block_address_bits),
        );
        if self.prefetch > 0 {
            let entry = self.block_address_bits + 2 * log2(self.block);
            g.add_memory(
                format!("fragment FIFO {} x {entry}", self.prefetch),
                1,
                t.table(u64::from(self.prefetch), entry),
            );
            let p = log2(self.prefetch).max(1);
            g.add(format!("FIFO pointers {p}"), 2, t.register(p) + t.adder(p));
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(lines: u32, ways: u32) -> CacheShape {
        CacheShape {
            lines,
            ways,
            block: 4,
            texel_bits: 16,
            block_address_bits: 14,
            xor_index: false,
            prefetch: 0,
        }
    }

    #[test]
    fn storage_is_the_data_tags_and_lru_state() {
        let t = CostTable::default();
        // 64 lines of 4x4 16-bit texels in 16 sets of 4: tags 14 - 4 = 10 bits
        let s = shape(64, 4);
        assert_eq!(s.tag_bits(), 10);
        let g = s.gates(&t);
        let bits = 64.0 * 16.0 * 16.0 + 64.0 * 11.0 + 16.0 * 4.0 * 2.0;
        assert!(
            (g.memory() - t.sram_bit * bits).abs() < 1e-9,
            "{}",
            g.memory()
        );
        // direct mapped: no LRU, no way select; fully associative: every tag bit kept
        let dm = shape(64, 1).gates(&t);
        assert!(!dm.items.iter().any(|i| i.what.contains("LRU")));
        assert_eq!(shape(64, 64).tag_bits(), 14);
        // a prefetching unit adds its FIFO; more ways cost more logic
        let pf = CacheShape { prefetch: 64, ..s };
        assert!(pf.gates(&t).memory() > g.memory());
        assert!(
            shape(64, 8).gates(&t).total() - shape(64, 8).gates(&t).memory()
                > g.total() - g.memory()
        );
    }
}

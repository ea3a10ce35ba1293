//! Gate-equivalent (GE) cost model: one primitive cost table shared by every unit.
//!
//! 1 GE is the area of a 2-input NAND. The cell figures come from a public 45 nm standard-cell
//! library (cell area / NAND2 area, `shared/facts/hardware-facts.md`); the composite figures
//! (ripple adder, array multiplier, squarer, register with enable) are derived from them. Every
//! figure and its source is listed in `docs/gates.md`, with a comparison against yosys.

use serde::{Deserialize, Serialize};

/// Primitive costs in gate equivalents. All fields can be overridden in a config.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CostTable {
    /// Inverter.
    pub inv: f64,
    /// 2-input AND.
    pub and2: f64,
    /// 2-input XOR.
    pub xor2: f64,
    /// 2:1 multiplexer.
    pub mux2: f64,
    /// Half adder.
    pub half_adder: f64,
    /// Full adder: one ripple-adder bit as synthesis builds it from gates (calibrated on
    /// yosys, docs/gates.md; the library's compound FA cell is 5.33 GE).
    pub full_adder: f64,
    /// D flip-flop.
    pub dff: f64,
    /// Register bit with load enable (a D flip-flop and a 2:1 mux).
    pub reg_bit: f64,
    /// Mask ROM / hard-wired table of unknown (random) contents, per bit (from yosys: 256x8
    /// random ROM ~ 820 GE); [`CostTable::rom_of`], which prices known contents, scales with
    /// it (`rom_bit / 0.4`).
    pub rom_bit: f64,
    /// Loadable SRAM table (colour-LUT style), per bit.
    pub sram_bit: f64,
    /// Latch RAM, per bit: a latch (3.33) and its share of the read multiplexer tree (one
    /// 2:1 mux per stored bit, 2.33); the write decoder is not counted.
    pub latch_ram_bit: f64,
    /// Flip-flop RAM, per bit: a register bit with load enable (8.0) and its share of the read
    /// multiplexer tree (2.33); the write decoder is not counted.
    pub flop_ram_bit: f64,
    /// What every loadable table of the engine is built as (docs/gates.md, "Memory"): the
    /// table's bits priced at `sram_bit`, `latch_ram_bit` or `flop_ram_bit`, or, for a table
    /// fixed at design time, its contents ([`CostTable::table_of`]).
    pub tables: MemoryKind,
    /// Per table role, a kind that replaces `tables` for the tables of that role (a unit's
    /// `table_kinds` in the config, [`CostTable::for_table`]); not a config field of `cost`.
    #[serde(skip)]
    pub by_role: [Option<MemoryKind>; TableRole::COUNT],
}

/// Which table of a unit a price is for, so that a config can build each table as its own
/// kind (a unit's `table_kinds`, docs/gates.md "Memory"): a quantized engine's colour table in
/// latches beside its normal table in SRAM, one unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum TableRole {
    /// Power (shininess) tables: `PowerTable`, `SpecGen`, the specular blend, the palette
    /// builder's specular tables.
    Power,
    /// The colour table of the palette LUT (`PaletteLut`, a quantized engine's entries).
    Colours,
    /// The palette builder's normal table.
    Normals,
    /// The bump palette of a paletted texture (`TexFetch`).
    BumpPalette,
}

impl TableRole {
    pub const COUNT: usize = 4;
    pub const ALL: [TableRole; TableRole::COUNT] = [
        TableRole::Power,
        TableRole::Colours,
        TableRole::Normals,
        TableRole::BumpPalette,
    ];
    /// The name the reports print.
    pub fn name(self) -> &'static str {
        match self {
            TableRole::Power => "power",
            TableRole::Colours => "colours",
            TableRole::Normals => "normals",
            TableRole::BumpPalette => "bump_palette",
        }
    }
}

/// How a table is built, and so priced per bit (`CostTable::tables`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum MemoryKind {
    /// A loadable SRAM macro (`sram_bit`): the dense choice, with a macro's periphery.
    #[default]
    Sram,
    /// Latches with a read mux tree (`latch_ram_bit`), standard cells only.
    LatchRam,
    /// Flip-flops with load enables and a read mux tree (`flop_ram_bit`): what synthesis
    /// builds from a plain Verilog memory.
    FlopRam,
    /// Hard-wired contents, the table the unit holds now, priced by them
    /// ([`CostTable::table_of`], [`CostTable::rom_of`]; `rom_bit` a bit, the random-contents
    /// bound, where the unit does not hold the words): not loadable, so the table cannot
    /// follow a material change at run time.
    Rom,
}

impl MemoryKind {
    /// The name the reports print.
    pub fn name(self) -> &'static str {
        match self {
            MemoryKind::Sram => "SRAM",
            MemoryKind::LatchRam => "latch RAM",
            MemoryKind::FlopRam => "flip-flop RAM",
            MemoryKind::Rom => "ROM",
        }
    }
}

impl Default for CostTable {
    fn default() -> Self {
        CostTable {
            inv: 0.67,
            and2: 1.33,
            xor2: 2.0,
            mux2: 2.33,
            half_adder: 3.33,
            full_adder: FULL_ADDER_GE,
            dff: 5.67,
            reg_bit: 8.0,
            rom_bit: 0.4,
            sram_bit: 1.5,
            latch_ram_bit: 5.66,
            flop_ram_bit: 10.33,
            tables: MemoryKind::Sram,
            by_role: [None; TableRole::COUNT],
        }
    }
}

/// The calibrated full-adder price: a ripple-adder bit as `synth; abc` builds it from the
/// library's gates (XOR, NAND, AND-OR). yosys 0.23 measures 6.6, 7.0 and 7.2 GE a bit for 8-,
/// 16- and 24-bit adders and 6.8-7.3 GE per full adder of the 8x8 to 16x16 array multipliers
/// (`hw/tests/gates_yosys.rs`); the figure is the one that puts every generated unit of the
/// bundled configs within +-10% of its synthesis (`hw/tests/rtl_synth.rs`, docs/gates.md).
pub const FULL_ADDER_GE: f64 = 6.8;

impl CostTable {
    /// The largest price a config may give a primitive, in GE (the largest default is 8).
    pub const MAX_PRICE: f64 = 1e6;

    /// Every price with its field name, in declaration order.
    pub fn prices(&self) -> [(&'static str, f64); 12] {
        [
            ("inv", self.inv),
            ("and2", self.and2),
            ("xor2", self.xor2),
            ("mux2", self.mux2),
            ("half_adder", self.half_adder),
            ("full_adder", self.full_adder),
            ("dff", self.dff),
            ("reg_bit", self.reg_bit),
            ("rom_bit", self.rom_bit),
            ("sram_bit", self.sram_bit),
            ("latch_ram_bit", self.latch_ram_bit),
            ("flop_ram_bit", self.flop_ram_bit),
        ]
    }

    /// Check a table of overrides: every price a finite number from 0 to
    /// [`CostTable::MAX_PRICE`] GE. The error is the field name and what was expected.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        for (name, ge) in self.prices() {
            if !(ge.is_finite() && (0.0..=Self::MAX_PRICE).contains(&ge)) {
                return Err((
                    name,
                    format!(
                        "price {ge}: expected a finite number of gate equivalents from 0 to {}",
                        Self::MAX_PRICE
                    ),
                ));
            }
        }
        Ok(())
    }

    /// n-bit ripple-carry adder or subtractor.
    pub fn adder(&self, n: u32) -> f64 {
        self.full_adder * n as f64
    }
    /// n x m array multiplier: n*m partial-product ANDs and n*(m-1) full adders.
    pub fn multiplier(&self, n: u32, m: u32) -> f64 {
        let (n, m) = (n as f64, m as f64);
        self.and2 * n * m + self.full_adder * n * (m - 1.0).max(0.0)
    }
    /// n-bit squarer: about half an n x n multiplier (the partial-product array folds).
    pub fn squarer(&self, n: u32) -> f64 {
        0.5 * self.multiplier(n, n)
    }
    /// n-bit k:1 multiplexer, built from 2:1 muxes.
    pub fn mux(&self, n: u32, k: u32) -> f64 {
        self.mux2 * n as f64 * k.saturating_sub(1) as f64
    }
    /// The decode of a `sel_bits`-bit code into `lines` one-hot select lines (a
    /// `sel_bits`-input AND a line, as two-input ANDs), shared by every select that reads the
    /// same code: the generators' register reads (`rtl::fixed::select`, a chain of `sel == i`
    /// tests) are `mux(n, k + 1)` over `k` inputs that are not a constant 0 plus this decode.
    /// yosys: a 12-way read of 9 bits with 10 such inputs 276 GE, a 14-way read of 10 bits with
    /// 12, 358.5 (`mux` + decode: 249.6 and 327.6); in the register combiners' final
    /// combiner, where four reads share each code, within 4%.
    pub fn decoder(&self, lines: u32, sel_bits: u32) -> f64 {
        self.and2 * f64::from(sel_bits.saturating_sub(1)) * f64::from(lines)
    }
    /// `x + c` for a constant `c` on `n` bits: a carry chain, a half adder a bit.
    pub fn constant_add(&self, n: u32) -> f64 {
        self.half_adder * n as f64
    }
    /// `x k` of an `n`-bit `x` as its signed digits' shifts and adds, each digit after the
    /// first a full adder where the two shifted copies overlap and a carry or borrow chain (a
    /// half adder a bit) where they do not (as the power table's index rounding): `x (2^16 -
    /// 1)` of a 13-bit `x` is a borrow chain, not a 13-bit subtractor, and the cast's rounding
    /// keeps only its top.
    pub fn shift_add(&self, n: u32, k: u128) -> f64 {
        let mut digits: Vec<u32> = crate::arith::csd(k).into_iter().map(|(s, _)| s).collect();
        digits.sort_unstable_by(|a, b| b.cmp(a));
        digits
            .windows(2)
            .map(|w| {
                let gap = w[0] - w[1];
                self.adder(n.saturating_sub(gap)) + self.half_adder * n.min(gap) as f64
            })
            .sum()
    }
    /// n-bit register with load enable.
    pub fn register(&self, n: u32) -> f64 {
        self.reg_bit * n as f64
    }
    /// n-bit magnitude comparator (a subtractor's carry chain).
    pub fn comparator(&self, n: u32) -> f64 {
        self.adder(n)
    }
    /// `x * k` for a constant `k > 0` on an `n`-bit `x`, as the canonical-signed-digit
    /// shifts and adds the generated Verilog has (`arith::csd`): one `n`-bit adder per
    /// nonzero digit after the first.
    pub fn constant_multiplier(&self, n: u32, k: u128) -> f64 {
        crate::arith::csd(k).len().saturating_sub(1) as f64 * self.adder(n)
    }
    /// Round-half-up `x / d` of an integer `x` in `[lo, hi]` for a constant `d > 0`, as the
    /// generated Verilog builds it (`rtl::divide::div_round`): `2x + d` (a constant add), the
    /// shift by `2d`'s trailing zeros, the offset into `[0, U]` and back when `x` may be
    /// negative (two constant adds), and the multiply by the reciprocal of the odd part
    /// ([`crate::arith::reciprocal`]) by its digits' shifts and adds ([`Self::shift_add`]).
    /// yosys, `d = 255` (the register combiners at width 9): `x` in `[0, S^2]` 259.5 GE (this:
    /// 239.1), `[-S^2, S^2]` 468.0 (458.1), `[-3 S^2, 3 S^2]` 510.6 (511.9), `[-2 S^2, 6 S^2]`
    /// 549.0 (518.6).
    pub fn div_round(&self, lo: i128, hi: i128, d: i128) -> f64 {
        let bits = |lo: i128, hi: i128| {
            crate::arith::bit_length(lo.unsigned_abs().max(hi.unsigned_abs())) + 1
        };
        let (nlo, nhi) = (2 * lo + d, 2 * hi + d);
        let mut ge = self.constant_add(bits(nlo, nhi));
        let t = (2 * d).trailing_zeros();
        let o = (2 * d) >> t;
        let (xlo, xhi) = (nlo >> t, nhi >> t);
        if o == 1 || xlo.div_euclid(o) == xhi.div_euclid(o) {
            return ge;
        }
        let k = if xlo < 0 { (-xlo + o - 1) / o } else { 0 };
        let (ulo, uhi) = (xlo + k * o, xhi + k * o);
        if k != 0 {
            ge += self.constant_add(bits(xlo, xhi)) + self.constant_add(bits(ulo / o, uhi / o));
        }
        let (m, _) = crate::arith::reciprocal(o, uhi);
        ge + self.shift_add(bits(ulo, uhi), m as u128)
    }
    /// Round-half-up `x k / d` (or its floor) of an integer `x` in `[lo, hi]` for constants
    /// `k, d > 0`, as synthesis builds [`CostTable::div_round`]'s datapath on `x k`: the
    /// multiply by `k` and the reciprocal's merge into one constant multiply of the narrow `x`
    /// (by `k M`), beside the rounding's constant adds (only above the divisor's power of two)
    /// and the offset into `[0, U]` when `x` may be negative. yosys: the ROP's colour
    /// conversions (`units::rop::conversion`, `docs/units/rop.md`), the emboss filter's
    /// rational rescale (`docs/units/emboss_filter.md`).
    pub fn scaled_div(&self, lo: i128, hi: i128, k: i128, d: i128) -> f64 {
        let bits = |lo: i128, hi: i128| {
            crate::arith::bit_length(lo.unsigned_abs().max(hi.unsigned_abs())) + 1
        };
        let w = bits(lo, hi);
        let (nlo, nhi) = (2 * lo * k + d, 2 * hi * k + d);
        let tz = (2 * d).trailing_zeros();
        let adds = self.constant_add(bits(nlo, nhi).saturating_sub(tz));
        let o = (2 * d) >> tz;
        let (ulo, uhi) = (nlo >> tz, nhi >> tz);
        if o == 1 || ulo.div_euclid(o) == uhi.div_euclid(o) {
            return self.shift_add(w, k as u128) + adds;
        }
        let off = if ulo < 0 { (-ulo + o - 1) / o } else { 0 };
        let offset = if off != 0 {
            2.0 * self.constant_add(bits(ulo, uhi))
        } else {
            0.0
        };
        let (m, _) = crate::arith::reciprocal(o, uhi + off * o);
        self.shift_add(w, (k * m) as u128) + adds + offset
    }
    /// A sequencer's step counter over `steps` clocks: a register bit and an incrementer bit
    /// per bit of the count.
    pub fn sequencer(&self, steps: u32) -> f64 {
        let bits = (32 - steps.leading_zeros()).max(1) as f64;
        (self.reg_bit + self.half_adder) * bits
    }
    /// Hard-wired table of `entries` words of `bits` bits, priced by its bit count at
    /// `rom_bit`: the bound for **random** contents (a 256 x 8 table of random words
    /// synthesises to 0.32-0.45 GE/bit from 16 to 1024 entries). For callers that do not know
    /// the contents; a table whose contents are known is priced by [`CostTable::rom_of`].
    pub fn rom(&self, entries: u64, bits: u32) -> f64 {
        self.rom_bit * entries as f64 * bits as f64
    }
    /// Hard-wired table of the given contents (`words[i]` the word at address `i`, its low
    /// `bits` bits; a length that is not a power of two reads 0 beyond the end, as
    /// `rtl::verilog::rom`'s default), priced by what synthesis builds from it:
    /// the nodes of the table's shared reduced ordered BDD ([`rom_bdd`]), a mux node
    /// [`ROM_MUX_GE`] and an AND/OR node [`ROM_GATE_GE`] ([`RomBdd::ge`]), in the cheaper of
    /// the two address orders (most or least significant bit at the root), times `rom_bit /
    /// 0.4`. A constant table is free, a table whose outputs are address bits too, a random
    /// one costs 0.35-0.45 GE a bit as `rom(e, b)`; yosys over 28 tables: 0.88-1.45
    /// (docs/gates.md, "Tables"). Time and memory are linear in
    /// `words.len() * bits` (2^16 x 16 in a few tens of ms); tables above 2^20 words fall back
    /// to [`CostTable::rom`].
    pub fn rom_of(&self, words: &[i64], bits: u32) -> f64 {
        if words.len() > ROM_OF_MAX_WORDS {
            return self.rom(words.len() as u64, bits);
        }
        // the cheaper of the two address orders (abc finds either); `rom_bit` is the price of
        // the random-contents bound, and an override scales this estimate with it
        let ge = rom_bdd(words, bits, true)
            .ge()
            .min(rom_bdd(words, bits, false).ge());
        self.rom_bit / DEFAULT_ROM_BIT * ge
    }
    /// The table for the tables of `role`: `tables` replaced by the role's own kind when the
    /// config gives one (a unit's `table_kinds`).
    pub fn for_table(&self, role: TableRole) -> CostTable {
        match self.by_role[role as usize] {
            Some(tables) => CostTable { tables, ..*self },
            None => *self,
        }
    }
    /// A table of the given contents as the engine builds its tables (`self.tables`): a
    /// loadable memory priced by its bits ([`CostTable::table`]), or, for
    /// [`MemoryKind::Rom`], a hard-wired table of these contents ([`CostTable::rom_of`]):
    /// the contents the unit holds now.
    pub fn table_of(&self, words: &[i64], bits: u32) -> f64 {
        match self.tables {
            MemoryKind::Rom => self.rom_of(words, bits),
            _ => self.table(words.len() as u64, bits),
        }
    }
    /// Loadable table of `entries` words of `bits` bits, built as `self.tables` says.
    pub fn table(&self, entries: u64, bits: u32) -> f64 {
        let per_bit = match self.tables {
            MemoryKind::Sram => self.sram_bit,
            MemoryKind::LatchRam => self.latch_ram_bit,
            MemoryKind::FlopRam => self.flop_ram_bit,
            MemoryKind::Rom => self.rom_bit,
        };
        per_bit * entries as f64 * bits as f64
    }
    /// Saturation / clamp logic on n bits: per bit an AND with the in-range flag and an OR
    /// with the overflow flag (about 2 GE a bit; yosys measures 16 GE for a 10-to-8 bit clamp,
    /// docs/gates.md).
    pub fn clamp(&self, n: u32) -> f64 {
        (self.and2 + self.inv) * n as f64
    }
}

/// One line of a unit's gate estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GateItem {
    pub what: String,
    pub ge: f64,
    /// A table's storage (priced by [`CostTable::table`]), reported apart from the logic.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub memory: bool,
    /// A table of fixed contents ([`CostTable::rom_of`], or [`CostTable::rom`] when its
    /// contents are unknown): logic in the total, but compared with synthesis apart (yosys
    /// prices each ROM module by its contents).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub rom: bool,
}

/// A unit's itemised gate estimate.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct GateBudget {
    pub items: Vec<GateItem>,
}

impl GateBudget {
    pub fn new() -> Self {
        Self::default()
    }
    /// Add `count` copies of a primitive costing `ge` each.
    pub fn add(&mut self, what: impl Into<String>, count: u32, ge: f64) -> &mut Self {
        self.push(what.into(), count, ge, Store::Logic)
    }
    /// Add `count` copies of a table of fixed contents costing `ge` each
    /// ([`CostTable::rom_of`], [`CostTable::rom`]).
    pub fn add_rom(&mut self, what: impl Into<String>, count: u32, ge: f64) -> &mut Self {
        self.push(what.into(), count, ge, Store::Rom)
    }
    /// Add `count` copies of a table's storage costing `ge` each ([`CostTable::table`]).
    pub fn add_memory(&mut self, what: impl Into<String>, count: u32, ge: f64) -> &mut Self {
        self.push(what.into(), count, ge, Store::Memory)
    }
    fn push(&mut self, what: String, count: u32, ge: f64, store: Store) -> &mut Self {
        if count > 0 && ge > 0.0 {
            self.items.push(GateItem {
                what,
                ge: ge * count as f64,
                memory: store == Store::Memory,
                rom: store == Store::Rom,
            });
        }
        self
    }
    /// Add `count` copies of every item of a part's budget, named `prefix` + the item (the
    /// memory items stay memory).
    pub fn add_part(&mut self, prefix: &str, count: u32, part: GateBudget) -> &mut Self {
        if count > 0 {
            self.items.extend(part.items.into_iter().map(|i| GateItem {
                what: format!("{prefix}{}", i.what),
                ge: i.ge * count as f64,
                ..i
            }));
        }
        self
    }
    /// The tables' storage ([`GateBudget::add_memory`] items) in the total.
    pub fn memory(&self) -> f64 {
        self.sum_of(|i| i.memory)
    }
    /// The tables of fixed contents ([`GateBudget::add_rom`] items) in the total.
    pub fn rom(&self) -> f64 {
        self.sum_of(|i| i.rom)
    }
    /// Every table, loadable and of fixed contents: what synthesis builds as ROM modules and
    /// prices apart from the logic (`bumpsim gates --synth`, `hw/tests/rtl_synth.rs`).
    pub fn tables(&self) -> f64 {
        self.memory() + self.rom()
    }
    /// The items `which` picks, summed (`+ 0.0`: none gives +0, not the empty sum's -0).
    fn sum_of(&self, which: impl Fn(&GateItem) -> bool) -> f64 {
        self.items
            .iter()
            .filter(|i| which(i))
            .map(|i| i.ge)
            .sum::<f64>()
            + 0.0
    }
    pub fn total(&self) -> f64 {
        self.items.iter().map(|i| i.ge).sum()
    }
}

/// Where an item's area sits: logic, a loadable table, or a table of fixed contents.
#[derive(Clone, Copy, PartialEq)]
enum Store {
    Logic,
    Memory,
    Rom,
}

/// The words of a table of several lanes per entry (colours, normals), each lane's code
/// masked to `width` bits and packed from bit 0, as one `lanes * width`-bit word an entry (at
/// most 64 bits: the lanes beyond are dropped): what [`CostTable::table_of`] prices. The order
/// of the lanes does not change the price (the BDD is shared between output bits).
pub fn packed_words<const L: usize>(entries: &[[i64; L]], width: u32) -> Vec<i64> {
    let mask = if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    };
    entries
        .iter()
        .map(|e| {
            e.iter()
                .enumerate()
                .filter(|(k, _)| (*k as u32 + 1) * width <= 64)
                .fold(0u64, |w, (k, &c)| {
                    w | (c as u64 & mask) << (k as u32 * width)
                }) as i64
        })
        .collect()
}

/// `rom_bit`'s default: [`CostTable::rom_of`] scales with an overridden `rom_bit`.
const DEFAULT_ROM_BIT: f64 = 0.4;
/// GE of a mux node of a table's BDD ([`RomBdd`]), fitted on yosys with [`ROM_GATE_GE`]
/// (docs/gates.md, "Tables"; `rom_calibration` in `hw/tests/gates_yosys.rs`): close to the
/// library's MUX2, 2.33.
pub const ROM_MUX_GE: f64 = 2.13;
/// GE of an AND/OR node (one child a constant) of a table's BDD, fitted with [`ROM_MUX_GE`].
pub const ROM_GATE_GE: f64 = 0.61;
/// The largest table [`CostTable::rom_of`] reads word by word (2^20 words).
pub const ROM_OF_MAX_WORDS: usize = 1 << 20;

/// The nodes of a table's shared reduced ordered binary decision diagram ([`rom_bdd`]): every
/// output bit a function of the address bits, one node per distinct sub-function that depends
/// on its level's address bit (shared between the output bits), the constants 0 and 1 the
/// leaves (not counted). Each node is a 2:1 mux on its address bit; by its children it is one
/// of four kinds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RomBdd {
    /// Children (0, 1): the address bit itself, a wire.
    pub wires: u64,
    /// Children (1, 0): the address bit inverted.
    pub inverters: u64,
    /// One child a constant, the other not: an AND or OR with the address bit.
    pub gates: u64,
    /// Neither child a constant: a 2:1 mux.
    pub muxes: u64,
}

impl RomBdd {
    /// All nodes.
    pub fn nodes(&self) -> u64 {
        self.wires + self.inverters + self.gates + self.muxes
    }
    /// The diagram's price at the default `rom_bit`: [`ROM_MUX_GE`] a mux, [`ROM_GATE_GE`] an
    /// AND/OR, wires and inverters nothing (synthesis absorbs the inverters; a fitted price
    /// for them came out negative).
    pub fn ge(&self) -> f64 {
        ROM_MUX_GE * self.muxes as f64 + ROM_GATE_GE * self.gates as f64
    }
}

/// The shared ROBDD of a table (see [`RomBdd`]): `words[i]`'s low `bits` bits (at most 64) at
/// address `i`, the address `ceil(log2(len))` bits wide, 0 beyond the end; `msb_root` puts
/// the most significant address bit at the root (the least significant next to the leaves),
/// else the reverse. Built bottom-up, a level per address bit, each sub-function an id from
/// its two halves' ids: time and memory linear in `len * bits`.
pub fn rom_bdd(words: &[i64], bits: u32, msb_root: bool) -> RomBdd {
    let bits = bits.min(64) as usize;
    let abits = usize::BITS - words.len().saturating_sub(1).leading_zeros();
    let size = 1usize << abits;
    let mut level: Vec<u32> = Vec::with_capacity(bits * size);
    for b in 0..bits {
        level.extend((0..size).map(|i| words.get(i).map_or(0, |&w| ((w as u64 >> b) & 1) as u32)));
    }
    let mut bdd = RomBdd::default();
    let mut next = 2u32;
    let mut block = size;
    let mut ids: std::collections::HashMap<u64, u32, NodeHash> = Default::default();
    while block > 1 {
        let half = block / 2;
        ids.clear();
        let mut up = Vec::with_capacity(level.len() / 2);
        for f in level.chunks_exact(block) {
            for i in 0..half {
                let (lo, hi) = if msb_root {
                    (f[2 * i], f[2 * i + 1])
                } else {
                    (f[i], f[i + half])
                };
                if lo == hi {
                    up.push(lo);
                    continue;
                }
                let id = *ids
                    .entry(u64::from(lo) << 32 | u64::from(hi))
                    .or_insert_with(|| {
                        match (lo, hi) {
                            (0, 1) => bdd.wires += 1,
                            (1, 0) => bdd.inverters += 1,
                            (0 | 1, _) | (_, 0 | 1) => bdd.gates += 1,
                            _ => bdd.muxes += 1,
                        }
                        next += 1;
                        next - 1
                    });
                up.push(id);
            }
        }
        level = up;
        block = half;
    }
    bdd
}

/// A multiplicative hash of the BDD's `(lo, hi)` keys (the std hasher is 3x slower here).
#[derive(Default, Clone, Copy)]
struct NodeHash;

impl std::hash::BuildHasher for NodeHash {
    type Hasher = NodeHasher;
    fn build_hasher(&self) -> NodeHasher {
        NodeHasher(0)
    }
}

struct NodeHasher(u64);

impl std::hash::Hasher for NodeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
    }
    fn write_u64(&mut self, k: u64) {
        self.0 = (k ^ (k >> 29)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_dividers_and_decoders_are_priced_as_documented() {
        // docs/gates.md: `div_round` by 255 over the register combiners' ranges at width 9,
        // each beside the yosys figure of its cone (259.5, 468.0, 510.6, 549.0 GE)
        let t = CostTable::default();
        let s = 255i128;
        for ((lo, hi), want) in [
            ((0, s * s), 239.09),
            ((-s * s, s * s), 458.06),
            ((-3 * s * s, 3 * s * s), 511.9),
            ((-2 * s * s, 6 * s * s), 518.56),
        ] {
            let got = t.div_round(lo, hi, s);
            assert!((got - want).abs() < 0.005, "[{lo}, {hi}]: {got}");
        }
        // a power-of-two divisor is the rounding add alone
        assert!((t.div_round(-100, 100, 64) - t.constant_add(10)).abs() < 1e-9);
        // register reads: yosys 276 and 358.5 GE
        assert!((t.mux(9, 11) + t.decoder(10, 4) - 249.6).abs() < 0.005);
        assert!((t.mux(10, 13) + t.decoder(12, 4) - 327.48).abs() < 0.005);
    }
    use super::*;

    #[test]
    fn derived_figures_follow_the_cell_table() {
        let t = CostTable::default();
        assert!((t.adder(16) - 16.0 * 6.8).abs() < 1e-9);
        // 8x8: 64 ANDs + 56 full adders
        assert!((t.multiplier(8, 8) - (64.0 * 1.33 + 56.0 * 6.8)).abs() < 1e-9);
        // 255 * 257 = 2^16 - 1: one subtractor; (2^12 + 1)(2^8 - 1): three adders
        assert!((t.constant_multiplier(20, 255 * 257) - t.adder(20)).abs() < 1e-9);
        assert!((t.constant_multiplier(20, 4097 * 255) - 3.0 * t.adder(20)).abs() < 1e-9);
        assert_eq!(t.constant_multiplier(20, 1 << 9), 0.0);
        assert!((t.sequencer(1) - (8.0 + 3.33)).abs() < 1e-9);
        assert!((t.sequencer(4) - 3.0 * (8.0 + 3.33)).abs() < 1e-9);
        assert!((t.squarer(8) - 0.5 * t.multiplier(8, 8)).abs() < 1e-9);
        assert!((t.mux(8, 4) - 8.0 * 3.0 * 2.33).abs() < 1e-9);
        assert!((t.rom(256, 8) - 819.2).abs() < 1e-9);
    }

    #[test]
    fn overrides_must_be_finite_and_not_negative() {
        assert!(CostTable::default().validate().is_ok());
        let zero = CostTable {
            rom_bit: 0.0,
            ..CostTable::default()
        };
        assert!(zero.validate().is_ok());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 1e7] {
            let t = CostTable {
                full_adder: bad,
                ..CostTable::default()
            };
            let (field, msg) = t.validate().unwrap_err();
            assert_eq!(field, "full_adder");
            assert!(msg.contains(&format!("price {bad}")), "{msg}");
        }
    }

    #[test]
    fn tables_are_priced_by_their_kind_and_kept_apart() {
        let bits = 256.0 * 8.0;
        for (kind, per_bit) in [
            (MemoryKind::Sram, 1.5),
            (MemoryKind::LatchRam, 3.33 + 2.33),
            (MemoryKind::FlopRam, 8.0 + 2.33),
            (MemoryKind::Rom, 0.4),
        ] {
            let t = CostTable {
                tables: kind,
                ..CostTable::default()
            };
            assert!((t.table(256, 8) - per_bit * bits).abs() < 1e-6, "{kind:?}");
            let mut part = GateBudget::new();
            part.add_memory("table", 1, t.table(256, 8));
            part.add("index adder", 1, t.adder(8));
            let mut g = GateBudget::new();
            g.add_part("gen: ", 2, part);
            g.add("output register", 1, t.register(8));
            assert!((g.memory() - 2.0 * per_bit * bits).abs() < 1e-6, "{kind:?}");
            assert_eq!(g.items[0].what, "gen: table");
            assert!(g.items[0].memory && !g.items[1].memory && !g.items[2].memory);
            assert!(
                (g.total() - g.memory() - 2.0 * t.adder(8) - t.register(8)).abs() < 1e-9,
                "{kind:?}"
            );
        }
        // no tables: memory is +0, not -0
        assert!(GateBudget::new().memory().is_sign_positive());
        assert!(GateBudget::new().rom().is_sign_positive());
        let mut b = GateBudget::new();
        b.add_rom("rom", 2, 10.0)
            .add_memory("ram", 1, 3.0)
            .add("logic", 1, 1.0);
        let mut c = GateBudget::new();
        c.add_part("u.", 1, b.clone());
        for g in [&b, &c] {
            assert_eq!((g.rom(), g.memory(), g.total()), (20.0, 3.0, 24.0));
        }
    }

    #[test]
    fn rom_contents_are_counted_as_a_shared_bdd() {
        let t = CostTable::default();
        let both = |w: &[i64], b: u32| (rom_bdd(w, b, true), rom_bdd(w, b, false));
        // a constant table: no node, free (its bit count would price it 819.2 GE)
        let (m, l) = both(&[0xa5; 256], 8);
        assert_eq!((m, l), (RomBdd::default(), RomBdd::default()));
        assert_eq!(t.rom_of(&[0xa5; 256], 8), 0.0);
        // the identity: each output bit is its address bit, one wire node each, free
        let id: Vec<i64> = (0..256).collect();
        let want = RomBdd {
            wires: 8,
            ..RomBdd::default()
        };
        assert_eq!(both(&id, 8), (want, want));
        assert_eq!(t.rom_of(&id, 8), 0.0);
        // one bit varying, y0 = a1 & a0: a wire (a0) under an AND node (a1) in either order
        let and = RomBdd {
            wires: 1,
            gates: 1,
            ..RomBdd::default()
        };
        assert_eq!(both(&[0, 0, 0, 1], 1), (and, and));
        assert!((t.rom_of(&[0, 0, 0, 1], 1) - 0.61).abs() < 1e-12);
        // y0 = y1 = a1 ^ a0: a wire and an inverter (a0) under one mux (a1), shared by both
        // output bits
        let xor = RomBdd {
            wires: 1,
            inverters: 1,
            muxes: 1,
            ..RomBdd::default()
        };
        assert_eq!(both(&[0, 3, 3, 0], 2), (xor, xor));
        assert!((t.rom_of(&[0, 3, 3, 0], 2) - 2.13).abs() < 1e-12);
        // three words: the fourth reads 0 (y = a1 & !a0 | !a1 & a0 ... = a0 ^ a1 with [3] = 0)
        assert_eq!(both(&[0, 1, 1], 1), both(&[0, 1, 1, 0], 1));
        // bits above `bits` are not read; the order matters: y0 = a0 of a 4-entry table
        // is a wire below a1 with the msb at the root, and a wire at the root the other way
        assert_eq!(
            both(&[0, 1 | 6, 0, 1], 1).0,
            RomBdd {
                wires: 1,
                ..RomBdd::default()
            }
        );
        // x^2 of 256 x 8 (the power table's contents): cheaper in one order
        let sq: Vec<i64> = (0..256).map(|i| (i * i) >> 8).collect();
        let (m, l) = both(&sq, 8);
        assert!((t.rom_of(&sq, 8) - m.ge().min(l.ge())).abs() < 1e-9);
        assert!(t.rom_of(&sq, 8) < t.rom(256, 8));
        // an overridden `rom_bit` scales the estimate; a loadable table ignores the contents
        let half = CostTable { rom_bit: 0.2, ..t };
        assert!((half.rom_of(&sq, 8) - 0.5 * t.rom_of(&sq, 8)).abs() < 1e-9);
        assert_eq!(t.table_of(&sq, 8), t.table(256, 8));
        let rom = CostTable {
            tables: MemoryKind::Rom,
            ..t
        };
        assert_eq!(rom.table_of(&sq, 8), t.rom_of(&sq, 8));
    }

    #[test]
    fn random_contents_cost_about_rom_bit() {
        // random words: about the bit-count bound (yosys 0.35-0.45 GE a bit)
        let mut s = 1u32;
        let words: Vec<i64> = (0..1024)
            .map(|_| {
                s = s.wrapping_mul(1103515245).wrapping_add(12345) & 0x7fff_ffff;
                i64::from(s >> 16 & 0xff)
            })
            .collect();
        let t = CostTable::default();
        let r = t.rom_of(&words, 8) / t.rom(1024, 8);
        assert!((0.6..1.0).contains(&r), "{r}");
        // a 2^16-entry, 16-bit table is read in bounded time (two diagrams of 2^20 leaves)
        let big: Vec<i64> = (0..1i64 << 16).map(|i| (i * i) >> 16).collect();
        let t0 = std::time::Instant::now();
        let ge = t.rom_of(&big, 16);
        println!(
            "2^16 x 16 ramp of squares: {ge:.1} GE in {:?}",
            t0.elapsed()
        );
        assert!(ge > 0.0 && ge < t.rom(1 << 16, 16));
    }

    #[test]
    fn budget_sums_items() {
        let t = CostTable::default();
        let mut b = GateBudget::new();
        b.add("adder 8", 3, t.adder(8))
            .add("reg 8", 1, t.register(8))
            .add("nothing", 0, 5.0);
        assert_eq!(b.items.len(), 2);
        assert!((b.total() - (3.0 * 8.0 * 6.8 + 64.0)).abs() < 1e-9);
    }
}

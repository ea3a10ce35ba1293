//! Paletted-texture lookup: a texel's index into the shaded colour table `C`.
//!
//! Tarini, Cignoni, Rocchini, Scopigno, "Real Time, Accurate, Multi-Featured Rendering of Bump
//! Mapped Surfaces" (quantized normal maps), §3 and §5: each texel of the normal map is an
//! index into a table `N` of `s_N` normals; per frame the builder
//! ([`crate::units::PaletteBuilder`]) turns `N` into a colour table `C`, and the surface is
//! rendered through the indexed texture, "Many hardware architectures, in fact, give hardware
//! support for paletted textures, and an explicit step is provided in the raster pipeline to
//! translate indexes into RGBA colors". This unit is that step.
//!
//! * Port `i`: 1 lane, the texel index, an unsigned integer word of 8 to
//!   [`MAX_INDEX_BITS`] = 16 bits (`Fixed`,
//!   no fraction bits). Port `c`: 4 lanes (RGBA) of the entry encoding.
//! * One lookup per clock (interval 1), latency 2: the index register, then the SRAM read
//!   into the output register.
//! * An index beyond the table (the table may hold fewer than `2^index_bits` entries) reads
//!   **0 in all four lanes** (in both modes): a range compare gates the output register.
//! * Per frame the table is written from the builder, `load_width` entries per clock:
//!   [`Unit::frame_cycles`] `= ceil(entries / load_width)`, and [`PaletteLut::load_bits`]
//!   `= entries x 4 x entry width` bits are moved. The builder's own computation time
//!   ([`crate::units::PaletteBuilder::cycles_per_frame`]) is charged by the pipeline on top
//!   (it hands the table to this unit and charges the build as the LUT's frame work).
//! * Exact mode returns the unquantized f64 entry, bit-accurate mode the encoded words.
//!   A table given as f64 values ([`PaletteLut::new`], [`PaletteLut::set_values`]) is encoded
//!   with the entry encoding; a table built bit-accurately is loaded as words
//!   ([`PaletteLut::load`]).
//! * Gates: the SRAM (entries x 4 x width, [`CostTable::table`](crate::gates::CostTable::table)), the index register and the
//!   output register (4 x width), plus the range compare when the table is not full.

use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget, TableRole};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// A colour table in both forms: real values (authoritative in exact mode) and the entry
/// words (authoritative in bit-accurate mode). Both have the same length.
#[derive(Debug, Clone, PartialEq)]
pub struct PaletteTable {
    pub values: Vec<[f64; 4]>,
    pub codes: Vec<[i64; 4]>,
}

impl PaletteTable {
    /// From real values: the words are their encodings.
    pub fn from_values(enc: &Encoding, values: Vec<[f64; 4]>) -> Self {
        let codes = values.iter().map(|v| v.map(|x| enc.encode(x))).collect();
        PaletteTable { values, codes }
    }
    /// From words: the values are their decodings.
    pub fn from_codes(enc: &Encoding, codes: Vec<[i64; 4]>) -> Self {
        let values = codes.iter().map(|c| c.map(|r| enc.decode(r))).collect();
        PaletteTable { values, codes }
    }
    pub fn len(&self) -> usize {
        self.values.len()
    }
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// Widest index word: 65,536 entries, room for every distinct normal of a 256 x 256 map (the
/// unquantized baseline of the quantized engine; Tarini's largest table, 16K, needs 14).
pub const MAX_INDEX_BITS: u32 = 16;

pub struct PaletteLut {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    index_bits: u32,
    load_width: u32,
    table: PaletteTable,
}

impl PaletteLut {
    /// `index`: the index word (unsigned `Fixed`, no fraction bits, 8 to
    /// [`MAX_INDEX_BITS`] bits); `entry`:
    /// the encoding of each RGBA lane (e.g. `UnitUnsigned` 8); `table`: 1 to `2^index_bits`
    /// entries; `load_width`: entries written per clock when the table is loaded (1 to 64).
    /// Errors name the parameter and what was expected.
    pub fn new(
        index: Encoding,
        entry: Encoding,
        table: Vec<[f64; 4]>,
        load_width: u32,
    ) -> Result<Self, String> {
        index.validate()?;
        entry.validate()?;
        let bits = index.width();
        if index.format.signed || index.codec != Codec::Fixed || index.format.frac != 0 {
            return Err(format!(
                "index encoding {index}: expected an unsigned integer (Fixed, no fraction bits)"
            ));
        }
        if !(8..=MAX_INDEX_BITS).contains(&bits) {
            return Err(format!(
                "index width {bits}: expected 8 to {MAX_INDEX_BITS} bits"
            ));
        }
        if !(1..=64).contains(&load_width) {
            return Err(format!("load_width {load_width}: expected 1 to 64"));
        }
        let mut lut = PaletteLut {
            inputs: vec![PortSpec::new("i", 1, index)],
            outputs: vec![PortSpec::new("c", 4, entry)],
            index_bits: bits,
            load_width,
            table: PaletteTable {
                values: Vec::new(),
                codes: Vec::new(),
            },
        };
        lut.set_values(table)?;
        Ok(lut)
    }

    fn check_len(&self, n: usize) -> Result<(), String> {
        let max = 1usize << self.index_bits;
        if (1..=max).contains(&n) {
            Ok(())
        } else {
            Err(format!(
                "palette of {n} entries: expected 1 to {max} for a {}-bit index",
                self.index_bits
            ))
        }
    }

    /// Replace the table by real values (encoded with the entry encoding).
    pub fn set_values(&mut self, values: Vec<[f64; 4]>) -> Result<(), String> {
        self.check_len(values.len())?;
        self.table = PaletteTable::from_values(&self.entry(), values);
        Ok(())
    }

    /// Load a table from the builder (both forms; the words must fit the entry format).
    pub fn load(&mut self, table: PaletteTable) -> Result<(), String> {
        self.check_len(table.len())?;
        if table.codes.len() != table.values.len() {
            return Err("palette values and codes differ in length".into());
        }
        let f = self.entry().format;
        if let Some(c) = table.codes.iter().flatten().find(|&&c| !f.contains(c)) {
            return Err(format!(
                "palette word {c} does not fit the entry format {f}"
            ));
        }
        self.table = table;
        Ok(())
    }

    pub fn entry(&self) -> Encoding {
        self.outputs[0].enc
    }
    /// Entries written per clock when the table is loaded.
    pub fn load_width(&self) -> u32 {
        self.load_width
    }
    pub fn entries(&self) -> usize {
        self.table.len()
    }
    pub fn table(&self) -> &PaletteTable {
        &self.table
    }
    /// Bits written into the table per frame: entries x 4 lanes x entry width.
    pub fn load_bits(&self) -> u64 {
        self.entries() as u64 * 4 * self.entry().width() as u64
    }
}

impl Unit for PaletteLut {
    fn kind(&self) -> &'static str {
        "palette_lut"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        2
    }
    fn interval(&self) -> u32 {
        1
    }
    fn frame_cycles(&self) -> u64 {
        (self.entries() as u64).div_ceil(self.load_width as u64)
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let w = self.entry().width();
        let n = self.entries() as u64;
        let mut g = GateBudget::new();
        g.add_memory(
            format!("colour table {n}x{} (loadable)", 4 * w),
            1,
            // as a ROM (`cost.tables = Rom`), the colours it holds now
            t.for_table(TableRole::Colours)
                .table_of(&crate::gates::packed_words(&self.table.codes, w), 4 * w),
        );
        g.add(
            format!("index register {}", self.index_bits),
            1,
            t.register(self.index_bits),
        );
        if n < 1u64 << self.index_bits {
            g.add(
                format!("index range compare {}", self.index_bits),
                1,
                t.comparator(self.index_bits),
            );
            g.add(
                format!("output gating {}", 4 * w),
                1,
                t.and2 * (4 * w) as f64,
            );
        }
        g.add(format!("output register {}", 4 * w), 1, t.register(4 * w));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.entry();
        let s = ins[0].lanes[0];
        let n = self.entries();
        outs[0] = match mode {
            Mode::Exact => {
                let x = s.x.round();
                let v = if x >= 0.0 && x < n as f64 {
                    self.table.values[x as usize]
                } else {
                    [0.0; 4]
                };
                Word::from_exact(&out, &v)
            }
            Mode::BitAccurate => {
                let c = if s.raw >= 0 && (s.raw as u64) < n as u64 {
                    self.table.codes[s.raw as usize]
                } else {
                    [0; 4]
                };
                Word::from_raw(&out, &c)
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Format;

    fn idx(bits: u8) -> Encoding {
        Encoding::fixed(Format::u(bits, 0))
    }
    fn rgba8() -> Encoding {
        Encoding::texel(Codec::UnitUnsigned, false, 8)
    }
    /// Deterministic pseudo-random values in [0, 1).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn palette_lut_exact_and_bit_accurate_agree_for_every_8_bit_index() {
        let mut seed = 7;
        let table: Vec<[f64; 4]> = (0..256)
            .map(|_| std::array::from_fn(|_| lcg(&mut seed)))
            .collect();
        let u = PaletteLut::new(idx(8), rgba8(), table.clone(), 1).unwrap();
        let bound = rgba8().max_error() + 1e-12;
        for i in 0..256i64 {
            let inp = [Word::from_raw(&idx(8), &[i])];
            let (mut e, mut b) = ([Word::default()], [Word::default()]);
            u.eval(Mode::Exact, &inp, &mut e);
            u.eval(Mode::BitAccurate, &inp, &mut b);
            for (l, &want) in table[i as usize].iter().enumerate() {
                assert_eq!(e[0].lanes[l].x, want);
                assert_eq!(b[0].lanes[l].x, rgba8().decode(b[0].lanes[l].raw));
                assert!(
                    (e[0].lanes[l].x - b[0].lanes[l].x).abs() <= bound,
                    "{i} {l}"
                );
            }
        }
    }

    #[test]
    fn palette_lut_index_beyond_the_table_reads_zero() {
        let u = PaletteLut::new(idx(8), rgba8(), vec![[1.0; 4]; 10], 1).unwrap();
        for mode in [Mode::Exact, Mode::BitAccurate] {
            let mut o = [Word::default()];
            u.eval(mode, &[Word::for_mode(mode, &idx(8), &[9.0])], &mut o);
            assert_eq!(o[0].lanes[0].raw, 255);
            u.eval(mode, &[Word::for_mode(mode, &idx(8), &[10.0])], &mut o);
            assert_eq!(o[0].xs::<4>(), [0.0; 4]);
            assert_eq!(o[0].raws::<4>(), [0; 4]);
        }
    }

    #[test]
    fn palette_lut_frame_cycles_load_bits_and_gates_by_hand() {
        let u = PaletteLut::new(idx(8), rgba8(), vec![[0.5; 4]; 256], 1).unwrap();
        assert_eq!(u.frame_cycles(), 256);
        assert_eq!(u.load_bits(), 256 * 4 * 8);
        assert_eq!((u.latency(), u.interval()), (2, 1));
        let t = CostTable::default();
        // 8192 SRAM bits x 1.5 + 8-bit index register + 32-bit output register
        let ge = 8192.0 * 1.5 + 8.0 * 8.0 + 32.0 * 8.0;
        assert!((u.gates(&t).total() - ge).abs() < 1e-9);
        let u = PaletteLut::new(idx(11), rgba8(), vec![[0.5; 4]; 2000], 4).unwrap();
        assert_eq!(u.frame_cycles(), 500);
        assert_eq!(u.load_bits(), 2000 * 32);
        let u = PaletteLut::new(idx(14), rgba8(), vec![[0.5; 4]; 16384], 3).unwrap();
        assert_eq!(u.frame_cycles(), 5462); // ceil(16384 / 3)
        assert_eq!(u.load_bits(), 16384 * 32);
    }

    #[test]
    fn palette_lut_rejects_bad_sizes() {
        assert!(PaletteLut::new(idx(8), rgba8(), vec![], 1).is_err());
        assert!(PaletteLut::new(idx(8), rgba8(), vec![[0.0; 4]; 257], 1).is_err());
        assert!(PaletteLut::new(idx(7), rgba8(), vec![[0.0; 4]; 4], 1).is_err());
        assert!(PaletteLut::new(idx(17), rgba8(), vec![[0.0; 4]; 4], 1).is_err());
        // 16 bits: the widest, 65536 entries
        assert!(PaletteLut::new(idx(16), rgba8(), vec![[0.0; 4]; 65536], 1).is_ok());
        assert!(PaletteLut::new(idx(16), rgba8(), vec![[0.0; 4]; 65537], 1).is_err());
        assert!(PaletteLut::new(idx(8), rgba8(), vec![[0.0; 4]; 4], 0).is_err());
        let signed = Encoding::fixed(Format::s(8, 0));
        assert!(PaletteLut::new(signed, rgba8(), vec![[0.0; 4]; 4], 1).is_err());
        let mut u = PaletteLut::new(idx(8), rgba8(), vec![[0.0; 4]; 4], 1).unwrap();
        let bad = PaletteTable {
            values: vec![[0.0; 4]],
            codes: vec![[256, 0, 0, 0]],
        };
        assert!(u.load(bad).is_err());
    }
}

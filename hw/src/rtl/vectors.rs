//! Test vectors for co-simulation, from the model: deterministic input words (a seeded
//! splitmix64) of four kinds in turn, and the model's bit-accurate outputs for them.
//!
//! * uniform raw words over each lane's format (overflows, clamps, every code);
//! * plausible values: unit vectors on 3-lane signed ports, `[0, 1]` elsewhere;
//! * corner words per lane (min, max, 0, +-1 code, the codes of 0.5, 1 and -1);
//! * aligned vectors: every 3-lane signed port near one random unit vector (dot products near
//!   1, where the clamps and the steep end of a power table are);
//! * near-flat vectors: every 3-lane signed port within two codes of `[0, 0, 1]` (the
//!   unperturbed-normal test of selective blending), other ports uniform.

use crate::unit::{Mode, PortSpec, Unit, Word};

/// splitmix64: a small deterministic generator.
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform integer in `[lo, hi]`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        let span = (hi - lo) as u64 + 1;
        lo + (self.next_u64() % span) as i64
    }
    fn unit_vec(&mut self) -> [f64; 3] {
        loop {
            let v = [0, 1, 2].map(|_| 2.0 * self.unit() - 1.0);
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

fn corner(p: &PortSpec, r: &mut SplitMix) -> i64 {
    let f = p.enc.format;
    let c = [
        f.min_raw(),
        f.max_raw(),
        0,
        1,
        -1,
        f.min_raw() + 1,
        f.max_raw() - 1,
        p.enc.encode(0.5),
        p.enc.encode(1.0),
        p.enc.encode(-1.0),
    ];
    f.overflow(
        c[r.range(0, c.len() as i64 - 1) as usize] as i128,
        crate::Overflow::Sat,
    )
}

/// Input words of vector `i` (its kind is `i % 5`).
fn inputs(ports: &[PortSpec], i: usize, r: &mut SplitMix) -> Vec<Word> {
    let axis = r.unit_vec();
    ports
        .iter()
        .map(|p| {
            let n = p.lanes as usize;
            let f = p.enc.format;
            let vec3 = n == 3 && f.signed;
            match i % 5 {
                4 if vec3 => {
                    let raws: Vec<i64> = [0.0, 0.0, 1.0]
                        .iter()
                        .map(|&x| {
                            f.overflow(
                                (p.enc.encode(x) + r.range(-2, 2)) as i128,
                                crate::Overflow::Sat,
                            )
                        })
                        .collect();
                    Word::from_raw(&p.enc, &raws)
                }
                0 | 4 => {
                    let raws: Vec<i64> =
                        (0..n).map(|_| r.range(f.min_raw(), f.max_raw())).collect();
                    Word::from_raw(&p.enc, &raws)
                }
                1 if vec3 => {
                    let s = 0.9 + 0.1 * r.unit();
                    Word::quantize(&p.enc, &r.unit_vec().map(|x| x * s))
                }
                1 => {
                    let xs: Vec<f64> = (0..n).map(|_| r.unit()).collect();
                    Word::quantize(&p.enc, &xs)
                }
                2 => {
                    let raws: Vec<i64> = (0..n).map(|_| corner(p, r)).collect();
                    Word::from_raw(&p.enc, &raws)
                }
                3 if vec3 => {
                    let e = 0.05 * r.unit();
                    let v = axis.map(|x| x + e * (2.0 * r.unit() - 1.0));
                    Word::quantize(&p.enc, &v)
                }
                _ => {
                    let xs: Vec<f64> = (0..n).map(|_| 0.5 + 0.5 * r.unit()).collect();
                    Word::quantize(&p.enc, &xs)
                }
            }
        })
        .collect()
}

/// `n` input vectors for `unit` from `seed`, with the model's bit-accurate outputs (the
/// ROP's datapath gets its depths paired, `rop_vectors`).
pub fn vectors(unit: &dyn Unit, n: usize, seed: u64) -> (Vec<Vec<Word>>, Vec<Vec<Word>>) {
    if unit.as_any().is::<crate::units::RopDatapath>() {
        return rop_vectors(unit, n, seed);
    }
    let mut r = SplitMix(seed);
    let ins: Vec<Vec<Word>> = (0..n).map(|i| inputs(unit.inputs(), i, &mut r)).collect();
    with_outputs(unit, ins)
}

/// The vectors of the ROP's datapath ([`crate::units::RopDatapath`]: ports `c`, `z`, `dc`,
/// `dz`), whose depth tests need equal and adjacent depths: in every other vector the
/// stored depth is the fragment's own, one code above or one below it (clamped), so that
/// `Equal`, `LEqual` and `GEqual` see both outcomes with every colour kind.
fn rop_vectors(unit: &dyn Unit, n: usize, seed: u64) -> (Vec<Vec<Word>>, Vec<Vec<Word>>) {
    let mut r = SplitMix(seed);
    let ins: Vec<Vec<Word>> = (0..n)
        .map(|i| {
            let mut w = inputs(unit.inputs(), i, &mut r);
            let enc = unit.inputs()[3].enc;
            let z = w[1].lanes[0].raw;
            let dz = match r.range(0, 5) {
                0 | 1 => z,
                2 => z + 1,
                3 => z - 1,
                _ => w[3].lanes[0].raw,
            };
            let dz = dz.clamp(enc.format.min_raw(), enc.format.max_raw());
            w[3] = Word::from_raw(&enc, &[dz]);
            w
        })
        .collect();
    with_outputs(unit, ins)
}

/// The model's bit-accurate outputs for `ins`.
fn with_outputs(unit: &dyn Unit, ins: Vec<Vec<Word>>) -> (Vec<Vec<Word>>, Vec<Vec<Word>>) {
    let outs = ins
        .iter()
        .map(|w| {
            let mut o = vec![Word::default(); unit.outputs().len()];
            unit.eval(Mode::BitAccurate, w, &mut o);
            o
        })
        .collect();
    (ins, outs)
}

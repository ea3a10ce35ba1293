//! Triangle packets: the exact bits sent from geometry to the rasterizer's setup engine per
//! triangle. A layout lists per-vertex fields (sent three times) and per-triangle fields.
//! Values are raw two's complement words; each field lane keeps the low `bits` bits.
//! Bit order: LSB first, vertex 0's fields in layout order (lanes consecutive), then
//! vertex 1, vertex 2, then the per-triangle fields.

use bitvec::order::Lsb0;
use bitvec::slice::BitSlice;
use bitvec::vec::BitVec;
use bitvec::view::BitView;
use serde::Serialize;

/// One field: `lanes` values of `bits` bits each (1..=64).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Field {
    pub name: String,
    pub lanes: u32,
    pub bits: u32,
}

impl Field {
    pub fn new(name: &str, lanes: u32, bits: u32) -> Field {
        Field {
            name: name.to_string(),
            lanes,
            bits,
        }
    }
    fn total_bits(&self) -> u64 {
        u64::from(self.lanes) * u64::from(self.bits)
    }
}

/// The layout of one triangle packet.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct PacketLayout {
    pub per_vertex: Vec<Field>,
    pub per_triangle: Vec<Field>,
}

fn values_in(fields: &[Field]) -> usize {
    fields.iter().map(|f| f.lanes as usize).sum()
}

/// The bit width of each value, in order.
fn widths(fields: &[Field]) -> impl Iterator<Item = u32> + '_ {
    fields
        .iter()
        .flat_map(|f| std::iter::repeat_n(f.bits, f.lanes as usize))
}

impl PacketLayout {
    /// 3 * Σ per-vertex lanes * bits + Σ per-triangle lanes * bits.
    pub fn bits_per_triangle(&self) -> u64 {
        3 * self.per_vertex.iter().map(Field::total_bits).sum::<u64>()
            + self.per_triangle.iter().map(Field::total_bits).sum::<u64>()
    }

    /// Pack raw values (two's complement, the low `bits` bits of each) in layout order:
    /// vertex 0 fields, vertex 1, vertex 2, then per-triangle fields. Errors when a value
    /// count does not match the layout or a field is wider than 64 bits.
    pub fn pack(
        &self,
        vertex_values: [&[u64]; 3],
        triangle_values: &[u64],
    ) -> Result<BitVec<u64, Lsb0>, String> {
        if let Some(f) = self
            .per_vertex
            .iter()
            .chain(self.per_triangle.iter())
            .find(|f| f.bits > 64)
        {
            return Err(format!(
                "field {}: expected 0 to 64 bits, found {}",
                f.name, f.bits
            ));
        }
        let nv = values_in(&self.per_vertex);
        for (i, vals) in vertex_values.iter().enumerate() {
            if vals.len() != nv {
                return Err(format!(
                    "vertex {i}: expected {nv} values, found {}",
                    vals.len()
                ));
            }
        }
        let nt = values_in(&self.per_triangle);
        if triangle_values.len() != nt {
            return Err(format!(
                "triangle: expected {nt} values, found {}",
                triangle_values.len()
            ));
        }
        let mut out: BitVec<u64, Lsb0> = BitVec::with_capacity(self.bits_per_triangle() as usize);
        let mut put = |fields: &[Field], vals: &[u64]| {
            for (v, bits) in vals.iter().zip(widths(fields)) {
                out.extend_from_bitslice(&v.view_bits::<Lsb0>()[..bits as usize]);
            }
        };
        for vals in vertex_values {
            put(&self.per_vertex, vals);
        }
        put(&self.per_triangle, triangle_values);
        Ok(out)
    }

    /// Inverse of [`pack`](Self::pack): the low `bits` bits of each value (zero-extended).
    /// Bits missing at the end of a short slice read as 0; extra bits are ignored.
    pub fn unpack(&self, bits: &BitSlice<u64, Lsb0>) -> ([Vec<u64>; 3], Vec<u64>) {
        let mut pos = 0usize;
        let mut take = |fields: &[Field]| -> Vec<u64> {
            widths(fields)
                .map(|w| {
                    let w = w.min(64) as usize;
                    let mut v = 0u64;
                    for k in 0..w {
                        if bits.get(pos + k).map(|b| *b).unwrap_or(false) {
                            v |= 1 << k;
                        }
                    }
                    pos += w;
                    v
                })
                .collect()
        };
        let v0 = take(&self.per_vertex);
        let v1 = take(&self.per_vertex);
        let v2 = take(&self.per_vertex);
        let t = take(&self.per_triangle);
        ([v0, v1, v2], t)
    }

    /// The documented baseline: a plain textured Gouraud triangle, 3 vertices x (x, y, z,
    /// 1/w, r, g, b, a, s, t, fog) as 32-bit IEEE single words = 3 x 352 = 1056 bits, no
    /// per-triangle fields (see docs/rasterizer.md).
    pub fn baseline_textured_gouraud() -> PacketLayout {
        let names = ["x", "y", "z", "1/w", "r", "g", "b", "a", "s", "t", "fog"];
        PacketLayout {
            per_vertex: names.iter().map(|n| Field::new(n, 1, 32)).collect(),
            per_triangle: Vec::new(),
        }
    }
}

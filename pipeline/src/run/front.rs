//! The front end of the engine as the simulator drives it: the rasterizer's fragments grouped
//! by triangle, and the attribute interpolator that fills each fragment's token in a mode.

use crate::config::{AttrSource, AttributeConfig};
use crate::engine::attributes;
use crate::raster::Fragment;
use bumpsim_hw::{Codec, Columns, Mode, Sample, Token, Word, BATCH, MAX_LANES};

/// [`triangle_ranges`] of the rasterizer's output, from its per-triangle fragment counts
/// (the fragments are in submission order): prefix sums over the triangles, without a pass
/// over the fragments (a scan of every fragment's 40 bytes was 2 % of a simulated frame, on
/// one thread whatever the threads). When the counts do not describe the fragments (their sum
/// differs, or a range's first or last fragment belongs to another triangle: fragments
/// edited after rasterization), by the scan.
pub(super) fn raster_ranges(
    r: &crate::raster::RasterOutput,
    ntri: usize,
) -> Vec<std::ops::Range<usize>> {
    let frags = &r.fragments;
    let mut ranges = Vec::with_capacity(ntri);
    let mut start = 0usize;
    for (t, s) in r.triangles.iter().enumerate().take(ntri) {
        let end = start.saturating_add(s.fragments as usize);
        let of_t = |k: usize| frags.get(k).is_some_and(|f| f.tri as usize == t);
        if end > start && !(of_t(start) && of_t(end - 1)) {
            return triangle_ranges(frags, ntri);
        }
        ranges.push(start..end);
        start = end;
    }
    if start != frags.len() || ranges.len() != ntri {
        return triangle_ranges(frags, ntri);
    }
    ranges
}

/// Fragments grouped by triangle: ranges into the fragment list, one per submitted triangle.
pub(super) fn triangle_ranges(frags: &[Fragment], ntri: usize) -> Vec<std::ops::Range<usize>> {
    let mut ranges = vec![0..0; ntri];
    let mut start = 0;
    while start < frags.len() {
        let t = frags[start].tri as usize;
        let mut end = start;
        while end < frags.len() && frags[end].tri as usize == t {
            end += 1;
        }
        ranges[t] = start..end;
        start = end;
    }
    // triangles without fragments keep an empty range at their own position
    let mut fixed = Vec::with_capacity(ntri);
    let mut cursor = 0;
    for r in ranges {
        if r.is_empty() {
            fixed.push(cursor..cursor);
        } else {
            cursor = r.end;
            fixed.push(r);
        }
    }
    fixed
}

/// The fixed-point interpolator's vertex words, weight bits and one fragment's weights.
type Weights<'a> = (&'a [Vec<[i64; 4]>], u32, [i64; 3]);

pub(super) struct Front<'a> {
    pub(super) frags: &'a [Fragment],
    pub(super) tris: &'a [[u32; 3]],
    pub(super) vd: &'a attributes::VertexData,
    /// The vertex values the interpolator reads: on each attribute's grid in bit-accurate
    /// mode ([`attributes::VertexData::snapped`]), as computed in exact mode.
    pub(super) values: &'a [Vec<[f64; 4]>],
    /// The fixed-point interpolator's vertex words and weight bits, when the bit-accurate
    /// engine has one.
    pub(super) fixed: Option<(&'a [Vec<[i64; 4]>], u32)>,
    /// Whether exact-mode attribute words carry their raw words (`encode(x)`), which only
    /// traces read; the units read `x` in exact mode.
    pub(super) exact_raw: bool,
}

impl Front<'_> {
    /// Fill a token with fragment `f`'s interpolated attributes.
    pub(super) fn fill(&self, attrs: &[AttributeConfig], mode: Mode, f: usize, t: &mut Token) {
        if mode == Mode::Exact && !self.exact_raw {
            return self.fill_values(attrs, f, t);
        }
        let frag = &self.frags[f];
        let fixed = self.weights(mode, frag);
        for (a, attr) in attrs.iter().enumerate() {
            self.fill_attribute(a, attr, mode, frag, fixed, &mut t.slots[a]);
        }
        (t.id, t.x, t.y) = (f as u64, frag.x, frag.y);
    }

    /// [`Front::fill`] of fragments `first..first + ts.len()` into `ts`, the same tokens. In
    /// bit-accurate mode each batch of up to [`BATCH`] fragments is interpolated as columns
    /// ([`Front::fill_columns`]) and its words decoded into the tokens.
    pub(super) fn fill_batch(
        &self,
        attrs: &[AttributeConfig],
        mode: Mode,
        first: usize,
        ts: &mut [Token],
    ) {
        if mode == Mode::Exact {
            for (k, t) in ts.iter_mut().enumerate() {
                self.fill(attrs, mode, first + k, t);
            }
            return;
        }
        let mut cols = Columns::new(attrs.len());
        for (c, ts) in ts.chunks_mut(BATCH).enumerate() {
            let first = first + c * BATCH;
            self.fill_columns(attrs, first, ts.len(), &mut cols);
            for (k, t) in ts.iter_mut().enumerate() {
                for (a, attr) in attrs.iter().enumerate() {
                    let lanes = attr.source.lanes() as usize;
                    t.slots[a] = cols.word(a, k, &attr.enc, lanes);
                }
                let frag = &self.frags[first + k];
                (t.id, t.x, t.y) = ((first + k) as u64, frag.x, frag.y);
            }
        }
    }

    /// The bit-accurate attribute words of fragments `first..first + n` (at most [`BATCH`])
    /// into the first slots of `cols`, which starts a batch of `n` fragments: the per-vertex
    /// attributes a lane of the batch at a time: with the exact interpolator the lanes of
    /// fixed-point attributes rounded by [`bumpsim_hw::Format::from_f64_slice`]
    /// ([`Front::lanes_rounded`]), with the fixed-point one each fragment's weights once
    /// ([`Front::lanes_weighted`]); the other attributes fragment by fragment.
    pub(super) fn fill_columns(
        &self,
        attrs: &[AttributeConfig],
        first: usize,
        n: usize,
        cols: &mut Columns,
    ) {
        cols.start(n);
        let n = cols.len();
        let frags = &self.frags[first..first + n];
        // each fragment's vertices, once for all attributes
        let mut verts = [[0u32; 3]; BATCH];
        for (v, frag) in verts.iter_mut().zip(frags) {
            *v = self.tris[frag.tri as usize];
        }
        let verts = &verts[..n];
        match self.fixed {
            Some((codes, bits)) => self.lanes_weighted(attrs, frags, verts, cols, codes, bits),
            None => self.lanes_rounded(attrs, frags, verts, cols),
        }
    }

    /// Whether attribute `a` is interpolated over a batch: per vertex, and not a quaternion
    /// (whose signs triangle setup chooses per triangle, [`Front::flips`]).
    fn batched(&self, a: usize, attr: &AttributeConfig) -> bool {
        !self.vd.flat[a] && !matches!(attr.source, AttrSource::Quaternion)
    }

    /// The attributes other than [`Front::batched`] ones, fragment by fragment.
    fn attribute_each(
        &self,
        a: usize,
        attr: &AttributeConfig,
        frags: &[Fragment],
        cols: &mut Columns,
    ) {
        let mode = Mode::BitAccurate;
        let mut w = Word::default();
        for (k, frag) in frags.iter().enumerate() {
            let fixed = self.weights(mode, frag);
            self.fill_attribute(a, attr, mode, frag, fixed, &mut w);
            cols.set_word(a, k, &w);
        }
    }

    /// A batch with the exact interpolator: the sums and roundings of
    /// [`Front::fill_attribute`]'s fixed-point case, a lane of the batch at a time.
    fn lanes_rounded(
        &self,
        attrs: &[AttributeConfig],
        frags: &[Fragment],
        verts: &[[u32; 3]],
        cols: &mut Columns,
    ) {
        let n = frags.len();
        let mut xs = [[0f64; BATCH]; MAX_LANES];
        for (a, attr) in attrs.iter().enumerate() {
            if !self.batched(a, attr) || attr.enc.codec != Codec::Fixed {
                self.attribute_each(a, attr, frags, cols);
                continue;
            }
            let (e, values) = (&attr.enc, &self.values[a]);
            let lanes = (attr.source.lanes() as usize).min(MAX_LANES);
            for (k, (frag, v)) in frags.iter().zip(verts).enumerate() {
                let (b, v) = (frag.bary, v.map(|i| &values[i as usize]));
                for (l, x) in xs.iter_mut().enumerate().take(lanes) {
                    x[k] = b[0] * v[0][l] + b[1] * v[1][l] + b[2] * v[2][l];
                }
            }
            for (l, (x, col)) in xs.iter().zip(cols.slots[a].iter_mut()).enumerate() {
                if l >= lanes {
                    col[..n].fill(0);
                    continue;
                }
                e.format
                    .from_f64_slice(&x[..n], e.quant, e.overflow, &mut col[..n]);
            }
        }
    }

    /// A batch with the fixed-point interpolator: each fragment's weights once, then
    /// [`attributes::interpolate_weighted`]'s lanes.
    fn lanes_weighted(
        &self,
        attrs: &[AttributeConfig],
        frags: &[Fragment],
        verts: &[[u32; 3]],
        cols: &mut Columns,
        codes: &[Vec<[i64; 4]>],
        bits: u32,
    ) {
        let mut weights = [[0i64; 3]; BATCH];
        for (w, frag) in weights.iter_mut().zip(frags) {
            *w = attributes::fixed_weights(frag.bary, bits);
        }
        for (a, attr) in attrs.iter().enumerate() {
            if !self.batched(a, attr) {
                self.attribute_each(a, attr, frags, cols);
                continue;
            }
            let cast = attributes::WeightedCast::new(&attr.enc, bits);
            let codes = &codes[a];
            let lanes = attr.source.lanes() as usize;
            for (l, col) in cols.slots[a].iter_mut().enumerate() {
                for (k, (w, v)) in weights.iter().zip(verts).enumerate() {
                    col[k] = if l < lanes {
                        cast.lane(v.map(|i| codes[i as usize][l]), *w)
                    } else {
                        0
                    };
                }
            }
        }
    }

    /// The fixed-point interpolator's vertex words, weight bits and the fragment's weights
    /// (once for all its attributes), when the bit-accurate engine has one.
    fn weights(&self, mode: Mode, frag: &Fragment) -> Option<Weights<'_>> {
        self.fixed
            .filter(|_| mode == Mode::BitAccurate)
            .map(|(codes, bits)| (codes, bits, attributes::fixed_weights(frag.bary, bits)))
    }

    /// Attribute `a`'s word of fragment `frag` into `w`.
    fn fill_attribute(
        &self,
        a: usize,
        attr: &AttributeConfig,
        mode: Mode,
        frag: &Fragment,
        fixed: Option<Weights<'_>>,
        w: &mut Word,
    ) {
        let tri = self.tris[frag.tri as usize];
        let lanes = attr.source.lanes() as usize;
        *w = if self.vd.flat[a] {
            attributes::flat(
                mode,
                &attr.enc,
                lanes,
                &self.vd.values[a][frag.tri as usize],
            )
        } else if let Some((codes, bits, weights)) = fixed {
            let mut c = tri.map(|i| codes[a][i as usize]);
            if let Some(flips) = self.flips(attr, a, tri) {
                for (v, flip) in c.iter_mut().zip(flips) {
                    if flip {
                        *v = v.map(|x| -x);
                    }
                }
            }
            attributes::interpolate_weighted(&attr.enc, lanes, [&c[0], &c[1], &c[2]], weights, bits)
        } else if mode == Mode::BitAccurate && attr.enc.codec == Codec::Fixed {
            // [`attributes::interpolate_snapped`] and [`Word::quantize`] of a fixed-point
            // word, the same sums and roundings, written in place (the common case: the
            // word built and copied through three calls was the profile's top entry)
            let values = &self.values[a];
            let mut v = tri.map(|i| &values[i as usize]);
            let flipped;
            if let Some(flips) = self.flips(attr, a, tri) {
                flipped =
                    std::array::from_fn::<_, 3, _>(|k| v[k].map(|x| if flips[k] { -x } else { x }));
                v = [&flipped[0], &flipped[1], &flipped[2]];
            }
            let (e, b) = (&attr.enc, frag.bary);
            let lsb = e.format.lsb();
            for (l, s) in w.lanes.iter_mut().enumerate() {
                *s = if l < lanes {
                    let x = b[0] * v[0][l] + b[1] * v[1][l] + b[2] * v[2][l];
                    Sample::fixed(e, lsb, x)
                } else {
                    Sample::default()
                };
            }
            return;
        } else {
            let mut v = tri.map(|i| self.values[a][i as usize]);
            if let Some(flips) = self.flips(attr, a, tri) {
                for (v, flip) in v.iter_mut().zip(flips) {
                    if flip {
                        *v = v.map(|x| -x);
                    }
                }
            }
            attributes::interpolate_snapped(
                mode,
                &attr.enc,
                lanes,
                [&v[0], &v[1], &v[2]],
                frag.bary,
            )
        };
    }

    /// [`Front::fill`] in exact mode without raw words: the values of
    /// [`attributes::flat`] and [`attributes::interpolate_snapped`] (the same sums in the same
    /// order), raw words left 0.
    fn fill_values(&self, attrs: &[AttributeConfig], f: usize, t: &mut Token) {
        let frag = &self.frags[f];
        let tri = self.tris[frag.tri as usize];
        let b = frag.bary;
        for (a, attr) in attrs.iter().enumerate() {
            let lanes = attr.source.lanes() as usize;
            let mut w = Word::default();
            if self.vd.flat[a] {
                let v = &self.vd.values[a][frag.tri as usize];
                for (l, s) in w.lanes.iter_mut().enumerate().take(lanes) {
                    s.x = v[l];
                }
            } else {
                let mut v = tri.map(|i| self.values[a][i as usize]);
                if let Some(flips) = self.flips(attr, a, tri) {
                    for (v, flip) in v.iter_mut().zip(flips) {
                        if flip {
                            *v = v.map(|x| -x);
                        }
                    }
                }
                for (l, s) in w.lanes.iter_mut().enumerate().take(lanes) {
                    s.x = b[0] * v[0][l] + b[1] * v[1][l] + b[2] * v[2][l];
                }
            }
            t.slots[a] = w;
        }
        (t.id, t.x, t.y) = (f as u64, frag.x, frag.y);
    }

    /// Triangle setup's sign choice for quaternion attributes
    /// ([`crate::engine::frames::hemisphere_flips`], decided on the geometry engine's values).
    fn flips(&self, attr: &AttributeConfig, a: usize, tri: [u32; 3]) -> Option<[bool; 3]> {
        matches!(attr.source, AttrSource::Quaternion).then(|| {
            let q = tri.map(|i| &self.vd.values[a][i as usize]);
            crate::engine::frames::hemisphere_flips(q)
        })
    }
}

/// The fixed-point interpolator's vertex words and weight bits, if `i` is one.
pub(super) fn fixed(
    codes: &[Vec<[i64; 4]>],
    i: crate::config::Interpolator,
) -> Option<(&[Vec<[i64; 4]>], u32)> {
    match i {
        crate::config::Interpolator::Exact => None,
        crate::config::Interpolator::Fixed { weight_bits } => Some((codes, weight_bits)),
    }
}

/// The front end in a mode as the simulator's [`crate::sim::Fill`]: one fragment, or a batch.
pub(super) struct FrontFill<'a> {
    pub(super) front: &'a Front<'a>,
    pub(super) attrs: &'a [AttributeConfig],
    pub(super) mode: Mode,
}

impl crate::sim::Fill for FrontFill<'_> {
    fn fill(&self, f: usize, t: &mut Token) {
        self.front.fill(self.attrs, self.mode, f, t)
    }
    fn fill_batch(&self, first: usize, ts: &mut [Token]) {
        self.front.fill_batch(self.attrs, self.mode, first, ts)
    }
    fn fill_columns(&self, first: usize, n: usize, cols: &mut Columns) {
        match self.mode {
            Mode::BitAccurate => self.front.fill_columns(self.attrs, first, n, cols),
            Mode::Exact => crate::sim::fill_columns_each(self, first, n, cols),
        }
    }
}

//! Texture memory: the texels an engine stores, shared by every unit that reads them.
//!
//! A [`Texture`] is one named object of the engine's texture memory: a 2D image (a 1D texture
//! is a 2D texture of height 1) or a cube map of six square faces, a mip chain of levels, and
//! one texel [`Encoding`] for its 1 to 4 lanes (every texel format of the project: unsigned
//! and signed 8-bit colour and normal texels, 16-bit two-lane HILO and SIGNED_HILO texels of
//! NV_texture_shader, index texels of a palette). Each texel is held twice: as the real
//! values it was made from (read by the exact mode) and as its raw words in the encoding (read
//! by the bit-accurate mode). Units hold a texture behind an [`std::sync::Arc`], so several
//! units (texture-shader stages, a fetch and a filter) read one memory, and the engine counts
//! its bits once and its traffic per reader.
//!
//! Texel addressing and filtering are the business of [`crate::sampler::Sampler`]; this
//! module only stores.

use crate::format::Encoding;
use crate::sampler::Address;
use crate::unit::MAX_LANES;

/// Largest side of a texture level, in texels.
pub const MAX_SIDE: u32 = 1 << 14;

/// Texture contents as built by the host: `width * height` texels of `lanes` real values
/// each, row-major, row 0 at v in [0, 1/height).
#[derive(Debug, Clone)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    pub lanes: u8,
    pub values: Vec<[f64; MAX_LANES]>,
}

/// One mip level: `faces` images of `width x height` texels, face-major.
#[derive(Debug, Clone)]
pub struct Level {
    width: u32,
    height: u32,
    log_w: u32,
    log_h: u32,
    values: Vec<[f64; MAX_LANES]>,
    codes: Vec<[i64; MAX_LANES]>,
}

impl Level {
    pub fn width(&self) -> u32 {
        self.width
    }
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Texels of the level, every face.
    pub fn len(&self) -> usize {
        self.values.len()
    }
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
    /// log2 of the width and of the height.
    pub fn logs(&self) -> (u32, u32) {
        (self.log_w, self.log_h)
    }
    /// Memory index of texel (i, j) of `face` after addressing each axis.
    #[inline]
    pub fn index(&self, face: usize, i: i64, j: i64, address: [Address; 2]) -> usize {
        let (w, h) = (self.width as i64, self.height as i64);
        let texel = address[1].apply(j, h) * w + address[0].apply(i, w);
        face * (self.width * self.height) as usize + texel as usize
    }
    /// The real values of the texel at a memory index (exact mode).
    #[inline]
    pub fn value(&self, k: usize) -> &[f64; MAX_LANES] {
        &self.values[k]
    }
    /// The raw words of the texel at a memory index (bit-accurate mode). While a thread
    /// [`reads::record`]s, the read is appended to its stream.
    #[inline]
    pub fn code(&self, k: usize) -> &[i64; MAX_LANES] {
        if reads::ACTIVE.load(std::sync::atomic::Ordering::Relaxed) != 0 {
            reads::push(self, k);
        }
        &self.codes[k]
    }
}

/// The stream of texel reads a thread makes (bit-accurate mode: every read of a texel's raw
/// words goes through [`Level::code`]): the addresses a texture cache sees, in the order the
/// units read them. Off unless a thread records; then each read costs a thread-local push on
/// that thread, and a thread-local check on the others.
pub mod reads {
    use super::Level;
    use std::cell::RefCell;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Threads recording now.
    pub(super) static ACTIVE: AtomicUsize = AtomicUsize::new(0);

    thread_local! {
        static STREAM: RefCell<Option<Vec<Read>>> = const { RefCell::new(None) };
    }

    /// One texel read: the level (its address, which [`Read::is_of`] compares) and the
    /// memory index in it (face-major: `face * width * height + j * width + i`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub struct Read {
        level: usize,
        pub index: u32,
    }

    impl Read {
        /// Whether the read is of level `l`.
        pub fn is_of(&self, l: &Level) -> bool {
            self.level == l as *const Level as usize
        }
        /// A key of the level read, equal for reads of one level (its address).
        pub fn level_key(&self) -> usize {
            self.level
        }
    }

    /// The key [`Read::level_key`] gives reads of `l`.
    pub fn level_key(l: &Level) -> usize {
        l as *const Level as usize
    }

    #[cold]
    pub(super) fn push(l: &Level, k: usize) {
        STREAM.with(|s| {
            if let Some(v) = s.borrow_mut().as_mut() {
                v.push(Read {
                    level: level_key(l),
                    index: k as u32,
                });
            }
        });
    }

    /// Run `f` on this thread with its texel reads recorded: `f` gets a drain that appends
    /// the reads since the last drain, in order, to the vector it is given. Threads record
    /// apart (a thread-local stream each), so chunks of fragments may be recorded in parallel.
    pub fn record<T>(f: impl FnOnce(&mut dyn FnMut(&mut Vec<Read>)) -> T) -> T {
        STREAM.with(|s| *s.borrow_mut() = Some(Vec::new()));
        ACTIVE.fetch_add(1, Ordering::Relaxed);
        // stop recording however `f` ends
        struct Stop;
        impl Drop for Stop {
            fn drop(&mut self) {
                ACTIVE.fetch_sub(1, Ordering::Relaxed);
                STREAM.with(|s| *s.borrow_mut() = None);
            }
        }
        let _stop = Stop;
        let mut drain = |out: &mut Vec<Read>| {
            STREAM.with(|s| {
                if let Some(v) = s.borrow_mut().as_mut() {
                    out.append(v); // keeps the stream's capacity
                }
            })
        };
        f(&mut drain)
    }
}

/// Whether a texture is an image or a cube map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A 2D image (1D: height 1), addressed by (s, t).
    Flat,
    /// Six square faces in OpenGL order +X, -X, +Y, -Y, +Z, -Z, addressed by a direction
    /// ([`crate::sampler::cube_face`]).
    Cube,
}

/// One texture of the engine's texture memory. See the module documentation.
#[derive(Debug, Clone)]
pub struct Texture {
    name: String,
    shape: Shape,
    lanes: u8,
    texel: Encoding,
    levels: Vec<Level>,
    palette: Option<u32>,
    /// The palette's entries as stored words (lane `l`'s code in bits `l w .. (l + 1) w` of
    /// `w`-bit lanes), when known ([`Texture::with_palette_table`]).
    palette_words: Option<Vec<i64>>,
}

fn check_side(what: &str, v: u32) -> Result<u32, String> {
    if !v.is_power_of_two() || v > MAX_SIDE {
        return Err(format!(
            "{what} {v}: expected a power of two from 1 to {MAX_SIDE}"
        ));
    }
    Ok(v.trailing_zeros())
}

impl Texture {
    /// A 2D texture of one level. Errors name the parameter and what was expected.
    pub fn new(name: &str, texel: Encoding, tex: Texels) -> Result<Self, String> {
        texel.validate()?;
        let lanes = tex.lanes;
        if !(1..=MAX_LANES as u8).contains(&lanes) {
            return Err(format!("texture {name}: {lanes} lanes: expected 1 to 4"));
        }
        let level = Self::level(name, &texel, vec![tex], lanes)?;
        Ok(Texture {
            name: name.to_string(),
            shape: Shape::Flat,
            lanes,
            texel,
            levels: vec![level],
            palette: None,
            palette_words: None,
        })
    }

    /// A cube map of six square faces of one size, in the order +X, -X, +Y, -Y, +Z, -Z.
    pub fn cube(name: &str, texel: Encoding, faces: Vec<Texels>) -> Result<Self, String> {
        if faces.len() != 6 {
            return Err(format!(
                "cube map {name}: {} faces: expected 6",
                faces.len()
            ));
        }
        let (w, lanes) = (faces[0].width, faces[0].lanes);
        if let Some(f) = faces
            .iter()
            .find(|f| f.width != w || f.height != w || f.lanes != lanes)
        {
            return Err(format!(
                "cube map {name}: a face of {}x{} texels and {} lanes: expected square faces of {w}x{w} and {lanes} lanes like the first",
                f.width, f.height, f.lanes
            ));
        }
        let mut t = Texture::new(name, texel, faces[0].clone())?;
        t.shape = Shape::Cube;
        t.levels = vec![Self::level(name, &texel, faces, lanes)?];
        Ok(t)
    }

    /// Add mip levels 1.. (coarsest last, built by the host), each no larger than the one
    /// before it on either axis.
    pub fn with_mips(mut self, levels: Vec<Texels>) -> Result<Self, String> {
        if self.shape == Shape::Cube {
            return Err(format!(
                "texture {}: mip levels of cube maps are not modelled",
                self.name
            ));
        }
        for (k, t) in levels.into_iter().enumerate() {
            let prev = self.levels.last().expect("a texture has a level");
            if t.width > prev.width || t.height > prev.height || t.lanes != self.lanes {
                return Err(format!(
                    "texture {} mip level {}: {}x{} texels of {} lanes: expected at most {}x{} and {} lanes",
                    self.name,
                    k + 1,
                    t.width,
                    t.height,
                    t.lanes,
                    prev.width,
                    prev.height,
                    self.lanes
                ));
            }
            let level = Self::level(&self.name, &self.texel, vec![t], self.lanes)?;
            self.levels.push(level);
        }
        Ok(self)
    }

    /// The texels as the application hands them over in `external` (OpenGL's `type` of
    /// `glTexImage2D`: GL_BYTE into a SIGNED_HILO16 texture is Wang et al.'s Fig. 2a): each
    /// value is rounded to an `external` code, and the internal code is the `texel` encoding
    /// of that code's value (the driver's conversion). Only the codes change, which
    /// bit-accurate mode reads; exact mode reads the values as given.
    pub fn with_upload(mut self, external: &Encoding) -> Result<Self, String> {
        external
            .validate()
            .map_err(|m| format!("texture {} upload type: {m}", self.name))?;
        let (texel, lanes) = (self.texel, self.lanes as usize);
        for level in &mut self.levels {
            for (v, c) in level.values.iter().zip(level.codes.iter_mut()) {
                for l in 0..lanes {
                    c[l] = texel.encode(external.decode(external.encode(v[l])));
                }
            }
        }
        Ok(self)
    }

    /// Store the texels as indices into a palette of `entries` texels (Ernst et al. §6): the
    /// texels given must already be palette entries; a texel then takes `ceil(log2 entries)`
    /// bits of memory.
    pub fn with_palette(mut self, entries: u32) -> Self {
        self.palette = Some(entries.max(1));
        self
    }

    /// [`Texture::with_palette`] of `entries` entries whose values (lanes `0..lanes`, in index
    /// order; fewer than `entries`: the rest hold 0) are `table`: the palette's words are then
    /// known, so the reading unit can price its palette table by its contents.
    pub fn with_palette_table(self, entries: u32, table: &[[f64; 4]]) -> Self {
        let w = self.texel.width();
        let mask = if w >= 63 { -1i64 } else { (1i64 << w) - 1 };
        let mut words: Vec<i64> = table
            .iter()
            .take(entries.max(1) as usize)
            .map(|v| {
                (0..self.lanes as usize).fold(0i64, |acc, l| {
                    acc | ((self.texel.encode(v[l]) & mask) << (l as u32 * w))
                })
            })
            .collect();
        words.resize(entries.max(1) as usize, 0);
        let mut t = self.with_palette(entries);
        t.palette_words = Some(words);
        t
    }

    /// Whether `o` stores the same words: shape, texel encoding, every level's size and raw
    /// words, and the palette (what the host must upload again when they differ).
    pub fn same_contents(&self, o: &Texture) -> bool {
        self.shape == o.shape
            && self.lanes == o.lanes
            && self.texel == o.texel
            && self.palette == o.palette
            && self.palette_words == o.palette_words
            && self.levels.len() == o.levels.len()
            && self
                .levels
                .iter()
                .zip(&o.levels)
                .all(|(a, b)| a.width == b.width && a.height == b.height && a.codes == b.codes)
    }

    fn level(name: &str, texel: &Encoding, faces: Vec<Texels>, lanes: u8) -> Result<Level, String> {
        let (width, height) = (faces[0].width, faces[0].height);
        let log_w = check_side(&format!("texture {name} width"), width)?;
        let log_h = check_side(&format!("texture {name} height"), height)?;
        let n = (width as usize) * (height as usize);
        let mut values = Vec::with_capacity(n * faces.len());
        for f in faces {
            if f.values.len() != n {
                return Err(format!(
                    "texture {name}: {} texels for a {width}x{height} level: expected {n}",
                    f.values.len()
                ));
            }
            values.extend(f.values);
        }
        // each texel's codes are a pure function of its values: encoded in parallel, in order
        use rayon::prelude::*;
        let codes = values
            .par_iter()
            .with_min_len(4096)
            .map(|t| {
                std::array::from_fn(|l| {
                    if l < lanes as usize {
                        texel.encode(t[l])
                    } else {
                        0
                    }
                })
            })
            .collect();
        Ok(Level {
            width,
            height,
            log_w,
            log_h,
            values,
            codes,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn shape(&self) -> Shape {
        self.shape
    }
    pub fn lanes(&self) -> u8 {
        self.lanes
    }
    /// The encoding of each lane of a texel.
    pub fn texel(&self) -> &Encoding {
        &self.texel
    }
    /// The palette size, if the texture is stored as palette indices.
    pub fn palette(&self) -> Option<u32> {
        self.palette
    }
    /// The palette's stored words, when known ([`Texture::with_palette_table`]).
    pub fn palette_words(&self) -> Option<&[i64]> {
        self.palette_words.as_deref()
    }
    /// Mip level `k` (0 is the finest).
    pub fn level_at(&self, k: usize) -> &Level {
        &self.levels[k]
    }
    pub fn levels(&self) -> usize {
        self.levels.len()
    }
    /// The level GL's `NEAREST_MIPMAP_NEAREST` selects for a level of detail `lod`:
    /// `clamp(floor(lod + 1/2), 0, levels - 1)`.
    pub fn nearest_level(&self, lod: f64) -> usize {
        ((lod + 0.5).floor().max(0.0) as usize).min(self.levels.len() - 1)
    }
    /// Stored bits per texel: the lanes' bits, or the palette index.
    pub fn bits_per_texel(&self) -> u32 {
        match self.palette {
            Some(n) => n.next_power_of_two().trailing_zeros().max(1),
            None => self.lanes as u32 * self.texel.width(),
        }
    }
    /// Texels stored, over every level and face.
    pub fn texels(&self) -> u64 {
        self.levels.iter().map(|l| l.values.len() as u64).sum()
    }
    /// Bits of memory the texture occupies (its palette, if any, is the reading unit's).
    pub fn stored_bits(&self) -> u64 {
        self.texels() * u64::from(self.bits_per_texel())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};

    fn flat(w: u32, h: u32, lanes: u8) -> Texels {
        Texels {
            width: w,
            height: h,
            lanes,
            values: (0..w * h)
                .map(|k| [k as f64 / (w * h) as f64, -0.5, 0.25, 1.0])
                .collect(),
        }
    }

    #[test]
    fn an_upload_type_rounds_the_codes_and_leaves_the_values() {
        // GL_BYTE ((2c + 1) / 255) into a 16-bit signed texel: every internal code is the
        // conversion of one of the 256 byte codes, and exact mode's values are untouched
        let byte = Encoding::texel(Codec::UnitSymmetric, true, 8);
        let hilo = Encoding::texel(Codec::UnitSigned, true, 16);
        let t = Texture::new("t", hilo, flat(8, 4, 3))
            .unwrap()
            .with_upload(&byte)
            .unwrap();
        let direct = Texture::new("d", hilo, flat(8, 4, 3)).unwrap();
        let grid: Vec<i64> = (-128..128).map(|c| hilo.encode(byte.decode(c))).collect();
        let (l, d) = (t.level_at(0), direct.level_at(0));
        let mut moved = 0;
        for i in 0..32 {
            for lane in 0..3 {
                assert!(grid.contains(&l.code(i)[lane]), "texel {i} lane {lane}");
                assert_eq!(l.value(i)[lane], d.value(i)[lane]);
                moved += (l.code(i)[lane] != d.code(i)[lane]) as u32;
            }
        }
        assert!(moved > 16, "{moved} codes moved");
        assert_eq!(t.stored_bits(), direct.stored_bits());
    }

    #[test]
    fn levels_and_faces_are_counted_and_encoded() {
        let texel = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let t = Texture::new("t", texel, flat(8, 4, 3))
            .unwrap()
            .with_mips(vec![flat(4, 2, 3), flat(2, 1, 3), flat(1, 1, 3)])
            .unwrap();
        assert_eq!((t.levels(), t.texels(), t.bits_per_texel()), (4, 43, 24));
        assert_eq!(t.stored_bits(), 43 * 24);
        assert_eq!(t.nearest_level(-3.0), 0);
        assert_eq!(t.nearest_level(1.49), 1);
        assert_eq!(t.nearest_level(1.5), 2);
        assert_eq!(t.nearest_level(99.0), 3);
        // texel 5 of level 0 is 5/32, lane 3 is not stored
        let l = t.level_at(0);
        assert_eq!(
            l.code(l.index(0, 5, 0, [Address::Wrap; 2]))[..],
            [40, 0, 64, 0]
        );
        let p = t.clone().with_palette(300);
        assert_eq!(p.bits_per_texel(), 9);
    }

    #[test]
    fn hilo_texels_hold_two_signed_16_bit_lanes() {
        // SIGNED_HILO16: -32768 = -1.0, 32767 = 0.99996 (NV_texture_shader)
        let hilo = Encoding::texel(Codec::UnitSigned, true, 16);
        let t = Texture::new(
            "hilo",
            hilo,
            Texels {
                width: 1,
                height: 1,
                lanes: 2,
                values: vec![[-1.0, 32767.0 / 32768.0, 0.0, 0.0]],
            },
        )
        .unwrap();
        assert_eq!(t.level_at(0).code(0)[..2], [-32768, 32767]);
        assert_eq!(t.bits_per_texel(), 32);
    }

    #[test]
    fn cube_faces_are_stored_face_major_and_checked() {
        let texel = Encoding::fixed(Format::u(8, 8));
        let faces: Vec<Texels> = (0..6)
            .map(|f| Texels {
                width: 2,
                height: 2,
                lanes: 1,
                values: vec![[f as f64 / 8.0, 0.0, 0.0, 0.0]; 4],
            })
            .collect();
        let c = Texture::cube("env", texel, faces.clone()).unwrap();
        assert_eq!((c.shape(), c.texels()), (Shape::Cube, 24));
        let l = c.level_at(0);
        for f in 0..6 {
            assert_eq!(
                l.code(l.index(f, 1, 1, [Address::Clamp; 2]))[0],
                f as i64 * 32
            );
        }
        assert!(Texture::cube("env", texel, faces[..5].to_vec())
            .unwrap_err()
            .contains("expected 6"));
        let mut bad = faces;
        bad[3] = flat(4, 2, 1);
        assert!(Texture::cube("env", texel, bad)
            .unwrap_err()
            .contains("square faces"));
        assert!(c.with_mips(vec![]).is_err());
    }

    #[test]
    fn bad_sizes_are_rejected() {
        let texel = Encoding::fixed(Format::u(8, 8));
        assert!(Texture::new("t", texel, flat(6, 4, 1))
            .unwrap_err()
            .contains("power of two"));
        let mut short = flat(4, 4, 1);
        short.values.pop();
        assert!(Texture::new("t", texel, short)
            .unwrap_err()
            .contains("expected 16"));
        let t = Texture::new("t", texel, flat(4, 4, 1)).unwrap();
        assert!(t
            .with_mips(vec![flat(8, 2, 1)])
            .unwrap_err()
            .contains("at most 4x4"));
    }
}

//! The engine's texture memory: every texture the units read, built once and shared.
//!
//! A unit spec asks the memory for a texture by a key naming what the texture holds (its
//! source in the scene, texel encoding and storage); the first request builds it, later ones
//! with the same key get the same [`Texture`], so two units reading one normal map read one
//! memory, the bake runs once, and the report counts its bits once and its traffic per reader
//! ([`TextureStats`]). Textures are named after the first unit that reads them.

use crate::scene::Scene;
use bumpsim_hw::{Stage, Texture};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::sync::Arc;

/// How the host builds a texture again for another frame's scene (its name given).
pub type Recipe = Arc<dyn Fn(&Scene, &str) -> Result<Texture, String> + Send + Sync>;

/// A texture the host builds from the frame's inputs (a lighting map, a cube map of the
/// lighting environment): built again for every frame and uploaded where its words changed
/// ([`crate::engine::Engine::begin_frame`]).
pub struct FrameTexture {
    pub texture: Arc<Texture>,
    pub recipe: Recipe,
}

/// The textures built so far, by key.
#[derive(Default)]
pub struct TextureMemory {
    textures: RefCell<BTreeMap<String, Arc<Texture>>>,
    per_frame: RefCell<Vec<FrameTexture>>,
}

impl TextureMemory {
    /// The texture of `key`, built by `build(name)` on the first request.
    pub fn get_or_build(
        &self,
        key: &str,
        name: &str,
        build: impl FnOnce(&str) -> Result<Texture, String>,
    ) -> Result<Arc<Texture>, String> {
        if let Some(t) = self.textures.borrow().get(key) {
            return Ok(t.clone());
        }
        // a unit that reads several textures names them apart; a name taken by another key
        // still gets a suffix, so that every texture of the report has its own name
        let taken = |n: &str| self.textures.borrow().values().any(|t| t.name() == n);
        let mut unique = name.to_string();
        let mut k = 2;
        while taken(&unique) {
            unique = format!("{name}#{k}");
            k += 1;
        }
        let t = Arc::new(build(&unique)?);
        self.textures
            .borrow_mut()
            .insert(key.to_string(), t.clone());
        Ok(t)
    }

    /// Mark `texture` as built from the frame's inputs, built again by `recipe` (once, however
    /// many units read it).
    pub fn each_frame(&self, texture: &Arc<Texture>, recipe: Recipe) {
        let mut v = self.per_frame.borrow_mut();
        if !v.iter().any(|f| Arc::ptr_eq(&f.texture, texture)) {
            v.push(FrameTexture {
                texture: texture.clone(),
                recipe,
            });
        }
    }

    /// The textures marked [`TextureMemory::each_frame`], in the order they were built.
    pub fn into_frame_textures(self) -> Vec<FrameTexture> {
        self.per_frame.into_inner()
    }
}

/// One texture of the memory in the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TextureStats {
    /// Units that read it, in pipeline order.
    pub readers: Vec<String>,
    /// "2d" or "cube".
    pub shape: &'static str,
    /// Width and height of level 0.
    pub size: [u32; 2],
    pub levels: usize,
    /// Stored bits per texel (palette indices count their index bits).
    pub bits_per_texel: u32,
    /// Bits of memory over every level and face.
    pub stored_bits: u64,
    /// Texels read per fragment, summed over the readers.
    pub texels_per_fragment: u32,
    /// Texel bits read per frame: fragments x texels per fragment x bits per texel, plus the
    /// frame work's reads.
    pub bits_per_frame: u64,
    /// Texels read per frame by the readers' frame work, not per fragment (the palette
    /// builder's environment images: [`bumpsim_hw::FrameRead`]); left out of the report when 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub texels_per_frame_work: u64,
}

fn is_zero(x: &u64) -> bool {
    *x == 0
}

/// The textures the stages read, by name (each once, in name order).
pub fn textures(stages: &[Stage]) -> Vec<(String, Arc<Texture>)> {
    let mut out: BTreeMap<String, Arc<Texture>> = BTreeMap::new();
    for s in stages {
        for r in s.unit().textures() {
            out.entry(r.texture.name().to_string()).or_insert(r.texture);
        }
    }
    out.into_iter().collect()
}

/// The textures the stages read, keyed by texture name, with `fragments` fragments per frame
/// through every stage.
pub fn stats(stages: &[Stage], fragments: u64) -> BTreeMap<String, TextureStats> {
    let mut out: BTreeMap<String, (Arc<Texture>, TextureStats)> = BTreeMap::new();
    for s in stages {
        for r in s.unit().textures() {
            let t = &r.texture;
            let e = out.entry(t.name().to_string()).or_insert_with(|| {
                let l = t.level_at(0);
                let stats = TextureStats {
                    readers: Vec::new(),
                    shape: match t.shape() {
                        bumpsim_hw::texture::Shape::Flat => "2d",
                        bumpsim_hw::texture::Shape::Cube => "cube",
                    },
                    size: [l.width(), l.height()],
                    levels: t.levels(),
                    bits_per_texel: t.bits_per_texel(),
                    stored_bits: t.stored_bits(),
                    texels_per_fragment: 0,
                    bits_per_frame: 0,
                    texels_per_frame_work: 0,
                };
                (t.clone(), stats)
            });
            debug_assert!(Arc::ptr_eq(&e.0, t), "texture names are unique");
            if !e.1.readers.contains(&s.name) {
                e.1.readers.push(s.name.clone());
            }
            e.1.texels_per_fragment += r.taps;
            e.1.bits_per_frame += fragments * u64::from(r.taps) * u64::from(t.bits_per_texel());
        }
    }
    let mut out: BTreeMap<String, TextureStats> =
        out.into_iter().map(|(k, (_, v))| (k, v)).collect();
    // the textures the frame work reads (the palette builder's environment images), named
    // after their unit
    for s in stages {
        for r in s.unit().frame_reads() {
            let bits = u64::from(r.bits_per_texel);
            let texels = u64::from(r.size[0]) * u64::from(r.size[1]);
            out.insert(
                format!("{}.{}", s.name, r.name),
                TextureStats {
                    readers: vec![s.name.clone()],
                    shape: "2d",
                    size: r.size,
                    levels: 1,
                    bits_per_texel: r.bits_per_texel,
                    stored_bits: texels.saturating_mul(bits),
                    texels_per_fragment: 0,
                    bits_per_frame: r.texels_per_frame.saturating_mul(bits),
                    texels_per_frame_work: r.texels_per_frame,
                },
            );
        }
    }
    out
}

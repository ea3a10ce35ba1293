//! One module per hardware unit. Each cites the paper section it models.

pub mod dot3;
pub mod emboss;
pub mod fetch;
pub mod normalize;
pub mod power;
pub mod shade;

pub use dot3::{Clamp, Dot3};
pub use emboss::EmbossFilter;
pub use fetch::{Address, Filter, TexFetch, Texels};
pub use normalize::Normalize;
pub use power::PowerTable;
pub use shade::{Shade, ShadeInputs, ShadeParams};
pub mod specgen;
pub use specgen::{SpecGen, SpecularGenerator};
pub mod blend;
pub use blend::{BlendKind, BumpBlend, BumpBlendParams, LightState, Selective, VecSource};
pub mod modulate;
pub use modulate::Modulate;
pub mod palette_lut;
pub use palette_lut::{PaletteLut, PaletteTable};
pub mod palette_builder;
pub use palette_builder::{BuilderFormats, Light, LightingFn, PaletteBuilder};
pub mod quantized_fetch;
pub use quantized_fetch::QuantizedFetch;
pub mod cull;
pub use cull::{CullFragment, CullTest};
pub mod fb_blend;
pub use fb_blend::{BlendEquation, FbBlend};
pub mod combiner;
pub mod rop;
pub use rop::{Rop, RopParams};
pub mod texture_shader;

//! NDF-based bump map synthesis (Kautz, Heidrich, Seidel, "Real-time bump map synthesis",
//! Graphics Hardware 2001): bumps generated from nothing but a normal density function and
//! shaded with the same NDF. `docs/units/ndf.md`.
//!
//! * `noise.rs`: Perlin's improved noise and its fractal sum (§4, §5.2.2), exact and
//!   bit-accurate;
//! * `ndf.rs`: the NDFs (Blinn-Phong, Beckmann, Ward, PNG) and the hemispherical map (§4);
//! * `tables.rs`: `g`, `G`, `M`, `C` and their inverses, the lookup table `L(r1, r2)`, the
//!   histogram and fit measures (§4);
//! * `surface.rs`: the synthesised surface, the scene's `bump: Ndf(...)`;
//! * `sources.rs`: the textures of the hardware path (§5.2): the noise mip levels, `L` and the
//!   NDF in 1-D (isotropic) or 2-D (anisotropic);
//! * `statistics.rs`: the report's `synthesis` section (the generated normals' fit to the NDF,
//!   the patch shading per level of detail).

#[allow(clippy::module_inception)]
pub mod ndf;
pub mod noise;
pub mod sources;
pub mod statistics;
pub mod surface;
pub mod tables;

pub use ndf::{Distribution, Ndf, NdfSpec};
pub use surface::{NdfSurface, SynthesisSpec};

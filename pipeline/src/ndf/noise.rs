//! Perlin's improved noise and its fractal sum (Kautz et al. §4, §5.2.2): the model lives in
//! the unit library, `hw/src/units/ndf_noise.rs` (exact and bit-accurate modes), so that the
//! per-fragment generator of the software path (`hw/src/units/ndf_turbulence.rs`) and the
//! host's noise textures share it.

pub use bumpsim_hw::units::ndf_noise::*;

//! The frame contract's inputs: what the host hands the units before each frame.
//!
//! A unit is built once per run; its hardware (ports, widths, tables' sizes) stays the same in
//! every frame. Before each frame the host loads the registers that follow the scene: the
//! lights, the viewer and the materials, all in the object's frame (a parallel light and a
//! parallel viewer taken at the object's origin, as Ernst et al. 1998 §4.2 load the bump-state
//! vectors and Tarini et al. 2002 §5 shade the normal table). [`crate::Unit::begin_frame`]
//! takes them; a unit rebuilds what depends on them (a palette, a power table, its quantized
//! registers) and reports that work through [`crate::Unit::frame_cycles`] and
//! [`crate::Unit::frame_writes`], as the hardware pays it every frame.
//!
//! Textures the host computes from the lights (a lighting map, a cube map of the lighting
//! environment) are host work, not unit state: the host uploads them into the texture memory
//! ([`crate::Unit::upload`]).

/// A light of the frame, in the object's frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameLight {
    /// Toward the light, unit length (zero where the direction is undefined).
    pub dir: [f64; 3],
    /// The half vector `unit(dir + view)` (zero where undefined).
    pub half: [f64; 3],
    /// RGB colour.
    pub color: [f64; 3],
}

/// A material's coefficients in the frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameMaterial {
    pub ambient: [f64; 3],
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
    pub shininess: f64,
}

/// Everything a unit may read of the frame. See the module documentation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameInputs {
    /// The lights the bump engine shades with, in the scene's order.
    pub lights: Vec<FrameLight>,
    /// Toward the viewer, unit length.
    pub view: [f64; 3],
    /// The world's up (+y), unit length: a landscape's up (Tarini's chrome).
    pub world_up: [f64; 3],
    /// The camera's up, unit length: with `view` it fixes a sphere map's eye frame.
    pub camera_up: [f64; 3],
    /// The materials by id; id 0 is the scene's material.
    pub materials: Vec<FrameMaterial>,
}

impl FrameInputs {
    /// Material `id`, or an error naming it.
    pub fn material(&self, id: usize) -> Result<&FrameMaterial, String> {
        self.materials.get(id).ok_or_else(|| {
            format!(
                "material {id}: the frame has {} materials",
                self.materials.len()
            )
        })
    }

    /// That the frame has `n` lights, as the unit `what` was built for: the number of lights
    /// is hardware (ports, datapath passes), so a frame may move lights but not add any.
    pub fn expect_lights(&self, n: usize, what: &str) -> Result<(), String> {
        if self.lights.len() == n {
            return Ok(());
        }
        Err(format!(
            "the frame has {} bump lights: {what} was built for {n} (a frame may move, recolour \
             or dim lights, not add or remove them)",
            self.lights.len()
        ))
    }
}

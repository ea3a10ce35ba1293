//! The unit catalogue: each config variant builds one hardware unit of `bumpsim-hw`.
//!
//! A unit takes the encodings of its inputs from the signals wired to them (so changing a width
//! upstream propagates), and states its own output encodings. Each unit spec has a file of its
//! own here, named after what it models (`tex_fetch.rs`, `dot3.rs`, ...): a struct of the
//! variant's fields (the config syntax: field names, defaults and docs) and its `Spec`, the
//! names of its input ports, the checks of its fields and the build of the `bumpsim-hw` unit,
//! in one place. Shared pieces: the texture sources (`textures.rs`), checks (`checks.rs`),
//! port names and lookups (`ports.rs`) and field defaults (`defaults.rs`).
//!
//! [`UnitSpec`] is a closed enum with one variant per spec, written in a config as a struct
//! variant, `Dot3(count: 2, out: ...)` (`struct_variant.rs` maps the spec structs to that
//! form). Adding a unit to bumpsim means writing it in `hw/src/units/`, writing its spec file
//! here and adding its `mod` line and its line in `unit_specs!` below; the simulator does not
//! change.

mod baked;
mod bump_blend;
mod checks;
mod cull_fragment;
mod defaults;
mod dot3;
mod emboss_filter;
mod fb_blend;
mod modulate;
mod ndf_turbulence;
mod normalize;
mod palette_lighting;
mod perturb;
mod ports;
mod power_table;
mod quantized_normals;
mod quat_frame;
mod register_combiners;
mod shade;
mod struct_variant;
mod tex_fetch;
mod texram_frame;
mod texture_shader;
mod textures;

pub use bump_blend::BumpBlendSpec;
pub use cull_fragment::CullFragmentSpec;
pub use dot3::Dot3Spec;
pub use emboss_filter::EmbossFilterSpec;
pub use fb_blend::FbBlendSpec;
pub use modulate::ModulateSpec;
pub use ndf_turbulence::TurbulenceSpec;
pub use normalize::NormalizeSpec;
pub use perturb::PerturbSpec;
pub use power_table::PowerTableSpec;
pub use quantized_normals::{BuilderDatapath, QuantizedNormalsSpec};
pub use quat_frame::QuatFrameSpec;
pub use register_combiners::RegisterCombinersSpec;
pub use shade::ShadeSpec;
pub use tex_fetch::TexFetchSpec;
pub use texram_frame::TexramFrameSpec;
pub use texture_shader::{StageConfig, StageTexture, TextureShaderSpec};
pub use textures::{cube_direction, CubeTerm, TextureSource, MAX_CUBE_SIDE};

use crate::engine::memory::{Recipe, TextureMemory};
use crate::scene::Scene;
use bumpsim_hw::{FrameInputs, PortSpec, Texture, Unit};
use serde::de::{Deserialize, Deserializer, EnumAccess, Visitor};
use serde::ser::{Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;
use struct_variant::{AsVariant, FromVariant};

/// What a unit's build may read: the scene, the engine's texture memory, and the name of the
/// unit being built (textures are named after their first reader).
pub struct BuildCtx<'a> {
    pub scene: &'a Scene,
    pub memory: &'a TextureMemory,
    pub unit: &'a str,
    /// The scene's frame inputs ([`crate::engine::frame_inputs`]): what the units' per-frame
    /// state is built from, here and before every later frame.
    pub frame: &'a FrameInputs,
}

impl BuildCtx<'_> {
    /// Indices of the lights the bump engine shades with.
    pub fn bump_lights(&self) -> Vec<usize> {
        self.scene
            .lights
            .iter()
            .enumerate()
            .filter(|(_, l)| l.bump)
            .map(|(i, _)| i)
            .collect()
    }
}

/// A texture build over a [`BuildCtx`] as a [`Recipe`] the host runs again for another
/// frame's scene: the build sees that scene, its frame inputs, an empty memory and the
/// texture's name as the unit's.
fn recipe(
    build: impl Fn(&BuildCtx, &str) -> Result<Texture, String> + Send + Sync + 'static,
) -> Recipe {
    std::sync::Arc::new(move |scene: &Scene, name: &str| {
        let frame = crate::engine::frame_inputs::of(scene);
        let memory = TextureMemory::default();
        let ctx = BuildCtx {
            scene,
            memory: &memory,
            unit: name,
            frame: &frame,
        };
        build(&ctx, name)
    })
}

/// A unit spec: what it wires and what it builds.
trait Spec {
    /// Names of the input ports the unit will have, for wiring before it is built.
    fn input_names(&self, ctx: &BuildCtx) -> Vec<String>;
    /// Check the fields and build the unit from the encodings of the signals wired to its
    /// inputs.
    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String>;
}

/// The enum of unit specs from one list of `Variant(SpecStruct)`: the dispatch to each spec,
/// and serde as the externally tagged enum of struct variants that `derive` would write (the
/// variant names and order are the config's tags and their numbers).
macro_rules! unit_specs {
    ($($variant:ident($spec:ident),)*) => {
        /// A hardware unit and its parameters, as written in a config: `Variant(field: value,
        /// ...)`, the fields those of the spec struct (documented in its file).
        #[derive(Debug, Clone, PartialEq)]
        pub enum UnitSpec {
            $($variant($spec),)*
        }

        impl UnitSpec {
            fn spec(&self) -> &dyn Spec {
                match self {
                    $(UnitSpec::$variant(s) => s,)*
                }
            }
        }

        /// The variant tags, in order.
        #[derive(serde::Deserialize)]
        #[serde(variant_identifier)]
        enum Tag {
            $($variant,)*
        }

        const VARIANTS: &[&str] = &[$(stringify!($variant),)*];

        impl Serialize for UnitSpec {
            fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
                match self {
                    $(UnitSpec::$variant(s) => s.serialize(AsVariant {
                        ser,
                        name: "UnitSpec",
                        index: Tag::$variant as u32,
                        variant: stringify!($variant),
                    }),)*
                }
            }
        }

        impl<'de> Deserialize<'de> for UnitSpec {
            fn deserialize<D: Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
                struct Variants;
                impl<'de> Visitor<'de> for Variants {
                    type Value = UnitSpec;
                    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                        f.write_str("enum UnitSpec")
                    }
                    fn visit_enum<A: EnumAccess<'de>>(self, data: A) -> Result<UnitSpec, A::Error> {
                        let (tag, variant) = data.variant::<Tag>()?;
                        Ok(match tag {
                            $(Tag::$variant => UnitSpec::$variant($spec::deserialize(
                                FromVariant(variant),
                            )?),)*
                        })
                    }
                }
                de.deserialize_enum("UnitSpec", VARIANTS, Variants)
            }
        }
    };
}

unit_specs! {
    TexFetch(TexFetchSpec),
    CullFragment(CullFragmentSpec),
    Dot3(Dot3Spec),
    PowerTable(PowerTableSpec),
    Normalize(NormalizeSpec),
    Shade(ShadeSpec),
    BumpBlend(BumpBlendSpec),
    Modulate(ModulateSpec),
    QuantizedNormals(QuantizedNormalsSpec),
    FbBlend(FbBlendSpec),
    EmbossFilter(EmbossFilterSpec),
    RegisterCombiners(RegisterCombinersSpec),
    Perturb(PerturbSpec),
    TexramFrame(TexramFrameSpec),
    QuatFrame(QuatFrameSpec),
    TextureShader(TextureShaderSpec),
    Turbulence(TurbulenceSpec),
}

impl UnitSpec {
    /// Names of the input ports this unit will have, for wiring before it is built.
    pub fn input_names(&self, ctx: &BuildCtx) -> Vec<String> {
        self.spec().input_names(ctx)
    }

    /// Build the unit from the encodings of the signals wired to its inputs.
    pub fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        self.spec().build(ins, ctx)
    }
}

//! The scene materials' lighting models as palette-builder functions (Tarini et al. §5, §7.1),
//! for the quantized normal maps.

use super::checks::NO_BUMP_LIGHT;
use super::BuildCtx;
use bumpsim_hw::units::LightingFn;

/// Material `id`'s lighting model as a palette-builder function for the frame's inputs
/// ([`LightingFn::with_frame`]: lights, viewer and coefficients in object space, Tarini §5: a
/// parallel light and viewer taken at the object's origin); the builder takes each later
/// frame's inputs the same way. `split`: the §7.1 form for blending with a base colour.
pub(super) fn lighting_fn(ctx: &BuildCtx, id: u8, split: bool) -> Result<LightingFn, String> {
    use crate::scene::Shading;
    let scene = ctx.scene;
    let m = scene.material(id);
    let lit = !matches!(m.model, Shading::Chrome { .. } | Shading::EnvMap { .. });
    if lit && ctx.frame.lights.is_empty() {
        return Err(NO_BUMP_LIGHT.into());
    }
    let (z, lights) = ([0.0; 3], Vec::new());
    let model = if split {
        let lambert = match m.model {
            Shading::Phong => false,
            Shading::Lambert => true,
            _ => {
                return Err(format!(
                    "split: material {id} uses the {} model: expected Phong or Lambert (Tarini \
                     §7 blends the specular and diffuse terms)",
                    m.model.name()
                ))
            }
        };
        LightingFn::SpecularSplit {
            ambient: 0.0,
            diffuse: 0.0,
            specular: z,
            shininess: 0.0,
            view: z,
            lights,
            lambert,
        }
    } else {
        match &m.model {
            Shading::Phong => LightingFn::Specular {
                ambient: z,
                diffuse: z,
                specular: z,
                shininess: 0.0,
                view: z,
                lights,
            },
            Shading::Lambert => LightingFn::Lambert {
                ambient: z,
                diffuse: z,
                lights,
            },
            Shading::Cartoon { bands } => LightingFn::Cartoon {
                bands: *bands,
                ambient: z,
                diffuse: z,
                lights,
            },
            Shading::DoubledAnglePhong => LightingFn::DoubledAnglePhong {
                ambient: z,
                diffuse: z,
                specular: z,
                shininess: 0.0,
                view: z,
                light: (z, z),
            },
            Shading::Chrome { sky, ground } => LightingFn::Chrome {
                view: z,
                up: z,
                sky: *sky,
                ground: *ground,
            },
            Shading::EnvMap { .. } => {
                let img = scene
                    .looks
                    .env_maps
                    .get(id as usize)
                    .and_then(Option::as_ref)
                    .ok_or_else(|| format!("material {id}: its environment map is not loaded"))?;
                LightingFn::EnvMap {
                    view: z,
                    up: z,
                    image: img.rows_bottom_up(),
                    width: img.width,
                    height: img.height,
                }
            }
        }
    };
    model.with_frame(ctx.frame, id as usize)
}

//! The scene materials' lighting models as palette-builder functions (Tarini et al. §5, §7.1),
//! for the quantized normal maps.

use super::checks::NO_BUMP_LIGHT;
use super::BuildCtx;
use bumpsim_hw::units::LightingFn;

/// Material `id`'s lighting model as a palette-builder function, every vector taken into
/// object space with the inverse model matrix (Tarini §5: a parallel light and viewer taken
/// at the object's origin). `split`: the §7.1 form for blending with a base colour.
pub(super) fn lighting_fn(ctx: &BuildCtx, id: u8, split: bool) -> Result<LightingFn, String> {
    use crate::scene::Shading;
    let scene = ctx.scene;
    let m = scene.material(id);
    let to_object = glam::DMat3::from_mat4(scene.model).inverse();
    let origin = scene.model.transform_point3(glam::DVec3::ZERO);
    let obj = |v: glam::DVec3| (to_object * v).normalize_or_zero().to_array();
    let view = obj(scene.camera.view_dir(origin));
    let lights: Vec<([f64; 3], [f64; 3])> = ctx
        .bump_lights()
        .iter()
        .map(|&i| (obj(scene.lights[i].dir_from(origin)), scene.lights[i].color))
        .collect();
    let lit = !matches!(m.model, Shading::Chrome { .. } | Shading::EnvMap { .. });
    if lit && lights.is_empty() {
        return Err(NO_BUMP_LIGHT.into());
    }
    let mean = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
    if split {
        let specular = match m.model {
            Shading::Phong => m.specular,
            Shading::Lambert => [0.0; 3],
            _ => {
                return Err(format!(
                    "split: material {id} uses the {} model: expected Phong or Lambert (Tarini \
                     §7 blends the specular and diffuse terms)",
                    m.model.name()
                ))
            }
        };
        return Ok(LightingFn::SpecularSplit {
            ambient: mean(m.ambient),
            diffuse: mean(m.diffuse),
            specular,
            shininess: m.shininess,
            view,
            lights,
        });
    }
    Ok(match &m.model {
        Shading::Phong => LightingFn::Specular {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            view,
            lights,
        },
        Shading::Lambert => LightingFn::Lambert {
            ambient: m.ambient,
            diffuse: m.diffuse,
            lights,
        },
        Shading::Cartoon { bands } => LightingFn::Cartoon {
            bands: *bands,
            ambient: m.ambient,
            diffuse: m.diffuse,
            lights,
        },
        Shading::DoubledAnglePhong => LightingFn::DoubledAnglePhong {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            view,
            light: lights[0],
        },
        Shading::Chrome { sky, ground } => LightingFn::Chrome {
            view,
            up: obj(glam::DVec3::Y),
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
                view,
                up: obj(glam::DVec3::from(scene.camera.up)),
                image: img.rows_bottom_up(),
                width: img.width,
                height: img.height,
            }
        }
    })
}

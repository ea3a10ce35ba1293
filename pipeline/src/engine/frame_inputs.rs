//! The host's side of the frame contract: the scene's lights, viewer and materials as the
//! units take them each frame ([`FrameInputs`], `hw/src/frame.rs`), in the object's frame (a
//! parallel light and a parallel viewer taken at the object's origin). Units are built from
//! these inputs and take them again before every later frame ([`bumpsim_hw::Unit::begin_frame`]),
//! so a frame's unit state is the same either way.

use crate::scene::Scene;
use bumpsim_hw::{FrameInputs, FrameLight, FrameMaterial};
use glam::{DMat3, DVec3};

/// The frame inputs of `scene`: its bump lights (scene order), the viewer, the world's and
/// the camera's up, every material by id.
pub fn of(scene: &Scene) -> FrameInputs {
    let to_object = DMat3::from_mat4(scene.model).inverse();
    let origin = scene.model.transform_point3(DVec3::ZERO);
    let obj = |v: DVec3| (to_object * v).normalize_or_zero();
    let view = obj(scene.camera.view_dir(origin));
    let lights = scene
        .lights
        .iter()
        .filter(|l| l.bump)
        .map(|l| {
            let dir = obj(l.dir_from(origin));
            FrameLight {
                dir: dir.to_array(),
                half: (dir + view).normalize_or_zero().to_array(),
                color: l.color,
            }
        })
        .collect();
    // material ids are bytes (Tarini §6: a discrete texel component)
    let materials = (0..scene.material_count().min(256))
        .map(|id| {
            let m = scene.material(id as u8);
            FrameMaterial {
                ambient: m.ambient,
                diffuse: m.diffuse,
                specular: m.specular,
                shininess: m.shininess,
            }
        })
        .collect();
    FrameInputs {
        lights,
        view: view.to_array(),
        world_up: obj(DVec3::Y).to_array(),
        camera_up: obj(DVec3::from(scene.camera.up)).to_array(),
        materials,
    }
}

//! The palette builder's functions for a frame (Tarini et al. 2002 §5.1: "for every frame
//! ... the colors of the palette are recomputed"): each material's [`LightingFn`] keeps its
//! model (the cartoon's bands, the chrome landscape's colours, the environment image) and takes
//! the frame's lights, viewer and coefficients ([`FrameInputs`]).

use crate::frame::FrameInputs;
use crate::units::palette_builder::{Light, LightingFn};

impl LightingFn {
    /// The function of the same model for frame `f`, as material `id`: the frame's bump
    /// lights, its viewer (and the world's up for `Chrome`, the camera's for `EnvMap`) and
    /// material `id`'s coefficients. The split form (§7.1) takes the mean of the ambient and
    /// diffuse colours, and no specular colour for a Lambert material.
    pub fn with_frame(&self, f: &FrameInputs, id: usize) -> Result<LightingFn, String> {
        let m = f.material(id)?;
        let lights: Vec<Light> = f.lights.iter().map(|l| (l.dir, l.color)).collect();
        let mean = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
        Ok(match self {
            LightingFn::Lambert { .. } => LightingFn::Lambert {
                ambient: m.ambient,
                diffuse: m.diffuse,
                lights,
            },
            LightingFn::Specular { .. } => LightingFn::Specular {
                ambient: m.ambient,
                diffuse: m.diffuse,
                specular: m.specular,
                shininess: m.shininess,
                view: f.view,
                lights,
            },
            LightingFn::Cartoon { bands, .. } => LightingFn::Cartoon {
                bands: *bands,
                ambient: m.ambient,
                diffuse: m.diffuse,
                lights,
            },
            LightingFn::DoubledAnglePhong { .. } => LightingFn::DoubledAnglePhong {
                ambient: m.ambient,
                diffuse: m.diffuse,
                specular: m.specular,
                shininess: m.shininess,
                view: f.view,
                light: *lights
                    .first()
                    .ok_or("DoubledAnglePhong: expected a bump light")?,
            },
            LightingFn::Chrome { sky, ground, .. } => LightingFn::Chrome {
                view: f.view,
                up: f.world_up,
                sky: *sky,
                ground: *ground,
            },
            LightingFn::EnvMap {
                image,
                width,
                height,
                ..
            } => LightingFn::EnvMap {
                view: f.view,
                up: f.camera_up,
                image: image.clone(),
                width: *width,
                height: *height,
            },
            LightingFn::SpecularSplit { lambert, .. } => LightingFn::SpecularSplit {
                ambient: mean(m.ambient),
                diffuse: mean(m.diffuse),
                specular: if *lambert { [0.0; 3] } else { m.specular },
                shininess: m.shininess,
                view: f.view,
                lights,
                lambert: *lambert,
            },
        })
    }

    /// The number of lights the function's datapath passes were built for, where it shades
    /// with every bump light (`DoubledAnglePhong` reads the first, `Chrome` and `EnvMap` none).
    pub fn light_passes(&self) -> Option<usize> {
        match self {
            LightingFn::Lambert { lights, .. }
            | LightingFn::Specular { lights, .. }
            | LightingFn::Cartoon { lights, .. }
            | LightingFn::SpecularSplit { lights, .. } => Some(lights.len()),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{FrameLight, FrameMaterial};
    use crate::units::palette_builder::tests::formats;
    use crate::units::palette_builder::PaletteBuilder;
    use crate::units::quantized_fetch::tests::normals;

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    }

    /// A frame with one or two lights, its vectors and coefficients varied by `k`.
    fn frame(k: f64, lights: usize) -> FrameInputs {
        let view = unit([0.1 * k, 0.2, 1.0]);
        let light = |i: f64| {
            let dir = unit([0.5 - 0.3 * k + i, 0.7, 0.6]);
            let half = unit(std::array::from_fn(|c| dir[c] + view[c]));
            FrameLight {
                dir,
                half,
                color: [1.0 - 0.1 * k, 0.9, 0.8 - 0.2 * i],
            }
        };
        let material = |m: f64| FrameMaterial {
            ambient: [0.05 * k, 0.1, 0.1 * m],
            diffuse: [0.7, 0.6 - 0.1 * k, 0.5 + 0.1 * m],
            specular: [0.4, 0.4 + 0.1 * k, 0.3],
            shininess: 16.0 + 8.0 * k + m,
        };
        FrameInputs {
            lights: (0..lights).map(|i| light(i as f64)).collect(),
            view,
            world_up: [0.0, 1.0, 0.0],
            camera_up: unit([0.1 * k, 1.0, 0.0]),
            materials: vec![material(0.0), material(1.0), material(2.0)],
        }
    }

    /// Material 2's Phong over the first 40 entries, material 1's Lambert split form over the
    /// rest: templates whose coefficients are all zero, given frame `f`.
    fn builder(f: &FrameInputs) -> PaletteBuilder {
        let z = [0.0; 3];
        let phong = LightingFn::Specular {
            ambient: z,
            diffuse: z,
            specular: z,
            shininess: 0.0,
            view: z,
            lights: Vec::new(),
        };
        let split = LightingFn::SpecularSplit {
            ambient: 0.0,
            diffuse: 0.0,
            specular: z,
            shininess: 0.0,
            view: z,
            lights: Vec::new(),
            lambert: true,
        };
        let materials = vec![
            (0..40, phong.with_frame(f, 2).unwrap()),
            (40..100, split.with_frame(f, 1).unwrap()),
        ];
        PaletteBuilder::new(normals(100), materials, formats(), 2)
            .unwrap()
            .with_material_ids(vec![2, 1])
            .unwrap()
    }

    #[test]
    fn a_builder_taking_a_frame_builds_the_table_of_one_built_for_it() {
        let (a, b) = (frame(0.0, 2), frame(1.0, 2));
        let mut moved = builder(&a);
        let before = moved.build_codes();
        moved.begin_frame(&b).unwrap();
        let built = builder(&b);
        assert_eq!(moved.build_codes(), built.build_codes());
        assert_eq!(moved.build_exact(), built.build_exact());
        assert_eq!(moved.materials(), built.materials());
        assert_ne!(moved.build_codes(), before, "the frame changes the table");
        // each interval took its own material: 2's shininess, and 1's split Lambert form
        // without a specular colour
        match &moved.materials()[0].1 {
            LightingFn::Specular { shininess, .. } => assert_eq!(*shininess, 26.0),
            f => panic!("{f:?}"),
        }
        match &moved.materials()[1].1 {
            LightingFn::SpecularSplit {
                specular, ambient, ..
            } => {
                assert_eq!(*specular, [0.0; 3]);
                assert_eq!(*ambient, (0.05 + 0.1 + 0.1) / 3.0);
            }
            f => panic!("{f:?}"),
        }
    }

    #[test]
    fn a_frame_with_another_number_of_lights_is_refused() {
        let mut b = builder(&frame(0.0, 2));
        let e = b.begin_frame(&frame(1.0, 1)).unwrap_err();
        assert!(
            e.contains("the frame has 1 bump lights: the palette builder was built for 2"),
            "{e}"
        );
        let none = FrameInputs {
            materials: Vec::new(),
            ..frame(1.0, 2)
        };
        let e = b.begin_frame(&none).unwrap_err();
        assert!(e.contains("material 2: the frame has 0 materials"), "{e}");
    }

    #[test]
    fn the_viewers_ups_go_to_the_models_that_read_them() {
        let f = frame(1.0, 1);
        let z = [0.0; 3];
        let chrome = LightingFn::Chrome {
            view: z,
            up: z,
            sky: [0.2, 0.4, 0.9],
            ground: [0.3, 0.2, 0.1],
        };
        match chrome.with_frame(&f, 0).unwrap() {
            LightingFn::Chrome { view, up, sky, .. } => {
                assert_eq!((view, up, sky), (f.view, f.world_up, [0.2, 0.4, 0.9]));
            }
            g => panic!("{g:?}"),
        }
        let env = LightingFn::EnvMap {
            view: z,
            up: z,
            image: vec![[0.5; 3]; 4],
            width: 2,
            height: 2,
        };
        match env.with_frame(&f, 0).unwrap() {
            LightingFn::EnvMap { up, image, .. } => {
                assert_eq!((up, image.len()), (f.camera_up, 4));
            }
            g => panic!("{g:?}"),
        }
    }
}

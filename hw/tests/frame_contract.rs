//! The frame contract (`bumpsim_hw::frame`, `Unit::begin_frame`): a unit built for frame A
//! that takes frame B's inputs computes, in both modes and on any input, what a unit built
//! for frame B computes, and holds the same tables. Property tests over random frames (two
//! bump lights, random directions, colours, coefficients and shininess) for the units whose
//! state follows the frame: the light combiner, the bump blend unit and the power table. (The
//! palette builder's are unit tests in `units/palette_frame.rs`; every bundled config's,
//! end to end, in the root package's `tests/animation.rs`.)

use bumpsim_hw::units::{
    BlendKind, BumpBlend, BumpBlendParams, LightState, PowerTable, Shade, ShadeInputs, ShadeParams,
};
use bumpsim_hw::{Codec, Encoding, FrameInputs, FrameLight, FrameMaterial, Mode, Unit, Word};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = [f64; 3]> {
    [lo..hi, lo..hi, lo..hi]
}

/// A direction in the upper hemisphere (away from the horizon, so `dir + view` is never 0).
fn direction() -> impl Strategy<Value = [f64; 3]> {
    (vec3(-1.0, 1.0), 0.2..1.0f64).prop_map(|(v, z)| unit([v[0], v[1], z]))
}

fn frame() -> impl Strategy<Value = FrameInputs> {
    let light = || (direction(), vec3(0.0, 1.0));
    let material = || (vec3(0.0, 0.3), vec3(0.0, 1.0), vec3(0.0, 1.0), 1.0..64.0f64);
    (direction(), [light(), light()], [material(), material()]).prop_map(
        |(view, lights, materials)| FrameInputs {
            lights: lights
                .into_iter()
                .map(|(dir, color)| FrameLight {
                    dir,
                    half: unit(std::array::from_fn(|c| dir[c] + view[c])),
                    color,
                })
                .collect(),
            view,
            world_up: [0.0, 1.0, 0.0],
            camera_up: [0.0, 1.0, 0.0],
            materials: materials
                .into_iter()
                .map(|(ambient, diffuse, specular, shininess)| FrameMaterial {
                    ambient,
                    diffuse,
                    specular,
                    shininess,
                })
                .collect(),
        },
    )
}

fn u(bits: u8) -> Encoding {
    Encoding::texel(Codec::UnitUnsigned, false, bits)
}

/// Random raw words for every input port of `unit`.
fn inputs(unit: &dyn Unit, seed: u64) -> Vec<Word> {
    let mut s = seed;
    unit.inputs()
        .iter()
        .map(|p| {
            let f = p.enc.format;
            let raws: Vec<i64> = (0..p.lanes)
                .map(|_| {
                    s = s
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    f.min_raw() + ((s >> 11) % (f.max_raw() - f.min_raw() + 1) as u64) as i64
                })
                .collect();
            Word::from_raw(&p.enc, &raws)
        })
        .collect()
}

/// Both units' outputs on the same random inputs, in both modes.
fn same_outputs(a: &dyn Unit, b: &dyn Unit, seed: u64) -> Result<(), TestCaseError> {
    for k in 0..8 {
        let ins = inputs(a, seed.wrapping_add(k));
        for mode in [Mode::Exact, Mode::BitAccurate] {
            let n = a.outputs().len();
            let (mut oa, mut ob) = (vec![Word::default(); n], vec![Word::default(); n]);
            a.eval(mode, &ins, &mut oa);
            b.eval(mode, &ins, &mut ob);
            prop_assert_eq!(oa, ob, "{:?}", mode);
        }
    }
    prop_assert_eq!(a.frame_cycles(), b.frame_cycles());
    Ok(())
}

fn shade(f: &FrameInputs) -> Shade {
    let has = ShadeInputs {
        specular: Some(u(8)),
        base: Some(u(8)),
        src: None,
    };
    let params = ShadeParams::from_frame(f).unwrap();
    Shade::new(u(8), has, params, u(10), 1, u(8))
}

fn blend(kind: BlendKind, f: &FrameInputs) -> BumpBlend {
    let p = BumpBlendParams {
        shininess: f.materials[0].shininess,
        ..BumpBlendParams::paper(kind, LightState::from_frame(kind, f).unwrap())
    };
    let wire = |n: &str| {
        Some(match n {
            "b" => Encoding::texel(Codec::UnitSigned, true, 10),
            _ => u(8),
        })
    };
    BumpBlend::new(p, wire).unwrap().following_material()
}

fn power(f: &FrameInputs) -> PowerTable {
    PowerTable::new(u(10), 2, 8, 10, f.materials[0].shininess, 1).following_material()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn a_light_combiner_taking_a_frame_is_one_built_for_it(a in frame(), b in frame(), seed: u64) {
        let mut moved = shade(&a);
        moved.begin_frame(&b).unwrap();
        same_outputs(&moved, &shade(&b), seed)?;
    }

    #[test]
    fn a_bump_blend_unit_taking_a_frame_is_one_built_for_it(a in frame(), b in frame(), seed: u64) {
        for kind in [BlendKind::Diffuse, BlendKind::Specular, BlendKind::Both] {
            let mut moved = blend(kind, &a);
            moved.begin_frame(&b).unwrap();
            let built = blend(kind, &b);
            prop_assert_eq!(moved.params(), built.params());
            same_outputs(&moved, &built, seed)?;
        }
    }

    #[test]
    fn a_power_table_taking_a_frame_is_one_built_for_it(a in frame(), b in frame(), seed: u64) {
        let mut moved = power(&a);
        moved.begin_frame(&b).unwrap();
        let built = power(&b);
        prop_assert_eq!(moved.table(), built.table());
        same_outputs(&moved, &built, seed)?;
    }
}

/// A unit built without following the material keeps its shininess; one built for two
/// lights refuses a frame with one.
#[test]
fn a_fixed_shininess_stays_and_the_number_of_lights_is_hardware() {
    let mut rng = proptest::test_runner::TestRunner::deterministic();
    let f = frame().new_tree(&mut rng).unwrap().current();
    let g = FrameInputs {
        materials: vec![FrameMaterial {
            shininess: 5.0,
            ..f.materials[0]
        }],
        ..f.clone()
    };
    let mut fixed = PowerTable::new(u(10), 2, 8, 10, 40.0, 1);
    fixed.begin_frame(&g).unwrap();
    assert_eq!(
        fixed.table(),
        PowerTable::new(u(10), 2, 8, 10, 40.0, 1).table()
    );
    let one = FrameInputs {
        lights: f.lights[..1].to_vec(),
        ..f.clone()
    };
    let e = shade(&f).begin_frame(&one).unwrap_err();
    assert!(
        e.starts_with("the frame has 1 bump lights: the light combiner was built for 2"),
        "{e}"
    );
    let e = blend(BlendKind::Both, &f).begin_frame(&one).unwrap_err();
    assert!(
        e.starts_with("the frame has 1 bump lights: the bump blend unit was built for 2"),
        "{e}"
    );
}

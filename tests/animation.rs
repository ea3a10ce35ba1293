//! Animations (`frames`, issue 8 item 4): the frames of `configs/quantized-sphere-orbit.ron`
//! (Tarini's quantized normal maps under an orbiting light), each paying the palette rebuild
//! as per-frame work, each the run of its own config, and their flicker.

mod common;

use bumpsim_pipeline::animation::{self, AnimationReport};
use bumpsim_pipeline::{config, run};
use common::*;

const ORBIT: &str = "quantized-sphere-orbit";
const SMALL64: [&str; 2] = ["scene.width=64", "scene.height=64"];

fn animate(sets: &[&str]) -> (bumpsim_pipeline::report::Report, AnimationReport, usize) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let l = config::load(&config(ORBIT), &sets).unwrap_or_else(|e| panic!("{e}"));
    let a = animation::run(&l).unwrap_or_else(|e| panic!("{e}"));
    let anim = a
        .first
        .report
        .animation
        .clone()
        .expect("an animation section");
    (a.first.report, anim, a.images.len())
}

#[test]
fn every_frame_is_the_run_of_its_own_config_and_pays_the_palette_build() {
    let (first, a, images) = animate(&SMALL64);
    assert_eq!((a.frames, a.per_frame.len(), images), (8, 8, 7));
    // frame 0 is the config itself: the report's own figures
    let f0 = &a.per_frame[0];
    assert_eq!(
        (f0.cycles, f0.frame_work),
        (first.cycles.total, first.cycles.frame)
    );
    assert!(f0.sets.is_empty() && f0.flicker_lsb.is_none());
    // the 256-entry table is rebuilt every frame: the same frame work each frame (256 builder
    // clocks and the LUT load), in the totals
    for r in &a.per_frame {
        assert_eq!(r.frame_work, 768, "frame {}", r.frame);
        assert!(r.flicker_lsb.is_some() == (r.frame > 0));
    }
    assert_eq!(a.frame_work_cycles, 8 * 768);
    assert_eq!(
        a.total_cycles,
        a.per_frame.iter().map(|r| r.cycles).sum::<u64>()
    );
    // frame 3 is the config with frame 3's overrides and no frames, rendered alone
    let f3 = &a.per_frame[3];
    let mut alone: Vec<&str> = SMALL64.to_vec();
    alone.push("frames=[]");
    alone.extend(f3.sets.iter().map(String::as_str));
    let r3 = config_report(ORBIT, &alone);
    assert!(r3.animation.is_none());
    assert_eq!(
        (f3.cycles, f3.frame_work, f3.fragments),
        (r3.cycles.total, r3.cycles.frame, r3.cycles.fragments)
    );
    assert_eq!(f3.total_psnr_db, r3.error.total.psnr_db);
    assert_eq!(f3.total_max_lsb, r3.error.total.max_abs_lsb);
    // and the light moved: the frames differ from frame 0
    assert_ne!(f3.total_max_lsb.to_bits(), 0f64.to_bits());
    assert_ne!(r3.config_hash, first.config_hash);
}

#[test]
fn a_256_entry_palette_flickers_more_than_unquantized_normals() {
    // the same animation, the same engine with every distinct normal (Quantizer::Exact,
    // 16-bit indices): measured at 64x64, 256 entries 2.2-2.9 LSB, exact 0.4-0.8 LSB
    let (_, q, _) = animate(&SMALL64);
    let mut exact = SMALL64.to_vec();
    exact.extend([
        "engine.units.qnm.unit.quantizer=Exact",
        "engine.units.qnm.unit.s_n=65536",
        "engine.units.qnm.unit.index_bits=16",
    ]);
    let (_, e, _) = animate(&exact);
    let mean = |a: &AnimationReport| {
        let f: Vec<f64> = a.per_frame.iter().filter_map(|r| r.flicker_lsb).collect();
        f.iter().sum::<f64>() / f.len() as f64
    };
    let (fq, fe) = (mean(&q), mean(&e));
    println!("flicker: 256 entries {fq:.3} LSB, exact normals {fe:.3} LSB");
    assert!(fq > 2.0 * fe && fe > 0.0, "{fq} {fe}");
    // the rebuild grows with the table: 65,536 entries cost 3 clocks each per frame
    assert!(e.frame_work_cycles > 100 * q.frame_work_cycles);
}

#[test]
fn render_writes_every_frame_and_the_report_lists_them() {
    let scratch = Scratch::new("animation-render");
    let out = scratch.join("out");
    let mut args = vec!["render".to_string(), config(ORBIT).display().to_string()];
    for s in SMALL64 {
        args.extend(["--set".to_string(), s.to_string()]);
    }
    args.extend(["--out".to_string(), out.display().to_string()]);
    let o = bumpsim(&args);
    o.expect_code(0, "render the orbit");
    assert!(o.stdout.contains("animation 8 frames"), "{}", o.stdout);
    let mut want: Vec<String> = (1..=7).map(|k| format!("frame-{k:03}.png")).collect();
    want.extend(["error.png", "image.png", "reference.png", "report.json"].map(String::from));
    want.sort();
    assert_eq!(listing(&out), want);
    let report = json(&std::fs::read_to_string(out.join("report.json")).unwrap());
    assert_eq!(uint(&report, "animation.frames"), 8);
    let first = image::open(out.join("image.png")).unwrap().to_rgb8();
    let seventh = image::open(out.join("frame-007.png")).unwrap().to_rgb8();
    assert_eq!(first.dimensions(), (64, 64));
    assert_ne!(first, seventh, "the light moved");
}

#[test]
fn a_frame_sets_per_frame_inputs_only_and_bad_frames_are_errors_before_rendering() {
    let cases: [(&str, &[&str]); 6] = [
        // the hardware is the same in every frame
        (
            "frames=[[\"engine.units.qnm.unit.s_n=16\"]]",
            &[
                "frames[0][0]",
                "per-frame inputs only",
                "scene.lights, scene.camera",
            ],
        ),
        (
            "frames=[[], [\"scene.width=32\"]]",
            &["frames[1][0]", "per-frame inputs only"],
        ),
        // the lighting model is the palette builder's hardware, not a register
        (
            "frames=[[\"scene.material.model=Cartoon(bands: 4)\"]]",
            &[
                "frames[0]",
                "frame 1 changes scene.material.model from Phong to Cartoon",
            ],
        ),
        // an override that does not apply, and a frame that is not a valid config
        (
            "frames=[[\"scene.lights[3].color=(1, 1, 1)\"]]",
            &["frames[0][0]", "scene.lights[3]"],
        ),
        (
            "frames=[[\"scene.lights[0].kind.dir=(0, 0, 0)\"]]",
            &["frames[0] (frame 1)", "scene.lights[0]"],
        ),
        (
            "frames=[[\"scene.camera.target=(0.0, 0.8, 3.2)\"]]",
            &[
                "frames[0] (frame 1)",
                "scene.camera.target",
                "different from the eye",
            ],
        ),
    ];
    for (set, needles) in cases {
        expect_rejected(&config(ORBIT), set, needles);
    }
    // at most 64 frames after frame 0
    let many = format!("frames=[{}]", vec!["[]"; 65].join(", "));
    expect_rejected(
        &config(ORBIT),
        &many,
        &["frames", "65 frames", "at most 64"],
    );
    // at most 64 overrides in a frame
    let long = format!(
        "frames=[[], [{}]]",
        vec!["\"scene.material.shininess=8\""; 65].join(", ")
    );
    expect_rejected(
        &config(ORBIT),
        &long,
        &["frames[1]", "65 overrides", "at most 64"],
    );
    // at most 2^26 pixels over all frames
    let scratch = Scratch::new("animation-bad");
    let out = scratch.join("out");
    let args = [
        "render",
        &config(ORBIT).display().to_string(),
        "--set",
        "scene.width=4096",
        "--set",
        "scene.height=4096",
        "--out",
        &out.display().to_string(),
    ];
    let o = bumpsim(&args);
    o.expect_code(2, "8 frames of 4096^2");
    assert!(o.stderr.contains("over all frames"), "{}", o.stderr);
    assert!(!out.exists(), "nothing is written on an error");
}

#[test]
fn a_frame_uploads_the_textures_whose_words_changed() {
    // the orbit rebuilds the palette's colours (frame work) and leaves the index texture as
    // it is: nothing to upload
    let (_, a, _) = animate(&SMALL64);
    assert_eq!(a.upload_bits, 0);
    assert!(a.per_frame.iter().all(|r| r.upload_bits == 0));
    // Direct3D 6 bump mapping's environment map holds the lighting for one light: a frame
    // whose light moved uploads it again (256 x 256 x 24 bits), one whose light stayed does not
    let sets = vec![
        "scene.width=64".to_string(),
        "scene.height=64".to_string(),
        "frames=[[\"scene.lights[0].kind=Directional(dir: (1.0, 1.0, 1.0))\"], [\"scene.lights[0].kind=Directional(dir: (1.0, 1.0, 1.0))\"], [\"scene.lights[0].kind=Directional(dir: (-1.0, 1.0, 1.0))\"]]".to_string(),
    ];
    let l = config::load(&config("d3d6-embm-quad"), &sets).unwrap();
    let r = animation::run(&l).unwrap();
    let a = r.first.report.animation.unwrap();
    let up: Vec<u64> = a.per_frame.iter().map(|f| f.upload_bits).collect();
    let map = r.first.report.bandwidth.texture_memory["shader.tex1"].stored_bits;
    assert_eq!(map, 256 * 256 * 24);
    assert_eq!(up, [0, map, 0, map]);
    assert_eq!(a.upload_bits, 2 * map);
}

/// The frame contract (issue 8 item 4): an engine built for frame 0 that takes frame 1's
/// inputs (`Engine::begin_frame`: the units reload their registers and tables, the host
/// rebuilds and uploads its light-dependent textures) renders frame 1 exactly as an engine
/// built for frame 1 does: the same bit-accurate and exact images and the same report, for
/// every bundled config. Frame 1 turns the object and moves the camera (so every light and
/// the viewer move in the object's frame), recolours light 0 and changes the material's
/// colours and shininess.
#[test]
fn an_engine_taking_a_frames_inputs_renders_the_frame_as_one_built_for_it() {
    let frame = r#"frames=[["scene.model.rotate_deg=(12.0, 41.0, 4.0)", "scene.camera.eye=(0.5, 0.9, 3.1)", "scene.lights[0].color=(0.9, 0.8, 0.7)", "scene.material.diffuse=(0.6, 0.55, 0.5)", "scene.material.specular=(0.5, 0.45, 0.35)", "scene.material.ambient=(0.05, 0.1, 0.15)", "scene.material.shininess=37.0"]]"#;
    let mut changed = 0;
    let configs = configs();
    for path in &configs {
        let name = stem(path);
        let sets = vec![
            "scene.width=40".to_string(),
            "scene.height=40".to_string(),
            frame.to_string(),
        ];
        let l = config::load(path, &sets).unwrap_or_else(|e| panic!("{name}: {e}"));
        let l1 = config::frames::frame(&l, 1).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (r0, engine) = run::run_frame(&l, None, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (next, _) =
            run::run_frame(&l1, None, Some(engine)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let built = run::run(&l1, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(next.image == built.image, "{name}: bit-accurate image");
        assert!(next.exact == built.exact, "{name}: exact-mode image");
        let json = |r: &bumpsim_pipeline::report::Report| serde_json::to_string(r).unwrap();
        assert_eq!(json(&next.report), json(&built.report), "{name}: report");
        changed += usize::from(next.image != r0.image);
    }
    // the frame changes what nearly every config renders (a config may light nothing in it)
    assert!(
        changed + 3 >= configs.len(),
        "{changed} of {}",
        configs.len()
    );
}

/// The number of bump lights is hardware (the light combiner's ports, its passes): a frame
/// may move, recolour or dim lights but not add one, and one that does is an error naming the
/// frame and the unit.
#[test]
fn a_frame_that_adds_a_bump_light_is_an_error_naming_the_frame_and_the_unit() {
    let three = r#"frames=[["scene.lights=[(kind: Directional(dir: (1.0, 1.0, 1.0)), color: (1.0, 1.0, 1.0)), (kind: Directional(dir: (-1.0, 1.0, 1.0)), color: (0.5, 0.5, 0.5)), (kind: Directional(dir: (0.0, 1.0, 0.2)), color: (0.3, 0.3, 0.3))]"]]"#;
    let sets = [
        "scene.width=32".to_string(),
        "scene.height=32".to_string(),
        three.to_string(),
    ];
    let l = config::load(&config("sgi-teapot"), &sets).unwrap_or_else(|e| panic!("{e}"));
    let e = match animation::run(&l) {
        Ok(_) => panic!("a frame with another bump light rendered"),
        Err(e) => e,
    };
    assert_eq!(e.field, "frames[0] (frame 1): scene");
    assert!(
        e.message.contains(
            "unit \"shade\": the frame has 3 bump lights: the light combiner was built for 2"
        ),
        "{}",
        e.message
    );
}

/// What a moving light costs each frame, engine by engine (docs/configs.md, "Frames"): the
/// units' frame work (cycles before the first triangle) and the host's uploads (bits), over
/// frame 0, two frames whose light moved and one whose material's shininess changed.
#[test]
fn each_engine_pays_its_own_per_frame_cost_for_a_moving_light() {
    let frames = r#"frames=[["scene.lights[0].kind.dir=(0.7071, 1.0, 1.2247)"], ["scene.lights[0].kind.dir=(0.3660, 1.0, 1.3660)"], ["scene.material.shininess=48.0"]]"#;
    let cases: [(&str, u64, [u64; 4]); 6] = [
        // the power table loaded each frame
        ("sgi-teapot", 256, [0; 4]),
        // the power table and one light's six register words
        ("gouraud-teapot", 262, [0; 4]),
        // Tarini's palette: 256 entries shaded, then loaded
        ("quantized-sphere", 768, [0; 4]),
        // Direct3D 6: the lighting environment map, rebuilt for every light and material
        ("d3d6-embm-quad", 0, [0, 1_572_864, 1_572_864, 1_572_864]),
        // NV20's cube maps of the lighting environment: the diffuse term's six 64 x 64 faces
        // and the specular term's six 256 x 256, 24 bits a texel
        (
            "nv20-reflect-cube",
            0,
            [0, 10_027_008, 10_027_008, 10_027_008],
        ),
        // the (N.L, N.H) lighting table holds the material, not the light's direction
        ("dependent-dot-lookup", 0, [0, 0, 0, 1_572_864]),
    ];
    for (name, work, uploads) in cases {
        let sets = vec![
            "scene.width=32".to_string(),
            "scene.height=32".to_string(),
            frames.to_string(),
        ];
        let l = config::load(&config(name), &sets).unwrap_or_else(|e| panic!("{name}: {e}"));
        let a = animation::run(&l).unwrap_or_else(|e| panic!("{name}: {e}"));
        let a = a.first.report.animation.expect("an animation section");
        let got: Vec<(u64, u64)> = a
            .per_frame
            .iter()
            .map(|f| (f.frame_work, f.upload_bits))
            .collect();
        let want: Vec<(u64, u64)> = uploads.iter().map(|&u| (work, u)).collect();
        assert_eq!(got, want, "{name}");
    }
}

/// A table priced by its contents (a ROM) is hardware too: a frame that would change it is an
/// error naming the frame and the unit, one that leaves it as it is renders.
#[test]
fn a_frame_cannot_reload_a_table_priced_as_a_rom() {
    let run = |frame: &str| {
        let sets: Vec<String> = [
            "scene.width=32",
            "scene.height=32",
            "engine.units.spec.tables=Rom",
            frame,
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let l = config::load(&config("sgi-teapot"), &sets).unwrap_or_else(|e| panic!("{e}"));
        animation::run(&l).map(|a| a.images.len())
    };
    // the light moves: the power table (x^32) stays
    let moved = r#"frames=[["scene.lights[0].kind.dir=(0.7071, 1.0, 1.2247)"]]"#;
    assert_eq!(run(moved).unwrap_or_else(|e| panic!("{e}")), 1);
    let shinier = r#"frames=[["scene.lights[0].kind.dir=(0.7071, 1.0, 1.2247)"], ["scene.material.shininess=48.0"]]"#;
    let e = match run(shinier) {
        Ok(_) => panic!("a frame reloaded a ROM"),
        Err(e) => e,
    };
    assert_eq!(e.field, "frames[1] (frame 2): scene");
    assert!(
        e.message
            .starts_with("unit \"spec\": the frame changes its gate estimate from ")
            && e.message.contains("cannot follow the frame's inputs"),
        "{}",
        e.message
    );
}

use super::*;

#[test]
fn blend_rounds_to_nearest_on_every_channel() {
    assert_eq!(blend([255, 0, 10, 255], [1, 2, 3, 4]), [255, 0, 10, 255]);
    assert_eq!(blend([255, 0, 10, 0], [1, 2, 3, 4]), [1, 2, 3, 4]);
    // (200 * 128 + 50 * 127) / 255 = 125.29.. -> 125; alpha (128 * 128 + 10 * 127) / 255
    assert_eq!(
        blend([200, 200, 200, 128], [50, 50, 50, 10]),
        [125, 125, 125, 69]
    );
}

#[test]
fn text_cells_are_ten_by_sixteen_pixels() {
    let t = Text {
        row: 1,
        col: 2,
        text: "ab".into(),
    };
    assert!(t.covers(40, 50) && t.covers(59, 65));
    assert!(!t.covers(39, 50) && !t.covers(60, 50) && !t.covers(40, 49) && !t.covers(40, 66));
}

/// The six world-space quads of `CombinerTests::CreateGeometry`, computed in f32 as there.
fn vertex_buffer_quads() -> Vec<Region> {
    let (k_left, k_right, k_top, k_bottom, spacing) =
        (-2.75f32, 2.75f32, 1.85f32, -1.75f32, 0.1f32);
    let unit_w = ((k_right - k_left) - 3.0 * spacing) / 4.0;
    let unit_h = ((k_top - k_bottom) - 2.0 * spacing) / 3.0;
    let (mut left, mut top) = (k_left, k_top - spacing);
    let mut quads = Vec::new();
    for _ in 0..6 {
        quads.push(Region::World {
            left,
            top,
            right: left + unit_w,
            bottom: top - unit_h,
            z: 1.0,
        });
        left += unit_w + spacing;
        if left >= k_right - unit_w {
            left = k_left;
            top -= unit_h + spacing * 4.0;
        }
    }
    quads
}

#[test]
fn world_quads_compare_the_columns_the_frames_show() {
    // covered pixels in Mux.png run 121..=214, 223..=316, 324..=417, 425..=519; the compared
    // ones lie 1.53125 px inside the projected edges
    let cols: Vec<((u32, u32), (u32, u32))> = vertex_buffer_quads()
        .iter()
        .take(4)
        .map(|r| {
            let c: Vec<u32> = (0..WIDTH).filter(|&x| r.compares(x, 150)).collect();
            let v: Vec<u32> = (0..WIDTH).filter(|&x| r.covers(x, 150)).collect();
            ((c[0], *c.last().unwrap()), (v[0], *v.last().unwrap()))
        })
        .collect();
    let compared: Vec<_> = cols.iter().map(|c| c.0).collect();
    let covered: Vec<_> = cols.iter().map(|c| c.1).collect();
    assert_eq!(
        compared,
        vec![(122, 212), (224, 314), (325, 415), (427, 517)]
    );
    // the picture paints centres inside the edges: within a pixel of the frame's coverage
    // (the viewport offset and the edge rule are not modelled)
    assert_eq!(
        covered,
        vec![(121, 214), (222, 315), (324, 417), (425, 518)]
    );
    // the bounds hold every covered pixel
    for r in vertex_buffer_quads() {
        let (x0, y0, x1, y1) = r.bounds();
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                if r.covers(x, y) {
                    assert!(x >= x0 && x < x1 && y >= y0 && y < y1, "{r:?} ({x}, {y})");
                }
            }
        }
    }
}

fn frame_with(region: Region, program: &str) -> String {
    format!(
        "(name: \"t\", golden: \"x.png\", quads: [(label: \"q\", region: {}, \
         under: Clear((0, 0, 0, 255)), passes: [(program: {program})])])",
        ron::to_string(&region).unwrap()
    )
}

#[test]
fn bad_fields_are_named() {
    let screen = Region::Screen {
        left: 0,
        top: 0,
        right: 10,
        bottom: 10,
    };
    let good = "(stages: [()], final_combiner: (d: (source: Primary, usage: Rgb)))";
    let f: Frame = crate::config::parse_as(&frame_with(screen, good), "t.ron").unwrap();
    assert_eq!(check(&f), Ok(()));
    let field = |r: Region, p: &str| {
        let f: Frame = crate::config::parse_as(&frame_with(r, p), "t.ron").unwrap();
        check(&f).unwrap_err().0
    };
    let wide = Region::Screen {
        left: 0,
        top: 0,
        right: 641,
        bottom: 10,
    };
    assert_eq!(field(wide, good), "quads[0].region");
    let behind = Region::World {
        left: 0.0,
        top: 1.0,
        right: 1.0,
        bottom: 0.0,
        z: -8.0,
    };
    assert_eq!(field(behind, good), "quads[0].region");
    // the programs are checked as the passes are built
    let build = |p: &str| {
        let f: Frame = crate::config::parse_as(&frame_with(screen, p), "t.ron").unwrap();
        check(&f).unwrap();
        QuadModel::new(&f, &f.quads[0], &Default::default(), Mode::BitAccurate)
            .err()
            .unwrap()
    };
    assert_eq!(build("(stages: [])").0, 0);
    assert!(build("(stages: [])").1.starts_with("program.stages: "));
    let bad = build("(stages: [(rgb: (a: (source: EfProduct, usage: Rgb)))])").1;
    assert!(bad.starts_with("program.stages[0].rgb.a.source: "), "{bad}");
    let mut f: Frame = crate::config::parse_as(&frame_with(screen, good), "t.ron").unwrap();
    f.combiner_width = 8;
    assert_eq!(check(&f).unwrap_err().0, "combiner_width");
    let e = crate::config::parse_as::<Frame>(
        "(name: \"t\", golden: \"x.png\", quads: [], colour: 1)",
        "t.ron",
    )
    .unwrap_err();
    assert!(e.message.contains("colour"), "{e:?}");
}

#[test]
fn the_work_of_a_frame_is_bounded() {
    let pass = "(shader: Some((stages: [(program: PassThrough)])), program: (stages: [()]))";
    let quad = "(label: \"q\", region: Screen(left: 0, top: 0, right: 640, bottom: 480), \
                under: Clear((0, 0, 0, 255)), passes: [P])";
    let quads = vec![quad.replace('P', &vec![pass; 16].join(", ")); 8].join(", ");
    let text = format!("(name: \"t\", golden: \"x.png\", quads: [{quads}])");
    let f: Frame = crate::config::parse_as(&text, "t.ron").unwrap();
    let (field, m) = check(&f).unwrap_err();
    assert_eq!(field, "quads");
    assert!(m.contains("39321600") && m.contains("16777216"), "{m}");
    let cells = vec!["(row: 0, col: 0, text: \"a\")"; 257].join(", ");
    let text = format!(
        "(name: \"t\", golden: \"x.png\", text: [{cells}], quads: [{}])",
        quad.replace('P', pass)
    );
    let f: Frame = crate::config::parse_as(&text, "t.ron").unwrap();
    assert_eq!(check(&f).unwrap_err().0, "text");
}

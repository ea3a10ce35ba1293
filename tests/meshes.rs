//! Meshes from files end to end: OBJ and PLY files (ASCII, binary little and big endian)
//! written to a scratch directory, loaded through a config and rendered at a small size;
//! scan defects that load by the rule of `docs/assets.md` ("Meshes from files"); bad files
//! that exit 2 naming the file and the line (or, in binary PLY, the element).
//!
//! `a_million_triangles_load` (ignored: run it with `cargo test --release --test meshes --
//! --ignored --nocapture`) writes a 1M-triangle sphere as binary and ASCII PLY and as OBJ and
//! prints the load times; no test here is timed.

mod common;

use common::*;
use std::path::{Path, PathBuf};

use bumpsim_pipeline::scene::MeshSpec;

/// A PLY encoding.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fmt {
    Ascii,
    Le,
    Be,
}

/// A triangle mesh as files hold it: f32 positions and uvs, faces of position indices.
#[derive(Debug, Clone, Default)]
struct Soup {
    positions: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    faces: Vec<Vec<u32>>,
}

/// A latitude-longitude sphere of radius `r` about the y axis: `slices x stacks` cells of two
/// triangles (counter-clockwise seen from outside), the poles one vertex per slice (so one
/// triangle of each pole cell has zero area), the seam's vertices doubled, `uv = (i/slices,
/// j/stacks)`.
fn sphere(r: f64, slices: u32, stacks: u32) -> Soup {
    let mut s = Soup::default();
    for j in 0..=stacks {
        let theta = std::f64::consts::PI * f64::from(j) / f64::from(stacks);
        for i in 0..=slices {
            let phi = std::f64::consts::TAU * f64::from(i) / f64::from(slices);
            let ring = r * theta.sin();
            s.positions.push([
                (ring * phi.cos()) as f32,
                (-r * theta.cos()) as f32,
                (-ring * phi.sin()) as f32,
            ]);
            s.uvs.push([
                (f64::from(i) / f64::from(slices)) as f32,
                (f64::from(j) / f64::from(stacks)) as f32,
            ]);
        }
    }
    let row = slices + 1;
    for j in 0..stacks {
        for i in 0..slices {
            let a = j * row + i;
            s.faces.push(vec![a, a + 1, a + row + 1]);
            s.faces.push(vec![a, a + row + 1, a + row]);
        }
    }
    s
}

/// The mesh as OBJ text (`v`, `vt` with the same index, `f v/vt`).
fn obj(s: &Soup) -> Vec<u8> {
    let mut out = String::from("# a test mesh\no mesh\n");
    for p in &s.positions {
        out += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &s.uvs {
        out += &format!("vt {} {}\n", t[0], t[1]);
    }
    for f in &s.faces {
        let c: Vec<String> = f.iter().map(|k| format!("{}/{}", k + 1, k + 1)).collect();
        out += &format!("f {}\n", c.join(" "));
    }
    out.into_bytes()
}

/// The mesh as a PLY file: vertices `x y z` (and `u v` if `uv`) as float, faces as `list uchar
/// int vertex_indices`.
fn ply(s: &Soup, fmt: Fmt, uv: bool) -> Vec<u8> {
    let format = match fmt {
        Fmt::Ascii => "ascii",
        Fmt::Le => "binary_little_endian",
        Fmt::Be => "binary_big_endian",
    };
    let mut head = format!(
        "ply\nformat {format} 1.0\ncomment a test mesh\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n",
        s.positions.len()
    );
    if uv {
        head += "property float u\nproperty float v\n";
    }
    head += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        s.faces.len()
    );
    let mut out = head.into_bytes();
    let f32s = |out: &mut Vec<u8>, xs: &[f32]| {
        for &x in xs {
            match fmt {
                Fmt::Le => out.extend_from_slice(&x.to_le_bytes()),
                _ => out.extend_from_slice(&x.to_be_bytes()),
            }
        }
    };
    for (k, p) in s.positions.iter().enumerate() {
        let mut xs = p.to_vec();
        if uv {
            xs.extend(s.uvs[k]);
        }
        match fmt {
            Fmt::Ascii => {
                let words: Vec<String> = xs.iter().map(|x| x.to_string()).collect();
                out.extend_from_slice(format!("{}\n", words.join(" ")).as_bytes());
            }
            _ => f32s(&mut out, &xs),
        }
    }
    for f in &s.faces {
        match fmt {
            Fmt::Ascii => {
                let words: Vec<String> = f.iter().map(|x| x.to_string()).collect();
                out.extend_from_slice(format!("{} {}\n", f.len(), words.join(" ")).as_bytes());
            }
            _ => {
                out.push(f.len() as u8);
                for &k in f {
                    match fmt {
                        Fmt::Le => out.extend_from_slice(&(k as i32).to_le_bytes()),
                        _ => out.extend_from_slice(&(k as i32).to_be_bytes()),
                    }
                }
            }
        }
    }
    out
}

/// The SGI teapot config at 40 x 40 pixels with `mesh` (a config mesh expression) and the
/// model at the origin, written to `scratch` as `name.ron`.
fn config_with(scratch: &Scratch, name: &str, mesh: &str) -> PathBuf {
    let mut text = std::fs::read_to_string(config("sgi-teapot")).unwrap();
    for (from, to) in [
        ("Teapot(subdivisions: 8, uv_repeat: (2.0, 2.0))", mesh),
        ("width: 256,", "width: 40,"),
        ("height: 256,", "height: 40,"),
        (
            "model: (translate: (-0.2, -1.2, 0.0)),",
            "model: (translate: (0.0, 0.0, 0.0)),",
        ),
    ] {
        assert!(text.contains(from), "sgi-teapot.ron no longer has {from:?}");
        text = text.replacen(from, to, 1);
    }
    let path = scratch.join(&format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Render a config; returns the framebuffer and the reference image's bytes.
fn render(cfg: &Path) -> (Vec<u8>, Vec<u8>) {
    let l = bumpsim_pipeline::config::load(cfg, &[]).unwrap_or_else(|e| panic!("{e}"));
    let r = bumpsim_pipeline::run::run(&l, None).unwrap_or_else(|e| panic!("{e}"));
    (r.image.into_raw(), r.reference.into_raw())
}

/// `mesh: Obj(...)` or `Ply(...)` for a file.
fn mesh(kind: &str, file: &str, atlas: bool) -> String {
    format!("{kind}(path: \"{file}\", uv_repeat: (1.0, 1.0), atlas: {atlas})")
}

/// Write `files` into `scratch`, render each with `kind` and the atlas setting, and return
/// the images.
fn render_files(
    scratch: &Scratch,
    files: &[(&str, &str, Vec<u8>)],
    atlas: bool,
) -> Vec<(Vec<u8>, Vec<u8>)> {
    files
        .iter()
        .map(|(kind, file, bytes)| {
            std::fs::write(scratch.join(file), bytes).unwrap();
            let stem = format!("{}-{atlas}", file.replace('.', "-"));
            render(&config_with(scratch, &stem, &mesh(kind, file, atlas)))
        })
        .collect()
}

#[test]
fn obj_and_ply_of_one_mesh_render_the_same_image() {
    let scratch = Scratch::new("meshes-same");
    let s = sphere(1.3, 24, 12);
    let files = [
        ("Obj", "s.obj", obj(&s)),
        ("Ply", "s-ascii.ply", ply(&s, Fmt::Ascii, true)),
        ("Ply", "s-le.ply", ply(&s, Fmt::Le, true)),
        ("Ply", "s-be.ply", ply(&s, Fmt::Be, true)),
    ];
    for atlas in [false, true] {
        let images = render_files(&scratch, &files, atlas);
        // something was drawn: the sphere covers the middle of the image
        let (image, _) = &images[0];
        let centre = (20 * 40 + 20) * 3;
        assert!(
            image[centre..centre + 3].iter().any(|&c| c > 0),
            "atlas {atlas}"
        );
        for (k, other) in images.iter().enumerate().skip(1) {
            assert!(
                *other == images[0],
                "{} differs from the OBJ (atlas {atlas})",
                files[k].1
            );
        }
    }
    // the files' own uvs and the atlas give different pictures
    let a = render_files(&scratch, &files[2..3], false);
    let b = render_files(&scratch, &files[2..3], true);
    assert!(a[0].0 != b[0].0);
}

/// `bumpsim check CFG` succeeds; returns its triangle count.
fn checked_triangles(cfg: &Path) -> usize {
    let o = bumpsim(&["check", &cfg.display().to_string()]);
    o.expect_code(0, "check");
    let at = o.stdout.find(" triangles").expect("a triangle count");
    let start = o.stdout[..at].rfind('(').unwrap() + 1;
    o.stdout[start..at].parse().unwrap()
}

#[test]
fn scan_defects_load_by_the_rule_and_render() {
    let scratch = Scratch::new("meshes-defects");
    let clean = sphere(1.3, 24, 12);
    // the sphere with: unreferenced vertices before and after its own (indices shifted), each
    // face of the first row again wound the other way (back-to-back), every tenth face again,
    // zero-area faces (collinear and repeated corners), points and edges as faces
    let mut s = Soup::default();
    let shift = 5;
    s.positions.extend([[9.0, 9.0, 9.0]; 5]);
    s.uvs.extend([[0.5, 0.5]; 5]);
    s.positions.extend(&clean.positions);
    s.uvs.extend(&clean.uvs);
    s.positions.push([0.0, 0.0, 0.0]);
    s.uvs.push([0.25, 0.75]);
    s.faces = clean
        .faces
        .iter()
        .map(|f| f.iter().map(|k| k + shift).collect())
        .collect();
    let n = s.faces.len();
    for t in 0..48 {
        let f = s.faces[t].clone();
        s.faces.push(vec![f[0], f[2], f[1]]);
    }
    for t in (0..n).step_by(10) {
        let f = s.faces[t].clone();
        s.faces.push(vec![f[1], f[2], f[0]]);
    }
    let a = shift + 100;
    s.faces.extend([
        vec![a, a, a + 1],
        vec![a, a + 1, a],
        vec![a],
        vec![a, a + 1],
    ]);
    let images = |files: &[(&str, &str, Vec<u8>)], atlas| render_files(&scratch, files, atlas);
    let reference = images(&[("Ply", "clean.ply", ply(&clean, Fmt::Le, true))], false);
    let defective = [
        ("Obj", "scan.obj", obj(&s)),
        ("Ply", "scan-ascii.ply", ply(&s, Fmt::Ascii, true)),
        ("Ply", "scan-be.ply", ply(&s, Fmt::Be, true)),
    ];
    for (k, got) in images(&defective, false).iter().enumerate() {
        assert!(
            *got == reference[0],
            "{}: not the clean sphere's picture",
            defective[k].1
        );
    }
    // the same counts as the clean sphere (its own zero-area pole faces dropped too)
    let kept = 2 * 24 * 12 - 2 * 24;
    for (kind, file, _) in &defective {
        let cfg = scratch.join(&format!("{}-false.ron", file.replace('.', "-")));
        assert_eq!(checked_triangles(&cfg), kept, "{kind} {file}");
    }
    // with the generated atlas (which the dropped faces do not reach either)
    let reference = images(&[("Ply", "clean.ply", ply(&clean, Fmt::Be, false))], true);
    let got = images(&[("Ply", "scan-nouv.ply", ply(&s, Fmt::Le, false))], true);
    assert!(got[0] == reference[0]);

    // a fin inside the sphere: two faces of equal area folded onto each other, whose tip's
    // face normals cancel; it loads (the tip takes its first face's normal) and renders
    let mut fin = clean.clone();
    let base = fin.positions.len() as u32;
    fin.positions.extend([
        [0.0, 0.0, 0.0],
        [0.1, 0.0, 0.0],
        [0.0, 0.1, 0.0],
        [0.1, 0.1, 0.0],
        [0.2, 0.2, 0.0],
    ]);
    fin.uvs
        .extend([[0.0, 0.0], [0.1, 0.0], [0.0, 0.1], [0.1, 0.1], [0.2, 0.2]]);
    for f in [[0, 1, 3], [0, 3, 2], [1, 4, 3], [2, 4, 3]] {
        fin.faces.push(f.iter().map(|k| k + base).collect());
    }
    let got = images(&[("Ply", "fin.ply", ply(&fin, Fmt::Le, true))], false);
    let clean_image = images(&[("Ply", "clean.ply", ply(&clean, Fmt::Le, true))], false);
    assert!(
        got[0] == clean_image[0],
        "the fin is hidden inside the sphere"
    );
    let cfg = scratch.join("fin-ply-false.ron");
    assert_eq!(checked_triangles(&cfg), kept + 4);
}

/// `bumpsim check` on a config whose mesh is `bytes` as `file`: exit 2 with the config's and
/// the mesh file's paths and every needle in the message.
fn check_fails(scratch: &Scratch, kind: &str, file: &str, bytes: &[u8], needles: &[&str]) {
    std::fs::write(scratch.join(file), bytes).unwrap();
    let cfg = config_with(scratch, &file.replace('.', "-"), &mesh(kind, file, false));
    let o = bumpsim(&["check", &cfg.display().to_string()]);
    o.expect_code(2, file);
    let msg = o.stderr;
    assert!(
        msg.contains(&scratch.join(file).display().to_string()),
        "{msg}"
    );
    for n in needles {
        assert!(msg.contains(n), "{file}: expected {n:?} in\n{msg}");
    }
}

#[test]
fn bad_mesh_files_exit_2_naming_the_file_and_the_line_or_element() {
    let scratch = Scratch::new("meshes-bad");
    let s = sphere(1.0, 6, 4); // 35 vertices, 48 faces
    let header = |fmt| {
        let b = ply(&s, fmt, true);
        let end = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        (b, end)
    };
    // truncated binary: the face element it ends in (each face is 13 bytes)
    let (b, _) = header(Fmt::Le);
    let cut = &b[..b.len() - 20];
    check_fails(
        &scratch,
        "Ply",
        "cut.ply",
        cut,
        &["face element 46", "ends inside it"],
    );
    // a bad header line
    let text = String::from_utf8(ply(&s, Fmt::Ascii, true)).unwrap();
    let bad = text.replacen("property float z", "property float", 1);
    check_fails(
        &scratch,
        "Ply",
        "head.ply",
        bad.as_bytes(),
        &["line 7", "bad header"],
    );
    // an index out of range: ASCII names the line, binary the element
    let mut wrong = s.clone();
    wrong.faces[3][2] = 35;
    let line = 12 + 35 + 4; // 12 header lines, the vertices, then faces 0 to 3
    let needles = [
        &format!("line {line} (face 3)")[..],
        "vertex index 35 out of range",
    ];
    check_fails(
        &scratch,
        "Ply",
        "index.ply",
        &ply(&wrong, Fmt::Ascii, true),
        &needles,
    );
    let needles = ["face element 3", "vertex index 35 out of range"];
    check_fails(
        &scratch,
        "Ply",
        "index-be.ply",
        &ply(&wrong, Fmt::Be, true),
        &needles,
    );
    // OBJ: the face's line (after the 2 comment lines, 35 v and 35 vt lines)
    let needles = ["line 76", "v index 36 out of range"];
    check_fails(&scratch, "Obj", "index.obj", &obj(&wrong), &needles);
    // NaN coordinates: the vertex element, and the line in ASCII files
    let mut nan = s.clone();
    nan.positions[7][0] = f32::NAN;
    let needles = ["vertex element 7", "expected finite numbers"];
    check_fails(
        &scratch,
        "Ply",
        "nan.ply",
        &ply(&nan, Fmt::Le, true),
        &needles,
    );
    check_fails(
        &scratch,
        "Ply",
        "nan-ascii.ply",
        &ply(&nan, Fmt::Ascii, true),
        &["line 20"],
    );
    check_fails(
        &scratch,
        "Obj",
        "nan.obj",
        &obj(&nan),
        &["line 10", "finite number"],
    );
    // no texture coordinates without the atlas
    let needles = ["no texture coordinates", "atlas: true"];
    check_fails(
        &scratch,
        "Ply",
        "nouv.ply",
        &ply(&s, Fmt::Le, false),
        &needles,
    );
    // and an unknown field in the config's Ply(...) is an error naming it
    let cfg = config_with(
        &scratch,
        "unknown-field",
        "Ply(path: \"nouv.ply\", uv_repeat: (1.0, 1.0), atlas: true, scale: 2.0)",
    );
    let o = bumpsim(&["check", &cfg.display().to_string()]);
    o.expect_code(2, "unknown field");
    assert!(o.stderr.contains("scale"), "{}", o.stderr);
}

/// Not run by default (`--ignored`): 1M triangles as binary PLY, ASCII PLY and OBJ, each
/// loaded through `MeshSpec::build`; prints the times (to compare with the claim that such
/// meshes load in seconds; no time is asserted).
#[test]
#[ignore]
fn a_million_triangles_load() {
    let scratch = Scratch::new("meshes-million");
    let s = sphere(1.0, 1024, 512); // 1,048,576 triangles, 2,048 of zero area at the poles
    for (kind, file, bytes) in [
        ("Ply", "m.ply", ply(&s, Fmt::Le, true)),
        ("Ply", "m-ascii.ply", ply(&s, Fmt::Ascii, true)),
        ("Obj", "m.obj", obj(&s)),
    ] {
        std::fs::write(scratch.join(file), &bytes).unwrap();
        let spec = match kind {
            "Ply" => MeshSpec::Ply {
                path: file.into(),
                uv_repeat: [1.0, 1.0],
                atlas: false,
            },
            _ => MeshSpec::Obj {
                path: file.into(),
                uv_repeat: [1.0, 1.0],
                atlas: false,
            },
        };
        let start = std::time::Instant::now();
        let m = spec.build(&scratch.path).unwrap();
        let secs = start.elapsed().as_secs_f64();
        println!(
            "{file}: {:.1} MB, {} triangles, {} vertices loaded in {secs:.2} s",
            bytes.len() as f64 / 1e6,
            m.triangles.len(),
            m.vertices.len()
        );
        assert_eq!(m.triangles.len(), 1024 * 512 * 2 - 2 * 1024);
    }
}

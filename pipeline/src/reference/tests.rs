//! Closed-form tests of the float reference.

use super::*;
use crate::scene::{
    BumpMap, Camera, HeightField, Light, LightKind, Material, Mesh, NormalMap, Vertex,
};
use glam::{DMat4, DVec2, DVec3, DVec4};

/// `F = a u + b v`.
struct Plane {
    a: f64,
    b: f64,
}

impl HeightField for Plane {
    fn height(&self, u: f64, v: f64) -> f64 {
        self.a * u + self.b * v
    }
    fn grad(&self, _u: f64, _v: f64) -> DVec2 {
        DVec2::new(self.a, self.b)
    }
}

/// `F = c u² / 2`: `Fu = c u`, `Fv = 0`.
struct Parabola {
    c: f64,
}

impl HeightField for Parabola {
    fn height(&self, u: f64, _v: f64) -> f64 {
        0.5 * self.c * u * u
    }
    fn grad(&self, u: f64, _v: f64) -> DVec2 {
        DVec2::new(self.c * u, 0.0)
    }
}

/// `F = k sin(4πu) cos(6πv)`.
struct Waves {
    k: f64,
}

impl HeightField for Waves {
    fn height(&self, u: f64, v: f64) -> f64 {
        use std::f64::consts::TAU;
        self.k * (2.0 * TAU * u).sin() * (3.0 * TAU * v).cos()
    }
    fn grad(&self, u: f64, v: f64) -> DVec2 {
        use std::f64::consts::TAU;
        let (su, cu) = (2.0 * TAU * u).sin_cos();
        let (sv, cv) = (3.0 * TAU * v).sin_cos();
        DVec2::new(self.k * 2.0 * TAU * cu * cv, -self.k * 3.0 * TAU * su * sv)
    }
}

fn vert(pos: DVec3, normal: DVec3, uv: DVec2, pu: DVec3, pv: DVec3) -> Vertex {
    Vertex {
        pos,
        normal,
        uv,
        pu,
        pv,
    }
}

/// A z = `z` rectangle `[-hx, hx] x [-hy, hy]` facing +z (two counter-clockwise triangles)
/// with constant `pu`, `pv` and texture coordinates `uv(x, y)`.
fn quad(hx: f64, hy: f64, z: f64, pu: DVec3, pv: DVec3, uv: impl Fn(f64, f64) -> DVec2) -> Mesh {
    let corners = [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)];
    Mesh {
        vertices: corners
            .iter()
            .map(|&(x, y)| vert(DVec3::new(x, y, z), DVec3::Z, uv(x, y), pu, pv))
            .collect(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// The unit-parameterised quad `[-h, h]²`: `Pu = x̂`, `Pv = ŷ`, `N = ẑ`, `uv = xy`.
fn unit_quad(h: f64) -> Mesh {
    quad(h, h, 0.0, DVec3::X, DVec3::Y, DVec2::new)
}

/// Orthographic camera on the +z axis looking down -z, view volume 2 x 2 (at aspect 1).
fn ortho() -> Camera {
    Camera {
        eye: [0.0, 0.0, 5.0],
        target: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_y_deg: 90.0,
        near: 1.0,
        far: 10.0,
        ortho_height: Some(2.0),
    }
}

/// Perspective camera at (0, 0, 2), 90° vertical field of view.
fn persp() -> Camera {
    Camera {
        eye: [0.0, 0.0, 2.0],
        ortho_height: None,
        ..ortho()
    }
}

fn directional(dir: [f64; 3], color: [f64; 3]) -> Light {
    Light {
        kind: LightKind::Directional { dir },
        color,
        bump: true,
    }
}

fn matte() -> Material {
    Material {
        ambient: [0.1, 0.05, 0.2],
        diffuse: [0.6, 0.7, 0.5],
        specular: [0.0; 3],
        shininess: 8.0,
        model: Default::default(),
    }
}

fn scene(
    mesh: Mesh,
    camera: Camera,
    bump: BumpMap,
    lights: Vec<Light>,
    material: Material,
) -> Scene {
    Scene {
        looks: Default::default(),
        mesh,
        model: DMat4::IDENTITY,
        camera,
        lights,
        material,
        bump,
        bake: None,
        color_texture: None,
        width: 16,
        height: 16,
        key: None,
    }
}

fn plane(a: f64, b: f64) -> BumpMap {
    BumpMap::Height(Box::new(Plane { a, b }))
}

fn close(a: DVec3, b: DVec3, tol: f64, what: &str) {
    assert!((a - b).abs().max_element() <= tol, "{what}: {a} vs {b}");
}

/// Every covered pixel has normal `n` and colour `c`; uncovered pixels are black with a zero
/// normal. Returns the covered count.
fn uniform(img: &ReferenceImage, n: DVec3, c: DVec3, tol: f64) -> usize {
    for i in 0..img.image.px.len() {
        if img.mask[i] {
            close(DVec3::from(img.normals[i]), n, tol, &format!("normal {i}"));
            close(DVec3::from(img.image.px[i]), c, tol, &format!("colour {i}"));
        } else {
            assert_eq!(img.image.px[i], [0.0; 3]);
            assert_eq!(img.normals[i], [0.0; 3]);
        }
    }
    img.covered()
}

/// Pixels `x0..x1` x `y0..y1` (image rows) are exactly the covered ones.
fn covers_exactly(img: &ReferenceImage, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) {
    for y in 0..img.image.height {
        for x in 0..img.image.width {
            let inside = xs.contains(&x) && ys.contains(&y);
            assert_eq!(img.mask[img.index(x, y)], inside, "pixel ({x}, {y})");
        }
    }
}

const RASTER: RasterConfig = RasterConfig {
    subpixel_bits: 4,
    depth_bits: 24,
    cull: crate::raster::Cull::None,
    setup_cycles: 8,
};

#[test]
fn flat_quad_plane_field_diffuse_closed_form() {
    let (a, b) = (0.3, -0.2);
    let l = DVec3::new(0.2, 0.4, 1.0).normalize();
    let col = DVec3::new(0.9, 0.8, 1.0);
    let m = matte();
    let n = DVec3::new(-a, -b, 1.0).normalize();
    let c = DVec3::from(m.ambient) + col * DVec3::from(m.diffuse) * n.dot(l).max(0.0);
    // Orthographic: [-0.5, 0.5]² of a 2 x 2 view on 16 x 16 pixels; perspective: [-1, 1]² at
    // distance 2 with a 90° field of view. Both cover window [4, 12)².
    for (camera, h) in [(ortho(), 0.5), (persp(), 1.0)] {
        for p in [Perturbation::Blinn, Perturbation::ScaleInvariant] {
            let s = scene(
                unit_quad(h),
                camera,
                plane(a, b),
                vec![directional(l.to_array(), col.to_array())],
                m.clone(),
            );
            let img = render_reference(&s, &RASTER, p);
            assert_eq!(uniform(&img, n, c, 1e-12), 64, "{p:?} {camera:?}");
            covers_exactly(&img, 4..12, 4..12);
        }
    }
}

#[test]
fn stretched_u_blinn_versus_scale_invariant() {
    // Pu = 2x̂: x = 2u on [-1, 1] x [-0.5, 0.5] (16 x 8 pixels), F = a u + b v.
    let (a, b) = (0.3, -0.2);
    let l = DVec3::new(-0.1, 0.3, 1.0).normalize();
    let lights = vec![directional(l.to_array(), [1.0; 3])];
    let m = matte();
    let stretched = || {
        quad(1.0, 0.5, 0.0, 2.0 * DVec3::X, DVec3::Y, |x, y| {
            DVec2::new(x / 2.0, y)
        })
    };
    // Blinn: N' = 2ẑ + a (ẑ × ŷ) + b (2x̂ × ẑ) = (-a, -2b, 2) ∝ (-a/2, -b, 1), the exact
    // normal of the displaced plane z = a x / 2 + b y.
    let blinn = DVec3::new(-a / 2.0, -b, 1.0).normalize();
    // Lingard: D = (-a, -2b, 0), D' = |∇F| |N| D / |D| = 2 g D / q with g = |(a, b)|,
    // q = |(a, 2b)|: N' ∝ (-a g/q, -2b g/q, 1), the tilt |∇F| of the unit quad.
    let (g, q) = (a.hypot(b), a.hypot(2.0 * b));
    let si = DVec3::new(-a * g / q, -2.0 * b * g / q, 1.0).normalize();
    assert!((si - blinn).length() > 0.05);
    assert!((si.truncate().length() / si.z - g).abs() < 1e-12);
    for (p, n) in [
        (Perturbation::Blinn, blinn),
        (Perturbation::ScaleInvariant, si),
    ] {
        let c = DVec3::from(m.ambient) + DVec3::from(m.diffuse) * n.dot(l).max(0.0);
        let s = scene(stretched(), ortho(), plane(a, b), lights.clone(), m.clone());
        let img = render_reference(&s, &RASTER, p);
        assert_eq!(uniform(&img, n, c, 1e-12), 128, "{p:?}");
        covers_exactly(&img, 0..16, 4..12);
        // The same stretch by the model transform: the unit quad scaled by (2, 1, 1).
        let mut s2 = scene(
            unit_quad(0.5),
            ortho(),
            plane(a, b),
            lights.clone(),
            m.clone(),
        );
        s2.model = DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0));
        let img2 = render_reference(&s2, &RASTER, p);
        assert_eq!(uniform(&img2, n, c, 1e-12), 128, "{p:?} model");
    }
}

#[test]
fn uniform_scaling_flattens_blinn_bumps_but_not_lingards() {
    // Lingard 1995: "when the surface is scaled by a factor of two, the surface normal is
    // scaled by a factor of four, but the perturbation vector is only scaled by a factor of
    // two. This has the effect of smoothing out the simulated wrinkles"; D' is scale
    // invariant. The unit quad (Pu = x̂, Pv = ŷ) scaled by s in the model transform, F = a u +
    // b v: Blinn's N' = s² ẑ + a s (ẑ × ŷ) + b s (x̂ × ẑ) ∝ (-a/s, -b/s, 1), tilt |∇F| / s;
    // Lingard's keeps (-a, -b, 1) at every scale.
    let (a, b) = (0.3, -0.2);
    let l = DVec3::new(-0.1, 0.3, 1.0).normalize();
    let lights = vec![directional(l.to_array(), [1.0; 3])];
    let m = matte();
    for scale in [0.5, 1.0, 2.0, 4.0] {
        let blinn = DVec3::new(-a / scale, -b / scale, 1.0).normalize();
        let si = DVec3::new(-a, -b, 1.0).normalize();
        for (p, n) in [
            (Perturbation::Blinn, blinn),
            (Perturbation::ScaleInvariant, si),
        ] {
            let mut s = scene(
                unit_quad(0.5),
                ortho(),
                plane(a, b),
                lights.clone(),
                m.clone(),
            );
            s.model = DMat4::from_scale(DVec3::splat(scale));
            let c = DVec3::from(m.ambient) + DVec3::from(m.diffuse) * n.dot(l).max(0.0);
            let img = render_reference(&s, &RASTER, p);
            assert!(uniform(&img, n, c, 1e-12) > 0, "{p:?} at scale {scale}");
        }
        // the tilt (angle of N' from the unscaled normal): Blinn's falls as 1/s
        let tilt = |n: DVec3| n.truncate().length() / n.z;
        assert!((tilt(blinn) * scale - a.hypot(b)).abs() < 1e-12);
        assert!((tilt(si) - a.hypot(b)).abs() < 1e-12);
    }
}

#[test]
fn specular_closed_form_with_orthographic_viewer() {
    let (a, b) = (0.1, 0.15);
    let l = DVec3::new(-0.3, 0.5, 1.0).normalize();
    let col = DVec3::new(1.0, 0.9, 0.7);
    let n = DVec3::new(-a, -b, 1.0).normalize();
    // Orthographic: V = normalize(eye - target) = ẑ at every pixel, so H is constant.
    let h = (l + DVec3::Z).normalize();
    let highlight = n.dot(h).powf(20.0);
    assert!(highlight > 0.2 && highlight < 1.0, "{highlight}");
    let spec = DVec3::new(0.3, 0.4, 0.5);
    let lights = vec![directional(l.to_array(), col.to_array())];
    // Specular only: the pixel is exactly color ⊙ specular · (N'·H)^n.
    let shiny = Material {
        ambient: [0.0; 3],
        diffuse: [0.0; 3],
        specular: spec.to_array(),
        shininess: 20.0,
        model: Default::default(),
    };
    let s = scene(unit_quad(0.5), ortho(), plane(a, b), lights.clone(), shiny);
    let img = render_reference(&s, &RASTER, Perturbation::Blinn);
    assert_eq!(uniform(&img, n, col * spec * highlight, 1e-12), 64);
    // With ambient and diffuse.
    let m = Material {
        specular: spec.to_array(),
        shininess: 20.0,
        model: Default::default(),
        ..matte()
    };
    let c = DVec3::from(m.ambient) + col * (DVec3::from(m.diffuse) * n.dot(l) + spec * highlight);
    let s = scene(unit_quad(0.5), ortho(), plane(a, b), lights, m.clone());
    let img = render_reference(&s, &RASTER, Perturbation::ScaleInvariant);
    assert_eq!(uniform(&img, n, c, 1e-12), 64);
}

fn constant_map(t: DVec3) -> BumpMap {
    BumpMap::Normals(NormalMap {
        width: 2,
        height: 2,
        texels: vec![t; 4],
    })
}

#[test]
fn normal_map_gives_the_texel_normal() {
    let t = DVec3::new(0.3, -0.4, 0.8).normalize();
    let l = DVec3::new(0.1, 0.2, 1.0).normalize();
    let m = matte();
    let lights = vec![directional(l.to_array(), [1.0; 3])];
    let c = |n: DVec3| DVec3::from(m.ambient) + DVec3::from(m.diffuse) * n.dot(l).max(0.0);
    let s = scene(
        unit_quad(0.5),
        ortho(),
        constant_map(t),
        lights.clone(),
        m.clone(),
    );
    let img = render_reference(&s, &RASTER, Perturbation::default());
    assert_eq!(uniform(&img, t, c(t), 1e-12), 64);
    // Rotated model: the frame (T, B, N) = R (x̂, ŷ, ẑ), so the normal is R t.
    let r = DMat4::from_rotation_y(0.5) * DMat4::from_rotation_x(0.3);
    let mut s = scene(unit_quad(0.5), ortho(), constant_map(t), lights, m.clone());
    s.model = r;
    let img = render_reference(&s, &RASTER, Perturbation::default());
    let rt = r.transform_vector3(t);
    assert!(uniform(&img, rt, c(rt), 1e-12) > 30);
}

#[test]
fn mirrored_frames_agree_between_height_field_and_normal_map() {
    let (a, b) = (0.3, -0.2);
    let l = DVec3::new(0.1, 0.2, 1.0).normalize();
    let lights = vec![directional(l.to_array(), [1.0; 3])];
    let m = matte();
    // v runs down the screen: Pv = -ŷ, so (Pu × Pv)·n̂ < 0. F = a x - b y: normal (-a, b, 1).
    let flipped_v = || quad(0.5, 0.5, 0.0, DVec3::X, -DVec3::Y, |x, y| DVec2::new(x, -y));
    let want = DVec3::new(-a, b, 1.0).normalize();
    // A mirroring model transform: world Pu = -x̂, F = -a x + b y: normal (a, -b, 1).
    let want_mirror = DVec3::new(a, -b, 1.0).normalize();
    for p in [Perturbation::Blinn, Perturbation::ScaleInvariant] {
        for bump in [
            plane(a, b),
            constant_map(DVec3::new(-a, -b, 1.0).normalize()),
        ] {
            let s = scene(flipped_v(), ortho(), bump, lights.clone(), m.clone());
            let c = DVec3::from(m.ambient) + DVec3::from(m.diffuse) * want.dot(l);
            assert_eq!(
                uniform(&render_reference(&s, &RASTER, p), want, c, 1e-12),
                64
            );
        }
        for bump in [
            plane(a, b),
            constant_map(DVec3::new(-a, -b, 1.0).normalize()),
        ] {
            let mut s = scene(unit_quad(0.5), ortho(), bump, lights.clone(), m.clone());
            s.model = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
            let c = DVec3::from(m.ambient) + DVec3::from(m.diffuse) * want_mirror.dot(l);
            let img = render_reference(&s, &RASTER, p);
            assert_eq!(uniform(&img, want_mirror, c, 1e-12), 64);
        }
    }
}

#[test]
fn nearest_surface_wins() {
    // Front quad (z = 0.5, [-0.5, 0.5]², Pu = 2x̂) over a back quad (z = 0, [-1, 1]²).
    let (a, b) = (0.4, 0.1);
    let mut mesh = quad(0.5, 0.5, 0.5, 2.0 * DVec3::X, DVec3::Y, |x, y| {
        DVec2::new(x / 2.0, y)
    });
    let back = unit_quad(1.0);
    let base = mesh.vertices.len() as u32;
    mesh.vertices.extend(back.vertices);
    mesh.triangles
        .extend(back.triangles.iter().map(|t| t.map(|i| i + base)));
    let front_n = DVec3::new(-a / 2.0, -b, 1.0).normalize();
    let back_n = DVec3::new(-a, -b, 1.0).normalize();
    for order in [false, true] {
        let mut mesh = mesh.clone();
        if order {
            mesh.triangles.reverse();
        }
        let s = scene(
            mesh,
            ortho(),
            plane(a, b),
            vec![directional([0.0, 0.0, 1.0], [1.0; 3])],
            matte(),
        );
        let img = render_reference(&s, &RASTER, Perturbation::Blinn);
        assert_eq!(img.covered(), 256);
        for y in 0..16 {
            for x in 0..16 {
                let centre = (4..12).contains(&x) && (4..12).contains(&y);
                let want = if centre { front_n } else { back_n };
                close(
                    DVec3::from(img.normals[img.index(x, y)]),
                    want,
                    1e-12,
                    "normal",
                );
            }
        }
    }
}

/// A bumpy 10 x 10 grid patch `P = (2u - 1, 2v - 1, 0.2 sin 3u cos 2v)` with its analytic
/// frame.
fn wavy_patch() -> Mesh {
    let n = 10;
    let mut mesh = Mesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            let pos = DVec3::new(
                2.0 * u - 1.0,
                2.0 * v - 1.0,
                0.2 * (3.0 * u).sin() * (2.0 * v).cos(),
            );
            let pu = DVec3::new(2.0, 0.0, 0.6 * (3.0 * u).cos() * (2.0 * v).cos());
            let pv = DVec3::new(0.0, 2.0, -0.4 * (3.0 * u).sin() * (2.0 * v).sin());
            mesh.vertices.push(vert(
                pos,
                pu.cross(pv).normalize(),
                DVec2::new(u, v),
                pu,
                pv,
            ));
        }
    }
    let idx = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            mesh.triangles
                .push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            mesh.triangles
                .push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    mesh
}

#[test]
fn bit_identical_at_any_thread_count() {
    let mut tex = image::RgbImage::new(3, 2);
    for (i, p) in tex.pixels_mut().enumerate() {
        *p = image::Rgb([(40 * i) as u8, 200 - (30 * i) as u8, (90 + 25 * i) as u8]);
    }
    let mut s = scene(
        wavy_patch(),
        Camera {
            eye: [0.5, -1.5, 2.5],
            fov_y_deg: 60.0,
            ..persp()
        },
        BumpMap::Height(Box::new(Waves { k: 0.03 })),
        vec![
            directional([0.3, 0.5, 1.0], [0.9, 0.9, 0.8]),
            Light {
                kind: LightKind::Point {
                    pos: [-1.0, 1.0, 1.5],
                },
                color: [0.4, 0.3, 0.6],
                bump: false,
            },
        ],
        Material::default(),
    );
    s.color_texture = Some(tex);
    s.width = 40;
    s.height = 32;
    s.model = DMat4::from_rotation_z(0.2);
    let bits = |img: &ReferenceImage| {
        let f = |v: &Vec<[f64; 3]>| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
        (f(&img.image.px), f(&img.normals), img.mask.clone())
    };
    for p in [Perturbation::Blinn, Perturbation::ScaleInvariant] {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| render_reference(&s, &RASTER, p))
        };
        let (one, two) = (run(1), run(2));
        assert!(one.covered() > 300, "{}", one.covered());
        assert!(one.image.px.iter().flatten().any(|&c| c > 0.2));
        assert_eq!(bits(&one), bits(&two), "{p:?}");
    }
}

/// Where the ray through the centre of pixel `(x, y)` meets the plane of world triangle `t`,
/// and the barycentrics of that point.
fn ray_hit(vp: DMat4, t: [DVec3; 3], x: u32, y: u32, w: u32, h: u32) -> (DVec3, DVec3) {
    let px = 2.0 * (f64::from(x) + 0.5) / f64::from(w) - 1.0;
    let py = 2.0 * (f64::from(h) - f64::from(y) - 0.5) / f64::from(h) - 1.0;
    let inv = vp.inverse();
    let un = |z: f64| {
        let q = inv * DVec4::new(px, py, z, 1.0);
        q.truncate() / q.w
    };
    let (o, e) = (un(-1.0), un(1.0));
    let d = e - o;
    let nrm = (t[1] - t[0]).cross(t[2] - t[0]);
    let hit = o + d * ((t[0] - o).dot(nrm) / d.dot(nrm));
    let area = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(c - a).dot(nrm);
    let full = area(t[0], t[1], t[2]);
    let bary = DVec3::new(
        area(hit, t[1], t[2]) / full,
        area(t[0], hit, t[2]) / full,
        area(t[0], t[1], hit) / full,
    );
    (hit, bary)
}

#[test]
fn pixel_barycentrics_are_perspective_correct() {
    let t = [
        DVec3::new(-1.0, -0.8, -0.5),
        DVec3::new(1.2, -0.5, 0.3),
        DVec3::new(0.1, 1.0, -1.5),
    ];
    let cam = Camera {
        eye: [0.3, 0.2, 3.0],
        fov_y_deg: 50.0,
        ..persp()
    };
    let (w, h) = (32, 24);
    let vp = cam.proj(f64::from(w) / f64::from(h)) * cam.view();
    let clip = t.map(|p| vp * p.extend(1.0));
    let mut inside = 0;
    for y in 0..h {
        for x in 0..w {
            let (_, want) = ray_hit(vp, t, x, y, w, h);
            if want.min_element() < 0.0 {
                continue;
            }
            inside += 1;
            let got = pixel_barycentrics(clip, x, y, w, h).expect("non-degenerate");
            close(got, want, 1e-12, &format!("pixel ({x}, {y})"));
        }
    }
    assert!(inside >= 80, "{inside}");
    // Edge-on (all three vertices on one line through the eye): degenerate.
    let line = [
        DVec4::new(0.0, 0.0, 0.0, 1.0),
        DVec4::new(0.0, 0.0, 0.5, 2.0),
        DVec4::new(0.0, 0.0, 1.0, 3.0),
    ];
    assert_eq!(pixel_barycentrics(line, 3, 3, 8, 8), None);
}

#[test]
fn tilted_quad_is_shaded_at_the_exact_pixel_centre_point() {
    // F = c u² / 2 on the quad x = 2u - 1, y = 2v - 1 (Pu = 2x̂, Pv = 2ŷ): Blinn's normal in
    // object space is ∝ (-c u / 2, 0, 1), so the normal encodes u at the pixel centre. With 0
    // sub-pixel bits the rasterizer's snapped barycentrics are off by up to half a pixel; the
    // reference must not be.
    let c = 1.5;
    let mesh = quad(1.0, 1.0, 0.0, 2.0 * DVec3::X, 2.0 * DVec3::Y, |x, y| {
        DVec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0)
    });
    let corners: Vec<DVec3> = mesh.vertices.iter().map(|v| v.pos).collect();
    let mut s = scene(
        mesh,
        Camera {
            eye: [0.0, 0.0, 3.0],
            fov_y_deg: 60.0,
            ..persp()
        },
        BumpMap::Height(Box::new(Parabola { c })),
        vec![directional([0.0, 0.0, 1.0], [1.0; 3])],
        matte(),
    );
    s.width = 32;
    s.height = 32;
    let r = DMat4::from_rotation_x(-1.0) * DMat4::from_rotation_z(0.3);
    s.model = r;
    let raster = RasterConfig {
        subpixel_bits: 0,
        ..RASTER
    };
    let img = render_reference(&s, &raster, Perturbation::Blinn);
    let vp = s.camera.proj(1.0) * s.camera.view();
    let world = [
        r.transform_point3(corners[0]),
        r.transform_point3(corners[1]),
        r.transform_point3(corners[2]),
    ];
    let inv = r.inverse();
    let mut checked = 0;
    for y in 0..32 {
        for x in 0..32 {
            if !img.mask[img.index(x, y)] {
                continue;
            }
            let (hit, _) = ray_hit(vp, world, x, y, 32, 32);
            let u = (inv.transform_point3(hit).x + 1.0) / 2.0;
            let want = r.transform_vector3(DVec3::new(-c * u / 2.0, 0.0, 1.0).normalize());
            close(
                DVec3::from(img.normals[img.index(x, y)]),
                want,
                1e-9,
                &format!("({x}, {y})"),
            );
            checked += 1;
        }
    }
    assert!(checked > 150, "{checked}");
}

#[test]
fn shade_with_point_light_and_local_viewer() {
    let m = Material {
        ambient: [0.05, 0.1, 0.15],
        diffuse: [0.5, 0.4, 0.3],
        specular: [0.2, 0.3, 0.4],
        shininess: 13.5,
        model: Default::default(),
    };
    let pos = DVec3::new(1.0, 2.0, 3.0);
    let s = scene(
        unit_quad(0.5),
        persp(),
        plane(0.0, 0.0),
        vec![
            Light {
                kind: LightKind::Point {
                    pos: pos.to_array(),
                },
                color: [0.9, 0.7, 0.5],
                bump: false,
            },
            // Below the surface: N·L < 0, contributes neither diffuse nor specular.
            directional([0.0, 0.1, -1.0], [1.0; 3]),
        ],
        m.clone(),
    );
    let (n, p, eye) = (
        DVec3::new(0.1, 0.2, 1.0).normalize(),
        DVec3::new(0.2, -0.1, 0.0),
        DVec3::new(0.0, 0.0, 5.0),
    );
    let l = (pos - p).normalize();
    let v = (eye - p).normalize();
    let h = (l + v).normalize();
    let want = DVec3::from(m.ambient)
        + DVec3::new(0.9, 0.7, 0.5)
            * (DVec3::from(m.diffuse) * n.dot(l) + DVec3::from(m.specular) * n.dot(h).powf(13.5));
    close(shade(n, p, eye, DVec2::ZERO, &s), want, 1e-15, "shade");
    // n is normalised inside.
    close(
        shade(3.0 * n, p, eye, DVec2::ZERO, &s),
        want,
        1e-15,
        "unnormalised n",
    );
    // Facing away from every light: ambient only.
    let away = -(l + DVec3::new(0.0, 0.1, -1.0).normalize()).normalize();
    close(
        shade(away, p, eye, DVec2::ZERO, &s),
        DVec3::from(m.ambient),
        0.0,
        "back",
    );
    // Clamped to [0, 1].
    let bright = Material {
        ambient: [2.0, 0.5, -1.0],
        ..m.clone()
    };
    let s2 = Scene {
        material: bright,
        lights: vec![],
        ..s
    };
    assert_eq!(
        shade(n, p, eye, DVec2::ZERO, &s2),
        DVec3::new(1.0, 0.5, 0.0)
    );
    // Perspective view vector is per pixel, orthographic constant.
    close(
        view_vector(&persp(), p),
        (DVec3::new(0.0, 0.0, 2.0) - p).normalize(),
        0.0,
        "persp V",
    );
    assert_eq!(view_vector(&ortho(), p), DVec3::Z);
}

#[test]
fn base_color_is_bilinear_and_wraps() {
    let mut tex = image::RgbImage::new(2, 2);
    tex.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    tex.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    tex.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    tex.put_pixel(1, 1, image::Rgb([255, 255, 255]));
    let t = Some(&tex);
    assert_eq!(base_color(None, DVec2::new(0.3, 0.7)), DVec3::ONE);
    assert_eq!(base_color(t, DVec2::new(0.25, 0.25)), DVec3::X);
    // Row 1 (v in [0.5, 1)) is the bottom image row: blue at u = 0.25.
    assert_eq!(base_color(t, DVec2::new(0.25, 0.75)), DVec3::Z);
    close(
        base_color(t, DVec2::new(0.5, 0.25)),
        DVec3::new(0.5, 0.5, 0.0),
        1e-15,
        "mid",
    );
    close(
        base_color(t, DVec2::new(0.0, 0.25)),
        DVec3::new(0.5, 0.5, 0.0),
        1e-15,
        "wrap u",
    );
    close(
        base_color(t, DVec2::new(-0.75, 1.25)),
        DVec3::X,
        1e-15,
        "wrap both",
    );
    close(
        base_color(t, DVec2::new(0.5, 0.5)),
        DVec3::new(0.5, 0.5, 0.5),
        1e-15,
        "centre",
    );
    let lit = Material {
        ambient: [1.0; 3],
        ..matte()
    };
    let mut s = scene(unit_quad(0.5), ortho(), plane(0.0, 0.0), vec![], lit);
    s.color_texture = Some(tex);
    close(
        shade(DVec3::Z, DVec3::ZERO, DVec3::Z, DVec2::new(0.75, 0.75), &s),
        DVec3::ONE,
        0.0,
        "ambient ⊙ base",
    );
}

#[test]
fn perturbation_formulas() {
    let g = DVec2::new(0.7, -0.25);
    let flat = DVec3::new(-g.x, -g.y, 1.0).normalize();
    for p in [Perturbation::Blinn, Perturbation::ScaleInvariant] {
        close(
            perturb_height(DVec3::Z, DVec3::X, DVec3::Y, g, p),
            flat,
            1e-15,
            "sign",
        );
        // Degenerate frame: the unperturbed normal.
        assert_eq!(
            perturb_height(DVec3::Z, DVec3::ZERO, DVec3::Y, g, p),
            DVec3::Z
        );
        // Zero gradient: unperturbed.
        close(
            perturb_height(DVec3::Z, 3.0 * DVec3::X, DVec3::Y, DVec2::ZERO, p),
            DVec3::Z,
            0.0,
            "zero",
        );
    }
    // Lingard: uniformly scaling the surface by k changes Blinn's slope by 1/k, not D'.
    let k = 4.0;
    let blinn = perturb_height(DVec3::Z, k * DVec3::X, k * DVec3::Y, g, Perturbation::Blinn);
    close(
        blinn,
        DVec3::new(-g.x / k, -g.y / k, 1.0).normalize(),
        1e-15,
        "Blinn scaled",
    );
    let si = perturb_height(
        DVec3::Z,
        k * DVec3::X,
        k * DVec3::Y,
        g,
        Perturbation::ScaleInvariant,
    );
    close(si, flat, 1e-15, "scale invariant");
    // Tangent frame: handedness follows Pv; Pu parallel to n falls back to Pv.
    assert_eq!(
        tangent_frame(DVec3::Z, DVec3::X, DVec3::Y),
        (DVec3::X, DVec3::Y)
    );
    assert_eq!(
        tangent_frame(DVec3::Z, DVec3::X, -DVec3::Y),
        (DVec3::X, -DVec3::Y)
    );
    assert_eq!(
        tangent_frame(DVec3::Z, DVec3::Z, DVec3::Y),
        (DVec3::X, DVec3::Y)
    );
    // A skewed Pu is made perpendicular to n.
    let (t, b) = tangent_frame(DVec3::Z, DVec3::new(1.0, 0.0, 0.5), DVec3::Y);
    close(t, DVec3::X, 1e-15, "T");
    close(b, DVec3::Y, 1e-15, "B");
}

#[test]
fn supersampled_reference_is_the_mean_of_its_samples() {
    let l = DVec3::new(0.2, 0.4, 1.0).normalize();
    let lights = vec![directional(l.to_array(), [1.0; 3])];
    // a plane field shades uniformly: any sample count gives the same pixels
    let s = scene(
        unit_quad(0.5),
        ortho(),
        plane(0.3, -0.2),
        lights.clone(),
        matte(),
    );
    let n = DVec3::new(-0.3, 0.2, 1.0).normalize();
    let m = matte();
    let c = DVec3::from(m.ambient) + DVec3::from(m.diffuse) * n.dot(l);
    let img = render_reference_sampled(&s, &RASTER, Perturbation::Blinn, 3);
    assert_eq!(uniform(&img, n, c, 1e-12), 64);
    // bumps: a pixel is the mean of its 3 x 3 sample shades, and differs from the centre
    let bump = crate::scene::BumpSpec::MexicanHat {
        cells: 2,
        sigma: 0.2,
        depth: 0.05,
    }
    .build(std::path::Path::new("."))
    .unwrap();
    let s = scene(unit_quad(0.5), ortho(), bump, lights, matte());
    let one = render_reference(&s, &RASTER, Perturbation::ScaleInvariant);
    let nine = render_reference_sampled(&s, &RASTER, Perturbation::ScaleInvariant, 3);
    let clip = clip_positions(&s);
    let (x, y) = (6u32, 7u32);
    let t = s.mesh.triangles.iter().position(|t| {
        pixel_barycentrics(t.map(|i| clip[i as usize]), x, y, 16, 16)
            .is_some_and(|b| b.min_element() >= 0.0)
    });
    let tri = t.unwrap() as u32;
    let cl = s.mesh.triangles[tri as usize].map(|i| clip[i as usize]);
    let mut sum = DVec3::ZERO;
    for j in 0..3 {
        for i in 0..3 {
            let (sx, sy) = (
                x as f64 + (i as f64 + 0.5) / 3.0,
                y as f64 + (j as f64 + 0.5) / 3.0,
            );
            let b = sample_barycentrics(cl, sx, sy, 16, 16).unwrap();
            let sp = surface_point(&s, tri, b);
            let n = perturbed_normal(&s.bump, &sp, Perturbation::ScaleInvariant);
            sum += shade_with_view(n, &sp, view_vector(&s.camera, sp.p), &s);
        }
    }
    let k = nine.index(x, y);
    close(
        DVec3::from(nine.image.px[k]),
        sum / 9.0,
        1e-12,
        "mean of 9 samples",
    );
    assert!((DVec3::from(nine.image.px[k]) - DVec3::from(one.image.px[k])).length() > 1e-4);
    assert_eq!(nine.normals, one.normals);
}

/// Two overlapping quads, the nearer one drawn first (the early depth test rejects part of
/// the farther one), and a third, farthest and taller, drawn last.
fn overlapping_quads() -> Mesh {
    let mut mesh = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for (dx, hy, z) in [(0.2, 0.4, 0.5), (-0.2, 0.4, 0.0), (0.0, 0.8, -0.5)] {
        let q = quad(0.5, hy, z, DVec3::X, DVec3::Y, DVec2::new);
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(q.vertices.iter().map(|v| Vertex {
            pos: v.pos + DVec3::new(dx, 0.0, 0.0),
            ..*v
        }));
        mesh.triangles
            .extend(q.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    mesh
}

#[test]
fn the_coverage_of_late_tested_fragments_is_the_early_tests() {
    let mut s = scene(
        overlapping_quads(),
        ortho(),
        BumpMap::Height(Box::new(Waves { k: 0.02 })),
        vec![directional([0.3, 0.5, 1.0], [0.9, 0.9, 0.8])],
        matte(),
    );
    (s.width, s.height) = (48, 40);
    let clip = clip_positions(&s);
    let (w, h) = (s.width, s.height);
    let tris = &s.mesh.triangles;
    let early = crate::raster::rasterize(&clip, tris, w, h, &RASTER);
    let late =
        crate::raster::rasterize_with(&clip, tris, w, h, &RASTER, crate::raster::DepthTest::Late);
    assert!(late.fragments.len() > early.fragments.len() + 100);
    let ce = Coverage::of_fragments(&early.fragments, w, h, &RASTER);
    let cl = Coverage::of_fragments(&late.fragments, w, h, &RASTER);
    let winners = |c: &Coverage, frags: &[Fragment]| -> Vec<Option<(u32, [u64; 3])>> {
        (0..h)
            .flat_map(|y| c.row(y).to_vec())
            .map(|k| {
                (k != Coverage::NONE).then(|| {
                    let f = &frags[k as usize];
                    (f.tri, f.bary.map(f64::to_bits))
                })
            })
            .collect()
    };
    let we = winners(&ce, &early.fragments);
    assert_eq!(we, winners(&cl, &late.fragments));
    // every quad wins somewhere, and the nearest one wins where they overlap
    for t in [0, 2, 4] {
        assert!(we.iter().flatten().any(|p| p.0 == t || p.0 == t + 1), "{t}");
    }
    // the reference on either coverage is the reference of the scene, without normals
    let whole = render_reference(&s, &RASTER, Perturbation::Blinn);
    let opts = Options {
        perturbation: Perturbation::Blinn,
        samples: 1,
        normals: false,
    };
    for (c, frags) in [(&ce, &early.fragments), (&cl, &late.fragments)] {
        let img = render_covered(&s, c, frags, opts);
        assert_eq!((&img.image.px, &img.mask), (&whole.image.px, &whole.mask));
        assert!(img.normals.is_empty());
    }
    let with_normals = render_covered(
        &s,
        &cl,
        &late.fragments,
        Options {
            normals: true,
            ..opts
        },
    );
    assert_eq!(with_normals, whole);
}

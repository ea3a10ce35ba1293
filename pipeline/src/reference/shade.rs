//! Step 4: the lighting model all engines approximate.

use glam::{DVec2, DVec3};
use image::RgbImage;

use crate::scene::perturb::{tangent_frame, SurfacePoint};
use crate::scene::{Camera, Scene, Shading};

/// The base (texture) colour at `uv`: bilinear with wrap-around, texel `(i, j)` centred at
/// `((i + 0.5) / w, (j + 0.5) / h)`, image row 0 at `v` in `[0, 1/h)` (`v` increases down
/// the image, as for normal maps). PNG values are taken as *linear* `c / 255` (no sRGB
/// decoding). White without a texture (or for an empty one, or a non-finite `uv`).
pub fn base_color(texture: Option<&RgbImage>, uv: DVec2) -> DVec3 {
    let Some(img) = texture else {
        return DVec3::ONE;
    };
    let (w, h) = (img.width(), img.height());
    if w == 0 || h == 0 || !uv.is_finite() {
        return DVec3::ONE;
    }
    let texel = |i: i64, j: i64| {
        let i = i.rem_euclid(i64::from(w)) as u32;
        let j = j.rem_euclid(i64::from(h)) as u32;
        let p = img.get_pixel(i, j);
        DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])) / 255.0
    };
    let x = uv.x.rem_euclid(1.0) * f64::from(w) - 0.5;
    let y = uv.y.rem_euclid(1.0) * f64::from(h) - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i, j) = (x0 as i64, y0 as i64);
    let top = texel(i, j).lerp(texel(i + 1, j), fx);
    let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
    top.lerp(bottom, fy)
}

/// The unit view vector `V` at `p`: `normalize(eye - p)` for a perspective camera; for an
/// orthographic camera the viewer is at infinity along the view axis, so
/// `V = normalize(eye - target)`, the same at every pixel.
pub fn view_vector(camera: &Camera, p: DVec3) -> DVec3 {
    camera.view_dir(p)
}

/// The lighting model with a local viewer at `eye`: [`shade_with_view`] with
/// `V = normalize(eye - p)` at a point whose parameterisation is world `Pu = x`, `Pv = y`.
pub fn shade(n: DVec3, p: DVec3, eye: DVec3, uv: DVec2, scene: &Scene) -> DVec3 {
    let sp = SurfacePoint {
        p,
        n: n.normalize_or_zero(),
        pu: DVec3::X,
        pv: DVec3::Y,
        uv,
    };
    shade_with_view(n, &sp, (eye - p).normalize_or_zero(), scene)
}

/// The lighting model all engines approximate, evaluated exactly with every vector per
/// pixel. The material is the scene's material at this point (`Scene::material_id`: Tarini
/// §6 regions), and its model ([`Shading`]) decides the formula:
///
/// ```text
/// Phong:    C = ambient ⊙ base + Σ_i a_i color_i ⊙ (diffuse ⊙ base · max(0, N'·L_i) + specular · s_i)
///           s_i = max(0, N'·H_i)^shininess if N'·L_i > 0, else 0;   H_i = normalize(L_i + V)
/// Lambert:  Phong without the specular term
/// Cartoon:  d = min(1, Σ_i a_i max(0, N'·L_i)), k = min(floor(d bands), bands - 1),
///           C = (ambient + diffuse k / (bands - 1)) ⊙ base
/// DoubledAnglePhong (Tarini Fig. 6), the first bump light L:  R = 2 (N'·L) N' - L,
///           c = R·V, s = max(0, 2 c² - 1)^shininess if c > 0 else 0,
///           C = ambient ⊙ base + a color ⊙ (diffuse ⊙ base · max(0, N'·L) + specular · s)
/// Chrome (Fig. 7):  R = 2 (N'·V) N' - V, t = clamp((1 + R_y) / 2, 0, 1),
///           C = ground + t (sky - ground)        (world +y is up)
/// EnvMap (Fig. 5):  R in the camera's eye frame (z = V, x = normalize(up × V), y = z × x)
///           reads the sphere map (`EnvImage::sphere_lookup`)
/// ```
///
/// (`a_i` the spot attenuation), each channel clamped to `[0, 1]`. `n` is the perturbed
/// normal (normalised here), `sp` the surface point (`p` its world position; its frame gives
/// an NDF bump's anisotropic tangent, `NdfSurface::shade_colour`), `v` the unit view vector,
/// `L_i = light.dir_from(p)` (per pixel, also for point lights), `base = base_color(texture,
/// uv)`. The power is `f64::powf` (so `shininess = 0` gives `s = 1` wherever `N'·L > 0`). Every
/// light is evaluated with the perturbed normal: `Light::bump` only tells engines which lights
/// go through the bump unit.
pub fn shade_with_view(n: DVec3, sp: &SurfacePoint, v: DVec3, scene: &Scene) -> DVec3 {
    let n = n.normalize_or_zero();
    let (p, uv) = (sp.p, sp.uv);
    if let crate::scene::BumpMap::Ndf(s) = &scene.bump {
        let tangent = tangent_frame(sp.n, sp.pu, sp.pv).0;
        return s.shade_colour(n, p, v, tangent, scene);
    }
    let id = scene.material_id(uv, n);
    let m = scene.material(id);
    let base = base_color(scene.color_texture.as_ref(), uv);
    let diffuse = DVec3::from(m.diffuse) * base;
    let specular = DVec3::from(m.specular);
    let ambient = DVec3::from(m.ambient) * base;
    let reflect = |d: DVec3| 2.0 * n.dot(d) * n - d;
    let c = match &m.model {
        Shading::Phong | Shading::Lambert => {
            let mut c = ambient;
            for light in &scene.lights {
                let l = light.dir_from(p);
                let ndl = n.dot(l);
                if ndl > 0.0 {
                    let s = if m.model == Shading::Phong {
                        let h = (l + v).normalize_or_zero();
                        n.dot(h).max(0.0).powf(m.shininess)
                    } else {
                        0.0
                    };
                    c += light.color() * light.attenuation(p) * (diffuse * ndl + specular * s);
                }
            }
            c
        }
        Shading::Cartoon { bands } => {
            let d: f64 = scene
                .lights
                .iter()
                .map(|l| l.attenuation(p) * n.dot(l.dir_from(p)).max(0.0))
                .sum::<f64>()
                .min(1.0);
            let k = ((d * f64::from(*bands)).floor() as u32).min(bands - 1);
            ambient + diffuse * (f64::from(k) / f64::from(bands - 1))
        }
        Shading::DoubledAnglePhong => {
            let Some(light) = scene
                .lights
                .iter()
                .find(|l| l.bump)
                .or(scene.lights.first())
            else {
                return ambient.clamp(DVec3::ZERO, DVec3::ONE);
            };
            let l = light.dir_from(p);
            let rv = reflect(l).dot(v);
            let s = if rv > 0.0 {
                (2.0 * rv * rv - 1.0).max(0.0).powf(m.shininess)
            } else {
                0.0
            };
            ambient
                + light.color()
                    * light.attenuation(p)
                    * (diffuse * n.dot(l).max(0.0) + specular * s)
        }
        Shading::Chrome { sky, ground } => {
            let t = ((1.0 + reflect(v).y) / 2.0).clamp(0.0, 1.0);
            DVec3::from(*ground).lerp(DVec3::from(*sky), t)
        }
        Shading::EnvMap { .. } => match scene.looks.env_maps.get(id as usize) {
            Some(Some(img)) => {
                let z = v;
                let x = DVec3::from(scene.camera.up).cross(z).normalize_or_zero();
                let y = z.cross(x);
                let r = reflect(v);
                img.sphere_lookup(DVec3::new(r.dot(x), r.dot(y), r.dot(z)))
            }
            _ => DVec3::ZERO,
        },
    };
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

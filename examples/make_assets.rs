//! Generate the procedural images the quantized normal map configs use (docs/assets.md):
//!
//! * `configs/assets/envmap.png`: an OpenGL sphere map (Tarini et al. Fig. 5 used "a photo
//!   shot to a Christmas tree ball"): a sky with a sun above the horizon, a checkered floor
//!   below, and four coloured windows around the horizon, as seen reflected in a mirror ball
//!   by a viewer on `+z` with `+y` up.
//! * `configs/assets/wood.png`: a wood-grain colour texture (Fig. 9's "wood grain stored in a
//!   color texture"): growth rings of a log cut along its axis, with a little waviness.
//!
//! Deterministic (no randomness): `cargo run --release --example make_assets`.

use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/assets");
    std::fs::create_dir_all(&dir)?;
    envmap(256).save(dir.join("envmap.png"))?;
    wood(256).save(dir.join("wood.png"))?;
    println!("wrote {}/envmap.png and wood.png", dir.display());
    Ok(())
}

fn to_rgb(c: [f64; 3]) -> image::Rgb<u8> {
    image::Rgb(c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8))
}

fn mix(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t)
}

/// The environment seen along the unit direction `r` (x right, y up, z towards the viewer).
fn environment(r: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = r;
    let sun = {
        let s = [0.45, 0.55, -0.7];
        let l = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
        let c = (x * s[0] + y * s[1] + z * s[2]) / l.sqrt();
        c > 0.995
    };
    if sun {
        return [1.0, 0.95, 0.7];
    }
    // four windows around the horizon, 20 degrees tall, 30 wide
    let az = x.atan2(-z).to_degrees();
    let el = y.asin().to_degrees();
    for (centre, colour) in [
        (0.0, [0.95, 0.2, 0.15]),
        (90.0, [0.2, 0.8, 0.3]),
        (180.0, [0.95, 0.85, 0.2]),
        (-90.0, [0.25, 0.4, 0.95]),
    ] {
        let d: f64 = ((az - centre + 540.0) % 360.0) - 180.0;
        if d.abs() < 15.0 && (2.0..22.0).contains(&el) {
            return colour;
        }
    }
    if y >= 0.0 {
        mix([0.85, 0.9, 1.0], [0.15, 0.35, 0.8], y.powf(0.6))
    } else {
        // the floor plane y = -1, 1 x 1 checks fading into haze at the horizon
        let (u, v) = (x / -y, z / -y);
        let check = ((u.floor() + v.floor()) as i64).rem_euclid(2) == 0;
        let tile = if check {
            [0.85, 0.8, 0.7]
        } else {
            [0.35, 0.22, 0.12]
        };
        mix([0.7, 0.7, 0.72], tile, (-y * 4.0).min(1.0))
    }
}

/// A sphere map: pixel `(s, t)` (t up) shows the mirror ball's normal `n = (2s - 1, 2t - 1,
/// z)` reflecting the viewer's ray `(0, 0, 1)`: `r = 2 n_z n - (0, 0, 1)`. Outside the disk:
/// black.
fn envmap(size: u32) -> image::RgbImage {
    image::RgbImage::from_fn(size, size, |i, j| {
        let s = (f64::from(i) + 0.5) / f64::from(size);
        let t = 1.0 - (f64::from(j) + 0.5) / f64::from(size);
        let (x, y) = (2.0 * s - 1.0, 2.0 * t - 1.0);
        let rr = x * x + y * y;
        if rr > 1.0 {
            return to_rgb([0.0; 3]);
        }
        let z = (1.0 - rr).sqrt();
        let r = [2.0 * z * x, 2.0 * z * y, 2.0 * z * z - 1.0];
        to_rgb(environment(r))
    })
}

/// Growth rings of a log cut along its axis (`v`), the pith off to one side.
fn wood(size: u32) -> image::RgbImage {
    image::RgbImage::from_fn(size, size, |i, j| {
        let u = (f64::from(i) + 0.5) / f64::from(size);
        let v = (f64::from(j) + 0.5) / f64::from(size);
        let wave = 0.02 * (v * 13.0 * std::f64::consts::TAU).sin()
            + 0.01 * (v * 31.0 * std::f64::consts::TAU + 1.3).sin();
        let d = ((u - 0.5 + wave) * 1.0).abs() + 0.15 * (v - 0.5) * (v - 0.5);
        let ring = (d * 28.0).fract();
        let late = (ring * std::f64::consts::PI).sin().powi(6);
        to_rgb(mix([0.78, 0.56, 0.32], [0.45, 0.27, 0.12], late))
    })
}

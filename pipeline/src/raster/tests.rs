//! Tests of the rasterizer (coverage, fill rule, perspective, clipping, depth) and packets.

use super::*;
use glam::DVec4;
use proptest::prelude::*;

fn cfg(bits: u32) -> RasterConfig {
    RasterConfig {
        subpixel_bits: bits,
        ..RasterConfig::default()
    }
}

/// Clip-space position of a window-space point (x, y in pixels, y up) at NDC depth `z` and
/// clip `w`. Exact for power-of-two sizes and w.
fn win(x: f64, y: f64, z: f64, w: f64, width: u32, height: u32) -> DVec4 {
    let nx = 2.0 * x / f64::from(width) - 1.0;
    let ny = 2.0 * y / f64::from(height) - 1.0;
    DVec4::new(nx * w, ny * w, z * w, w)
}

/// Clip-space corners of a triangle given in window space (pixels, y up) at depth 0, w = 1.
fn flat_tri(p: [(f64, f64); 3], w: u32, h: u32) -> [DVec4; 3] {
    p.map(|(x, y)| win(x, y, 0.0, 1.0, w, h))
}

/// The one triangle `v` rasterized into a `w` x `h` image with `bits` subpixel bits.
fn draw_one(v: &[DVec4], w: u32, h: u32, bits: u32) -> RasterOutput {
    rasterize(v, &[[0, 1, 2]], w, h, &cfg(bits))
}

/// Per-pixel count of emitted fragments (image rows).
fn coverage(out: &RasterOutput, width: u32, height: u32) -> Vec<u32> {
    let mut c = vec![0u32; (width * height) as usize];
    for f in &out.fragments {
        c[(f.y * width + f.x) as usize] += 1;
    }
    c
}

fn full_quad() -> (Vec<DVec4>, Vec<[u32; 3]>) {
    let v = vec![
        DVec4::new(-1.0, -1.0, 0.0, 1.0),
        DVec4::new(1.0, -1.0, 0.0, 1.0),
        DVec4::new(1.0, 1.0, 0.0, 1.0),
        DVec4::new(-1.0, 1.0, 0.0, 1.0),
    ];
    (v, vec![[0, 1, 2], [0, 2, 3]])
}

#[test]
fn full_screen_quad_covers_every_pixel_once() {
    let (v, t) = full_quad();
    for (w, h) in [(7u32, 5u32), (64, 64), (1, 1), (13, 31)] {
        for bits in [0, 4, 8] {
            let out = rasterize(&v, &t, w, h, &cfg(bits));
            assert_eq!(out.fragments.len(), (w * h) as usize, "{w}x{h} bits {bits}");
            assert_eq!(out.depth_rejected, 0);
            assert!(coverage(&out, w, h).iter().all(|&c| c == 1));
            assert_eq!(out.triangles[0].status, TriStatus::Drawn);
            assert_eq!(out.triangles[1].status, TriStatus::Drawn);
            let total: u32 = out.triangles.iter().map(|s| s.fragments).sum();
            assert_eq!(total, w * h);
        }
    }
    // Both windings at once (second triangle reversed) still tile exactly.
    let out = rasterize(&v, &[[0, 1, 2], [0, 3, 2]], 7, 5, &cfg(4));
    assert_eq!(out.fragments.len(), 35);
    assert_eq!(out.depth_rejected, 0);
}

#[test]
fn fill_rule_right_triangles_on_pixel_corners() {
    let (w, h) = (32u32, 32u32);
    for bits in [0, 4, 8] {
        // Hypotenuse on the upper right: a right edge, excluded. N(N-1)/2 = 45.
        let a = flat_tri([(2.0, 3.0), (12.0, 3.0), (2.0, 13.0)], w, h);
        let out = draw_one(&a, w, h, bits);
        assert_eq!(out.fragments.len(), 45, "bits {bits}");
        // Hypotenuse on the upper left: a left edge, included. N(N+1)/2 = 55.
        let b = flat_tri([(2.0, 3.0), (12.0, 3.0), (12.0, 13.0)], w, h);
        let out = draw_one(&b, w, h, bits);
        assert_eq!(out.fragments.len(), 55, "bits {bits}");
    }
}

#[test]
fn fill_rule_edges_through_pixel_centres() {
    let (w, h) = (32u32, 32u32);
    // Legs through pixel centres. Bottom edge (window y = 0.5) excluded, left edge included,
    // hypotenuse (right) excluded: sum_{j=1..9} (10 - j) = 45.
    let a = flat_tri([(0.5, 0.5), (10.5, 0.5), (0.5, 10.5)], w, h);
    let out = draw_one(&a, w, h, 4);
    assert_eq!(out.fragments.len(), 45);
    assert!(
        out.fragments.iter().all(|f| f.y != h - 1),
        "bottom row excluded"
    );
    assert!(
        out.fragments.iter().any(|f| f.x == 0),
        "left column included"
    );
    // Top edge (window y = 10.5) included, left included, hypotenuse excluded: 55.
    let b = flat_tri([(0.5, 10.5), (10.5, 10.5), (0.5, 0.5)], w, h);
    let out = draw_one(&b, w, h, 4);
    assert_eq!(out.fragments.len(), 55);
    assert_eq!(out.fragments.iter().map(|f| f.y).min(), Some(h - 1 - 10));
}

#[test]
fn image_rows_are_flipped_and_scan_order_is_rows_then_columns() {
    let (w, h) = (8u32, 8u32);
    let v = flat_tri([(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)], w, h);
    let out = draw_one(&v, w, h, 4);
    let xy: Vec<(u32, u32)> = out.fragments.iter().map(|f| (f.x, f.y)).collect();
    assert_eq!(xy, vec![(0, 5), (0, 6), (1, 6), (0, 7), (1, 7), (2, 7)]);
}

#[test]
fn cull_modes() {
    let (w, h) = (16u32, 16u32);
    // Counter-clockwise in window coordinates (y up): front-facing.
    let v = flat_tri([(2.0, 2.0), (10.0, 2.0), (2.0, 10.0)], w, h);
    let ccw = [[0u32, 1, 2]];
    let cw = [[0u32, 2, 1]];
    let run = |t: &[[u32; 3]], cull| {
        let c = RasterConfig {
            cull,
            ..RasterConfig::default()
        };
        let out = rasterize(&v, t, w, h, &c);
        (out.triangles[0].status, out.fragments.len())
    };
    assert_eq!(run(&ccw, Cull::None), (TriStatus::Drawn, 28));
    assert_eq!(run(&cw, Cull::None), (TriStatus::Drawn, 28));
    assert_eq!(run(&ccw, Cull::Back), (TriStatus::Drawn, 28));
    assert_eq!(run(&cw, Cull::Back), (TriStatus::Culled, 0));
    assert_eq!(run(&ccw, Cull::Front), (TriStatus::Culled, 0));
    assert_eq!(run(&cw, Cull::Front), (TriStatus::Drawn, 28));
}

/// Solve for the attribute of the plane through clip-space v0, v1, v2 seen through the
/// centre of pixel (px, image row py): ray–plane intersection in clip space.
fn exact_attr(v: &[DVec4; 3], a: [f64; 3], px: u32, py: u32, w: u32, h: u32) -> f64 {
    let nx = 2.0 * (f64::from(px) + 0.5) / f64::from(w) - 1.0;
    let wy = f64::from(h - 1 - py) + 0.5;
    let ny = 2.0 * wy / f64::from(h) - 1.0;
    // P(s, t) = v0 + s (v1 - v0) + t (v2 - v0); X - nx W = 0, Y - ny W = 0.
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let r = |p: DVec4, n: f64, x: bool| if x { p.x - n * p.w } else { p.y - n * p.w };
    let (a11, a12, b1) = (r(e1, nx, true), r(e2, nx, true), -r(v[0], nx, true));
    let (a21, a22, b2) = (r(e1, ny, false), r(e2, ny, false), -r(v[0], ny, false));
    let det = a11 * a22 - a12 * a21;
    let s = (b1 * a22 - a12 * b2) / det;
    let t = (a11 * b2 - b1 * a21) / det;
    a[0] + s * (a[1] - a[0]) + t * (a[2] - a[0])
}

#[test]
fn perspective_correct_quad_in_tilted_plane() {
    let (w, h) = (64u32, 64u32);
    // A parallelogram in clip space (v3 = v0 + v2 - v1), receding: w = 1 at the bottom, 2 at
    // the top. Window positions are on integer pixels: (8,8) (56,8) (48,48) (24,48).
    let v = [
        DVec4::new(-0.75, -0.75, -0.5, 1.0),
        DVec4::new(0.75, -0.75, -0.5, 1.0),
        DVec4::new(1.0, 1.0, 1.0, 2.0),
        DVec4::new(-0.5, 1.0, 1.0, 2.0),
    ];
    assert_eq!(v[3], v[0] + v[2] - v[1]);
    let a = [1.0, 3.0, -2.0, 1.0 - 2.0 - 3.0];
    let tris = [[0u32, 1, 2], [0, 2, 3]];
    let out = rasterize(&v, &tris, w, h, &cfg(4));
    // Trapezoid rows 8..48 (window): left edge x = 8 + 0.4 (y - 8) inclusive, right edge
    // x = 56 - 0.2 (y - 8) exclusive; in units of 1/20 pixel with t = 2 (y - 8).
    let mut expected = 0;
    for j in 8..48i64 {
        let t = 2 * j + 1 - 16;
        expected += (0..64i64)
            .filter(|i| 160 + 4 * t <= 20 * i + 10 && 20 * i + 10 < 1120 - 2 * t)
            .count();
    }
    assert_eq!(expected, 1436);
    assert_eq!(out.fragments.len(), expected);
    assert_eq!(out.depth_rejected, 0);
    let plane = [v[0], v[1], v[2]];
    let mut worst = 0.0f64;
    for f in &out.fragments {
        let t = tris[f.tri as usize];
        let got: f64 = (0..3).map(|i| f.bary[i] * a[t[i] as usize]).sum();
        let want = exact_attr(&plane, [a[0], a[1], a[2]], f.x, f.y, w, h);
        worst = worst.max((got - want).abs());
        assert!((f.bary.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
    assert!(worst < 1e-9, "worst error {worst}");
    // Screen-linear interpolation would be far off: the tilt matters.
    let f = out
        .fragments
        .iter()
        .find(|f| f.x == 32 && f.y == 63 - 30)
        .unwrap();
    let t = tris[f.tri as usize];
    let want = exact_attr(&plane, [a[0], a[1], a[2]], 32, 33, w, h);
    let got: f64 = (0..3).map(|i| f.bary[i] * a[t[i] as usize]).sum();
    assert!((got - want).abs() < 1e-9);
}

#[test]
fn near_plane_clipping_matches_the_visible_part() {
    let (w, h) = (32u32, 32u32);
    // v2 is behind the camera (w < 0). Near plane z + w = 0 cuts v0-v2 and v1-v2 at t = 0.2.
    let v = [
        DVec4::new(-0.5, -0.5, 0.0, 1.0),
        DVec4::new(0.5, -0.5, 0.0, 1.0),
        DVec4::new(0.0, 0.8, -3.0, -1.0),
    ];
    let out = draw_one(&v, w, h, 4);
    assert_eq!(out.triangles[0].status, TriStatus::Drawn);
    assert_eq!(out.triangles[0].setups, 2);
    assert!(!out.fragments.is_empty());
    for f in &out.fragments {
        assert!(f
            .bary
            .iter()
            .all(|b| b.is_finite() && (0.0..=1.0).contains(b)));
        assert!((f.bary.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // Reconstructed clip position is in front of the near plane and projects onto the
        // pixel centre (within the snapping error).
        let p = v[0] * f.bary[0] + v[1] * f.bary[1] + v[2] * f.bary[2];
        assert!(p.w > 0.0 && p.z >= -p.w - 1e-9);
        let x = (p.x / p.w + 1.0) * 0.5 * f64::from(w);
        let y = (p.y / p.w + 1.0) * 0.5 * f64::from(h);
        assert!((x - (f64::from(f.x) + 0.5)).abs() < 0.1);
        assert!((y - (f64::from(h - 1 - f.y) + 0.5)).abs() < 0.1);
    }
    // Reference: the visible quad drawn directly as two in-front triangles.
    let p12 = v[1] + (v[2] - v[1]) * 0.2;
    let p02 = v[0] + (v[2] - v[0]) * 0.2;
    let rv = [v[0], v[1], p12, p02];
    let rb = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.8, 0.2],
        [0.8, 0.0, 0.2],
    ];
    let rt = [[0u32, 1, 2], [0, 2, 3]];
    let r = rasterize(&rv, &rt, w, h, &cfg(4));
    assert_eq!(r.fragments.len(), out.fragments.len());
    assert_eq!(out.fragments.len(), 38);
    for (f, g) in out.fragments.iter().zip(r.fragments.iter()) {
        assert_eq!((f.x, f.y), (g.x, g.y));
        // The intersection is computed from the canonical end point: last-ulp differences
        // may move a depth code by one.
        assert!(f.depth.abs_diff(g.depth) <= 1);
        let t = rt[g.tri as usize];
        for (k, fb) in f.bary.iter().enumerate() {
            let b: f64 = (0..3).map(|i| g.bary[i] * rb[t[i] as usize][k]).sum();
            assert!((b - fb).abs() < 1e-9);
        }
    }
    // Entirely behind the camera, or with w = 0 everywhere: clipped, nothing drawn.
    let behind = [
        DVec4::new(0.0, 0.0, 0.0, -1.0),
        DVec4::new(1.0, 0.0, 0.0, -1.0),
        DVec4::new(0.0, 1.0, 0.0, -2.0),
        DVec4::new(1.0, 1.0, 0.0, 0.0),
    ];
    let out = rasterize(&behind, &[[0, 1, 2], [3, 3, 0]], w, h, &cfg(4));
    assert_eq!(out.triangles[0].status, TriStatus::Clipped);
    assert_eq!(out.triangles[1].status, TriStatus::Clipped);
    assert!(out.fragments.is_empty());
}

#[test]
fn depth_test_either_order_same_winner() {
    let (w, h) = (16u32, 16u32);
    // Quad A: window x 0..10 at NDC z 0; quad B: x 6..16 at NDC z -0.5 (nearer).
    let quad = |x0: f64, x1: f64, z: f64| {
        [
            win(x0, 0.0, z, 1.0, w, h),
            win(x1, 0.0, z, 1.0, w, h),
            win(x1, 16.0, z, 1.0, w, h),
            win(x0, 16.0, z, 1.0, w, h),
        ]
    };
    let mut v = quad(0.0, 10.0, 0.0).to_vec();
    v.extend(quad(6.0, 16.0, -0.5));
    let a = [[0u32, 1, 2], [0, 2, 3]];
    let b = [[4u32, 5, 6], [4, 6, 7]];
    let ab: Vec<[u32; 3]> = a.iter().chain(b.iter()).copied().collect();
    let ba: Vec<[u32; 3]> = b.iter().chain(a.iter()).copied().collect();
    let o1 = rasterize(&v, &ab, w, h, &cfg(4));
    let o2 = rasterize(&v, &ba, w, h, &cfg(4));
    assert_eq!(o1.depth_rejected, 0);
    assert_eq!(o1.fragments.len(), 320);
    assert_eq!(o2.depth_rejected, 64);
    assert_eq!(o2.fragments.len(), 256);
    // Final winner per pixel: the last fragment written, identified by its depth.
    let winner = |o: &RasterOutput| {
        let mut d = vec![u32::MAX; 256];
        for f in &o.fragments {
            d[(f.y * w + f.x) as usize] = f.depth;
        }
        d
    };
    let (w1, w2) = (winner(&o1), winner(&o2));
    assert_eq!(w1, w2);
    // z 0 -> window 0.5 -> 8388608 at 24 bits; z -0.5 -> 0.25 -> 4194304.
    assert_eq!(w1[0], 8_388_608);
    assert_eq!(w1[15], 4_194_304);
    assert_eq!(w1.iter().filter(|&&d| d == 4_194_304).count(), 160);
    let rej: Vec<u32> = o2.triangles.iter().map(|t| t.depth_rejected).collect();
    assert_eq!(rej.iter().sum::<u32>(), 64);
    assert_eq!(o2.cycles(&cfg(4)), 4 * 8 + 256 + 64);

    // Interpenetrating: A at NDC z 0, C tilted from z -1 (left) to +1 (right) over x 0..16.
    let mut v2 = quad(0.0, 16.0, 0.0).to_vec();
    v2.extend([
        DVec4::new(-1.0, -1.0, -1.0, 1.0),
        DVec4::new(1.0, -1.0, 1.0, 1.0),
        DVec4::new(1.0, 1.0, 1.0, 1.0),
        DVec4::new(-1.0, 1.0, -1.0, 1.0),
    ]);
    let c = [[4u32, 5, 6], [4, 6, 7]];
    let ac: Vec<[u32; 3]> = a.iter().chain(c.iter()).copied().collect();
    let ca: Vec<[u32; 3]> = c.iter().chain(a.iter()).copied().collect();
    let o1 = rasterize(&v2, &ac, w, h, &cfg(4));
    let o2 = rasterize(&v2, &ca, w, h, &cfg(4));
    assert_eq!(winner(&o1), winner(&o2));
    // C is nearer in the 8 left columns (window x centre < 8): 128 pixels each way.
    assert_eq!(o1.depth_rejected, 128);
    assert_eq!(o2.depth_rejected, 128);
}

#[test]
fn degenerate_invalid_and_huge_inputs() {
    let (w, h) = (16u32, 16u32);
    let v = vec![
        win(1.0, 1.0, 0.0, 1.0, w, h),
        win(5.0, 5.0, 0.0, 1.0, w, h),
        win(9.0, 9.0, 0.0, 1.0, w, h),
        DVec4::new(f64::NAN, 0.0, 0.0, 1.0),
        DVec4::new(0.0, f64::INFINITY, 0.0, 1.0),
        win(3.1, 3.1, 0.0, 1.0, w, h),
        win(3.2, 3.3, 0.0, 1.0, w, h),
        win(3.3, 3.1, 0.0, 1.0, w, h),
    ];
    let tris = [
        [0u32, 1, 2], // collinear
        [0, 1, 3],    // NaN
        [0, 4, 1],    // infinity
        [0, 1, 99],   // index out of range
        [5, 6, 7],    // collapses at 0 sub-pixel bits
        [1, 1, 1],    // a point
    ];
    let out = rasterize(&v, &tris, w, h, &cfg(0));
    let st: Vec<TriStatus> = out.triangles.iter().map(|t| t.status).collect();
    use TriStatus::*;
    assert_eq!(
        st,
        vec![Degenerate, Invalid, Invalid, Invalid, Degenerate, Degenerate]
    );
    assert!(out.fragments.is_empty());
    assert!(out.triangles.iter().all(|t| t.fragments == 0));
    // At 8 bits the tiny one has area but covers no pixel centre.
    let out = rasterize(&v, &tris[4..5], w, h, &cfg(8));
    assert_eq!(out.triangles[0].status, Drawn);
    assert_eq!(out.fragments.len(), 0);
    // Zero-sized images: empty output, no panic.
    let (qv, qt) = full_quad();
    for (a, b) in [(0, 5), (5, 0), (0, 0)] {
        let out = rasterize(&qv, &qt, a, b, &cfg(4));
        assert!(out.fragments.is_empty());
        assert_eq!(out.triangles.len(), 2);
    }
    // Huge coordinates: the guard band clips them; the viewport is covered exactly.
    for big in [1e12, 1e300, f64::MAX / 4.0] {
        let hv = [
            DVec4::new(-1.0, -1.0, 0.0, 1.0),
            DVec4::new(big, -1.0, 0.0, 1.0),
            DVec4::new(-1.0, big, 0.0, 1.0),
        ];
        for bits in [0, 8] {
            let out = rasterize(&hv, &[[0, 1, 2]], 7, 5, &cfg(bits));
            assert_eq!(out.triangles[0].status, Drawn, "{big}");
            assert_eq!(out.fragments.len(), 35, "{big} bits {bits}");
        }
    }
    // Tiny positive w (beyond the w epsilon) and a triangle off to the side in the guard
    // band.
    let tv = [
        DVec4::new(0.5, 0.5, 0.0, 1e-300),
        DVec4::new(0.6, 0.5, 0.0, 1e-300),
        DVec4::new(0.5, 0.6, 0.0, 1e-300),
        DVec4::new(2.0, 0.0, 0.0, 1.0),
        DVec4::new(3.0, 0.0, 0.0, 1.0),
        DVec4::new(2.0, 1.0, 0.0, 1.0),
    ];
    let out = rasterize(&tv, &[[0, 1, 2], [3, 4, 5]], w, h, &cfg(4));
    assert_eq!(out.triangles[0].status, Clipped);
    assert_eq!(out.triangles[1].status, Clipped);
    // Out-of-range config values are clamped, not a panic.
    let bad = RasterConfig {
        subpixel_bits: 40,
        depth_bits: 99,
        setup_cycles: 0,
        cull: Cull::None,
    };
    assert_eq!(rasterize(&qv, &qt, 7, 5, &bad).fragments.len(), 35);
}

#[test]
fn subpixel_precision_changes_a_sliver() {
    let (w, h) = (32u32, 32u32);
    let v = flat_tri([(0.2, 4.45), (28.7, 5.2), (0.2, 4.8)], w, h);
    let n = |bits| draw_one(&v, w, h, bits).fragments.len();
    // At 0 bits the vertices snap to (0,4) (29,5) (0,5): the centres of row y = 4.5 left of
    // the lower edge's crossing at x = 14.5 (excluded: a bottom edge), i.e. 14 pixels.
    // At 8 bits the lower edge (4.449, slope 0.75/28.5) crosses y = 4.5 at x = 2.13: centres
    // 0.5 and 1.5. At 4 bits it crosses at x = 2.56: 3 pixels.
    assert_eq!(n(0), 14);
    assert_eq!(n(8), 2);
    assert_eq!(n(4), 3);
}

#[test]
fn depth_quantisation() {
    assert_eq!(scan::quantise_depth(0.0, 16), 0);
    assert_eq!(scan::quantise_depth(1.0, 16), 65535);
    assert_eq!(scan::quantise_depth(0.5, 16), 32768);
    assert_eq!(scan::quantise_depth(2.0, 16), 65535);
    assert_eq!(scan::quantise_depth(f64::NAN, 24), 16_777_215);
    assert_eq!(scan::quantise_depth(1.0, 32), u32::MAX);
    assert_eq!(scan::depth_max(32), u32::MAX);
}

#[test]
fn config_defaults_and_validation() {
    let c: RasterConfig = serde_json::from_str("{}").unwrap();
    assert_eq!(c, RasterConfig::default());
    assert_eq!(
        (c.subpixel_bits, c.depth_bits, c.cull, c.setup_cycles),
        (4, 24, Cull::None, 8)
    );
    let c: RasterConfig = serde_json::from_str(r#"{"cull":"Back","subpixel_bits":9}"#).unwrap();
    assert_eq!(c.cull, Cull::Back);
    assert_eq!(
        c.validate("raster"),
        Err("raster.subpixel_bits: expected 0 to 8, found 9".to_string())
    );
    assert!(serde_json::from_str::<RasterConfig>(r#"{"bogus":1}"#).is_err());
    let mut c = RasterConfig::default();
    assert_eq!(c.validate("raster"), Ok(()));
    c.depth_bits = 15;
    assert_eq!(
        c.validate("x.raster"),
        Err("x.raster.depth_bits: expected 16 to 32, found 15".to_string())
    );
    c.depth_bits = 32;
    c.setup_cycles = 1025;
    assert_eq!(
        c.validate("raster"),
        Err("raster.setup_cycles: expected 1 to 1024, found 1025".to_string())
    );
}

/// Exact integer point-in-closed-triangle and on-segment tests for the fan property test.
fn cross(a: (i64, i64), b: (i64, i64), p: (i64, i64)) -> i64 {
    (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0)
}

fn in_closed(t: [(i64, i64); 3], p: (i64, i64)) -> bool {
    let c = [
        cross(t[0], t[1], p),
        cross(t[1], t[2], p),
        cross(t[2], t[0], p),
    ];
    c.iter().all(|&x| x >= 0) || c.iter().all(|&x| x <= 0)
}

fn on_segment(a: (i64, i64), b: (i64, i64), p: (i64, i64)) -> bool {
    cross(a, b, p) == 0
        && p.0 >= a.0.min(b.0)
        && p.0 <= a.0.max(b.0)
        && p.1 >= a.1.min(b.1)
        && p.1 <= a.1.max(b.1)
}

/// The random shape of a fan of `n` triangles around a centre: each spoke's angle jittered,
/// each vertex's clip w a power of two, each triangle's winding flipped or not.
#[derive(Debug, Clone)]
struct Fan {
    n: usize,
    jitter: Vec<f64>,
    wexp: Vec<i32>,
    flip: Vec<bool>,
}

fn fan() -> impl Strategy<Value = Fan> {
    (
        4usize..=9,
        proptest::collection::vec(-1.0f64..1.0, 9),
        proptest::collection::vec(-1i32..=2, 10),
        proptest::collection::vec(any::<bool>(), 9),
    )
        .prop_map(|(n, jitter, wexp, flip)| Fan {
            n,
            jitter,
            wexp,
            flip,
        })
}

impl Fan {
    /// Window-space points: the centre `(cx, cy)`, then the end of spoke k at `radius[k]`,
    /// every coordinate passed through `snap`.
    fn points(
        &self,
        cx: f64,
        cy: f64,
        radius: &[f64],
        snap: impl Fn(f64) -> f64,
    ) -> Vec<(f64, f64)> {
        let n = self.n;
        let mut pts = vec![(snap(cx), snap(cy))];
        for (k, r) in radius.iter().enumerate().take(n) {
            let a = std::f64::consts::TAU * (k as f64 + 0.5 * self.jitter[k]) / n as f64;
            pts.push((snap(cx + r * a.cos()), snap(cy + r * a.sin())));
        }
        pts
    }

    /// The fan on `pts` rasterized into a `w` x `h` image with `bits` subpixel bits.
    fn draw(&self, pts: &[(f64, f64)], w: u32, h: u32, bits: u32) -> RasterOutput {
        let n = self.n;
        let verts: Vec<DVec4> = pts
            .iter()
            .zip(self.wexp.iter())
            .map(|(&(x, y), &e)| win(x, y, 0.0, 2f64.powi(e), w, h))
            .collect();
        let tris: Vec<[u32; 3]> = (0..n)
            .map(|k| {
                let (a, b) = (1 + k as u32, 1 + ((k + 1) % n) as u32);
                if self.flip[k] {
                    [0, b, a]
                } else {
                    [0, a, b]
                }
            })
            .collect();
        rasterize(&verts, &tris, w, h, &cfg(bits))
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A fan around a centre with shared edges, random windings and random w: every pixel
    /// centre inside is covered exactly once, none outside.
    #[test]
    fn fan_has_no_holes_or_double_hits(
        (bits, cx, cy) in (0u32..=8, 8.0f64..56.0, 6.0f64..26.0),
        fan in fan(),
        radius in proptest::collection::vec(4.0f64..40.0, 9),
    ) {
        let (w, h) = (64u32, 32u32);
        let n = fan.n;
        let s = f64::from(1u32 << bits);
        let grid = |x: f64| (x * s).round() / s;
        let pts = fan.points(cx, cy, &radius, grid);
        let out = fan.draw(&pts, w, h, bits);
        let cov = coverage(&out, w, h);
        // Independent classification in units of 1/2^(bits+1) pixel, window y up.
        let u = 2.0 * s;
        let ip: Vec<(i64, i64)> = pts.iter().map(|&(x, y)| ((x * u) as i64, (y * u) as i64)).collect();
        // snapping two spokes at nearly the same angle to the subpixel grid can swap their
        // order, folding a triangle over its neighbours: then the fan overlaps itself (a
        // case of the generator, not of the rasterizer), so such fans are not drawn
        prop_assume!((0..n).all(|k| cross(ip[0], ip[1 + k], ip[1 + (k + 1) % n]) >= 0));
        prop_assert_eq!(out.depth_rejected, 0);
        let fan: Vec<[(i64, i64); 3]> = (0..n)
            .map(|k| [ip[0], ip[1 + k], ip[1 + (k + 1) % n]])
            .filter(|t| cross(t[0], t[1], t[2]) != 0)
            .collect();
        let mut inside = 0u32;
        for py in 0..h {
            for px in 0..w {
                let half = s as i64;
                let p = (
                    i64::from(px) * (u as i64) + half,
                    i64::from(h - 1 - py) * (u as i64) + half,
                );
                let c = cov[(py * w + px) as usize];
                let closed = fan.iter().any(|t| in_closed(*t, p));
                let boundary = (0..n).any(|k| on_segment(ip[1 + k], ip[1 + (k + 1) % n], p));
                if !closed {
                    prop_assert_eq!(c, 0, "outside pixel ({}, {}) covered", px, py);
                } else if !boundary {
                    inside += 1;
                    prop_assert_eq!(c, 1, "inside pixel ({}, {}) covered {} times", px, py, c);
                } else {
                    prop_assert!(c <= 1);
                }
            }
        }
        prop_assert!(inside > 0);
    }

    /// A fan far larger than the guard band: every triangle is clipped against the guard
    /// band planes, and the clipped shared edges still tile the viewport exactly.
    #[test]
    fn guard_band_clipped_fan_tiles_the_viewport(
        (bits, cx, cy) in (0u32..=8, 0.0f64..64.0, 0.0f64..32.0),
        fan in fan(),
        radius in proptest::collection::vec(1e5f64..1e9, 9),
    ) {
        let (w, h) = (64u32, 32u32);
        let out = fan.draw(&fan.points(cx, cy, &radius, |x| x), w, h, bits);
        prop_assert_eq!(out.depth_rejected, 0);
        prop_assert_eq!(out.fragments.len(), (w * h) as usize);
        prop_assert!(coverage(&out, w, h).iter().all(|&c| c == 1));
        prop_assert!(out.triangles.iter().any(|t| t.setups > 1));
    }

    /// Arbitrary clip coordinates (huge, tiny, behind the camera, NaN, infinite): no panic,
    /// fragments inside the image with valid barycentrics, statuses consistent with counts.
    #[test]
    fn arbitrary_input_is_safe(
        raw in proptest::collection::vec(
            prop_oneof![
                4 => -3.0f64..3.0,
                1 => -1e300f64..1e300,
                1 => Just(f64::NAN),
                1 => Just(f64::INFINITY),
                1 => Just(0.0),
                1 => -1e-7f64..1e-7,
            ],
            36,
        ),
        idx in proptest::collection::vec(0u32..10, 9),
        bits in 0u32..=8,
        cull in prop_oneof![Just(Cull::None), Just(Cull::Back), Just(Cull::Front)],
    ) {
        let verts: Vec<DVec4> = raw.chunks(4).map(|c| DVec4::new(c[0], c[1], c[2], c[3])).collect();
        let tris: Vec<[u32; 3]> = idx.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let c = RasterConfig { subpixel_bits: bits, cull, ..RasterConfig::default() };
        let (w, h) = (7u32, 5u32);
        let out = rasterize(&verts, &tris, w, h, &c);
        prop_assert_eq!(out.triangles.len(), 3);
        for f in &out.fragments {
            prop_assert!(f.x < w && f.y < h);
            prop_assert!(f.bary.iter().all(|b| b.is_finite() && *b >= 0.0 && *b <= 1.0 + 1e-9));
            prop_assert!((f.bary.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
        let total: u64 = out.triangles.iter().map(|t| u64::from(t.fragments)).sum();
        prop_assert_eq!(total, out.fragments.len() as u64);
        for t in &out.triangles {
            if t.status != TriStatus::Drawn {
                prop_assert_eq!(t.fragments + t.depth_rejected, 0);
            }
        }
    }

    #[test]
    fn packet_round_trip(
        pv in proptest::collection::vec((1u32..=4, 1u32..=32), 0..6),
        pt in proptest::collection::vec((1u32..=4, 1u32..=32), 0..4),
        seed in proptest::collection::vec(any::<u64>(), 120),
    ) {
        let layout = PacketLayout {
            per_vertex: pv.iter().enumerate().map(|(i, &(l, b))| Field::new(&format!("v{i}"), l, b)).collect(),
            per_triangle: pt.iter().enumerate().map(|(i, &(l, b))| Field::new(&format!("t{i}"), l, b)).collect(),
        };
        let nv: usize = pv.iter().map(|p| p.0 as usize).sum();
        let nt: usize = pt.iter().map(|p| p.0 as usize).sum();
        let vals: Vec<Vec<u64>> = (0..3).map(|k| seed[k * 24..k * 24 + nv].to_vec()).collect();
        let tv = seed[100..100 + nt].to_vec();
        let bits = layout.pack([&vals[0], &vals[1], &vals[2]], &tv).unwrap();
        prop_assert_eq!(bits.len() as u64, layout.bits_per_triangle());
        let (uv, ut) = layout.unpack(&bits);
        let mask = |v: u64, b: u32| if b == 64 { v } else { v & ((1u64 << b) - 1) };
        let vw: Vec<u32> = pv.iter().flat_map(|&(l, b)| std::iter::repeat_n(b, l as usize)).collect();
        let tw: Vec<u32> = pt.iter().flat_map(|&(l, b)| std::iter::repeat_n(b, l as usize)).collect();
        for k in 0..3 {
            let want: Vec<u64> = vals[k].iter().zip(&vw).map(|(&v, &b)| mask(v, b)).collect();
            prop_assert_eq!(&uv[k], &want);
        }
        let want: Vec<u64> = tv.iter().zip(&tw).map(|(&v, &b)| mask(v, b)).collect();
        prop_assert_eq!(ut, want);
    }
}

#[test]
fn packet_baseline_and_errors() {
    let b = PacketLayout::baseline_textured_gouraud();
    assert_eq!(b.per_vertex.len(), 11);
    assert_eq!(b.bits_per_triangle(), 1056);
    let vals: Vec<u64> = (0..11).map(|i| 0x3f80_0000 + i).collect();
    let bits = b.pack([&vals, &vals, &vals], &[]).unwrap();
    assert_eq!(bits.len(), 1056);
    let (v, t) = b.unpack(&bits);
    assert_eq!(v[2], vals);
    assert!(t.is_empty());
    // Three extra 16-bit per-triangle words: 48 / 1056 = 4.5 % (< 5 %).
    let mut ext = b.clone();
    ext.per_triangle.push(Field::new("bump", 3, 16));
    assert_eq!(ext.bits_per_triangle() - b.bits_per_triangle(), 48);
    let ratio: f64 = 48.0 / 1056.0;
    assert!((ratio - 0.04545).abs() < 1e-4 && ratio < 0.05);
    // Two's complement: -1 in a 5-bit field keeps 0b11111.
    let l = PacketLayout {
        per_vertex: vec![Field::new("a", 1, 5)],
        per_triangle: vec![Field::new("b", 2, 3)],
    };
    let bits = l.pack([&[-1i64 as u64], &[2], &[0]], &[7, 9]).unwrap();
    assert_eq!(bits.len(), 21);
    assert_eq!(bits.count_ones(), 5 + 1 + 3 + 1);
    assert_eq!(l.unpack(&bits), ([vec![31], vec![2], vec![0]], vec![7, 1]));
    // Errors: count mismatch, too-wide field. A short slice unpacks missing bits as 0.
    assert!(l.pack([&[1], &[2], &[]], &[7, 9]).is_err());
    assert!(l.pack([&[1], &[2], &[3]], &[7]).is_err());
    let wide = PacketLayout {
        per_vertex: vec![Field::new("w", 1, 65)],
        per_triangle: vec![],
    };
    assert!(wide.pack([&[1], &[2], &[3]], &[]).is_err());
    assert_eq!(
        l.unpack(&bits[..7]),
        ([vec![31], vec![2], vec![0]], vec![0, 0])
    );
}

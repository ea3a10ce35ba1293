//! View directions "uniformly distributed around the object" (Wang et al. §2, Fig. 4a: 12
//! for baking; §5: 30 for the evaluation).
//!
//! Choices (the paper does not say how it distributes them): 12 views are the icosahedron's
//! 12 vertices, the most uniform set of 12 points on the sphere; any other count `n` is the
//! Fibonacci (golden-angle) spiral `y_i = 1 - (2 i + 1) / n`, `phi_i = i * 2.39996...`. The
//! evaluation views are the spiral of 30 turned by half a golden angle about y, so that none
//! coincides with a baking view. Adding views one by one (Fig. 3a) takes them in this order.

use glam::DVec3;

/// The largest view count.
pub const MAX_VIEWS: usize = 1024;

/// `n` unit directions, from the object's centre towards the camera.
pub fn directions(n: usize) -> Vec<DVec3> {
    if n == 12 {
        return icosahedron();
    }
    spiral(n, 0.0)
}

/// The 30 evaluation directions of §5 (see the module).
pub fn evaluation() -> Vec<DVec3> {
    spiral(30, 0.5 * golden_angle())
}

fn golden_angle() -> f64 {
    std::f64::consts::PI * (3.0 - 5f64.sqrt())
}

fn spiral(n: usize, turn: f64) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let y = 1.0 - (2 * i + 1) as f64 / n as f64;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = i as f64 * golden_angle() + turn;
            DVec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// The icosahedron's vertices `(0, ±1, ±φ)` and their cyclic permutations, normalised.
fn icosahedron() -> Vec<DVec3> {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut out = Vec::with_capacity(12);
    for &(a, b) in &[(1.0, phi), (1.0, -phi), (-1.0, phi), (-1.0, -phi)] {
        out.push(DVec3::new(0.0, a, b));
        out.push(DVec3::new(a, b, 0.0));
        out.push(DVec3::new(b, 0.0, a));
    }
    out.into_iter().map(DVec3::normalize).collect()
}

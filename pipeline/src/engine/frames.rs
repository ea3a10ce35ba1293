//! The geometry engine's share of the per-pixel perturbation engines (Ernst et al. 1998 §3):
//! what the host or geometry engine computes per vertex or per triangle for Texram (the main
//! direction), VISA+ (the alignment matrix, or quaternions at the vertices) and Harmony (the
//! interpolated Blinn axes). All in world space, in f64; the attribute's encoding decides what
//! the triangle packet carries (`docs/units/perturb.md`).
//!
//! Every engine perturbs as `N' = base + Fu Du + Fv Dv` with the bump map's gradient
//! `(Fu, Fv)`; the axes follow the reference's rule ([`Perturbation`]): Blinn's
//! `Du = s (n̂ × Pv) / |Pu × Pv|`, `Dv = s (Pu × n̂) / |Pu × Pv|` (`crate::scene::perturb`,
//! with `s` the orientation sign), or the same with `Pu`, `Pv` scaled to unit length for the
//! scale-invariant rule (Lingard's `D'` wherever `Pu ⟂ Pv`: then `Du = -T`, `Dv = -B`).

use crate::config::Axis;
use crate::scene::perturb::{tangent_frame, Perturbation};
use glam::{DQuat, DVec2, DVec3};

/// Blinn's axes `(Du, Dv)` at a point with unit normal `n` and derivatives `pu`, `pv` by
/// `rule`. Zero axes (no perturbation, the reference's fallback too) where `Pu × Pv` is zero
/// or not finite.
pub fn blinn_axes(n: DVec3, pu: DVec3, pv: DVec3, rule: Perturbation) -> (DVec3, DVec3) {
    let (pu, pv) = match rule {
        Perturbation::Blinn => (pu, pv),
        Perturbation::ScaleInvariant => (pu.normalize_or_zero(), pv.normalize_or_zero()),
    };
    let ng = pu.cross(pv);
    let len = ng.length();
    if !(len > 0.0 && len.is_finite()) {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let s = if ng.dot(n) < 0.0 { -1.0 } else { 1.0 };
    (n.cross(pv) * (s / len), pu.cross(n) * (s / len))
}

/// One of the three Harmony axes (§3.5) at a vertex.
pub fn blinn_axis(axis: Axis, n: DVec3, pu: DVec3, pv: DVec3, rule: Perturbation) -> DVec3 {
    let (du, dv) = blinn_axes(n, pu, pv, rule);
    match axis {
        Axis::Du => du,
        Axis::Dv => dv,
        Axis::N => n,
    }
}

/// A triangle's own `Pu`, `Pv`: the derivatives of its flat parameterisation, solved from
/// its vertex positions `p` and texture coordinates `uv`; None without uv area.
pub fn triangle_derivatives(p: [DVec3; 3], uv: [DVec2; 3]) -> Option<(DVec3, DVec3)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d2.x * d1.y;
    let scale = d1.length() * d2.length();
    if !(det.abs() > 1e-12 * scale && det.is_finite()) {
        return None;
    }
    let pu = (e1 * d2.y - e2 * d1.y) / det;
    let pv = (e2 * d1.x - e1 * d2.x) / det;
    (pu.is_finite() && pv.is_finite()).then_some((pu, pv))
}

/// A column of VISA+'s per-triangle alignment matrix (§3.2: "a local orthogonal coordinate
/// system constructed by the local surface normal N and the texture coordinates of the
/// triangle", so that `Pv × N` and `N × Pu` "are held constant over the triangle"): the
/// Blinn axes of the triangle's own plane, its face normal (turned to the side of `mean`, the
/// mean vertex normal) and its own `Pu`, `Pv` (solved from positions and texture
/// coordinates, [`triangle_derivatives`]), or the face normal itself (`column: N`). Two
/// triangles whose planes meet at a dihedral angle get axes turned by that angle: the
/// discontinuity of §3.2. A triangle without uv area or without area uses `mean` and
/// `fallback` (its vertices' mean `Pu`, `Pv`, made tangent to `mean`).
pub fn alignment(
    column: Axis,
    p: [DVec3; 3],
    uv: [DVec2; 3],
    mean: DVec3,
    fallback: (DVec3, DVec3),
    rule: Perturbation,
) -> DVec3 {
    let face = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize();
    let (n, (pu, pv)) = match (face, triangle_derivatives(p, uv)) {
        (Some(f), Some(d)) => (if f.dot(mean) < 0.0 { -f } else { f }, d),
        _ => {
            let tangent = |d: DVec3| d - mean * d.dot(mean);
            (mean, (tangent(fallback.0), tangent(fallback.1)))
        }
    };
    blinn_axis(column, n, pu, pv, rule)
}

/// The vertex frame `(T, n̂ × T, n̂)` (`T` from [`tangent_frame`], `B` always `n̂ × T` so the
/// frame is a rotation) as a unit quaternion, and the 2x2 matrix `M` that takes `(T, B)` to
/// Blinn's axes: `Du = m00 T + m10 B`, `Dv = m01 T + m11 B`.
pub fn quaternion_frame(n: DVec3, pu: DVec3, pv: DVec3, rule: Perturbation) -> (DQuat, [f64; 4]) {
    let (t, _) = tangent_frame(n, pu, pv);
    let b = n.cross(t);
    let q = DQuat::from_mat3(&glam::DMat3::from_cols(t, b, n)).normalize();
    let (du, dv) = blinn_axes(n, pu, pv, rule);
    (q, [du.dot(t), dv.dot(t), du.dot(b), dv.dot(b)])
}

/// Texram's main direction at a vertex (§3.1): `Pu / |Pu|`, or the tangent frame's `T` where
/// `Pu` is zero or parallel to the normal.
pub fn main_direction(n: DVec3, pu: DVec3, pv: DVec3) -> DVec3 {
    match pu.try_normalize() {
        Some(m) if m.cross(n).length() > 1e-9 => m,
        _ => tangent_frame(n, pu, pv).0,
    }
}

/// Whether triangle setup negates each vertex's quaternion so that all three lie in the
/// first vertex's hemisphere (`q` and `-q` are the same rotation; interpolation needs one
/// sign).
pub fn hemisphere_flips(q: [&[f64; 4]; 3]) -> [bool; 3] {
    let dot = |a: &[f64; 4], b: &[f64; 4]| (0..4).map(|i| a[i] * b[i]).sum::<f64>();
    [false, dot(q[0], q[1]) < 0.0, dot(q[0], q[2]) < 0.0]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn blinn_axes_of_an_orthonormal_frame_are_minus_t_and_minus_b() {
        let (du, dv) = blinn_axes(DVec3::Z, DVec3::X, DVec3::Y, Perturbation::Blinn);
        assert!(close(du, -DVec3::X) && close(dv, -DVec3::Y));
        // Blinn's rule scales by 1/|Pu|, 1/|Pv|; the scale-invariant one does not
        let (du, dv) = blinn_axes(
            DVec3::Z,
            DVec3::X * 2.0,
            DVec3::Y * 4.0,
            Perturbation::Blinn,
        );
        assert!(close(du, -DVec3::X * 0.5) && close(dv, -DVec3::Y * 0.25));
        let (du, dv) = blinn_axes(
            DVec3::Z,
            DVec3::X * 2.0,
            DVec3::Y * 4.0,
            Perturbation::ScaleInvariant,
        );
        assert!(close(du, -DVec3::X) && close(dv, -DVec3::Y));
        // mirrored texture coordinates flip the perturbation (the reference's sign s)
        let (du, dv) = blinn_axes(DVec3::Z, DVec3::X, -DVec3::Y, Perturbation::Blinn);
        assert!(close(du, -DVec3::X) && close(dv, DVec3::Y));
        // degenerate: zero axes
        let z = blinn_axes(DVec3::Z, DVec3::X, DVec3::X, Perturbation::Blinn);
        assert_eq!(z, (DVec3::ZERO, DVec3::ZERO));
    }

    #[test]
    fn the_axes_reproduce_the_reference_perturbation() {
        // N' = n + Fu Du + Fv Dv is the reference's Blinn normal up to length
        let (n, pu, pv) = (
            DVec3::new(0.1, 0.2, 1.0).normalize(),
            DVec3::new(1.5, 0.1, -0.1),
            DVec3::new(0.2, 0.7, -0.05),
        );
        let g = DVec2::new(0.3, -0.2);
        let want = crate::scene::perturb::perturb_height(n, pu, pv, g, Perturbation::Blinn);
        let (du, dv) = blinn_axes(n, pu, pv, Perturbation::Blinn);
        let got = (n + du * g.x + dv * g.y).normalize();
        assert!(close(got, want), "{got} {want}");
    }

    #[test]
    fn triangle_derivatives_solve_the_flat_parameterisation() {
        let p = [
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 3.0, 1.0),
        ];
        let uv = [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)];
        let (pu, pv) = triangle_derivatives(p, uv).unwrap();
        assert!(close(pu, p[1]) && close(pv, p[2]));
        assert!(triangle_derivatives(p, [DVec2::ZERO; 3]).is_none());
    }

    #[test]
    fn alignment_follows_the_triangle_plane() {
        // a triangle tilted by 30 degrees about y, uv along its edges
        let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
        let p = [
            DVec3::ZERO,
            DVec3::new(c, 0.0, s),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let uv = [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)];
        // the mean vertex normal only picks the side
        let mean = DVec3::Z;
        let rule = Perturbation::Blinn;
        let n = alignment(Axis::N, p, uv, mean, (DVec3::X, DVec3::Y), rule);
        assert!(close(n, DVec3::new(-s, 0.0, c)), "{n}");
        let du = alignment(Axis::Du, p, uv, mean, (DVec3::X, DVec3::Y), rule);
        assert!(close(du, -p[1]), "{du}");
        // no uv area: the mean frame
        let du = alignment(
            Axis::Du,
            p,
            [DVec2::ZERO; 3],
            mean,
            (DVec3::X, DVec3::Y),
            rule,
        );
        assert!(close(du, -DVec3::X), "{du}");
    }

    #[test]
    fn quaternion_frames_rotate_z_to_the_normal_and_m_rebuilds_the_axes() {
        let (n, pu, pv) = (
            DVec3::new(0.3, -0.2, 0.9).normalize(),
            DVec3::new(1.0, 0.4, 0.0),
            DVec3::new(-0.3, 1.2, 0.2),
        );
        for rule in [Perturbation::Blinn, Perturbation::ScaleInvariant] {
            let (q, m) = quaternion_frame(n, pu, pv, rule);
            assert!(close(q * DVec3::Z, n));
            let (t, b) = (q * DVec3::X, q * DVec3::Y);
            let (du, dv) = blinn_axes(n, pu, pv, rule);
            assert!(close(t * m[0] + b * m[2], du));
            assert!(close(t * m[1] + b * m[3], dv));
        }
    }

    #[test]
    fn hemisphere_flips_follow_the_first_vertex() {
        let (a, b) = ([0.0, 0.0, 0.0, 1.0], [0.0, 0.1, 0.0, -0.99]);
        assert_eq!(hemisphere_flips([&a, &b, &a]), [false, true, false]);
    }

    #[test]
    fn main_direction_is_the_unit_pu() {
        assert!(close(
            main_direction(DVec3::Z, DVec3::X * 3.0, DVec3::Y),
            DVec3::X
        ));
        // Pu along the normal: the tangent frame's T
        let m = main_direction(DVec3::Z, DVec3::Z, DVec3::Y);
        assert!(m.dot(DVec3::Z).abs() < 1e-12 && (m.length() - 1.0).abs() < 1e-12);
    }
}

//! The perturbed normal: what a bump map does to a surface (Blinn 1978 as given in Ernst et
//! al. 1998 §2, Lingard 1995's scale-invariant variant, tangent-space normal maps in the
//! `(T, B, N)` frame of §3.4). Part of the scene's definition: the float reference evaluates it
//! exactly per pixel (`crate::reference`, step 3), the object-space bakes per texel
//! (`super::bake`).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::BumpMap;

/// How a height-field gradient perturbs the normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Perturbation {
    /// Blinn 1978 (Ernst et al. 1998 §2): `N' = N + D`,
    /// `D = (Fu (N × Pv) + Fv (Pu × N)) / |N|`, `N = Pu × Pv`. Exactly the normal of the
    /// displaced surface `P + F n̂` to first order; the visible bump slope therefore scales
    /// with `1 / |Pu|`, `1 / |Pv|` (Lingard: scaling the surface by 2 scales `N` by 4 but `D`
    /// only by 2, smoothing the wrinkles).
    Blinn,
    /// Lingard 1995's scale-invariant perturbation `D' = sqrt(Fu² + Fv²) · D · |N| / |D|`:
    /// the direction of Blinn's `D`, with `|D'| / |N| = |∇F|` whatever the parameterisation
    /// scale, so the bumps look the same on a surface of any size.
    #[default]
    ScaleInvariant,
}

/// A surface point in world space, at a pixel centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Position.
    pub p: DVec3,
    /// Interpolated smooth unit normal `n̂` (zero only if the interpolation vanishes).
    pub n: DVec3,
    /// `∂P/∂u`, `∂P/∂v` (unnormalised).
    pub pu: DVec3,
    pub pv: DVec3,
    /// Texture coordinates (unwrapped).
    pub uv: DVec2,
}

/// `v / |v|`, or `fallback` if `v` is zero or not finite.
fn normalize_or(v: DVec3, fallback: DVec3) -> DVec3 {
    v.try_normalize().unwrap_or(fallback)
}

/// The world-space perturbed unit normal at a surface point: [`perturb_height`] with the
/// analytic gradient `(Fu, Fv)` at `uv` for height fields, [`perturb_normal_map`] with the
/// bilinearly sampled texel for normal maps.
pub fn perturbed_normal(bump: &BumpMap, sp: &SurfacePoint, perturbation: Perturbation) -> DVec3 {
    match bump.grad(sp.uv.x, sp.uv.y) {
        Some(g) => perturb_height(sp.n, sp.pu, sp.pv, g, perturbation),
        None => perturb_normal_map(sp.n, sp.pu, sp.pv, bump.normal_ts(sp.uv.x, sp.uv.y)),
    }
}

/// Blinn's perturbed normal (Ernst et al. 1998 §2; Lingard 1995 "Blinn's Method") for a
/// height-field gradient `grad = (Fu, Fv)`, returned normalised.
///
/// With `N = Pu × Pv` replaced by the interpolated smooth unit normal scaled to the same
/// length, `|Pu × Pv| n̂` (so curved meshes keep their smooth shading):
///
/// ```text
/// N' = |Pu × Pv| n̂ + s D,    D = Fu (n̂ × Pv) + Fv (Pu × n̂)
/// ```
///
/// which is Blinn's `N + D` with `D = (Fu (N × Pv) + Fv (Pu × N)) / |N|`. On a flat quad with
/// `Pu = x̂`, `Pv = ŷ`, `n̂ = ẑ` it gives `(-Fu, -Fv, 1)`.
///
/// **Orientation** `s`: Blinn assumes `Pu × Pv` points the same way as the surface normal.
/// When it does not (mirrored texture coordinates, or a model transform with negative
/// determinant), `s = -1`: the whole perturbation `D` changes sign. This is exactly the normal
/// `P'u × P'v` of the displaced surface `P' = P + F n̂` (bumps always rise along `n̂`),
/// flipped to the side of `n̂`; it agrees with the handedness rule of [`tangent_frame`], so a
/// height field and its baked normal map `normalize(-Fu, -Fv, 1)` give the same normal.
///
/// [`Perturbation::ScaleInvariant`] replaces `D` by Lingard's
/// `D' = sqrt(Fu² + Fv²) · D · |N| / |D|` (zero when `D` is zero).
///
/// Degenerate frames: if `|Pu × Pv|` is zero or not finite (e.g. a parametric pole), or the
/// result cannot be normalised, the unperturbed `n̂` is returned.
pub fn perturb_height(
    n: DVec3,
    pu: DVec3,
    pv: DVec3,
    grad: DVec2,
    perturbation: Perturbation,
) -> DVec3 {
    let ng = pu.cross(pv);
    let len = ng.length();
    if !(len > 0.0 && len.is_finite()) {
        return n;
    }
    let s = if ng.dot(n) < 0.0 { -1.0 } else { 1.0 };
    let d = (n.cross(pv) * grad.x + pu.cross(n) * grad.y) * s;
    let d = match perturbation {
        Perturbation::Blinn => d,
        Perturbation::ScaleInvariant => {
            let dl = d.length();
            if dl > 0.0 && dl.is_finite() {
                d * (grad.length() * len / dl)
            } else {
                DVec3::ZERO
            }
        }
    };
    normalize_or(n * len + d, n)
}

/// The orthonormal tangent frame `(T, B)` around the unit normal `n` (Ernst et al. 1998 §3.4,
/// `TS = (T, B, N)`, `T = Pu / |Pu|`, `B = N × T`), with `T` made exactly perpendicular to
/// `n` (Gram–Schmidt): `T = normalize(Pu - (Pu · n) n)`, `B = n × T`.
///
/// **Handedness**: `B` follows `Pv`. If `(Pu × Pv) · n < 0` (mirrored texture coordinates)
/// `B = -(n × T)`, so a texel `y` always points along `+Pv`.
///
/// Fallbacks: if `Pu` is (nearly) parallel to `n` or zero, `B = normalize(Pv - (Pv · n) n)`
/// and `T = B × n`; if both are, any orthonormal pair around `n`.
pub fn tangent_frame(n: DVec3, pu: DVec3, pv: DVec3) -> (DVec3, DVec3) {
    let tu = pu - n * pu.dot(n);
    if tu.length() > 1e-12 * pu.length() {
        if let Some(t) = tu.try_normalize() {
            let b = n.cross(t);
            let b = if pu.cross(pv).dot(n) < 0.0 { -b } else { b };
            return (t, b);
        }
    }
    let tv = pv - n * pv.dot(n);
    if tv.length() > 1e-12 * pv.length() {
        if let Some(b) = tv.try_normalize() {
            return (b.cross(n), b);
        }
    }
    let t = n.any_orthonormal_vector();
    (t, n.cross(t))
}

/// A tangent-space normal-map texel `t` (unit, `x` along `Pu`, `y` along `Pv`, `z` along the
/// normal) taken to world space (Ernst et al. 1998 §3.4): `N' = T t.x + B t.y + n̂ t.z` with
/// the frame of [`tangent_frame`], returned normalised (`n̂` if that fails).
pub fn perturb_normal_map(n: DVec3, pu: DVec3, pv: DVec3, t: DVec3) -> DVec3 {
    let (tt, bb) = tangent_frame(n, pu, pv);
    normalize_or(tt * t.x + bb * t.y + n * t.z, n)
}

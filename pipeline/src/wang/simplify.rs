//! Simplification to a target face count (Wang et al. §4: "We adopted Garland's
//! simplification method \[1\]"): the quadric error metric of Garland and Heckbert, through
//! the `meshopt` crate (meshoptimizer's `meshopt_simplify`, edge collapses ordered by
//! quadric error, topology kept).
//!
//! Where edge collapses that keep the topology stop above the target (meshes with many
//! borders or small components, as scans have), the result is finished with
//! `meshopt_simplifySloppy` (vertex clustering, which may change the topology; the method
//! does not mind, §1), and [`Simplified::sloppy`] says so.
//!
//! The simplified mesh keeps only its own vertices, renumbered in order of first use, with
//! smooth normals of its own faces: no map back to the detailed mesh (the method needs none).

use glam::DVec3;

use super::Surface;
use crate::scene::mesh::degenerate3;

/// The smallest target face count.
pub const MIN_FACES: usize = 4;

/// A simplified mesh and how it was made.
#[derive(Debug, Clone)]
pub struct Simplified {
    pub surface: Surface,
    /// The face count asked for.
    pub target: usize,
    /// Whether vertex clustering finished it (see the module).
    pub sloppy: bool,
    /// meshoptimizer's error estimate, relative to the mesh's extent.
    pub error: f32,
}

/// Simplify `detailed` to at most `target` faces (exactly, where meshoptimizer reaches it).
/// `target` must be at least [`MIN_FACES`] and at most the detailed mesh's face count.
pub fn simplify(detailed: &Surface, target: usize) -> Result<Simplified, String> {
    let faces = detailed.triangles.len();
    if target < MIN_FACES || target > faces {
        return Err(format!(
            "expected a target face count from {MIN_FACES} to the mesh's {faces} faces, found \
             {target}"
        ));
    }
    let positions: Vec<[f32; 3]> = detailed
        .positions
        .iter()
        .map(|p| p.as_vec3().to_array())
        .collect();
    let indices: Vec<u32> = detailed.triangles.iter().flatten().copied().collect();
    let mut error = 0.0f32;
    let mut out = meshopt::simplify_decoder(
        &indices,
        &positions,
        target * 3,
        f32::MAX,
        meshopt::SimplifyOptions::None,
        Some(&mut error),
    );
    let sloppy = out.len() > target * 3;
    if sloppy {
        out = meshopt::simplify_sloppy_decoder(&out, &positions, target * 3, f32::MAX, None);
    }
    let surface = compact(detailed, &out);
    if surface.triangles.is_empty() {
        return Err(format!(
            "simplification to {target} faces left no face of non-zero area"
        ));
    }
    Ok(Simplified {
        surface,
        target,
        sloppy,
        error,
    })
}

/// The faces of `indices` (into `detailed`'s positions) with their own vertices, renumbered
/// in order of first use; faces of zero area dropped; smooth normals recomputed.
fn compact(detailed: &Surface, indices: &[u32]) -> Surface {
    let mut map = vec![u32::MAX; detailed.positions.len()];
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles = Vec::with_capacity(indices.len() / 3);
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|k| detailed.positions[k as usize]);
        if degenerate3(a, b, c) {
            continue;
        }
        let tri = [t[0], t[1], t[2]].map(|k| {
            let slot = &mut map[k as usize];
            if *slot == u32::MAX {
                *slot = positions.len() as u32;
                positions.push(detailed.positions[k as usize]);
            }
            *slot
        });
        triangles.push(tri);
    }
    Surface::with_smooth_normals(positions, triangles)
}

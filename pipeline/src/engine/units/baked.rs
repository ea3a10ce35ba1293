//! The normal maps baked from a scene's bump map, shared by the engines of this process that
//! bake the same map (`crate::memo`): a sweep's points, a study's rows, the units of one
//! engine that read the same map in two forms.
//!
//! A bake is a pure function of the bump map (and, for object-space normals, the mesh), its
//! size and its method, so it is kept under the scene's bump key ([`crate::scene::SceneKey`]:
//! the bump and mesh specs, the config's directory, the files read), the size and the
//! method. Scenes without a key bake every time.

use super::BuildCtx;
use crate::memo::Memo;
use crate::scene::NormalMethod;
use glam::DVec3;
use std::sync::Arc;

/// Maps kept at most, and the texels they may hold together (4 M: 100 MB; a larger one
/// is not kept).
const CAPACITY: usize = 8;
const BUDGET_TEXELS: usize = 4 << 20;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Space {
    /// Tangent space from the bump map alone (`BumpMap::bake_normals`).
    Tangent(NormalMethod),
    /// Object space, the mesh rasterised in uv space (`scene::bake`).
    Object,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    bump: [u64; 2],
    size: u32,
    space: Space,
}

static MAPS: Memo<Key, Arc<Vec<DVec3>>> = Memo::weighed(CAPACITY, BUDGET_TEXELS, |m| m.len());

fn shared(
    ctx: &BuildCtx,
    size: u32,
    space: Space,
    bake: impl FnOnce() -> Vec<DVec3>,
) -> Arc<Vec<DVec3>> {
    match ctx.scene.key {
        Some(k) => MAPS.get_or_build(
            Key {
                bump: k.bump,
                size,
                space,
            },
            || Arc::new(bake()),
        ),
        _ => Arc::new(bake()),
    }
}

/// The scene's bump map as a `size` x `size` tangent-space normal map baked by `method`.
pub(super) fn tangent_normals(ctx: &BuildCtx, size: u32, method: NormalMethod) -> Arc<Vec<DVec3>> {
    shared(ctx, size, Space::Tangent(method), || {
        ctx.scene.bump.bake_normals(size, size, method).texels
    })
}

/// The mesh's perturbed normals in object space, `size` x `size` (`scene::bake`).
pub(super) fn object_normals(ctx: &BuildCtx, size: u32) -> Arc<Vec<DVec3>> {
    shared(ctx, size, Space::Object, || {
        crate::scene::bake::bake(
            &ctx.scene.mesh,
            &ctx.scene.bump,
            size,
            crate::scene::bake::BakeSpace::Object,
            crate::reference::Perturbation::ScaleInvariant,
        )
        .map
        .texels
    })
}

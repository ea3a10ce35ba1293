//! Checks that several unit specs share. A unit's own limits are checked in its spec file (and
//! some again by the `bumpsim-hw` unit, e.g. texture sides there go up to 16384).

use super::BuildCtx;

/// `parallel` datapaths for `count` inputs or lights.
pub(super) fn check_parallel(parallel: u32, count: u32) -> Result<(), String> {
    if (1..=count.max(1)).contains(&parallel) {
        Ok(())
    } else {
        Err(format!(
            "parallel {parallel}: expected 1 to {} datapaths",
            count.max(1)
        ))
    }
}

/// A texture side.
pub(super) fn check_size(size: u32) -> Result<(), String> {
    if size.is_power_of_two() && (1..=4096).contains(&size) {
        Ok(())
    } else {
        Err(format!(
            "size {size}: expected a power of two from 1 to 4096"
        ))
    }
}

/// The error of a unit that shades with the bump lights when the scene has none.
pub(super) const NO_BUMP_LIGHT: &str =
    "the scene has no light with bump: true: expected at least one";

/// The scene's bump lights, at least one.
pub(super) fn some_bump_lights(ctx: &BuildCtx) -> Result<Vec<usize>, String> {
    let lights = ctx.bump_lights();
    if lights.is_empty() {
        return Err(NO_BUMP_LIGHT.into());
    }
    Ok(lights)
}

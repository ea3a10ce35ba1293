//! A sweep's light shares (`shares: [...]` in the sweep file): the light a point's image keeps
//! on a class of pixels, as a share of the reference's light there ([`metrics::light_share`]).
//! The class is the pixels where a *mask* (the point's own config with the share's overrides
//! added last, rendered bit-accurately, e.g. `engine.output="tex.t"`: the texture the engine
//! fetched) has the share's colour. This is what judges a claim about one kind of texel, e.g.
//! Ernst et al. §5.1's "no effect on black texture color" (`docs/sweep.md`, "Light shares").

use super::table::Cell;
use crate::config::{self, InputError, LoadOptions};
use crate::metrics;
use crate::run::RunResult;
use bumpsim_hw::Mode;
use serde::Deserialize;
use std::path::Path;

/// One `share.NAME` column.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Share {
    /// The column is `share.NAME`.
    pub name: String,
    /// Overrides (after the point's) that make the mask's config.
    pub mask: Vec<String>,
    /// The class: the pixels where the mask's 8-bit image is this colour.
    pub colour: [u8; 3],
}

/// The mask's bit-accurate 8-bit image: `config` with `sets` (no reference, no error).
fn mask_image(config: &Path, sets: &[String], force: bool) -> Result<image::RgbImage, InputError> {
    let l = config::load_with(config, sets, LoadOptions { force })?;
    let p = crate::run::prepare(&l)?;
    let bit = p.simulate_lanes(None);
    let extra = p.pass_outputs(Mode::BitAccurate);
    let fb = p.framebuffer(Mode::BitAccurate, &bit.outputs, &extra, &p.raster.fragments);
    Ok(fb.rgb8)
}

/// The share cells of run `r` of `config` with the point's `sets`, in `shares` order: each
/// mask rendered once (shares with the same overrides share it); a share whose class holds
/// no lit reference pixel is empty.
pub fn cells(
    shares: &[Share],
    config: &Path,
    sets: &[String],
    force: bool,
    r: &RunResult,
) -> Result<Vec<Cell>, InputError> {
    let mut masks: Vec<(&[String], image::RgbImage)> = Vec::new();
    let mut out = Vec::with_capacity(shares.len());
    for s in shares {
        let at = match masks.iter().position(|(m, _)| *m == s.mask.as_slice()) {
            Some(k) => k,
            None => {
                let all: Vec<String> = sets.iter().chain(&s.mask).cloned().collect();
                let img = mask_image(config, &all, force).map_err(|mut e| {
                    e.message = format!("the mask of share {:?}: {}", s.name, e.message);
                    e
                })?;
                masks.push((&s.mask, img));
                masks.len() - 1
            }
        };
        let share = metrics::light_share(&r.image, &r.reference, &masks[at].1, s.colour);
        out.push(share.map_or(Cell::Empty, Cell::Float));
    }
    Ok(out)
}

/// The shares' names are distinct and non-empty (`file`: the sweep file, for the message).
pub fn check(shares: &[Share], file: &str) -> Result<(), InputError> {
    for (k, s) in shares.iter().enumerate() {
        let bad = |m: String| Err(InputError::new(file, format!("shares[{k}].name"), m));
        if s.name.trim().is_empty() {
            return bad("expected a name (the column is share.NAME)".into());
        }
        if shares[..k].iter().any(|t| t.name == s.name) {
            return bad(format!("{:?} twice: expected distinct names", s.name));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn share_names_are_checked() {
        let s = |n: &str| Share {
            name: n.into(),
            mask: vec![],
            colour: [0; 3],
        };
        assert!(check(&[s("black"), s("white")], "f").is_ok());
        assert_eq!(
            check(&[s("a"), s("a")], "f").unwrap_err().field,
            "shares[1].name"
        );
        assert_eq!(check(&[s(" ")], "f").unwrap_err().field, "shares[0].name");
    }
}

//! The stage rules: NV_texture_shader 3.8.13, "Texture Shader Consistency" (a stage whose
//! rule is broken is inconsistent and behaves as NONE; later stages that read it see an
//! invalid result and are inconsistent in turn), and the operations' requirements on the
//! previous texture input (section 3.8.13's per-operation descriptions).

use super::program::{Program, Result_};
use super::StageSpec;
use crate::format::Codec;
use crate::texture::Shape;

/// What a checked earlier stage offers its readers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Offer {
    pub result: Result_,
    pub lanes: u8,
    pub width: u32,
    pub signed: bool,
    pub program: Program,
    pub consistent: bool,
}

/// The broken rule of each stage, in order (`None`: consistent).
pub(crate) fn check(stages: &[StageSpec]) -> Vec<Option<String>> {
    let n = stages.len();
    let mut offers: Vec<Offer> = Vec::with_capacity(n);
    let mut out = Vec::with_capacity(n);
    for (i, s) in stages.iter().enumerate() {
        let r = rule(i, stages, &offers);
        let p = s.program;
        let tex = s.texture.as_ref();
        offers.push(Offer {
            result: if r.is_some() {
                Result_::Invalid
            } else {
                p.result()
            },
            lanes: match p {
                Program::PassThrough => 4,
                _ => tex.map(|t| t.lanes()).unwrap_or(0),
            },
            width: match p {
                Program::PassThrough => 8,
                _ => tex.map(|t| t.texel().width()).unwrap_or(0),
            },
            signed: p != Program::PassThrough && tex.is_some_and(|t| t.texel().format.signed),
            program: p,
            consistent: r.is_none(),
        });
        out.push(r);
    }
    out
}

fn rule(i: usize, stages: &[StageSpec], offers: &[Offer]) -> Option<String> {
    let s = &stages[i];
    let p = s.program;
    let name = p.name();
    // the stage's own texture
    if let Some(cube) = p.texture_kind() {
        match &s.texture {
            None => return Some(format!("{name} needs a texture bound to the stage")),
            Some(t) => {
                let want = if cube { Shape::Cube } else { Shape::Flat };
                if t.shape() != want {
                    let w = if cube { "a cube map" } else { "a 2D texture" };
                    return Some(format!(
                        "{name} reads {w}: texture {} is {}",
                        t.name(),
                        if cube { "a 2D texture" } else { "a cube map" }
                    ));
                }
                if matches!(t.texel().codec, Codec::Fixed) {
                    return Some(format!(
                        "{name}: texture {} has fixed-point texels: expected a unit codec",
                        t.name()
                    ));
                }
            }
        }
    }
    let prev = p.prev()?;
    if i == 0 {
        return Some(format!(
            "{name} reads a previous stage: not allowed in stage 0"
        ));
    }
    if prev >= i {
        return Some(format!(
            "{name} reads stage {prev}: expected an earlier stage (0 to {})",
            i - 1
        ));
    }
    let o = offers[prev];
    if o.result == Result_::Invalid {
        return Some(format!(
            "{name} reads stage {prev}, whose result is invalid ({}{}): expected a texel or \
             a PASS_THROUGH colour",
            o.program.name(),
            if o.consistent { "" } else { ", inconsistent" }
        ));
    }
    match p {
        Program::OffsetTexture2d { offset, .. } | Program::OffsetTexture2dScale { offset, .. } => {
            let scale = matches!(p, Program::OffsetTexture2dScale { .. });
            let need = if scale { 3 } else { 2 };
            if o.result != Result_::Texel {
                return Some(format!("{name} reads stage {prev}: expected a DSDT texel"));
            }
            for (k, &l) in offset.lanes[..need].iter().enumerate() {
                if l >= o.lanes as usize {
                    return Some(format!(
                        "{name}: offset.lanes[{k}] = {l}: stage {prev}'s texel has {} lanes",
                        o.lanes
                    ));
                }
            }
            // the NV2A reading (`twos_complement`) takes any 8-bit texel as signed
            if !o.signed && !offset.twos_complement {
                return Some(format!(
                    "{name} reads stage {prev}: expected signed DS, DT (a DSDT texture, or \
                     offset.twos_complement, the NV2A's reading of an unsigned map)"
                ));
            }
        }
        Program::DependentAr { .. } | Program::DependentGb { .. } => {
            let need = if matches!(p, Program::DependentAr { .. }) {
                4
            } else {
                3
            };
            if o.signed || o.lanes < need {
                return Some(format!(
                    "{name} reads stage {prev}: expected an unsigned texel of {need} lanes"
                ));
            }
        }
        _ => {}
    }
    if let Some(m) = p.mapping() {
        if m.is_hilo() {
            let ok = (o.lanes == 2 && o.width == 16) || (o.lanes == 4 && o.width == 8);
            if !ok {
                return Some(format!(
                    "{name} with {m:?} reads stage {prev}: expected a 2-lane 16-bit HILO texel \
                     or a 4-lane 8-bit texel"
                ));
            }
        } else if o.lanes < 3 {
            return Some(format!(
                "{name} with {m:?} reads stage {prev}: expected a texel of 3 or 4 lanes"
            ));
        }
    }
    // the dot-product groups
    let is_dot_of = |k: usize| {
        offers.get(k).is_some_and(|o| {
            o.consistent
                && matches!(o.program, Program::DotProduct { .. })
                && o.program.prev() == Some(prev)
        })
    };
    let need = |back: usize, what: &str| -> Option<String> {
        if i < back {
            return Some(format!("{name} needs {back} stages before it: {what}"));
        }
        None
    };
    match p {
        Program::DotProductTexture2d { .. } | Program::DotProductDepthReplace { .. } => {
            if let Some(e) = need(2, "a texel and a DOT_PRODUCT") {
                return Some(e);
            }
            if !is_dot_of(i - 1) {
                return Some(format!(
                    "{name}: stage {} must be a consistent DOT_PRODUCT reading stage {prev}",
                    i - 1
                ));
            }
        }
        Program::DotProductTextureCube { .. } => {
            if let Some(e) = need(3, "a texel and two DOT_PRODUCTs") {
                return Some(e);
            }
            if !is_dot_of(i - 1) || !is_dot_of(i - 2) {
                return Some(format!(
                    "{name}: stages {} and {} must be consistent DOT_PRODUCTs reading stage {prev}",
                    i - 2,
                    i - 1
                ));
            }
        }
        Program::DotProductReflectCube { .. } | Program::DotProductConstEyeReflectCube { .. } => {
            if let Some(e) = need(3, "a texel and two dot-product stages") {
                return Some(e);
            }
            let mid = offers[i - 1];
            let mid_ok = is_dot_of(i - 1)
                || (mid.consistent
                    && matches!(mid.program, Program::DotProductDiffuseCube { .. })
                    && mid.program.prev() == Some(prev));
            if !is_dot_of(i - 2) || !mid_ok {
                return Some(format!(
                    "{name}: stage {} must be a consistent DOT_PRODUCT and stage {} a \
                     DOT_PRODUCT or DOT_PRODUCT_DIFFUSE_CUBE_MAP, reading stage {prev}",
                    i - 2,
                    i - 1
                ));
            }
        }
        Program::DotProductDiffuseCube { .. } => {
            if let Some(e) = need(2, "a texel and a DOT_PRODUCT") {
                return Some(e);
            }
            let next_ok = stages.get(i + 1).is_some_and(|s| {
                matches!(
                    s.program,
                    Program::DotProductReflectCube { .. }
                        | Program::DotProductConstEyeReflectCube { .. }
                ) && s.program.prev() == Some(prev)
            });
            if !is_dot_of(i - 1) || !next_ok {
                return Some(format!(
                    "{name}: stage {} must be a consistent DOT_PRODUCT and stage {} a \
                     DOT_PRODUCT_REFLECT_CUBE_MAP or _CONST_EYE_, reading stage {prev}",
                    i - 1,
                    i + 1
                ));
            }
        }
        _ => {}
    }
    None
}

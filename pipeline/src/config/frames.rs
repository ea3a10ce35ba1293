//! A config's `frames`: a short animation. Frame 0 is the config itself; frame `k` (1 to
//! `frames.len()`) is the config with the `--set` overrides `frames[k - 1]`, which may only
//! change the per-frame inputs (lights, camera, material, model transform): the hardware is
//! the same in every frame, and each frame pays its own per-frame work (table loads, palette
//! builds) as the hardware would (`docs/configs.md`, "Frames").

use super::{hash_of, overrides, validate, InputError, Loaded};

/// Most frames after frame 0.
pub const MAX_FRAMES: usize = 64;
/// Most pixels over all frames (every frame's image is kept until the outputs are written):
/// 64 frames of 1024 x 1024.
pub const MAX_FRAME_PIXELS: u64 = 1 << 26;
/// Most overrides in one frame.
pub const MAX_FRAME_SETS: usize = 64;
/// The config paths a frame may set: the inputs the host hands the units each frame.
pub const PER_FRAME: [&str; 4] = [
    "scene.lights",
    "scene.camera",
    "scene.material",
    "scene.model",
];

/// The checks of `frames` when a config loads: the count, the pixels, every override a
/// per-frame input, and every frame a valid config (so a bad frame is an error before
/// anything renders).
pub(super) fn check(l: &Loaded) -> Result<(), InputError> {
    let frames = &l.config.frames;
    if frames.is_empty() {
        return Ok(());
    }
    if frames.len() > MAX_FRAMES {
        return Err(l.error(
            "frames",
            "frames:",
            format!(
                "{} frames: expected at most {MAX_FRAMES} after frame 0",
                frames.len()
            ),
        ));
    }
    let s = &l.config.scene;
    let pixels = (frames.len() as u64 + 1) * u64::from(s.width.0) * u64::from(s.height.0);
    if pixels > MAX_FRAME_PIXELS {
        return Err(l.error(
            "frames",
            "frames:",
            format!(
                "{} frames of {}x{} are {pixels} pixels: expected at most {MAX_FRAME_PIXELS} \
                 over all frames",
                frames.len() + 1,
                s.width.0,
                s.height.0
            ),
        ));
    }
    for (i, sets) in frames.iter().enumerate() {
        if sets.len() > MAX_FRAME_SETS {
            return Err(l.error(
                &format!("frames[{i}]"),
                "frames:",
                format!(
                    "{} overrides: expected at most {MAX_FRAME_SETS} in a frame",
                    sets.len()
                ),
            ));
        }
        for (j, set) in sets.iter().enumerate() {
            let path = set.split_once('=').map_or(set.as_str(), |p| p.0).trim();
            let per_frame = PER_FRAME.iter().any(|p| {
                path.strip_prefix(p)
                    .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
            });
            if !per_frame {
                return Err(l.error(
                    &format!("frames[{i}][{j}]"),
                    &format!("{set:?}"),
                    format!(
                        "{set:?}: a frame sets per-frame inputs only: expected a path under {}",
                        PER_FRAME.join(", ")
                    ),
                ));
            }
        }
    }
    for k in 1..=frames.len() {
        let f = frame(l, k)?;
        // the lighting model is hardware: the palette builder's function (its passes, its power
        // generator, a sphere-map address), not a register the host loads
        if f.config.scene.material.model != l.config.scene.material.model {
            let i = k - 1;
            return Err(l.error(
                &format!("frames[{i}]"),
                "frames:",
                format!(
                    "frame {k} changes scene.material.model from {} to {}: expected the same \
                     lighting model in every frame (a frame may change the material's colours \
                     and shininess)",
                    l.config.scene.material.model.name(),
                    f.config.scene.material.model.name()
                ),
            ));
        }
    }
    Ok(())
}

/// Frame `k` of the animation: the config itself for 0, else the config without its
/// `frames` and with the overrides `frames[k - 1]`, validated. Errors name the frame's
/// override (`frames[i][j]`) or, for a frame that is not a valid config, the frame and the
/// field.
pub fn frame(l: &Loaded, k: usize) -> Result<Loaded, InputError> {
    if k == 0 {
        return Ok(l.clone());
    }
    let i = k - 1;
    let sets = l.config.frames.get(i).ok_or_else(|| {
        InputError::new(
            l.path.display().to_string(),
            "frames",
            format!(
                "no frame {k}: the config has {} frames",
                l.config.frames.len() + 1
            ),
        )
    })?;
    let mut config = l.config.clone();
    config.frames.clear();
    for (j, set) in sets.iter().enumerate() {
        config = overrides::apply(&config, std::slice::from_ref(set)).map_err(|e| {
            let field = format!("frames[{i}][{j}]");
            let what = match e.field.is_empty() {
                true => String::new(),
                false => format!(" {}:", e.field),
            };
            l.error(
                &field,
                &format!("{set:?}"),
                format!("{set:?}:{what} {}", e.message),
            )
        })?;
    }
    let frame = Loaded {
        hash: hash_of(&config),
        config,
        sets: l.sets.iter().chain(sets).cloned().collect(),
        ..l.clone()
    };
    validate(&frame).map_err(|e| InputError {
        field: format!("frames[{i}] (frame {k}): {}", e.field),
        ..e
    })?;
    Ok(frame)
}

//! `bumpsim nv2a FRAME.ron... [--set P=V] [--exact] [--json] [--out DIR]`: render NV2A frame
//! configs (`configs/nv2a/`) with the model's units and compare them with the frames real
//! hardware rendered (`bumpsim_pipeline::nv2a`, `docs/nv2a.md`). Prints per frame the pixels
//! compared, the exact ones, their share, the largest difference and where the mismatches
//! sit; with `--out`, writes the model's picture of each frame (`NAME.png`), where it differs
//! from the hardware's (`NAME-diff.png`: misses magenta) and the comparisons (`nv2a.json`),
//! all or nothing.

use crate::Failure;
use bumpsim_hw::Mode;
use bumpsim_pipeline::config::InputError;
use bumpsim_pipeline::nv2a::{self, Comparison};
use bumpsim_pipeline::output::OutputSet;
use std::path::{Path, PathBuf};

pub fn execute(
    frames: &[PathBuf],
    sets: &[String],
    exact: bool,
    json: bool,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let mode = if exact {
        Mode::Exact
    } else {
        Mode::BitAccurate
    };
    let mut results: Vec<Comparison> = Vec::new();
    let mut set = out.map(OutputSet::new);
    for path in frames {
        let l = nv2a::load(path, sets)?;
        let internal = |m: String| Failure::Internal(format!("{}: {m}", path.display()));
        let c = nv2a::compare(&l, mode).map_err(internal)?;
        if let Some(set) = set.as_mut() {
            let name = format!("{}.png", l.frame.name);
            if results.iter().any(|r| r.frame == l.frame.name) {
                return Err(Failure::Input(InputError::new(
                    path.display().to_string(),
                    "name",
                    format!(
                        "a second frame named {:?}: expected distinct names with --out",
                        l.frame.name
                    ),
                )));
            }
            set.add(&name, nv2a::render_png(&l, mode).map_err(internal)?);
            let diff = nv2a::diff(&l, mode).and_then(|d| nv2a::png(&d));
            set.add(
                &format!("{}-diff.png", l.frame.name),
                diff.map_err(internal)?,
            );
        }
        results.push(c);
    }
    let text =
        serde_json::to_string_pretty(&results).map_err(|e| Failure::Internal(e.to_string()))?;
    if let (Some(set), Some(dir)) = (set.as_mut(), out) {
        set.add("nv2a.json", format!("{text}\n").into_bytes());
        std::mem::replace(set, OutputSet::new(dir))
            .commit()
            .map_err(|e| Failure::Input(InputError::new(dir.display().to_string(), "--out", e)))?;
    }
    if json {
        println!("{text}");
        return Ok(());
    }
    println!("{}", Comparison::header());
    for r in &results {
        println!("{}", r.line());
    }
    if results.len() > 1 {
        let (c, e) = results
            .iter()
            .fold((0, 0), |(c, e), r| (c + r.compared, e + r.exact));
        println!(
            "{:<24} {:>9} {:>9} {:>8.3}%",
            "all",
            c,
            e,
            100.0 * e as f64 / c.max(1) as f64
        );
    }
    Ok(())
}

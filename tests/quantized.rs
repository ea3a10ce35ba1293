//! Quantized normal maps (Tarini, Cignoni, Rocchini, Scopigno 1999) end to end on
//! `configs/quantized-sphere.ron`: the error falls as the table grows (§4), the per-frame
//! work grows with the table (§5.1) and does not depend on the texture size (§1).

use bumpsim_pipeline::config;
use bumpsim_pipeline::run::{run, RunResult};
use std::path::PathBuf;

fn run_with(sets: &[String]) -> RunResult {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("configs/quantized-sphere.ron");
    let l = config::load(&path, sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    run(&l, None).unwrap_or_else(|e| panic!("{sets:?}: {e}"))
}

fn table(s_n: u32, size: u32) -> RunResult {
    let bits = s_n.next_power_of_two().trailing_zeros().max(8);
    run_with(&[
        format!("engine.units.qnm.unit.s_n={s_n}"),
        format!("engine.units.qnm.unit.index_bits={bits}"),
        format!("engine.units.qnm.unit.size={size}"),
    ])
}

#[test]
fn error_falls_and_frame_cycles_grow_with_the_table_size() {
    let runs: Vec<(u32, RunResult)> = [16u32, 256, 2048]
        .into_iter()
        .map(|s| (s, table(s, 256)))
        .collect();
    for (s, r) in &runs {
        println!(
            "s_n {s}: total PSNR {:.2} dB, algorithm {:.2} dB, frame cycles {}, gates {:.0}",
            r.report.error.total.psnr_db,
            r.report.error.algorithm.psnr_db,
            r.report.cycles.frame,
            r.report.gates.total
        );
    }
    for w in runs.windows(2) {
        let ((s0, a), (s1, b)) = (&w[0], &w[1]);
        assert!(
            b.report.error.total.psnr_db > a.report.error.total.psnr_db + 1.0,
            "s_n {s0} -> {s1}: PSNR {} -> {}",
            a.report.error.total.psnr_db,
            b.report.error.total.psnr_db
        );
        assert!(b.report.cycles.frame > a.report.cycles.frame);
    }
    // Blinn-Phong, one light: 2 builder clocks per entry, then 1 clock per entry to load
    for (s, r) in &runs {
        assert_eq!(r.report.cycles.frame, 3 * *s as u64, "s_n {s}");
    }
}

#[test]
fn frame_cycles_do_not_depend_on_the_bake_size() {
    let (a, b) = (table(256, 128), table(256, 256));
    assert_eq!(a.report.cycles.frame, b.report.cycles.frame);
    assert_eq!(a.report.bandwidth.textures["qnm"], 8);
}

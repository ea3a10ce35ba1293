//! Bad quantized-normal-map configs (Tarini et al.): each is rejected with exit code 2 and a
//! message naming the field and what was expected.

mod common;

use common::*;

#[test]
fn bad_quantized_configs_are_rejected() {
    let cfg = config("quantized-sphere");
    let cases: [(&str, &[&str]); 6] = [
        (
            "engine.units.qnm.unit.s_n=0",
            &["s_n 0", "expected 1 to 2^index_bits = 256"],
        ),
        (
            "engine.units.qnm.unit.s_n=300",
            &["s_n 300", "expected 1 to 2^index_bits = 256"],
        ),
        (
            "engine.units.qnm.unit.index_bits=15",
            &["index_bits 15", "expected 8 to 14"],
        ),
        (
            "engine.units.qnm.unit.index_bits=7",
            &["index_bits 7", "expected 8 to 14"],
        ),
        (
            "engine.units.qnm.unit.size=100",
            &["size 100", "power of two"],
        ),
        (
            "engine.units.qnm.unit.quantizer=NeuQuant(sample_factor: 0)",
            &["sample_factor", "1..=30"],
        ),
    ];
    for (set, needles) in cases {
        let args = [
            "check".to_string(),
            cfg.display().to_string(),
            "--set".into(),
            set.to_string(),
        ];
        let o = bumpsim(&args);
        o.expect_code(2, set);
        assert!(
            o.stderr.contains("engine.units[0].unit"),
            "{set}: no field in {}",
            o.stderr
        );
        for n in needles {
            assert!(
                o.stderr.contains(n),
                "{set}: the message lacks {n:?}: {}",
                o.stderr
            );
        }
    }
}

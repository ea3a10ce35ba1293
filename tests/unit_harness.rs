//! The generic unit harness: every unit of every bundled engine, in the configuration the
//! config gives it, on fragments of its own scene.
//!
//! * bit-accurate mode: every output lane is a word of its port's format and `x` is
//!   `decode(raw)` exactly;
//! * exact mode: `raw` is `encode(x)` (kept for traces);
//! * function is apart from timing: the timed run's output of each fragment is the untimed
//!   evaluation's, whatever the FIFO depths (1, 2 or 7), so back-pressure never changes a
//!   value.

mod common;

use bumpsim_hw::Mode;
use bumpsim_pipeline::config;
use bumpsim_pipeline::run::{prepare, Prepared};
use common::*;

/// Fragments sampled per config: spread evenly over the frame.
const SAMPLES: usize = 300;

fn sample(p: &Prepared) -> Vec<usize> {
    let n = p.raster.fragments.len();
    (0..SAMPLES.min(n))
        .map(|k| k * n / SAMPLES.min(n))
        .collect()
}

/// The configs of the harness: all bundled ones but the quantized vase's s_N series, which
/// only repeats one engine at other table sizes.
fn harness_configs() -> Vec<std::path::PathBuf> {
    configs()
        .into_iter()
        .filter(|c| !stem(c).starts_with("quantized-vase-sn"))
        .collect()
}

#[test]
fn every_output_word_decodes_to_its_value_in_both_modes() {
    let mut checked = 0u64;
    for cfg in harness_configs() {
        let name = stem(&cfg);
        let l = config::load(&cfg, &[]).unwrap();
        let p = prepare(&l).unwrap();
        for f in sample(&p) {
            let bit = p.fragment_token(Mode::BitAccurate, f);
            let exact = p.fragment_token(Mode::Exact, f);
            for s in &p.engine.stages {
                let specs = s.unit().outputs();
                for (port, (wb, we)) in specs
                    .iter()
                    .zip(s.output_words(&bit).iter().zip(s.output_words(&exact)))
                {
                    let enc = &port.enc;
                    for l in 0..port.lanes as usize {
                        let (b, e) = (wb.lanes[l], we.lanes[l]);
                        let at = format!("{name}: {}.{} lane {l}, fragment {f}", s.name, port.name);
                        assert!(
                            enc.format.contains(b.raw),
                            "{at}: raw {} out of {}",
                            b.raw,
                            enc
                        );
                        assert_eq!(b.x, enc.decode(b.raw), "{at}: x is not decode(raw)");
                        assert_eq!(e.raw, enc.encode(e.x), "{at}: exact raw is not encode(x)");
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 50_000, "only {checked} lanes checked");
}

/// Every stage over batches of columns (`Stage::eval_columns`: the unit's batch datapath, or
/// its `eval` on words decoded from the columns) writes each output port's raw words that
/// `eval_token` writes, on the fragments of every harness config: whatever the output
/// columns held before (they are filled with junk first).
#[test]
fn batches_of_columns_give_each_stages_words() {
    use bumpsim_hw::{ColumnScratch, Columns, BATCH};
    let mut checked = 0u64;
    for cfg in harness_configs() {
        let name = stem(&cfg);
        let l = config::load(&cfg, &[]).unwrap();
        let p = prepare(&l).unwrap();
        let tokens: Vec<_> = sample(&p)
            .into_iter()
            .map(|f| (f, p.fragment_token(Mode::BitAccurate, f)))
            .collect();
        let mut scratch = ColumnScratch::default();
        for batch in tokens.chunks(BATCH) {
            for s in &p.engine.stages {
                let mut cols = Columns::new(p.engine.slots());
                cols.start(batch.len());
                for (k, (_, t)) in batch.iter().enumerate() {
                    for (slot, w) in t.slots.iter().enumerate() {
                        cols.set_word(slot, k, w);
                    }
                }
                for &o in s.out_slots() {
                    *cols.slots[o] = [[0x5a5a_5a5a; BATCH]; bumpsim_hw::MAX_LANES];
                }
                s.eval_columns(&mut cols, &mut scratch);
                let ports = s.unit().outputs();
                for (k, (f, t)) in batch.iter().enumerate() {
                    for ((port, w), &o) in ports.iter().zip(s.output_words(t)).zip(s.out_slots()) {
                        for l in 0..port.lanes as usize {
                            assert_eq!(
                                cols.slots[o][l][k], w.lanes[l].raw,
                                "{name}: {}.{} lane {l}, fragment {f}",
                                s.name, port.name
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 50_000, "only {checked} lanes checked");
}

#[test]
fn timed_outputs_are_the_untimed_evaluation_at_any_fifo_depth() {
    for name in [
        "sgi-teapot",
        "gouraud-sphere-spots",
        "cull-fragment",
        "quantized-bunny-wood-eq2",
    ] {
        let mut first = None;
        for depth in [1, 2, 7] {
            let l = config::load(&config(name), &[format!("sim.fifo_depth={depth}")]).unwrap();
            let mut p = prepare(&l).unwrap();
            let timed = p.simulate(None);
            let n = p.raster.fragments.len();
            for f in sample(&p) {
                let t = p.fragment_token(Mode::BitAccurate, f);
                let untimed = t.live.then(|| p.engine.output.wire.read(&t.slots));
                assert_eq!(
                    timed.outputs[f], untimed,
                    "{name} depth {depth} fragment {f}"
                );
            }
            assert_eq!(timed.outputs.len(), n);
            match &first {
                None => first = Some((timed.outputs, timed.cycles.total)),
                Some((outs, cycles)) => {
                    assert_eq!(
                        &timed.outputs, outs,
                        "{name}: depth {depth} changed a value"
                    );
                    // shallower FIFOs can only cost cycles
                    assert!(timed.cycles.total <= *cycles, "{name} depth {depth}");
                }
            }
        }
    }
}

/// The ROP's datapath (`RopDatapath`, the function `Rop::write` applies) on what each pass's
/// ROP read in the frame: every output word of its port's format with `x = decode(raw)`, the
/// write flags as the outcome, and the codes written the stored ones when nothing is.
#[test]
fn the_rops_datapath_words_decode_on_the_frames_own_fragments() {
    use bumpsim_hw::units::RopDatapath;
    use bumpsim_hw::{Unit, Word};
    let mut outcomes = [0usize; 2];
    for name in [
        "sgi-teapot",
        "rop-alpha-test",
        "cull-fragment",
        "quantized-bunny-wood-eq1",
    ] {
        let l = config::load(&config(name), &[]).unwrap();
        let p = prepare(&l).unwrap();
        let inputs = p.rop_inputs(SAMPLES);
        assert_eq!(inputs.len(), 1 + p.engine.passes.len(), "{name}");
        for ((label, _, rop), ins) in p.engine.rops().into_iter().zip(inputs) {
            let u = RopDatapath::new(rop);
            let specs = u.inputs();
            assert!(
                !ins.is_empty(),
                "{name} {label}: no fragment reached the ROP"
            );
            for r in ins {
                let words = vec![
                    r.color,
                    Word::from_raw(&specs[1].enc, &[i64::from(r.depth)]),
                    Word::from_raw(&specs[2].enc, &r.dst.code),
                    Word::from_raw(&specs[3].enc, &[i64::from(r.dst_depth)]),
                ];
                let mut o = vec![Word::default(); 3];
                u.eval(Mode::BitAccurate, &words, &mut o);
                for (port, w) in u.outputs().iter().zip(&o) {
                    for s in &w.lanes[..port.lanes as usize] {
                        assert!(port.enc.format.contains(s.raw), "{name} {label}");
                        assert_eq!(s.x, port.enc.decode(s.raw), "{name} {label}");
                    }
                }
                let written = o[0].lanes[0].raw == 1;
                outcomes[usize::from(written)] += 1;
                if !written {
                    assert_eq!(o[2].raws::<3>(), r.dst.code, "{name} {label}");
                    assert_eq!(o[1].lanes[0].raw, 0, "{name} {label}");
                }
            }
        }
    }
    // both outcomes seen (hidden fragments, alpha-tested ones, the blend passes' Equal)
    assert!(outcomes.iter().all(|&n| n > 100), "{outcomes:?}");
}

//! Wire expressions: what a unit's input port reads.
//!
//! A plain wire names one signal (`uv`, `dot.d0`). An expression rearranges the lanes of
//! earlier signals into one input, as the routing of a fixed-function pipe does (wires only:
//! no logic, no delay, no gates):
//!
//! * **swizzle / lane select**: `fetch.t.gb`, `tex.t.aaa`, `fetch.t.x`, with the letters of one
//!   set, `xyzw`, `rgba` or `stpq`, each naming a lane of the signal;
//! * **concatenation**: `cat(dot.d0, dot.d1)` (two 1-lane dot products forming (s, t)), whose
//!   parts may be swizzled: `cat(a.t.r, b.t.g)`.
//!
//! The result has at most 4 lanes and one encoding: every part must carry the same encoding
//! (a port has one format for all its lanes). The resolved input is checked against the port
//! like a plain wire, and traces show the gathered word on the port.

use super::Signal;
use bumpsim_hw::{PortSpec, Wire, MAX_LANES};

/// A wire expression resolved against the signals defined so far.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// Lanes and encoding of what the port receives (named after the expression).
    pub spec: PortSpec,
    pub wire: Wire,
}

/// The signal names an expression refers to (without swizzles), in order, for dependency
/// ordering before any signal exists. Each is the text of one part; a part `a.b.c` refers to
/// `a.b`, a part `a.b` to `a.b` or (as attribute `a` swizzled) `a`: callers take the unit
/// name before the first `.`, which is the same in both readings.
pub fn parts(expr: &str) -> Vec<&str> {
    let e = expr.trim();
    match e.strip_prefix("cat(").and_then(|r| r.strip_suffix(')')) {
        Some(inner) => inner.split(',').map(str::trim).collect(),
        None => vec![e],
    }
}

/// Lane index of a swizzle letter, with the set it belongs to.
fn lane_of(c: char) -> Option<(usize, u8)> {
    const SETS: [&str; 3] = ["xyzw", "rgba", "stpq"];
    SETS.iter()
        .enumerate()
        .find_map(|(set, s)| s.find(c).map(|i| (set, i as u8)))
}

fn parse_swizzle(s: &str) -> Option<Vec<u8>> {
    if s.is_empty() || s.len() > MAX_LANES {
        return None;
    }
    let mut set = None;
    let mut lanes = Vec::new();
    for c in s.chars() {
        let (k, lane) = lane_of(c)?;
        if *set.get_or_insert(k) != k {
            return None;
        }
        lanes.push(lane);
    }
    Some(lanes)
}

/// One part: a signal and the lanes it contributes.
fn resolve_part<'a>(part: &str, signals: &'a [Signal]) -> Result<(&'a Signal, Vec<u8>), String> {
    let find = |n: &str| signals.iter().find(|s| s.name == n);
    if let Some(s) = find(part) {
        return Ok((s, (0..s.spec.lanes).collect()));
    }
    let unknown = || {
        let known: Vec<&str> = signals.iter().map(|s| s.name.as_str()).collect();
        format!(
            "no signal {part:?}: expected one of {} (optionally swizzled, e.g. {}.x, or cat(a, b))",
            known.join(", "),
            known.first().copied().unwrap_or("uv")
        )
    };
    let Some((name, swz)) = part.rsplit_once('.') else {
        return Err(unknown());
    };
    let Some(sig) = find(name) else {
        return Err(unknown());
    };
    let lanes = parse_swizzle(swz).ok_or_else(|| {
        format!(
            "{part:?}: {swz:?} is not a swizzle: expected 1 to 4 letters of one set, xyzw, rgba or stpq"
        )
    })?;
    if let Some(&bad) = lanes.iter().find(|&&l| l >= sig.spec.lanes) {
        return Err(format!(
            "{part:?}: lane {bad} of {name}, which carries {} lanes",
            sig.spec.lanes
        ));
    }
    Ok((sig, lanes))
}

/// Resolve `expr` against `signals`. Errors say what was expected.
pub fn resolve(expr: &str, signals: &[Signal]) -> Result<Resolved, String> {
    let e = expr.trim();
    let is_cat = e.starts_with("cat(");
    if is_cat && !e.ends_with(')') {
        return Err(format!(
            "{e:?}: expected cat(a, b, ...) with a closing parenthesis"
        ));
    }
    let ps = parts(e);
    if ps.iter().any(|p| p.is_empty()) {
        return Err(format!("{e:?}: an empty part: expected cat(a, b, ...)"));
    }
    let mut from = Vec::new();
    let mut enc = None;
    let mut first = "";
    for p in &ps {
        let (sig, lanes) = resolve_part(p, signals)?;
        match enc {
            None => (enc, first) = (Some(sig.spec.enc), p),
            Some(e0) if e0 != sig.spec.enc => {
                return Err(format!(
                    "{e:?}: {first} carries {e0} but {p} carries {}: expected one encoding for all lanes of a port",
                    sig.spec.enc
                ))
            }
            Some(_) => {}
        }
        from.extend(lanes.into_iter().map(|l| (sig.slot as u32, l)));
        if !is_cat && ps.len() == 1 && sig.name == *p {
            return Ok(Resolved {
                spec: sig.spec.clone(),
                wire: Wire::Slot(sig.slot),
            });
        }
    }
    if from.len() > MAX_LANES {
        return Err(format!(
            "{e:?} has {} lanes: expected at most {MAX_LANES}",
            from.len()
        ));
    }
    let lanes = from.len() as u8;
    let mut arr = [(0u32, 0u8); MAX_LANES];
    arr[..from.len()].copy_from_slice(&from);
    Ok(Resolved {
        spec: PortSpec::new(e, lanes, enc.expect("at least one part")),
        wire: Wire::Gather { lanes, from: arr },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use bumpsim_hw::{Encoding, Format, Sample, Word};

    fn sig(name: &str, slot: usize, lanes: u8, w: u8) -> Signal {
        Signal {
            name: name.into(),
            slot,
            spec: PortSpec::new(name, lanes, Encoding::fixed(Format::s(w, w - 2))),
        }
    }

    fn signals() -> Vec<Signal> {
        vec![
            sig("uv", 0, 2, 16),
            sig("tex.t", 1, 4, 10),
            sig("dot.d0", 2, 1, 10),
            sig("dot.d1", 3, 1, 10),
            sig("wide.d0", 4, 1, 12),
        ]
    }

    /// Token slots whose lane `l` of slot `s` holds raw `10 * s + l`.
    fn slots() -> Vec<Word> {
        (0..5)
            .map(|s| {
                let mut w = Word::default();
                for l in 0..4 {
                    w.lanes[l] = Sample {
                        x: 0.0,
                        raw: 10 * s + l as i64,
                    };
                }
                w
            })
            .collect()
    }

    fn gathered(expr: &str) -> (u8, Vec<i64>) {
        let r = resolve(expr, &signals()).unwrap();
        let w = r.wire.read(&slots());
        let n = r.spec.lanes;
        (n, w.lanes[..n as usize].iter().map(|s| s.raw).collect())
    }

    #[test]
    fn a_plain_name_is_a_whole_slot() {
        let r = resolve("tex.t", &signals()).unwrap();
        assert_eq!(r.wire, Wire::Slot(1));
        assert_eq!(r.spec.lanes, 4);
        assert_eq!(resolve(" uv ", &signals()).unwrap().wire, Wire::Slot(0));
    }

    #[test]
    fn swizzles_select_and_repeat_lanes_in_any_letter_set() {
        assert_eq!(gathered("tex.t.gb"), (2, vec![11, 12]));
        assert_eq!(gathered("tex.t.aaa"), (3, vec![13, 13, 13]));
        assert_eq!(gathered("tex.t.ar"), (2, vec![13, 10]));
        assert_eq!(gathered("tex.t.wzyx"), (4, vec![13, 12, 11, 10]));
        assert_eq!(gathered("tex.t.q"), (1, vec![13]));
        assert_eq!(gathered("uv.ts"), (2, vec![1, 0]));
    }

    #[test]
    fn concatenation_joins_parts_in_order() {
        assert_eq!(gathered("cat(dot.d0, dot.d1)"), (2, vec![20, 30]));
        assert_eq!(
            gathered("cat(dot.d1,tex.t.rg, dot.d0)"),
            (4, vec![30, 10, 11, 20])
        );
        assert_eq!(parts("cat(dot.d0, tex.t.b)"), vec!["dot.d0", "tex.t.b"]);
        // a cat of one whole signal is still a gather (it has the expression's name)
        assert_eq!(gathered("cat(uv)"), (2, vec![0, 1]));
    }

    #[test]
    fn bad_expressions_say_what_was_expected() {
        let err = |e: &str| resolve(e, &signals()).unwrap_err();
        assert!(err("nope").contains("no signal \"nope\": expected one of uv, tex.t"));
        assert!(err("tex.t.rgx").contains("one set"));
        assert!(err("tex.t.rgbar").contains("not a swizzle"));
        assert!(err("uv.z").contains("lane 2 of uv, which carries 2 lanes"));
        assert!(err("cat(tex.t, tex.t.xy)").contains("6 lanes: expected at most 4"));
        assert!(err("cat(dot.d0, wide.d0)").contains("expected one encoding"));
        assert!(err("cat(dot.d0, dot.d1").contains("closing parenthesis"));
        assert!(err("cat(dot.d0,,dot.d1)").contains("empty part"));
        assert!(err("cat()").contains("empty part"));
    }
}

//! `bumpsim trace`: text and VCD traces of the teapot engine, unit selection, bad unit names.

mod common;

use common::*;
use std::collections::BTreeMap;
use std::path::Path;
use vcd::{IdCode, ScopeItem};

/// The scan converter, the engine's units in pipe order, the ROP.
const UNITS: [&str; 6] = ["scan", "fetch", "dot", "spec", "shade", "rop"];
const WINDOW: (u64, u64) = (300, 340);

fn trace(out: &Path, format: &str, units: Option<&str>) -> Out {
    let cfg = config("sgi-teapot");
    let mut args: Vec<std::ffi::OsString> = vec![
        "trace".into(),
        cfg.into(),
        "--cycles".into(),
        format!("{}..{}", WINDOW.0, WINDOW.1).into(),
        "--format".into(),
        format.into(),
        "--out".into(),
        out.into(),
    ];
    if let Some(u) = units {
        args.push("--units".into());
        args.push(u.into());
    }
    bumpsim(&args)
}

/// The bytes of a successful `trace --format <format> [--units <units>]` of the window.
fn traced(test: &str, format: &str, units: Option<&str>) -> Vec<u8> {
    let scratch = Scratch::new(test);
    let out = scratch.join("t.out");
    let what = format!("trace --format {format} --units {units:?}");
    trace(&out, format, units).expect_code(0, &what);
    std::fs::read(&out).unwrap()
}

/// Body lines of a text trace grouped by unit name: `unit -> [(cycle, line)]`.
fn body(text: &str) -> BTreeMap<String, Vec<(u64, String)>> {
    let mut m: BTreeMap<String, Vec<(u64, String)>> = BTreeMap::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let mut f = line.split_whitespace();
        let cycle: u64 = f
            .next()
            .and_then(|c| c.parse().ok())
            .unwrap_or_else(|| panic!("line without a cycle: {line:?}"));
        let unit = f
            .next()
            .unwrap_or_else(|| panic!("line without a unit: {line:?}"));
        let state = f
            .next()
            .unwrap_or_else(|| panic!("line without a state: {line:?}"));
        assert!(
            ["idle", "busy", "stall"].contains(&state),
            "bad state in {line:?}"
        );
        m.entry(unit.to_string())
            .or_default()
            .push((cycle, line.to_string()));
    }
    m
}

#[test]
fn text_trace_has_every_unit_every_cycle() {
    let text = String::from_utf8(traced("trace-text", "text", None)).unwrap();
    assert!(!text.is_empty());
    let n = WINDOW.1 - WINDOW.0;
    let first = text.lines().next().unwrap();
    assert_eq!(
        first,
        format!(
            "# bumpsim trace: 6 units, cycles {}..={}, {} records",
            WINDOW.0,
            WINDOW.1 - 1,
            6 * n
        )
    );
    for u in UNITS {
        assert!(
            text.lines()
                .any(|l| l.starts_with(&format!("# unit {u} ("))),
            "no header for unit {u}"
        );
    }
    let b = body(&text);
    assert_eq!(b.keys().map(String::as_str).collect::<Vec<_>>(), {
        let mut u = UNITS.to_vec();
        u.sort();
        u
    });
    for (u, lines) in &b {
        let cycles: Vec<u64> = lines.iter().map(|l| l.0).collect();
        assert_eq!(
            cycles,
            (WINDOW.0..WINDOW.1).collect::<Vec<_>>(),
            "unit {u}: one line per cycle of the window"
        );
    }
    // the window is inside the fragment phase: the datapath moves fragments
    assert!(
        b["dot"].iter().any(|(_, l)| l.contains(" in#")),
        "dot accepts no fragment in {WINDOW:?}"
    );
    assert!(b["shade"].iter().any(|(_, l)| l.contains(" out#")));
    // the scan converter hands each fragment's attributes to the fetch (uv first), which
    // takes them in a later cycle; the ROP takes the colour the shade unit gave
    let after = |unit: &str, tag: &str, id: &str| {
        b[unit].iter().find_map(|(c, l)| {
            let at = l.find(&format!("{tag}#{id} "))?;
            Some((*c, l[at..].split_whitespace().nth(1)?.to_string()))
        })
    };
    let (mut uv, mut colour) = (0, 0);
    for (c, l) in &b["scan"] {
        let Some(at) = l.find("out#") else { continue };
        let mut f = l[at + 4..].split_whitespace();
        let id = f.next().unwrap();
        let given = f.next().unwrap().to_string();
        assert!(given.starts_with("uv="), "{l}");
        if let Some((c2, taken)) = after("fetch", "in", id) {
            assert!(c2 > *c, "fragment {id}: scanned at {c}, fetched at {c2}");
            assert_eq!(taken, given, "fragment {id}'s uv");
            uv += 1;
        }
    }
    for (c, l) in &b["shade"] {
        let Some(at) = l.find("out#") else { continue };
        let mut f = l[at + 4..].split_whitespace();
        let (id, given) = (f.next().unwrap(), f.next().unwrap());
        if let Some((c2, taken)) = after("rop", "in", id) {
            assert!(c2 > *c, "fragment {id}: shaded at {c}, written at {c2}");
            assert_eq!(taken, given, "fragment {id}'s colour");
            colour += 1;
        }
    }
    assert!(uv > 3 && colour > 3, "{uv} uv, {colour} colours followed");
}

#[test]
fn unit_selection_keeps_the_named_units_and_their_lines() {
    let scratch = Scratch::new("trace-units");
    let all = scratch.join("all.txt");
    let some = scratch.join("some.txt");
    trace(&all, "text", None).expect_code(0, "trace all units");
    trace(&some, "text", Some("spec,dot")).expect_code(0, "trace --units spec,dot");
    let all = std::fs::read_to_string(&all).unwrap();
    let some = std::fs::read_to_string(&some).unwrap();
    assert!(some.starts_with("# bumpsim trace: 2 units,"), "{some}");
    let headers: Vec<&str> = some.lines().filter(|l| l.starts_with("# unit ")).collect();
    assert_eq!(headers.len(), 2, "{headers:?}");
    // in the engine's order, whatever the order asked for
    assert!(headers[0].starts_with("# unit dot ("), "{headers:?}");
    assert!(headers[1].starts_with("# unit spec ("), "{headers:?}");
    let (ball, bsome) = (body(&all), body(&some));
    assert_eq!(bsome.keys().collect::<Vec<_>>(), ["dot", "spec"]);
    // the same lines as in the full trace (all names fit the 8-column minimum)
    assert_eq!(bsome["dot"], ball["dot"]);
    assert_eq!(bsome["spec"], ball["spec"]);
    for u in ["dot", "spec"] {
        let h = all
            .lines()
            .find(|l| l.starts_with(&format!("# unit {u} (")))
            .unwrap();
        assert!(headers.contains(&h), "header of {u} differs");
    }
}

#[test]
fn unknown_unit_name_is_an_input_error() {
    let scratch = Scratch::new("trace-unknown-unit");
    let out = scratch.join("t.txt");
    let o = trace(&out, "text", Some("dot,dot9"));
    o.expect_code(2, "trace --units dot,dot9");
    assert!(o.stderr.contains("--units"), "{}", o.stderr);
    assert!(o.stderr.contains("dot9"), "{}", o.stderr);
    for u in UNITS {
        assert!(
            o.stderr.contains(u),
            "the error lists the known unit {u}: {}",
            o.stderr
        );
    }
    assert!(!out.exists(), "nothing is written on an error");
    assert!(listing(&scratch.path).is_empty());
}

/// Value changes of a VCD: `(time, id, bits)` with `None` for x/z.
fn changes(bytes: &[u8]) -> (vcd::Header, Vec<bumpsim_pipeline::trace::vcd::VcdChange>) {
    bumpsim_pipeline::trace::vcd::read_vcd(bytes).expect("the VCD reads back")
}

fn scopes(h: &vcd::Header) -> Vec<String> {
    h.find_scope(&["bumpsim"])
        .expect("a top scope bumpsim")
        .items
        .iter()
        .filter_map(|i| match i {
            ScopeItem::Scope(s) => Some(s.identifier.clone()),
            _ => None,
        })
        .collect()
}

fn vars(h: &vcd::Header, unit: &str) -> Vec<(String, IdCode, u32)> {
    h.find_scope(&["bumpsim", unit])
        .unwrap_or_else(|| panic!("no scope for unit {unit}"))
        .items
        .iter()
        .filter_map(|i| match i {
            ScopeItem::Var(v) => Some((v.reference.clone(), v.code, v.size)),
            _ => None,
        })
        .collect()
}

#[test]
fn vcd_trace_parses_and_has_every_unit() {
    let (h, ch) = changes(&traced("trace-vcd", "vcd", None));
    assert_eq!(scopes(&h), UNITS);
    let clk = h.find_var(&["bumpsim", "clk"]).expect("clk").code;
    let cycle = h.find_var(&["bumpsim", "cycle"]).expect("cycle").code;
    // one clock period is 2 time units: timestamps 2c and 2c + 1 for c in the window
    let (t0, t1) = (
        ch.iter().map(|c| c.0).min().unwrap(),
        ch.iter().map(|c| c.0).max().unwrap(),
    );
    assert_eq!((t0, t1), (2 * WINDOW.0, 2 * WINDOW.1 - 1));
    let clk_highs = ch.iter().filter(|c| c.1 == clk && c.2 == Some(1)).count() as u64;
    assert_eq!(clk_highs, WINDOW.1 - WINDOW.0);
    assert!(ch.iter().any(|c| c.1 == cycle && c.2 == Some(WINDOW.0)));

    let dot = vars(&h, "dot");
    let names: Vec<&str> = dot.iter().map(|v| v.0.as_str()).collect();
    for v in [
        "state",
        "in_valid",
        "in_id",
        "out_valid",
        "out_id",
        "a_0",
        "b0_0",
        "d0_0",
    ] {
        assert!(names.contains(&v), "dot has no var {v}: {names:?}");
    }
    // widths follow the port formats: a (fetch.t) is s2.8 = 10 bits, d0 is u1.8 = 9 bits
    let size = |n: &str| dot.iter().find(|v| v.0 == n).unwrap().2;
    assert_eq!(size("a_0"), 10);
    assert_eq!(size("d0_0"), 9);
    // the dot unit's input changes within the window (after the initial dump)
    let a0 = dot.iter().find(|v| v.0 == "a_0").unwrap().1;
    let later: Vec<_> = ch
        .iter()
        .filter(|c| c.1 == a0 && c.0 > t0 && c.2.is_some())
        .collect();
    assert!(!later.is_empty(), "dot.a_0 never changes in the window");
    let ov = dot.iter().find(|v| v.0 == "out_valid").unwrap().1;
    assert!(
        ch.iter().any(|c| c.1 == ov && c.2 == Some(1)),
        "dot never emits"
    );
}

#[test]
fn vcd_unit_selection() {
    let (h, _) = changes(&traced("trace-vcd-units", "vcd", Some("dot,spec")));
    assert_eq!(scopes(&h), ["dot", "spec"]);
}

#[test]
fn reversed_or_empty_cycle_windows_are_rejected() {
    let scratch = Scratch::new("trace-bad-window");
    let cfg = config("sgi-teapot");
    for w in ["50..10", "10..10", "10", "a..b", "-5..3"] {
        let out = scratch.join("t.txt");
        let o = bumpsim(&[
            "trace".as_ref(),
            cfg.as_os_str(),
            format!("--cycles={w}").as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        o.expect_code(2, &format!("--cycles {w}"));
        assert!(o.stderr.contains("--cycles"), "{}", o.stderr);
        assert!(o.stderr.contains(w), "{}", o.stderr);
        assert!(o.stderr.contains("expected A..B"), "{}", o.stderr);
        assert!(!out.exists());
    }
}

/// `--frame K` traces frame K of an animation: `quantized-sphere-orbit`'s palette entries
/// written in the LUT load (cycles 600..604 of its 768 cycles of frame work) are shaded for
/// frame 3's light: not frame 0's words, and those of the config with frame 3's override and
/// no `frames`. A frame beyond the animation is an input error.
#[test]
fn a_trace_of_frame_k_shows_the_palette_built_for_its_light() {
    let scratch = Scratch::new("trace-frame");
    let cfg = config("quantized-sphere-orbit");
    let run = |name: &str, extra: &[&str]| {
        let out = scratch.join(name);
        let mut args: Vec<std::ffi::OsString> = vec![
            "trace".into(),
            cfg.clone().into(),
            "--cycles".into(),
            "600..604".into(),
            "--units".into(),
            "qnm".into(),
            "--out".into(),
            out.clone().into(),
        ];
        args.extend(extra.iter().map(Into::into));
        bumpsim(&args).expect_code(0, name);
        std::fs::read_to_string(&out).unwrap()
    };
    let f0 = run("f0.txt", &[]);
    let f3 = run("f3.txt", &["--frame", "3"]);
    let alone = run(
        "alone.txt",
        &[
            "--set",
            "frames=[]",
            "--set",
            "scene.lights[0].kind.dir=(0.0000, 1.0, 1.4142)",
        ],
    );
    assert_eq!(f3, alone);
    assert_ne!(f3, f0);
    // entry 89 is written at clock 601 in both, with other words
    let entry = |t: &str| {
        t.lines()
            .find(|l| l.trim_start().starts_with("601 "))
            .map(str::to_string)
            .unwrap()
    };
    assert!(entry(&f0).contains("out#89 c=(39:"), "{}", entry(&f0));
    assert!(entry(&f3).contains("out#89 c=(14:"), "{}", entry(&f3));
    let out = scratch.join("f9.txt");
    let args: Vec<std::ffi::OsString> = vec![
        "trace".into(),
        cfg.into(),
        "--cycles".into(),
        "0..4".into(),
        "--frame".into(),
        "9".into(),
        "--out".into(),
        out.clone().into(),
    ];
    let o = bumpsim(&args);
    o.expect_code(2, "trace --frame 9");
    assert!(
        o.stderr.contains("no frame 9: the config has 8 frames"),
        "{}",
        o.stderr
    );
    assert!(!out.exists());
}

//! The cube-map arithmetic of the texture shader as Verilog, bit-exact with the model's
//! `FixedArith::reflect` (`units/texture_shader/eval.rs`) and
//! [`crate::sampler::cube_face_bits`]: the reflection of the eye vector about the normal
//! `R = 2 N (N.E) / (N.N) - E` (NV_texture_shader, DOT_PRODUCT_REFLECT_CUBE_MAP_NV) and the
//! cube-face selection and projection of a direction (OpenGL 1.3 §3.8.6, table 3.19).

use super::super::fixed::{
    add, constant, make, mul, overflow, scale, select, square, sub, sum, Fx,
};
use super::super::verilog::{lit, unsigned_bits, Module};
use super::arith::{floor_quotient, restoring};
use crate::format::{Encoding, Overflow};

/// `R_k = round_half_up((2 N_k (N.E) - E_k (N.N)) / (N.N))` of raw coordinate words (`n`,
/// `e`, integers at the coordinate's fraction bits), each into the coordinate encoding by
/// its overflow mode; `-E` when `N = 0`. Returns the three coordinate codes. One component's
/// numerator and division are a submodule (`sub`: its name and the list of submodule texts),
/// instantiated three times with a varying eye (synthesised once, as ABC maps a module at a
/// time), or one module per component with a constant eye inside it (`{name}_{k}`: its
/// products by the constant are shifts and adds).
pub(super) fn reflect(
    m: &mut Module,
    n: &[Fx; 3],
    e: &[Fx; 3],
    coord: &Encoding,
    sub: (&str, &mut Vec<String>),
) -> [String; 3] {
    m.comment("reflection: 2 N (N.E) - E (N.N) over N.N");
    let sq: Vec<Fx> = n.iter().map(|x| square(m, x)).collect();
    let nn = sum(m, &sq.iter().collect::<Vec<_>>());
    let pr: Vec<Fx> = (0..3).map(|k| mul(m, &n[k], &e[k])).collect();
    let ne = sum(m, &pr.iter().collect::<Vec<_>>());
    let w = coord.width();
    let (name, subs) = sub;
    let port = |cm: &mut Module, p: &str, x: &Fx| {
        cm.input(p, x.width());
        make(cm, p, x.lo, x.hi, 0, &format!("$signed({p})"))
    };
    // a constant eye: its component inside each module (three modules)
    let varying = e.iter().any(|x| x.lo != x.hi);
    let mut modules: Vec<String> = Vec::new();
    std::array::from_fn(|k| {
        let mname = if varying {
            name.to_string()
        } else {
            format!("{name}_{k}")
        };
        if !modules.contains(&mname) {
            let mut cm = Module::new(&mname);
            let pn = port(&mut cm, "n", &n[0]);
            let pe = if varying {
                port(&mut cm, "e", &e[0])
            } else {
                make(&mut cm, "e", e[k].lo, e[k].hi, 0, &lit(e[k].lo))
            };
            let (pne, pnn) = (port(&mut cm, "ne", &ne), port(&mut cm, "nn", &nn));
            let y = component(&mut cm, &pn, &pe, &pne, &pnn, coord);
            cm.output_wire("y", w, &y);
            subs.push(cm.text());
            modules.push(mname.clone());
        }
        let net = m.net("refl", w);
        let ep = if varying {
            format!(".e({}), ", e[k].name)
        } else {
            String::new()
        };
        m.stmt(format!(
            "{mname} {net}_i (.n({}), {ep}.ne({}), .nn({}), .y({net}));",
            n[k].name, ne.name, nn.name
        ));
        net
    })
}

/// One component of [`reflect`]: the numerator `2 N_k (N.E) - E_k (N.N)`, its rounded
/// division by `N.N` (a restoring divider) and the overflow into the coordinate encoding,
/// `-E_k` when `N.N = 0`.
fn component(m: &mut Module, n: &Fx, e: &Fx, ne: &Fx, nn: &Fx, coord: &Encoding) -> String {
    // N.N >= 0: its magnitude bits, doubled as the divisor 2 N.N
    let ub = unsigned_bits(nn.hi.max(1) as u128);
    let nnu = m.uwire("nnu", ub, &format!("{}[{}:0]", nn.name, ub - 1));
    let d2 = m.uwire("nnd", ub + 1, &format!("{{{nnu}, 1'b0}}"));
    let zero = m.uwire("nnz", 1, &format!("{nnu} == {ub}'d0"));
    let w = coord.width();
    let sat = !matches!(coord.overflow, Overflow::Wrap);
    let a = mul(m, n, ne);
    let a = scale(m, &a, 2);
    let b = mul(m, e, nn);
    let num = sub(m, &a, &b);
    // round half up: floor((2 num + N.N) / (2 N.N))
    let twice = scale(m, &num, 2);
    let big = add(m, &twice, nn);
    let nw = big.width();
    let hi = big.hi.max(-big.lo);
    let q = floor_quotient(m, &big.name, nw, (&d2, ub + 1), &zero, sat.then_some(w), hi);
    let qc = overflow(m, &q, &coord.format, coord.overflow);
    let neg = sub(m, &constant(0, 0), e);
    let nc = overflow(m, &neg, &coord.format, coord.overflow);
    m.uwire("refl", w, &format!("{zero} ? {nc} : {qc}"))
}

/// The cube face and face coordinates of a direction of raw words `d` (integers): the major
/// axis (ties to x before y before z), `s = floor(((sc + ma) 2^f + ma) / (2 ma))` and `t`
/// alike, in `[0, 2^f]`; a zero direction reads the centre of face +X. Returns the face
/// (3 bits) and `s`, `t` as `f + 2`-bit signed words (`Format::s(f + 2, f)`).
pub(super) fn face(m: &mut Module, d: &[Fx; 3], f: u32) -> (String, String, String) {
    m.comment("cube face: the major axis and the projection onto its face");
    let neg: Vec<Fx> = d.iter().map(|x| sub(m, &constant(0, 0), x)).collect();
    let sign: Vec<String> = d
        .iter()
        .map(|x| m.uwire("csg", 1, &format!("{}[{}]", x.name, x.width() - 1)))
        .collect();
    let abs: Vec<Fx> = (0..3)
        .map(|k| select(m, &sign[k], &[d[k].clone(), neg[k].clone()]))
        .collect();
    let cx = m.uwire(
        "cmx",
        1,
        &format!(
            "({a} >= {b}) && ({a} >= {c})",
            a = abs[0].name,
            b = abs[1].name,
            c = abs[2].name
        ),
    );
    let cy = m.uwire("cmy", 1, &format!("{} >= {}", abs[1].name, abs[2].name));
    let fc = m.uwire(
        "cface",
        3,
        &format!(
            "{cx} ? {{2'd0, {}}} : {cy} ? {{2'd1, {}}} : {{2'd2, {}}}",
            sign[0], sign[1], sign[2]
        ),
    );
    let [x, z] = [&d[0], &d[2]];
    let [nx, ny, nz] = [&neg[0], &neg[1], &neg[2]];
    // faces +X, -X, +Y, -Y, +Z, -Z
    let sc = select(
        m,
        &fc,
        &[
            nz.clone(),
            z.clone(),
            x.clone(),
            x.clone(),
            x.clone(),
            nx.clone(),
        ],
    );
    let tc = select(
        m,
        &fc,
        &[
            ny.clone(),
            ny.clone(),
            z.clone(),
            nz.clone(),
            ny.clone(),
            ny.clone(),
        ],
    );
    let ma = select(
        m,
        &fc,
        &[
            abs[0].clone(),
            abs[0].clone(),
            abs[1].clone(),
            abs[1].clone(),
            abs[2].clone(),
            abs[2].clone(),
        ],
    );
    let ma = make(m, "cma", 0, ma.hi, 0, &ma.name);
    let mb = unsigned_bits(ma.hi.max(1) as u128);
    let mau = m.uwire("cmau", mb, &format!("{}[{}:0]", ma.name, mb - 1));
    let d2 = m.uwire("cmd", mb + 1, &format!("{{{mau}, 1'b0}}"));
    let zero = m.uwire("cmz", 1, &format!("{mau} == {mb}'d0"));
    let half = 1u128 << f.saturating_sub(1);
    let mut proj = |c: &Fx| {
        // (c + ma) 2^f + ma >= 0; the quotient is at most 2^f: f + 1 steps, the numerator's
        // top bits (below 2 ma) the first partial remainder
        let a = add(m, c, &ma);
        let a = make(m, "cpa", 0, a.hi, 0, &a.name);
        let sh = scale(m, &a, 1i128 << f);
        let num = add(m, &sh, &ma);
        let nb = unsigned_bits(num.hi.max(1) as u128);
        let numu = m.uwire("cpn", nb, &format!("{}[{}:0]", num.name, nb - 1));
        let k = f + 1;
        let db = mb + 1;
        let r0 = if nb <= k {
            m.uwire("cpr", db, &format!("{db}'d0"))
        } else if nb - k >= db {
            m.uwire("cpr", db, &format!("{numu}[{}:{k}]", k + db - 1))
        } else {
            m.uwire(
                "cpr",
                db,
                &format!("{{{}'d0, {numu}[{}:{k}]}}", db - (nb - k), nb - 1),
            )
        };
        let low = if nb < k {
            m.uwire("cpl", k, &format!("{{{}'d0, {numu}}}", k - nb))
        } else {
            numu
        };
        let q = restoring(m, &low, k, &d2, db, r0);
        m.uwire(
            "cst",
            f + 2,
            &format!("{zero} ? {}'d{half} : {{1'b0, {q}}}", f + 2),
        )
    };
    let s = proj(&sc);
    let t = proj(&tc);
    (fc, s, t)
}

//! OBJ files: the reader of `MeshSpec::Obj` (`read`, one pass, every error with its line),
//! giving a [`FileMesh`] that `super::mesh` builds by the rule for scan defects
//! (`docs/assets.md`).

use std::path::Path;

use glam::{DVec2, DVec3};

use super::mesh::{Corners, FileMesh, Place, NONE};
use super::SceneError;

pub(crate) use super::mesh::smooth_normals;

/// Read an OBJ file for `MeshSpec::Obj`: a regular file of at most
/// [`super::files::MAX_OBJ_BYTES`] of UTF-8 text, parsed by [`parse`]. Errors are file errors
/// naming the path; the file's own problems start with `could not load OBJ: line N`.
pub(crate) fn read(path: &Path) -> Result<FileMesh, SceneError> {
    let bytes = super::files::read_bounded(path, super::files::MAX_OBJ_BYTES, "OBJ")?;
    from_bytes(path, &bytes)
}

/// [`read`] of the bytes already read from `path` (named in the errors).
pub(crate) fn from_bytes(path: &Path, bytes: &[u8]) -> Result<FileMesh, SceneError> {
    let fail = |message: String| SceneError::file(path.display(), message);
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        fail(format!(
            "could not load OBJ: line {line}: not UTF-8 text (expected a text file)"
        ))
    })?;
    parse(text).map_err(|m| fail(format!("could not load OBJ: {m}")))
}

/// A number of a `v`, `vt` or `vn` line, read as f32 (as tobj does: OBJ files hold single
/// precision), finite and within the f32 range.
fn number(n: usize, key: &str, tok: &str) -> Result<f32, String> {
    match tok.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(x) if x.is_infinite() && tok.parse::<f64>().is_ok_and(f64::is_finite) => Err(format!(
            "line {n}: {key}: {tok} is out of range: OBJ coordinates are read as f32, expected \
             at most {:e} in magnitude",
            f32::MAX
        )),
        Ok(_) => Err(format!(
            "line {n}: {key}: expected a finite number, found {tok}"
        )),
        Err(_) => Err(format!("line {n}: {key}: {tok:?} is not a number")),
    }
}

/// One index of a face corner: 1-based, or negative counting back from the last of the
/// `so_far` values defined before this line; 0-based in the result.
fn index(n: usize, tok: &str, part: &str, what: &str, so_far: usize) -> Result<u32, String> {
    let k: i64 = part.parse().map_err(|_| {
        format!(
            "line {n}: f: {tok:?} is not a vertex reference (expected v, v/vt, v//vn or \
             v/vt/vn with integer indices)"
        )
    })?;
    let resolved = match k {
        0 => {
            return Err(format!(
                "line {n}: f: {tok:?}: {what} index 0: OBJ indices start at 1"
            ))
        }
        k if k > 0 => k - 1,
        k => so_far as i64 + k,
    };
    if resolved < 0 {
        return Err(format!(
            "line {n}: f: {tok:?}: {what} index {k} refers before the first {what} ({so_far} \
             defined so far)"
        ));
    }
    // at most NONE - 1: larger ones are out of range of any file read
    Ok(u32::try_from(resolved).unwrap_or(NONE - 1).min(NONE - 1))
}

/// Parse OBJ text: `v` (x y z, an optional w dividing them as tobj does, further numbers such
/// as colours ignored), `vt` (u v), `vn` (x y z) and `f` lines (corners `v`, `v/vt`, `v//vn`
/// or `v/vt/vn`, negative indices relative); polygons are fanned, faces of fewer than three
/// corners counted and ignored, all objects and groups share one index space, other lines
/// (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, ...) and `#` comments are ignored. Every
/// number is checked and every index is checked against the file's counts; errors name the
/// line.
pub(crate) fn parse(text: &str) -> Result<FileMesh, String> {
    let mut m = FileMesh {
        place: Place::Line,
        ..FileMesh::default()
    };
    let (mut uvs, mut normals) = (Vec::<DVec2>::new(), Vec::<DVec3>::new());
    let (mut uv_index, mut normal_index) = (Vec::<[u32; 3]>::new(), Vec::<[u32; 3]>::new());
    let mut any_normal = false;
    let mut missing_vt = None;
    let mut corners: Vec<[u32; 3]> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let line = line.split('#').next().unwrap_or_default();
        let mut it = line.split_whitespace();
        let Some(key) = it.next() else { continue };
        match key {
            "v" | "vt" | "vn" => {
                let mut x = [0f32; 4];
                let mut count = 0;
                for tok in it {
                    let v = number(n, key, tok)?;
                    if count < 4 {
                        x[count] = v;
                    }
                    count += 1;
                }
                let need = if key == "vt" { 2 } else { 3 };
                if count < need {
                    return Err(format!(
                        "line {n}: {key}: expected {need} numbers, found {count}"
                    ));
                }
                match key {
                    "v" => {
                        let mut p = [x[0], x[1], x[2]];
                        if count == 4 {
                            let w = x[3];
                            if w == 0.0 {
                                return Err(format!(
                                    "line {n}: v: a weight w of 0: expected a non-zero w"
                                ));
                            }
                            p = p.map(|c| c / w);
                            if !p.iter().all(|c| c.is_finite()) {
                                return Err(format!(
                                    "line {n}: v: x y z / w is out of the f32 range"
                                ));
                            }
                        }
                        m.positions.push(DVec3::from(p.map(f64::from)));
                    }
                    "vt" => uvs.push(DVec2::new(f64::from(x[0]), f64::from(x[1]))),
                    _ => normals.push(DVec3::new(
                        f64::from(x[0]),
                        f64::from(x[1]),
                        f64::from(x[2]),
                    )),
                }
            }
            "f" => {
                corners.clear();
                for tok in it {
                    let mut parts = tok.split('/');
                    let v = parts.next().unwrap_or_default();
                    let vt = parts.next().unwrap_or_default();
                    let vn = parts.next().unwrap_or_default();
                    if parts.next().is_some() || v.is_empty() {
                        return Err(format!(
                            "line {n}: f: {tok:?} is not a vertex reference (expected v, \
                             v/vt, v//vn or v/vt/vn)"
                        ));
                    }
                    let opt = |part: &str, what: &str, so_far: usize| {
                        if part.is_empty() {
                            Ok(NONE)
                        } else {
                            index(n, tok, part, what, so_far)
                        }
                    };
                    corners.push([
                        index(n, tok, v, "v", m.positions.len())?,
                        opt(vt, "vt", uvs.len())?,
                        opt(vn, "vn", normals.len())?,
                    ]);
                }
                if corners.len() < 3 {
                    m.short_faces += 1;
                    continue;
                }
                let has_vt = corners.iter().all(|c| c[1] != NONE);
                if !has_vt && missing_vt.is_none() {
                    missing_vt = Some(n);
                }
                any_normal |= corners.iter().any(|c| c[2] != NONE);
                for k in 1..corners.len() - 1 {
                    let tri = [corners[0], corners[k], corners[k + 1]];
                    m.triangles.push(tri.map(|c| c[0]));
                    uv_index.push(if has_vt { tri.map(|c| c[1]) } else { [NONE; 3] });
                    normal_index.push(tri.map(|c| c[2]));
                    m.places.push(n as u64);
                }
            }
            _ => {}
        }
    }
    // positive indices may refer forward: check them against the file's counts
    for (t, tri) in m.triangles.iter().enumerate() {
        let checks = [
            (tri, m.positions.len(), "v"),
            (&uv_index[t], uvs.len(), "vt"),
            (&normal_index[t], normals.len(), "vn"),
        ];
        for (ix, len, what) in checks {
            if let Some(&k) = ix.iter().find(|&&k| k != NONE && k as usize >= len) {
                return Err(format!(
                    "line {}: f: {what} index {} out of range: the file has {len} {what} lines",
                    m.places[t],
                    u64::from(k) + 1
                ));
            }
        }
    }
    m.no_uv = missing_vt.map(|line| {
        format!(
            "line {line}: a face without texture coordinates (vt): expected `f v/vt ...` on \
             every face; bump mapping needs them (or use atlas: true)"
        )
    });
    m.uvs = Some(Corners {
        values: uvs,
        index: uv_index,
    });
    m.normals = any_normal.then_some(Corners {
        values: normals,
        index: normal_index,
    });
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse(text).unwrap_err()
    }

    #[test]
    fn indices_are_checked_with_their_line() {
        let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
        let e = err(&format!("{v}f 1/1 2/1 9/1\n"));
        assert!(
            e.starts_with("line 5: f: v index 9 out of range: the file has 3 v lines"),
            "{e}"
        );
        let e = err(&format!("{v}f 1/1 2/1 3/2\n"));
        assert!(e.starts_with("line 5: f: vt index 2 out of range"), "{e}");
        let e = err(&format!("{v}f 1//1 2//1 3//1\n"));
        assert!(e.starts_with("line 5: f: vn index 1 out of range"), "{e}");
        let e = err(&format!("{v}f 0 1 2\n"));
        assert!(e.starts_with("line 5: f: \"0\": v index 0"), "{e}");
        let e = err(&format!("{v}f -4 1 2\n"));
        assert!(
            e.starts_with("line 5: f: \"-4\": v index -4 refers before"),
            "{e}"
        );
        let e = err(&format!("{v}f 1/x 2 3\n"));
        assert!(
            e.starts_with("line 5: f: \"1/x\" is not a vertex reference"),
            "{e}"
        );
        let e = err(&format!("{v}f 1/1/1/1 2 3\n"));
        assert!(e.starts_with("line 5: f: \"1/1/1/1\""), "{e}");
        // numbers
        let e = err("v 0 nan 0\n");
        assert!(
            e.starts_with("line 1: v: expected a finite number, found nan"),
            "{e}"
        );
        let e = err("v 0 0\n");
        assert!(
            e.starts_with("line 1: v: expected 3 numbers, found 2"),
            "{e}"
        );
        let e = err("\nvt 0 zero\n");
        assert!(e.starts_with("line 2: vt: \"zero\" is not a number"), "{e}");
        let e = err("v 0 0 0 0\n");
        assert!(e.starts_with("line 1: v: a weight w of 0"), "{e}");
    }

    #[test]
    fn references_negative_forward_and_across_groups() {
        // negative indices count back; a face may refer to a vertex defined after it; the
        // groups share one index space (so computed normals are smooth across them)
        let text = "g a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                    f -3/-4 -2/-3 -1/-2 # a comment\ng b\nf 1/1 3/3 4/4\nv 0 1 0\n";
        let m = parse(text).unwrap();
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.uvs.as_ref().unwrap().index, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.places, [9, 11]);
        assert!(m.normals.is_none() && m.no_uv.is_none());
        let (mesh, d) = m.to_mesh(DVec2::ONE).unwrap();
        assert_eq!((mesh.vertices.len(), d.unreferenced), (4, 0));
        // polygons are fanned; points and lines are ignored and counted
        let m = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2\nl 1 2\n").unwrap();
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!((m.short_faces, m.places.as_slice()), (1, &[5, 5][..]));
        // a face without vt is named when the file's uvs are needed
        let why = m.no_uv.unwrap();
        assert!(
            why.starts_with("line 5: a face without texture coordinates (vt)"),
            "{why}"
        );
    }

    #[test]
    fn file_normals_partial_and_zero() {
        // corner normals where given; a zero vn and a corner without one take the computed
        // normal (+z here)
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                    vn 0 0 0\nvn 0 0 5\nf 1/1/1 2/2/2 3/3/2\nf 1/1 3/3/2 4/4/2\n";
        let m = parse(text).unwrap();
        let (mesh, d) = m.to_mesh(DVec2::ONE).unwrap();
        assert_eq!(d.zero_file_normals, 1);
        // (1, vt 1, vn 1), (2, 2, 2), (3, 3, 2), (1, 1, none), (4, 4, 2)
        assert_eq!(mesh.vertices.len(), 5);
        assert!(mesh.vertices.iter().all(|v| v.normal == DVec3::Z));
    }

    #[test]
    fn read_names_the_file_and_a_line_that_is_not_utf8() {
        let p = crate::scratch::Scratch::file("latin1.obj");
        std::fs::write(&p, b"v 0 0 0\n# caf\xe9\n").unwrap();
        match read(&p) {
            Err(SceneError::File { path, message }) => {
                assert!(path.ends_with("latin1.obj"));
                assert!(message.contains("line 2: not UTF-8"), "{message}");
            }
            other => panic!("expected a file error, got {other:?}"),
        }
    }
}

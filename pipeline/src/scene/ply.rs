//! PLY files (the `ply-rs-bw` crate): ASCII, binary little endian and binary big endian, read
//! into a [`FileMesh`] that `super::mesh` builds by the rule for scan defects
//! (`docs/assets.md`, "Meshes from files").
//!
//! # What is read
//!
//! * `element vertex`: `x`, `y`, `z` (any scalar type; required), `nx`, `ny`, `nz` (all three
//!   or none: the file's normals), and texture coordinates as one pair of `u v`, `s t`,
//!   `texture_u texture_v` or `texture_s texture_t`. Other properties are ignored.
//! * `element face`: the list `vertex_indices` (or `vertex_index`) of any integer type, and
//!   optionally a float list `texcoord` of two numbers per corner (per-corner texture
//!   coordinates, used when the vertices have none). Faces of fewer than three corners are
//!   counted and ignored, polygons fanned. Other properties and elements are read past.
//! * Coordinates, normals and texture coordinates must be finite, coordinates within the
//!   f32 range (as for OBJ); indices from 0 to the vertex count less one.
//!
//! Errors name the line of ASCII files and the element (`vertex element 12`, `face element
//! 7`, counting from 0) of binary ones. The elements are read one at a time with the crate's
//! element readers, so a truncated binary file names the element it ends in.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec2, DVec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::mesh::{Corners, FileMesh, FxBuild, Place};
use super::SceneError;

/// Read a PLY file for `MeshSpec::Ply`: a regular file of at most
/// [`super::files::MAX_PLY_BYTES`], parsed by [`parse`]. Errors are file errors naming the
/// path; the file's own problems start with `could not load PLY`.
pub(crate) fn read(path: &Path) -> Result<FileMesh, SceneError> {
    let bytes = super::files::read_bounded(path, super::files::MAX_PLY_BYTES, "PLY")?;
    parse(&bytes).map_err(|m| SceneError::file(path.display(), format!("could not load PLY: {m}")))
}

/// The names of the texture coordinate pairs a vertex may have, in order of preference.
const UV_NAMES: [(&str, &str); 4] = [
    ("u", "v"),
    ("s", "t"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

/// The face list properties that hold the corners.
const INDEX_NAMES: [&str; 2] = ["vertex_indices", "vertex_index"];

/// Which vertex properties of the file are used.
#[derive(Debug, Clone, Copy)]
struct Layout {
    normals: bool,
    /// The slot of the texture coordinate pair's first name ([`slot`]), if there is one.
    uv: Option<usize>,
}

/// One vertex element: the properties of [`slot`] (0 where absent).
#[derive(Debug, Clone)]
struct VertexRecord {
    values: [f64; 14],
}

/// The slot of a vertex property in [`VertexRecord::values`]: x y z, nx ny nz, then the
/// names of [`UV_NAMES`] in order.
fn slot(name: &str) -> Option<usize> {
    Some(match name {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        "nx" => 3,
        "ny" => 4,
        "nz" => 5,
        "u" => 6,
        "v" => 7,
        "s" => 8,
        "t" => 9,
        "texture_u" => 10,
        "texture_v" => 11,
        "texture_s" => 12,
        "texture_t" => 13,
        _ => return None,
    })
}

impl VertexRecord {
    fn set(&mut self, name: &str, x: f64) -> PropertyAccessResult {
        match slot(name) {
            Some(k) => {
                self.values[k] = x;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }
}

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        VertexRecord { values: [0.0; 14] }
    }
    fn set_char(&mut self, name: &str, x: i8) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_uchar(&mut self, name: &str, x: u8) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_short(&mut self, name: &str, x: i16) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_ushort(&mut self, name: &str, x: u16) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_int(&mut self, name: &str, x: i32) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_uint(&mut self, name: &str, x: u32) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_float(&mut self, name: &str, x: f32) -> PropertyAccessResult {
        self.set(name, f64::from(x))
    }
    fn set_double(&mut self, name: &str, x: f64) -> PropertyAccessResult {
        self.set(name, x)
    }
}

/// One face element: its corners (as read: negative values are reported) and per-corner
/// texture coordinates if the file has them.
#[derive(Debug, Clone, Default)]
struct FaceRecord {
    corners: Vec<i64>,
    texcoord: Vec<f64>,
}

impl FaceRecord {
    fn set_ints(&mut self, name: &str, v: impl Iterator<Item = i64>) -> PropertyAccessResult {
        if INDEX_NAMES.contains(&name) {
            self.corners.extend(v);
            PropertyAccessResult::Set
        } else {
            PropertyAccessResult::Ignored
        }
    }
    fn set_reals(&mut self, name: &str, v: impl Iterator<Item = f64>) -> PropertyAccessResult {
        if name == "texcoord" {
            self.texcoord.extend(v);
            PropertyAccessResult::Set
        } else {
            PropertyAccessResult::Ignored
        }
    }
}

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        FaceRecord::default()
    }
    fn set_list_char(&mut self, name: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_uchar(&mut self, name: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_short(&mut self, name: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_ushort(&mut self, name: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_int(&mut self, name: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_uint(&mut self, name: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.set_ints(name, v.into_iter().map(i64::from))
    }
    fn set_list_float(&mut self, name: &str, v: Vec<f32>) -> PropertyAccessResult {
        self.set_reals(name, v.into_iter().map(f64::from))
    }
    fn set_list_double(&mut self, name: &str, v: Vec<f64>) -> PropertyAccessResult {
        self.set_reals(name, v.into_iter())
    }
}

/// An element read past.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// The least number of bytes one element of `def` takes in the payload (0 for a binary
/// element without properties).
fn min_bytes(def: &ElementDef, encoding: Encoding) -> usize {
    let size = |t: &ScalarType| match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    };
    match encoding {
        // a number and a separator (or the line break) per property, a line at least
        Encoding::Ascii => (2 * def.properties.len()).max(1),
        _ => def
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(t) => size(t),
                PropertyType::List(count, _) => size(count),
            })
            .sum(),
    }
}

/// Check the header: a vertex element with scalar x, y, z; normals all three or none; at most
/// one pair of texture coordinates; a face element with an integer corner list. Returns the
/// vertex layout.
fn check_header(header: &Header) -> Result<Layout, String> {
    let vertex = header
        .elements
        .get("vertex")
        .ok_or("the header has no `element vertex`: expected vertices with properties x, y, z")?;
    let scalar = |name: &str| {
        vertex
            .properties
            .get(name)
            .is_some_and(|p| matches!(p.data_type, PropertyType::Scalar(_)))
    };
    for name in ["x", "y", "z"] {
        if !scalar(name) {
            return Err(format!(
                "the vertex element has no scalar property {name}: expected x, y and z"
            ));
        }
    }
    let normal = ["nx", "ny", "nz"].map(scalar);
    let normals = normal.iter().all(|&b| b);
    if normal.iter().any(|&b| b) && !normals {
        return Err(
            "the vertex element has some of nx, ny, nz but not all: expected all three (the \
             file's normals) or none (computed normals)"
                .into(),
        );
    }
    let pairs: Vec<(&str, &str)> = UV_NAMES
        .into_iter()
        .filter(|(u, v)| scalar(u) && scalar(v))
        .collect();
    if pairs.len() > 1 {
        return Err(format!(
            "the vertex element has two pairs of texture coordinates, {} {} and {} {}: \
             expected one",
            pairs[0].0, pairs[0].1, pairs[1].0, pairs[1].1
        ));
    }
    let face = header.elements.get("face").ok_or(
        "the header has no `element face`: expected faces (a point cloud cannot be rendered)",
    )?;
    let list = INDEX_NAMES
        .iter()
        .find_map(|n| face.properties.get(*n))
        .ok_or("the face element has no list vertex_indices (or vertex_index): expected one")?;
    match &list.data_type {
        PropertyType::List(_, ScalarType::Float | ScalarType::Double) | PropertyType::Scalar(_) => {
            return Err(format!(
                "the face element's {} is not a list of integers: expected e.g. `property list \
                 uchar int {}`",
                list.name, list.name
            ))
        }
        PropertyType::List(..) => {}
    }
    if let Some(t) = face.properties.get("texcoord") {
        if !matches!(
            t.data_type,
            PropertyType::List(_, ScalarType::Float | ScalarType::Double)
        ) {
            return Err(
                "the face element's texcoord is not a list of float or double: expected e.g. \
                 `property list uchar float texcoord`"
                    .into(),
            );
        }
    }
    Ok(Layout {
        normals,
        uv: pairs.first().and_then(|(u, _)| slot(u)),
    })
}

/// The payload, read one element at a time; knows where it is for messages.
struct Payload<'a> {
    rest: &'a [u8],
    encoding: Encoding,
    /// The line of the next element (ASCII).
    line: usize,
}

impl Payload<'_> {
    /// How many elements of `def` the rest of the file can hold at most (for reservations:
    /// a header's count is not trusted).
    fn room(&self, def: &ElementDef) -> usize {
        match min_bytes(def, self.encoding) {
            0 => 0,
            least => def.count.min(self.rest.len() / least),
        }
    }

    /// Where element `i` of `def` is, before it is read: "line N (face i)" (ASCII) or
    /// "face element i" (binary; elements count from 0).
    fn place(&self, def: &ElementDef, i: usize) -> String {
        place(self.encoding, self.line, def, i)
    }

    /// Read element `i` of `def`.
    fn element<E: PropertyAccess>(&mut self, def: &ElementDef, i: usize) -> Result<E, String> {
        let parser = Parser::<E>::new();
        let mut text_line = "";
        let read = match self.encoding {
            Encoding::Ascii => {
                if self.rest.is_empty() {
                    return Err(format!(
                        "line {}: the file ends after {i} of its {} {} elements",
                        self.line, def.count, def.name
                    ));
                }
                let end = self
                    .rest
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(self.rest.len(), |k| k + 1);
                let (line, rest) = self.rest.split_at(end);
                self.rest = rest;
                let text = std::str::from_utf8(line).map_err(|_| {
                    format!("line {}: not UTF-8 text (an ASCII PLY file)", self.line)
                })?;
                text_line = text;
                let e = parser.read_ascii_element(text, def);
                if e.is_ok() {
                    self.line += 1;
                }
                e
            }
            Encoding::BinaryLittleEndian => parser.read_little_endian_element(&mut self.rest, def),
            Encoding::BinaryBigEndian => parser.read_big_endian_element(&mut self.rest, def),
        };
        read.map_err(|e| {
            if e.kind() == std::io::ErrorKind::UnexpectedEof {
                format!(
                    "{}: the file ends inside it (the header declares {} {} elements)",
                    self.place(def, i),
                    def.count,
                    def.name
                )
            } else if let Some(tok) = text_line
                .split_whitespace()
                .find(|t| t.parse::<f64>().is_ok_and(|x| !x.is_finite()))
            {
                format!("{}: {tok}: expected finite numbers", self.place(def, i))
            } else {
                format!("{}: {}", self.place(def, i), one_line(&e.to_string()))
            }
        })
    }
}

/// Where element `i` of `def` is: "line N (face i)" in an ASCII file (`line` its line) or
/// "face element i" in a binary one (elements count from 0).
fn place(encoding: Encoding, line: usize, def: &ElementDef, i: usize) -> String {
    match encoding {
        Encoding::Ascii => format!("line {line} ({} {i})", def.name),
        _ => format!("{} element {i}", def.name),
    }
}

/// The crate's message on one line, without the header grammar's internal state.
fn one_line(message: &str) -> String {
    let message = message.trim_end().replace("\n\t", "; ").replace('\n', " ");
    match message.find("; Error: ParseError {") {
        Some(k) => message[..k].to_string(),
        None => message,
    }
}

/// Parse a PLY file's bytes: the header ([`check_header`]), then every element in header
/// order (vertices and faces kept, others read past), then the checks of numbers and indices.
/// Errors are messages naming the line (ASCII) or element (binary).
pub(crate) fn parse(bytes: &[u8]) -> Result<FileMesh, String> {
    let mut reader = Reader::new(bytes);
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| {
            let message = one_line(&e.to_string());
            match e.line() {
                Some(l) => {
                    let prefix = format!("Line {l}: ");
                    let message = message.strip_prefix(&prefix).unwrap_or(&message);
                    format!("line {l}: a bad header: {message}")
                }
                None => format!("a bad header: {message}"),
            }
        })?;
    let line = reader.line();
    let rest = reader.into_inner();
    let layout = check_header(&header)?;
    let mut payload = Payload {
        rest,
        encoding: header.encoding,
        line,
    };
    read_elements(&header, layout, &mut payload)
}

fn read_elements(
    header: &Header,
    layout: Layout,
    payload: &mut Payload,
) -> Result<FileMesh, String> {
    let vertex_count = header.elements["vertex"].count;
    let ascii = header.encoding == Encoding::Ascii;
    let mut m = FileMesh {
        place: if ascii {
            Place::Line
        } else {
            Place::FaceElement
        },
        ..FileMesh::default()
    };
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    // per-corner texture coordinates of the faces: (position, u bits, v bits) -> value
    let mut corner_uvs: Vec<DVec2> = Vec::new();
    let mut corner_index: Vec<[u32; 3]> = Vec::new();
    let mut corner_ids: HashMap<(u32, u64, u64), u32, FxBuild> = HashMap::default();
    let mut all_texcoords = true;
    for def in header.elements.values() {
        match def.name.as_str() {
            "vertex" => {
                m.positions.reserve(payload.room(def));
                for i in 0..def.count {
                    let line = payload.line;
                    let here = || place(header.encoding, line, def, i);
                    let v: VertexRecord = payload.element(def, i)?;
                    let x = v.values;
                    let finite = |k: std::ops::Range<usize>, what: &str| {
                        if x[k.clone()].iter().all(|c| c.is_finite()) {
                            Ok(())
                        } else {
                            Err(format!(
                                "{}: {what} {:?}: expected finite numbers",
                                here(),
                                &x[k]
                            ))
                        }
                    };
                    finite(0..3, "position")?;
                    if let Some(c) = x[..3].iter().find(|c| c.abs() > f64::from(f32::MAX)) {
                        return Err(format!(
                            "{}: coordinate {c:e} is out of range: expected at most {:e} in \
                             magnitude (the f32 range, as for OBJ)",
                            here(),
                            f32::MAX
                        ));
                    }
                    m.positions.push(DVec3::new(x[0], x[1], x[2]));
                    if layout.normals {
                        finite(3..6, "normal")?;
                        normals.push(DVec3::new(x[3], x[4], x[5]));
                    }
                    if let Some(k) = layout.uv {
                        finite(k..k + 2, "texture coordinates")?;
                        uvs.push(DVec2::new(x[k], x[k + 1]));
                    }
                }
            }
            "face" => {
                m.triangles.reserve(payload.room(def));
                for i in 0..def.count {
                    let line = payload.line;
                    let at = if ascii { line } else { i };
                    let here = || place(header.encoding, line, def, i);
                    let f: FaceRecord = payload.element(def, i)?;
                    let n = f.corners.len();
                    if let Some(&k) = f
                        .corners
                        .iter()
                        .find(|&&k| k < 0 || k >= vertex_count as i64)
                    {
                        let expected = match vertex_count {
                            0 => "the file has no vertices".to_string(),
                            n => format!("expected 0 to {} (the file has {n} vertices)", n - 1),
                        };
                        return Err(format!(
                            "{}: vertex index {k} out of range: {expected}",
                            here()
                        ));
                    }
                    if n < 3 {
                        m.short_faces += 1;
                        continue;
                    }
                    let has_texcoord = !f.texcoord.is_empty();
                    if has_texcoord && f.texcoord.len() != 2 * n {
                        return Err(format!(
                            "{}: texcoord has {} numbers for {n} corners: expected two per \
                             corner",
                            here(),
                            f.texcoord.len()
                        ));
                    }
                    if let Some(t) = f.texcoord.iter().find(|t| !t.is_finite()) {
                        return Err(format!("{}: texcoord {t}: expected finite numbers", here()));
                    }
                    all_texcoords &= has_texcoord;
                    let mut ids = [0u32; 3];
                    for k in 1..n - 1 {
                        let c = [0, k, k + 1];
                        m.triangles.push(c.map(|j| f.corners[j] as u32));
                        m.places.push(at as u64);
                        if has_texcoord {
                            for (slot, j) in ids.iter_mut().zip(c) {
                                let uv = DVec2::new(f.texcoord[2 * j], f.texcoord[2 * j + 1]);
                                let key = (f.corners[j] as u32, uv.x.to_bits(), uv.y.to_bits());
                                *slot = *corner_ids.entry(key).or_insert_with(|| {
                                    corner_uvs.push(uv);
                                    corner_uvs.len() as u32 - 1
                                });
                            }
                            corner_index.push(ids);
                        }
                    }
                }
            }
            // a binary element without properties takes no bytes: nothing to read past
            _ if min_bytes(def, header.encoding) == 0 => {}
            _ => {
                for i in 0..def.count {
                    payload.element::<Skip>(def, i)?;
                }
            }
        }
    }
    if layout.normals {
        m.normals = Some(Corners {
            values: normals,
            index: m.triangles.clone(),
        });
    }
    if layout.uv.is_some() {
        m.uvs = Some(Corners {
            values: uvs,
            index: m.triangles.clone(),
        });
    } else if all_texcoords && corner_index.len() == m.triangles.len() {
        m.uvs = Some(Corners {
            values: corner_uvs,
            index: corner_index,
        });
    } else {
        m.no_uv = Some(
            "no texture coordinates: expected the vertex properties u and v (or s and t, \
             texture_u and texture_v) or a face list texcoord on every face; bump mapping needs \
             them (or use atlas: true)"
                .into(),
        );
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::{Defects, Mesh};
    use crate::scene::shapes::{load_file, FileKind};

    /// A PLY encoding.
    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Fmt {
        Ascii,
        Le,
        Be,
    }

    /// A value of a PLY element, written as the property's type.
    #[derive(Debug, Clone)]
    enum Val {
        N(f64),
        L(Vec<f64>),
    }

    /// An element: name, properties (`("float", "x")`, `("list uchar int", "vertex_indices")`)
    /// and rows.
    struct Element<'a> {
        name: &'a str,
        props: Vec<(&'a str, &'a str)>,
        rows: Vec<Vec<Val>>,
    }

    fn put(out: &mut Vec<u8>, fmt: Fmt, ty: &str, x: f64) {
        macro_rules! b {
            ($v:expr) => {
                if fmt == Fmt::Le {
                    out.extend_from_slice(&$v.to_le_bytes())
                } else {
                    out.extend_from_slice(&$v.to_be_bytes())
                }
            };
        }
        match ty {
            "char" => b!(x as i8),
            "uchar" => b!(x as u8),
            "short" => b!(x as i16),
            "ushort" => b!(x as u16),
            "int" => b!(x as i32),
            "uint" => b!(x as u32),
            "float" => b!(x as f32),
            "double" => b!(x),
            _ => panic!("type {ty}"),
        }
    }

    /// The bytes of a PLY file. ASCII numbers are written as the type's shortest exact
    /// decimal, so every encoding holds the same values.
    fn write(fmt: Fmt, elements: &[Element]) -> Vec<u8> {
        let format = match fmt {
            Fmt::Ascii => "ascii",
            Fmt::Le => "binary_little_endian",
            Fmt::Be => "binary_big_endian",
        };
        let mut out = format!("ply\nformat {format} 1.0\ncomment written by a test\n");
        for e in elements {
            out += &format!("element {} {}\n", e.name, e.rows.len());
            for (ty, name) in &e.props {
                out += &format!("property {ty} {name}\n");
            }
        }
        out += "end_header\n";
        let mut out = out.into_bytes();
        for e in elements {
            for row in &e.rows {
                let mut words = Vec::new();
                for ((full, _), v) in e.props.iter().zip(row) {
                    let ty = full.rsplit(' ').next().unwrap();
                    let text = |x: f64| match ty {
                        "float" => format!("{}", x as f32),
                        _ => format!("{x}"),
                    };
                    match (v, fmt) {
                        (Val::N(x), Fmt::Ascii) => words.push(text(*x)),
                        (Val::L(xs), Fmt::Ascii) => {
                            words.push(xs.len().to_string());
                            words.extend(xs.iter().map(|&x| text(x)));
                        }
                        (Val::N(x), _) => put(&mut out, fmt, ty, *x),
                        (Val::L(xs), _) => {
                            let count_ty = full.split(' ').nth(1).unwrap();
                            put(&mut out, fmt, count_ty, xs.len() as f64);
                            for &x in xs {
                                put(&mut out, fmt, ty, x);
                            }
                        }
                    }
                }
                if fmt == Fmt::Ascii {
                    out.extend_from_slice(words.join(" ").as_bytes());
                    out.push(b'\n');
                }
            }
        }
        out
    }

    /// Vertex rows of `x y z u v` and face rows of corner lists.
    fn mesh_elements<'a>(
        positions: &[[f64; 3]],
        uvs: Option<&[[f64; 2]]>,
        faces: &[Vec<i64>],
        index_type: &'a str,
    ) -> Vec<Element<'a>> {
        let mut props = vec![("float", "x"), ("float", "y"), ("float", "z")];
        if uvs.is_some() {
            props.extend([("float", "u"), ("float", "v")]);
        }
        let rows = positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut r: Vec<Val> = p.iter().map(|&x| Val::N(x)).collect();
                if let Some(uv) = uvs {
                    r.extend(uv[i].iter().map(|&x| Val::N(x)));
                }
                r
            })
            .collect();
        vec![
            Element {
                name: "vertex",
                props,
                rows,
            },
            Element {
                name: "face",
                props: vec![(index_type, "vertex_indices")],
                rows: faces
                    .iter()
                    .map(|f| vec![Val::L(f.iter().map(|&k| k as f64).collect())])
                    .collect(),
            },
        ]
    }

    /// Positions, uvs and faces.
    type Grid = (Vec<[f64; 3]>, Vec<[f64; 2]>, Vec<Vec<i64>>);

    /// A 3 x 2 grid of quads in z = 0 bent up along x = 2 (so normals vary), uv = (x/3, y/2):
    /// 12 vertices, six quads, the last one a triangle fan of the file's polygon.
    fn grid() -> Grid {
        let mut p = Vec::new();
        let mut uv = Vec::new();
        for j in 0..3 {
            for i in 0..4 {
                let (x, y) = (f64::from(i), f64::from(j));
                p.push([x, y, if i == 3 { 0.5 } else { 0.0 }]);
                uv.push([x / 4.0, y / 2.0]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..2 {
            for i in 0..3 {
                let a = j * 4 + i;
                faces.push(vec![a, a + 1, a + 5, a + 4]);
            }
        }
        (p, uv, faces)
    }

    /// A file `name` holding `bytes` in a fresh directory (removed when dropped).
    fn temp(name: &str, bytes: &[u8]) -> crate::scratch::Scratch {
        let p = crate::scratch::Scratch::file(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    fn load(name: &str, bytes: &[u8], atlas: bool) -> Result<(Mesh, Defects), String> {
        load_file(FileKind::Ply, &temp(name, bytes), DVec2::ONE, atlas).map_err(|e| match e {
            SceneError::File { path, message } => {
                assert!(path.ends_with(name), "{path}");
                message
            }
            other => panic!("expected a file error, got {other:?}"),
        })
    }

    fn same(a: &Mesh, b: &Mesh) {
        assert_eq!(a.triangles, b.triangles);
        assert_eq!(a.vertices, b.vertices);
    }

    #[test]
    fn ascii_and_binary_of_both_orders_load_the_same_mesh() {
        let (p, uv, f) = grid();
        for index_type in [
            "list uchar int",
            "list uchar uint",
            "list int uchar",
            "list ushort short",
        ] {
            let els = mesh_elements(&p, Some(&uv), &f, index_type);
            let (ascii, d) = load("a.ply", &write(Fmt::Ascii, &els), false).unwrap();
            assert_eq!((ascii.triangles.len(), ascii.vertices.len()), (12, 12));
            assert_eq!(
                d,
                Defects {
                    triangles: 12,
                    ..Defects::default()
                }
            );
            ascii.validate("mesh").unwrap();
            for fmt in [Fmt::Le, Fmt::Be] {
                let (m, d2) = load("b.ply", &write(fmt, &els), false).unwrap();
                same(&ascii, &m);
                assert_eq!(d, d2);
            }
            // and with the atlas
            let (a, _) = load("a.ply", &write(Fmt::Ascii, &els), true).unwrap();
            let (b, _) = load("b.ply", &write(Fmt::Be, &els), true).unwrap();
            same(&a, &b);
            assert_eq!(a.vertices.len(), 36);
        }
    }

    #[test]
    fn obj_and_ply_of_the_same_mesh_give_the_same_mesh() {
        let (p, uv, f) = grid();
        let mut obj = String::from("# the grid\no grid\n");
        for (q, t) in p.iter().zip(&uv) {
            obj += &format!("v {} {} {}\nvt {} {}\n", q[0], q[1], q[2], t[0], t[1]);
        }
        for face in &f {
            let c: Vec<String> = face
                .iter()
                .map(|k| format!("{}/{}", k + 1, k + 1))
                .collect();
            obj += &format!("f {}\n", c.join(" "));
        }
        let obj_path = temp("grid.obj", obj.as_bytes());
        let ply = write(Fmt::Le, &mesh_elements(&p, Some(&uv), &f, "list uchar int"));
        for atlas in [false, true] {
            let (a, da) = load_file(FileKind::Obj, &obj_path, DVec2::ONE, atlas).unwrap();
            let (b, db) = load("grid.ply", &ply, atlas).unwrap();
            same(&a, &b);
            assert_eq!(da, db);
        }
    }

    #[test]
    fn scan_defects_load_by_the_rule() {
        // the grid's faces, then: a back-to-back copy of face 0, an exact copy of face 1, a
        // zero-area face (two corners equal), a two-corner face; plus an unreferenced vertex
        let (mut p, mut uv, mut f) = grid();
        p.push([7.0, 7.0, 7.0]);
        uv.push([0.9, 0.9]);
        f.push(vec![f[0][0], f[0][3], f[0][2], f[0][1]]);
        f.push(f[1].clone());
        f.push(vec![0, 0, 5]);
        f.push(vec![1, 2]);
        let els = mesh_elements(&p, Some(&uv), &f, "list uchar int");
        let (m, d) = load("scan.ply", &write(Fmt::Be, &els), false).unwrap();
        let (clean, _) = load(
            "clean.ply",
            &write(
                Fmt::Be,
                &mesh_elements(&grid().0, Some(&grid().1), &grid().2, "list uchar int"),
            ),
            false,
        )
        .unwrap();
        same(&m, &clean);
        assert_eq!(
            d,
            Defects {
                triangles: 12 + 2 + 2 + 1,
                short_faces: 1,
                zero_area: 1,
                repeated: 4,
                unreferenced: 1,
                ..Defects::default()
            }
        );
        // with the atlas too
        let (m, d2) = load("scan.ply", &write(Fmt::Ascii, &els), true).unwrap();
        assert_eq!((m.triangles.len(), d2), (12, d));
        m.validate("mesh").unwrap();
    }

    #[test]
    fn normals_texcoords_types_and_other_elements() {
        // double coordinates, the file's normals (one of zero length), per-face texcoord
        // lists, an element before the vertices and one between vertices and faces
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let n = [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 2.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ];
        let vertex = |i: usize| {
            p[i].iter()
                .chain(&n[i])
                .map(|&x| Val::N(x))
                .collect::<Vec<_>>()
        };
        let els = [
            Element {
                name: "material",
                props: vec![("uchar", "red"), ("list uchar float", "stuff")],
                rows: vec![vec![Val::N(200.0), Val::L(vec![1.0, 2.0])]],
            },
            Element {
                name: "vertex",
                props: vec![
                    ("double", "x"),
                    ("double", "y"),
                    ("double", "z"),
                    ("float", "nx"),
                    ("float", "ny"),
                    ("float", "nz"),
                ],
                rows: (0..4).map(vertex).collect(),
            },
            Element {
                name: "edge",
                props: vec![("int", "vertex1"), ("int", "vertex2")],
                rows: vec![vec![Val::N(0.0), Val::N(1.0)]],
            },
            Element {
                name: "face",
                props: vec![
                    ("uchar", "flags"),
                    ("list uchar int", "vertex_index"),
                    ("list uchar float", "texcoord"),
                ],
                rows: vec![
                    vec![
                        Val::N(1.0),
                        Val::L(vec![0.0, 1.0, 2.0]),
                        Val::L(vec![0.0, 0.0, 0.5, 0.0, 0.5, 0.5]),
                    ],
                    vec![
                        Val::N(1.0),
                        Val::L(vec![0.0, 2.0, 3.0]),
                        Val::L(vec![0.0, 0.0, 0.5, 0.5, 0.0, 0.5]),
                    ],
                ],
            },
        ];
        for fmt in [Fmt::Ascii, Fmt::Le, Fmt::Be] {
            let (m, d) = load("n.ply", &write(fmt, &els), false).unwrap();
            assert_eq!((m.vertices.len(), m.triangles.len()), (4, 2), "{fmt:?}");
            assert_eq!(d.zero_file_normals, 1);
            assert!(m.vertices.iter().all(|v| v.normal == DVec3::Z));
            assert!(m.vertices.iter().all(|v| v.uv == v.pos.truncate() * 0.5));
            m.validate("mesh").unwrap();
        }
        // no texture coordinates: named, unless atlas
        let els = mesh_elements(&p, None, &[vec![0, 1, 2, 3]], "list uchar int");
        let e = load("nouv.ply", &write(Fmt::Le, &els), false).unwrap_err();
        assert!(
            e.contains("no texture coordinates") && e.contains("atlas: true"),
            "{e}"
        );
        let (m, _) = load("nouv.ply", &write(Fmt::Le, &els), true).unwrap();
        assert_eq!(m.triangles.len(), 2);
    }

    #[test]
    fn malformed_files_name_the_line_or_element() {
        let (p, uv, f) = grid();
        let els = mesh_elements(&p, Some(&uv), &f, "list uchar int");
        let header_lines = 3 + 6 + 2 + 1; // ply, format, comment; element lines; end_header
                                          // truncated binary: the element it ends in
        let bin = write(Fmt::Le, &els);
        let e = load("cut.ply", &bin[..bin.len() - 10], false).unwrap_err();
        assert!(
            e.starts_with("could not load PLY: face element 5: the file ends inside it"),
            "{e}"
        );
        let end = bin.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let e = load("cut.ply", &bin[..end + 30], false).unwrap_err();
        assert!(
            e.contains(": vertex element 1: the file ends inside it"),
            "{e}"
        );
        // a count the file cannot hold is not trusted (nothing is reserved for it)
        let huge = String::from_utf8(bin[..end].to_vec()).unwrap().replacen(
            "element vertex 12",
            "element vertex 4000000000",
            1,
        );
        let e = load("cut.ply", huge.as_bytes(), false).unwrap_err();
        assert!(
            e.contains("vertex element 0: the file ends inside it"),
            "{e}"
        );
        // truncated ASCII: the line after the last
        let text = write(Fmt::Ascii, &els);
        let cut = text.len() - 30;
        let lines = text[..cut].iter().filter(|&&b| b == b'\n').count();
        let e = load("cut.ply", &text[..cut], false).unwrap_err();
        assert!(e.contains(&format!("line {}", lines + 1)), "{e}");
        // bad header lines
        for (from, to, line) in [
            ("property float y", "property flot y", 6),
            ("format ascii 1.0", "format text 1.0", 2),
            ("end_header", "end_head", 12),
        ] {
            let bad = String::from_utf8(text.clone())
                .unwrap()
                .replacen(from, to, 1);
            let e = load("head.ply", bad.as_bytes(), false).unwrap_err();
            assert!(
                e.starts_with(&format!("could not load PLY: line {line}: a bad header")),
                "{from}: {e}"
            );
        }
        let e = load("head.ply", b"solid stl\n", false).unwrap_err();
        assert!(
            e.starts_with("could not load PLY: line 1: a bad header"),
            "{e}"
        );
        let bad = String::from_utf8(text.clone())
            .unwrap()
            .replacen("property float z\n", "", 1);
        let e = load("head.ply", bad.as_bytes(), false).unwrap_err();
        assert!(e.contains("no scalar property z"), "{e}");
        // an index out of range: the line (ASCII) or the face element (binary)
        let mut bad_faces = f.clone();
        bad_faces[2][1] = 12;
        let els = mesh_elements(&p, Some(&uv), &bad_faces, "list uchar int");
        let e = load("index.ply", &write(Fmt::Ascii, &els), false).unwrap_err();
        let line = header_lines + 12 + 3;
        assert!(
            e.contains(&format!(
                "line {line} (face 2): vertex index 12 out of range: expected 0 to 11"
            )),
            "{e}"
        );
        let e = load("index.ply", &write(Fmt::Be, &els), false).unwrap_err();
        assert!(
            e.contains("face element 2: vertex index 12 out of range"),
            "{e}"
        );
        bad_faces[2][1] = -1;
        let els = mesh_elements(&p, Some(&uv), &bad_faces, "list uchar int");
        let e = load("index.ply", &write(Fmt::Le, &els), false).unwrap_err();
        assert!(
            e.contains("face element 2: vertex index -1 out of range"),
            "{e}"
        );
        // NaN and infinite coordinates
        let mut bad_p = p.clone();
        bad_p[4][1] = f64::NAN;
        let els = mesh_elements(&bad_p, Some(&uv), &f, "list uchar int");
        let e = load("nan.ply", &write(Fmt::Le, &els), false).unwrap_err();
        assert!(
            e.contains("vertex element 4: position") && e.contains("finite"),
            "{e}"
        );
        let e = load("nan.ply", &write(Fmt::Ascii, &els), false).unwrap_err();
        let needle = format!(
            "line {} (vertex 4): NaN: expected finite numbers",
            header_lines + 5
        );
        assert!(e.contains(&needle), "{e}");
        bad_p[4][1] = 1e300;
        let mut els = mesh_elements(&bad_p, Some(&uv), &f, "list uchar int");
        for prop in &mut els[0].props[..3] {
            prop.0 = "double";
        }
        let e = load("big.ply", &write(Fmt::Be, &els), false).unwrap_err();
        assert!(
            e.contains("vertex element 4: coordinate 1e300 is out of range"),
            "{e}"
        );
    }
}

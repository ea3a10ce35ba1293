//! Sampling and packing (Wang et al. §2, "Sampling the simplified model"): "Each face of the
//! simplified mesh is sampled into a right-angled triangle patch of equal resolution, two
//! triangle patches that share one edge in the model form a square, and each of the
//! remaining triangle patches occupies a square. These squares are packed together and form
//! the rectangular normal map array", each patch "one or two pixels wider" against seams of
//! the filter.
//!
//! Choices where the paper is silent (docs/studies/normal-map-baking.md):
//! * **Pairing**: greedy in face order: an unpaired face takes the first unpaired face across
//!   its edges `(v0 v1)`, `(v1 v2)`, `(v2 v0)` that shares exactly that edge (a manifold
//!   edge, two faces). Deterministic.
//! * **Grid**: `g = ceil(sqrt(squares))` squares per side, each a cell of
//!   `c = floor(size / g)` texels, row-major from the map's top-left; the patch spans the
//!   cell's inner `c - 2 w` texels, `w` (the widening, 0 to 2) texels of border all round.
//! * **Patch layout**: in the square's coordinates `(s, t)` in `[0, 1]²` the first face of a
//!   square has its apex (the corner off the shared edge) at `(0, 0)` and the shared edge
//!   from `(1, 0)` to `(0, 1)`; the second face has its apex at `(1, 1)` and the same edge,
//!   so the diagonal is continuous. A lone face takes the first place with its corners
//!   `v0, v1, v2` at `(0, 0)`, `(1, 0)`, `(0, 1)`.
//! * **Samples**: every texel centre of a cell belongs to the face on its side of the
//!   diagonal (`s + t <= 1`: the first face); border texels, and the empty half of a lone
//!   face's square, are samples of the face's plane extended (barycentrics outside
//!   `[0, 1]`), so that bilinear filtering inside the patch reads only its own face.

use glam::DVec2;
use std::collections::HashMap;

use super::Surface;

/// Largest widening in texels (the paper: "one or two pixels wider").
pub const MAX_WIDEN: u32 = 2;

/// A packed sample layout for a simplified mesh.
#[derive(Debug, Clone)]
pub struct Packing {
    /// Map side in texels.
    pub size: u32,
    /// Squares per side of the grid.
    pub grid: u32,
    /// Cell side in texels.
    pub cell: u32,
    /// Border texels around each patch.
    pub widen: u32,
    /// Per square, its faces (the second `None` for a lone face).
    pub squares: Vec<[Option<u32>; 2]>,
    /// Per face, its texture coordinates (in `[0, 1]²`, `v` down the map's rows: row
    /// `floor(v size)`) at its corners `v0, v1, v2`.
    pub uv: Vec<[DVec2; 3]>,
    /// Per face: its square and whether it is the square's second face.
    pub place: Vec<(u32, bool)>,
}

/// One texel's sample: its face and barycentrics w.r.t. the face's corners `v0, v1, v2`
/// (outside `[0, 1]` on the border).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub face: u32,
    pub bary: [f64; 3],
}

/// Pair the faces of `s` (unless `pairs` is false: one square per face, each patch widened
/// on all its sides) and lay the squares out on a `size`-texel map with `widen` texels of
/// border. `size` must be a power of two from 16 to 16,384; the patches must keep at least
/// two texels inside the border.
pub fn pack(s: &Surface, size: u32, widen: u32, pairs: bool) -> Result<Packing, String> {
    if !(16..=16_384).contains(&size) || !size.is_power_of_two() {
        return Err(format!(
            "expected a map size that is a power of two from 16 to 16384, found {size}"
        ));
    }
    if widen > MAX_WIDEN {
        return Err(format!(
            "expected a widening from 0 to {MAX_WIDEN} texels, found {widen}"
        ));
    }
    let squares = if pairs {
        pair(s)
    } else {
        (0..s.triangles.len() as u32)
            .map(|f| [Some(f), None])
            .collect()
    };
    let n = squares.len() as u64;
    let mut grid = ((n as f64).sqrt() as u64).max(1);
    while grid * grid < n {
        grid += 1;
    }
    let grid = u32::try_from(grid).unwrap_or(u32::MAX);
    let cell = size / grid;
    if cell < 2 * widen + 2 {
        return Err(format!(
            "a {size}x{size} map holds {grid}x{grid} squares of {cell} texels for {} faces: \
             expected at least {} texels per square (widening {widen}); use a larger map or \
             fewer faces",
            s.triangles.len(),
            2 * widen + 2
        ));
    }
    let mut uv = vec![[DVec2::ZERO; 3]; s.triangles.len()];
    let mut place = vec![(0, false); s.triangles.len()];
    let packing0 = Packing {
        size,
        grid,
        cell,
        widen,
        squares: Vec::new(),
        uv: Vec::new(),
        place: Vec::new(),
    };
    for (q, faces) in squares.iter().enumerate() {
        for (second, f) in faces.iter().enumerate() {
            let Some(f) = *f else { continue };
            place[f as usize] = (q as u32, second == 1);
            let st = corner_st(s, faces, second == 1);
            uv[f as usize] = st.map(|p| packing0.st_to_uv(q as u32, p));
        }
    }
    Ok(Packing {
        squares,
        uv,
        place,
        ..packing0
    })
}

/// The greedy pairing of the module's doc.
fn pair(s: &Surface) -> Vec<[Option<u32>; 2]> {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (f, t) in s.triangles.iter().enumerate() {
        for i in 0..3 {
            edges
                .entry(key(t[i], t[(i + 1) % 3]))
                .or_default()
                .push(f as u32);
        }
    }
    let mut taken = vec![false; s.triangles.len()];
    let mut out = Vec::new();
    for (f, t) in s.triangles.iter().enumerate() {
        if taken[f] {
            continue;
        }
        taken[f] = true;
        let mut mate = None;
        for i in 0..3 {
            let e = &edges[&key(t[i], t[(i + 1) % 3])];
            if e.len() == 2 {
                let g = if e[0] == f as u32 { e[1] } else { e[0] };
                if !taken[g as usize] {
                    mate = Some(g);
                    break;
                }
            }
        }
        if let Some(g) = mate {
            taken[g as usize] = true;
        }
        out.push([Some(f as u32), mate]);
    }
    out
}

/// Square coordinates of the corners `v0, v1, v2` of a square's first or second face.
fn corner_st(s: &Surface, faces: &[Option<u32>; 2], second: bool) -> [DVec2; 3] {
    let [Some(f), Some(g)] = *faces else {
        return [DVec2::ZERO, DVec2::X, DVec2::Y];
    };
    let (tf, tg) = (s.triangles[f as usize], s.triangles[g as usize]);
    // the shared edge: the corners of f that g also has (two: `pair` found the edge)
    let mut shared = tf.iter().copied().filter(|k| tg.contains(k));
    let (a, b) = (shared.next(), shared.next());
    let apex = if second { DVec2::ONE } else { DVec2::ZERO };
    let me = if second { tg } else { tf };
    me.map(|k| {
        if Some(k) == a {
            DVec2::X
        } else if Some(k) == b {
            DVec2::Y
        } else {
            apex
        }
    })
}

impl Packing {
    /// Texture coordinates of square point `st` of square `q`.
    fn st_to_uv(&self, q: u32, st: DVec2) -> DVec2 {
        let (x0, y0) = self.origin(q);
        let inner = f64::from(self.cell - 2 * self.widen);
        let x = f64::from(x0 + self.widen) + st.x * inner;
        let y = f64::from(y0 + self.widen) + st.y * inner;
        DVec2::new(x, y) / f64::from(self.size)
    }

    /// Top-left texel of square `q`.
    pub fn origin(&self, q: u32) -> (u32, u32) {
        ((q % self.grid) * self.cell, (q / self.grid) * self.cell)
    }

    /// The sample of texel `(x, y)` (row `y` from the top), `None` outside every square.
    pub fn sample(&self, x: u32, y: u32) -> Option<Sample> {
        let (gx, gy) = (x / self.cell, y / self.cell);
        if gx >= self.grid || gy >= self.grid {
            return None;
        }
        let q = gy * self.grid + gx;
        let faces = self.squares.get(q as usize)?;
        let inner = f64::from(self.cell - 2 * self.widen);
        let (x0, y0) = self.origin(q);
        let st = DVec2::new(
            (f64::from(x - x0) + 0.5 - f64::from(self.widen)) / inner,
            (f64::from(y - y0) + 0.5 - f64::from(self.widen)) / inner,
        );
        let second = st.x + st.y > 1.0 && faces[1].is_some();
        let face = faces[usize::from(second)]?;
        Some(Sample {
            face,
            bary: barycentric(self.uv[face as usize], self.st_to_uv(q, st)),
        })
    }

    /// Every texel's sample, row-major.
    pub fn samples(&self) -> Vec<Option<Sample>> {
        (0..self.size)
            .flat_map(|y| (0..self.size).map(move |x| (x, y)))
            .map(|(x, y)| self.sample(x, y))
            .collect()
    }

    /// Texels that hold a sample.
    pub fn used_texels(&self) -> u64 {
        u64::from(self.cell) * u64::from(self.cell) * self.squares.len() as u64
    }
}

/// Barycentrics of `p` w.r.t. the triangle `t` (any side, extrapolated outside).
fn barycentric(t: [DVec2; 3], p: DVec2) -> [f64; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let det = e1.perp_dot(e2);
    if det == 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let b1 = d.perp_dot(e2) / det;
    let b2 = e1.perp_dot(d) / det;
    [1.0 - b1 - b2, b1, b2]
}

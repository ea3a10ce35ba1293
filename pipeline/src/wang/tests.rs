//! Tests of the normal-map baking on a bumpy icosphere (no file needed).

use glam::DVec3;
use std::collections::HashMap;

use super::bake::{quantize, BakeConfig, Baker, Buffer};
use super::evaluate::{mean, Evaluation};
use super::pack::pack;
use super::simplify::simplify;
use super::views::{directions, evaluation};
use super::Surface;

/// An icosphere subdivided `levels` times, radius `1 + amp sin(k x) sin(k y) sin(k z)`.
pub(crate) fn bumpy_sphere(levels: u32, amp: f64, k: f64) -> Surface {
    let ico = directions(12);
    // the 20 faces: triples of mutually nearest vertices
    let edge = (ico[0] - ico[1]).length().min((ico[0] - ico[3]).length());
    let near = |a: DVec3, b: DVec3| ((a - b).length() - edge).abs() < 1e-9;
    let mut tris = Vec::new();
    for i in 0..12 {
        for j in i + 1..12 {
            for l in j + 1..12 {
                if near(ico[i], ico[j]) && near(ico[j], ico[l]) && near(ico[i], ico[l]) {
                    let (a, b, c) = (ico[i], ico[j], ico[l]);
                    let t = if (b - a).cross(c - a).dot(a) > 0.0 {
                        [i as u32, j as u32, l as u32]
                    } else {
                        [i as u32, l as u32, j as u32]
                    };
                    tris.push(t);
                }
            }
        }
    }
    let mut pos = ico.clone();
    for _ in 0..levels {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::new();
        for t in &tris {
            let m = [0, 1, 2].map(|i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    pos.push(((pos[a as usize] + pos[b as usize]) * 0.5).normalize());
                    pos.len() as u32 - 1
                })
            });
            next.push([t[0], m[0], m[2]]);
            next.push([m[0], t[1], m[1]]);
            next.push([m[2], m[1], t[2]]);
            next.push([m[0], m[1], m[2]]);
        }
        tris = next;
    }
    let pos = pos
        .into_iter()
        .map(|p| p * (1.0 + amp * (k * p.x).sin() * (k * p.y).sin() * (k * p.z).sin()))
        .collect();
    Surface::with_smooth_normals(pos, tris)
}

#[test]
fn twelve_views_are_the_icosahedron_and_others_spread() {
    let d = directions(12);
    assert_eq!(d.len(), 12);
    let mut min = f64::MAX;
    for i in 0..12 {
        assert!((d[i].length() - 1.0).abs() < 1e-12);
        for j in i + 1..12 {
            min = min.min(d[i].angle_between(d[j]));
        }
    }
    // the icosahedron's nearest neighbours are 63.43 degrees apart
    assert!(
        (min.to_degrees() - 63.434_948_822_922).abs() < 1e-6,
        "{min}"
    );
    let e = evaluation();
    assert_eq!(e.len(), 30);
    for a in &e {
        assert!(d.iter().all(|b| a.angle_between(*b) > 1e-3));
    }
    assert_eq!(directions(5).len(), 5);
}

#[test]
fn simplify_reaches_the_target_and_rejects_bad_targets() {
    let s = bumpy_sphere(4, 0.0, 0.0); // 5120 faces
    assert_eq!(s.triangles.len(), 5120);
    let r = simplify(&s, 500).unwrap();
    let n = r.surface.triangles.len();
    assert!((450..=500).contains(&n), "{n}");
    assert!(!r.sloppy);
    // only its own vertices, all used
    let mut used = vec![false; r.surface.positions.len()];
    r.surface
        .triangles
        .iter()
        .flatten()
        .for_each(|&k| used[k as usize] = true);
    assert!(used.iter().all(|u| *u));
    for bad in [0, 3, 5121] {
        let e = simplify(&s, bad).unwrap_err();
        assert!(e.contains("expected a target face count from 4"), "{e}");
    }
}

#[test]
fn packing_pairs_neighbours_and_gives_each_face_an_equal_patch() {
    let s = simplify(&bumpy_sphere(3, 0.0, 0.0), 200).unwrap().surface;
    let p = pack(&s, 256, 1, true).unwrap();
    let paired = p.squares.iter().filter(|q| q[1].is_some()).count();
    assert_eq!(paired * 2 + (p.squares.len() - paired), s.triangles.len());
    assert!(paired * 2 >= s.triangles.len() * 8 / 10, "{paired}");
    // a pair's shared edge has the same texture coordinates in both faces
    for q in &p.squares {
        if let [Some(f), Some(g)] = *q {
            let (tf, tg) = (s.triangles[f as usize], s.triangles[g as usize]);
            for (i, k) in tf.iter().enumerate() {
                if let Some(j) = tg.iter().position(|x| x == k) {
                    assert_eq!(p.uv[f as usize][i], p.uv[g as usize][j]);
                }
            }
        }
    }
    // samples inside the patch (barycentrics in [0, 1]) per face: equal up to the diagonal
    let mut inside = vec![0usize; s.triangles.len()];
    for smp in p.samples().into_iter().flatten() {
        if smp.bary.iter().all(|b| (-1e-12..=1.0 + 1e-12).contains(b)) {
            inside[smp.face as usize] += 1;
        }
    }
    let (lo, hi) = (inside.iter().min().unwrap(), inside.iter().max().unwrap());
    assert!(*lo > 0 && hi - lo <= (p.cell as usize), "{lo} {hi}");
    for (size, widen, want) in [
        (100, 1, "power of two"),
        (256, 3, "widening"),
        (16, 2, "larger map"),
    ] {
        let e = pack(&s, size, widen, true).unwrap_err();
        assert!(e.contains(want), "{e}");
    }
}

#[test]
fn baking_recovers_the_detail_and_stops_improving_after_the_views_cover_it() {
    let detailed = bumpy_sphere(5, 0.04, 7.0); // 20480 faces
    let simple = simplify(&detailed, 320).unwrap().surface;
    let cfg = BakeConfig {
        map_size: 256,
        view_size: 256,
        ..BakeConfig::default()
    };
    let eval = Evaluation::new(&detailed, &simple, &evaluation()[..10], 128);
    let mut baker = Baker::new(&detailed, &simple, cfg).unwrap();
    let phong = mean(&eval.errors(&detailed, &baker.packing, &baker.map(None)));
    let mut after = Vec::new();
    for d in directions(12) {
        baker.add_view(d);
        after.push(mean(&eval.errors(&detailed, &baker.packing, &baker.map(None))).normal);
    }
    let twelve = *after.last().unwrap();
    assert!(phong.normal > 3.0 * twelve, "{} vs {twelve}", phong.normal);
    assert!(after[0] < phong.normal);
    assert!(baker.updated() as f64 > 0.97 * baker.sample_count() as f64);
    // the colour buffer is coarser than the item buffer
    let mut colour = Baker::new(
        &detailed,
        &simple,
        BakeConfig {
            buffer: Buffer::Color8,
            ..cfg
        },
    )
    .unwrap();
    directions(12).into_iter().for_each(|d| colour.add_view(d));
    let c = mean(&eval.errors(&detailed, &colour.packing, &colour.map(None))).normal;
    assert!(c > twelve, "{c} vs {twelve}");
    // 16-bit storage is within a hundredth of a colour step of exact
    let q16 = mean(&eval.errors(&detailed, &baker.packing, &baker.map(Some(16)))).normal;
    assert!((q16 - twelve).abs() < 0.01, "{q16} vs {twelve}");
}

#[test]
fn quantize_rounds_each_component() {
    let q = quantize(DVec3::new(1.0, -1.0, 0.5), 8);
    assert_eq!(q, DVec3::new(1.0, -1.0, 64.0 / 127.0));
    assert_eq!(
        quantize(DVec3::new(0.3, 0.0, 0.0), 16).x,
        (0.3f64 * 32767.0).round() / 32767.0
    );
}

#[test]
fn face_space_texels_give_back_the_baked_normals_in_the_engines_frame() {
    use super::scene::face_mesh;
    use crate::scene::perturb::perturb_normal_map;
    let detailed = bumpy_sphere(4, 0.04, 7.0);
    let simple = simplify(&detailed, 200).unwrap().surface;
    let cfg = BakeConfig {
        map_size: 128,
        view_size: 128,
        ..BakeConfig::default()
    };
    let mut b = Baker::new(&detailed, &simple, cfg).unwrap();
    directions(12).into_iter().for_each(|d| b.add_view(d));
    let mesh = face_mesh(&simple, &b.packing.uv);
    assert_eq!(mesh.vertices.len(), 3 * simple.triangles.len());
    let (texels, below) = super::scene::face_space(&b, &mesh);
    let mut worst = 0.0f64;
    for (k, s) in b.samples.iter().enumerate() {
        let Some((s, _)) = s else {
            assert_eq!(texels[k], DVec3::Z);
            continue;
        };
        let v = mesh.vertices[3 * s.face as usize];
        let n = perturb_normal_map(v.normal, v.pu, v.pv, texels[k]);
        worst = worst.max((n - b.normals[k].normalize()).length());
    }
    assert!(worst < 1e-9, "{worst}");
    // face space keeps the baked normals above their faces (HILO needs z >= 0)
    assert!(below * 100 < b.sample_count(), "{below}");
}

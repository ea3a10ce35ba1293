//! Bad quantized-normal-map configs (Tarini et al.): each is rejected with exit code 2 and a
//! message naming the field and what was expected.

mod common;

use common::*;

#[test]
fn bad_quantized_configs_are_rejected() {
    let cfg = config("quantized-sphere");
    let cases: [(&str, &[&str]); 7] = [
        (
            "engine.units.qnm.unit.s_n=0",
            &["s_n 0", "expected 1 to 2^index_bits = 256"],
        ),
        (
            "engine.units.qnm.unit.s_n=300",
            &["s_n 300", "expected 1 to 2^index_bits = 256"],
        ),
        (
            "engine.units.qnm.unit.index_bits=17",
            &["index_bits 17", "expected 8 to 16"],
        ),
        (
            "engine.units.qnm.unit.index_bits=7",
            &["index_bits 7", "expected 8 to 16"],
        ),
        // Exact must hold every distinct normal of the 256 x 256 map
        (
            "engine.units.qnm.unit.quantizer=Exact",
            &["Exact keeps every distinct normal", "more than s_n = 256"],
        ),
        (
            "engine.units.qnm.unit.size=100",
            &["size 100", "power of two"],
        ),
        (
            "engine.units.qnm.unit.quantizer=NeuQuant(sample_factor: 0)",
            &["sample_factor 0", "expected 1 to 30"],
        ),
    ];
    for (set, needles) in cases {
        let msg = expect_rejected(&cfg, set, needles);
        assert!(
            msg.contains("engine.units[0].unit"),
            "{set}: no field in {msg}"
        );
    }
    // 16-bit indices hold 65536 entries, but only Exact keeps more than 16384
    let c = cfg.display().to_string();
    let o = bumpsim(&[
        "check",
        &c,
        "--set",
        "engine.units.qnm.unit.index_bits=16",
        "--set",
        "engine.units.qnm.unit.s_n=16385",
    ]);
    o.expect_code(2, "s_n 16385");
    assert!(
        o.stderr.contains("engine.units[0].unit.s_n")
            && o.stderr.contains("expected at most 16384 for MedianCut"),
        "{}",
        o.stderr
    );
}

/// `check` of a bundled config with one override: exit 2 and every needle.
fn rejected(stem: &str, set: &str, needles: &[&str]) {
    expect_rejected(&config(stem), set, needles);
}
#[test]
fn bad_materials_are_rejected() {
    let m = "(ambient: (0.1, 0.1, 0.1), diffuse: (0.5, 0.5, 0.5), specular: (0.5, 0.5, 0.5), shininess: 8.0)";
    let eight = [m; 8].join(", ");
    // nine materials: more than the 3-bit material field holds (Tarini §6)
    rejected(
        "quantized-bunny-materials",
        &format!("scene.regions=Some((materials: [{eight}], rule: Split(of: NormalY, at: 0.0)))"),
        &["scene.regions.materials", "9 in all", "expected 1 to 7"],
    );
    rejected(
        "quantized-vase-colors",
        "scene.regions.rule=Bands(of: V, width: 0.1, count: 3)",
        &["scene.regions.rule.count", "expected 2 to 2"],
    );
    rejected(
        "quantized-bunny-materials",
        "scene.regions.materials[0].model=Cartoon(bands: 1)",
        &[
            "scene.regions.materials[0].model.bands",
            "expected 2 to 256",
        ],
    );
    // two materials cannot share a one-entry table
    rejected(
        "quantized-bunny-materials",
        "engine.units.qnm.unit.s_n=1",
        &[
            "engine.units[0].unit",
            "s_n = 1",
            "number of materials present (2)",
        ],
    );
    // the split form of §7 needs Phong or Lambert materials
    rejected(
        "quantized-bunny-wood-eq2",
        "scene.material.model=Chrome(sky: (0.5, 0.6, 0.9), ground: (0.3, 0.2, 0.1))",
        &["split", "Chrome", "expected Phong or Lambert"],
    );
}

#[test]
fn missing_or_bad_environment_maps_are_rejected() {
    rejected(
        "quantized-vase-envmap",
        "scene.material.model=EnvMap(image: \"assets/no-such-map.png\")",
        &[
            "no-such-map.png",
            "scene.material.model.image",
            "expected an RGB PNG",
        ],
    );
    // a file that exists but is not an image: a config
    rejected(
        "quantized-vase-envmap",
        "scene.material.model=EnvMap(image: \"quantized-sphere.ron\")",
        &[
            "quantized-sphere.ron",
            "scene.material.model.image",
            "expected an RGB PNG",
        ],
    );
    rejected(
        "quantized-vase-envmap",
        "scene.material.model=EnvMap(image: \"\")",
        &["scene.material.model.image", "empty"],
    );
}

#[test]
fn sphere_address_widths_out_of_range_are_rejected() {
    for (field, value, expected) in [
        ("r_frac", "31", "expected 2 to 30 fraction bits"),
        ("table_bits", "17", "expected 2 to 16 bits"),
        ("value_bits", "3", "expected 4 to 32 bits"),
    ] {
        let path = format!("engine.units[0].unit.datapath.sphere.{field}");
        rejected(
            "quantized-vase-envmap",
            &format!("engine.units.qnm.unit.datapath.sphere.{field}={value}"),
            &[&path, expected],
        );
    }
}

#[test]
fn bad_index_mipmaps_are_rejected() {
    rejected(
        "quantized-plane-mipmap",
        "engine.attributes[1].source=Lod(size: 100)",
        &[
            "engine.attributes[1].source.size",
            "expected a power of two",
        ],
    );
    rejected(
        "quantized-plane-mipmap",
        "engine.units.qnm.inputs={\"uv\": \"uv\"}",
        &["input port \"lod\"", "not wired"],
    );
    rejected(
        "quantized-plane-mipmap",
        "scene.mesh.subdivisions=0",
        &["mesh.Quad.subdivisions", "1..=2048"],
    );
    rejected(
        "quantized-plane-mipmap",
        "reference.samples=0",
        &["reference.samples", "expected 1 to 16"],
    );
}

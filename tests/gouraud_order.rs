//! Ernst et al. 1998 §5.1 (Figs. 2 and 3), the pipeline order: "blending the diffuse and
//! specular color together after the texture pass has no effect on black texture color due
//! to the multiplication". The measure that can show it is the light left on the checker's
//! black squares, where the reference (the texture modulating the diffuse term, the specular
//! added) holds only the highlight: `metrics::light_share`, the engine's light there over the
//! reference's. The three orders share scene, attributes and units
//! (`configs/gouraud-order-*.ron`).

mod common;

use bumpsim_pipeline::metrics::light_share;
use common::*;

/// The bit-accurate image and the reference of a bundled config with overrides.
fn render(stem: &str, sets: &[&str]) -> (image::RgbImage, image::RgbImage) {
    let r = config_run(stem, sets);
    (r.image, r.reference)
}

/// Measured: split keeps 0.873 of the highlight on black texels, the additive combined order
/// puts 4.281 times the highlight there (the diffuse light too), the multiplying order 0; all
/// three keep 0.989 of the light on white texels.
#[test]
fn only_the_multiplying_order_loses_the_highlight_on_black_texels() {
    // the checker as the engine fetches it (the interior of the squares is exactly black or
    // white; the bilinear rims are neither and left out)
    let (texture, _) = render("gouraud-order-split", &[r#"engine.output="tex.t""#]);
    let mut share = std::collections::BTreeMap::new();
    for order in ["split", "combined", "multiplicative"] {
        let (img, reference) = render(&format!("gouraud-order-{order}"), &[]);
        let black = light_share(&img, &reference, &texture, [0; 3]).expect("a highlight on black");
        let white = light_share(&img, &reference, &texture, [255; 3]).expect("light on white");
        println!(
            "{order}: light on black texels {black:.3} of the reference's, on white {white:.3}"
        );
        share.insert(order, (black, white));
    }
    // split: the highlight survives on black (the specular blend runs after the texture)
    assert!((0.8..1.2).contains(&share["split"].0), "{share:?}");
    // combined, additive (texture first, then the blend adds diffuse and specular): black
    // squares get the diffuse light too, far more than the highlight
    assert!(share["combined"].0 > 3.0, "{share:?}");
    // the paper's wording: the texture multiplies the combined blend: nothing on black
    assert_eq!(share["multiplicative"].0, 0.0, "{share:?}");
    // every order lights the white squares
    for (order, (_, w)) in &share {
        assert!((0.9..1.1).contains(w), "{order}: {share:?}");
    }
}

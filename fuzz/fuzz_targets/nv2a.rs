//! NV2A frame configs of arbitrary bytes: `nv2a::load` of the file (read, parse, the checks,
//! the textures, every pass's units built) beside a 640 x 480 frame `golden.png`, and on
//! success the comparison when the frame's work is small (at most 65,536 shaded pixels, so
//! that an input stays within the time-out at opt-level 1). Nothing may panic, and a load
//! error must name a field or a position (or be a file error).
#![no_main]

use bumpsim_hw::Mode;
use bumpsim_pipeline::nv2a;
use libfuzzer_sys::fuzz_target;
use std::sync::Once;

#[path = "common.rs"]
mod common;

static GOLDEN: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    GOLDEN.call_once(|| {
        let mut png = Vec::new();
        image::RgbaImage::from_pixel(640, 480, image::Rgba([34, 34, 34, 255]))
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .expect("a PNG encodes");
        common::scratch_file("golden.png", &png);
    });
    let path = common::scratch_file("frame.ron", data);
    match nv2a::load(&path, &[]) {
        Ok(l) => {
            if nv2a::shaded_pixels(&l.frame) <= 1 << 16 {
                let c = nv2a::compare(&l, Mode::BitAccurate).expect("a loaded frame compares");
                assert!(c.exact <= c.compared);
            }
        }
        Err(e) => assert!(
            !e.field.is_empty() || e.pos.is_some() || e.message.starts_with("cannot read"),
            "a load error without a field or position: {e}"
        ),
    }
});

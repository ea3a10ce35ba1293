//! Config parsing and validation of arbitrary bytes: `config::parse` of the text, then
//! `config::load_with` of the file (read, parse, validation, the budget estimate). Neither
//! may panic, and an error must name a field or a position (or be a file error).
#![no_main]

use bumpsim_pipeline::config::{self, LoadOptions};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = config::parse(text, "fuzz.ron") {
            assert!(
                !e.field.is_empty() || e.pos.is_some(),
                "a parse error without a field or position: {e}"
            );
        }
    }
    let path = common::scratch_file("fuzz.ron", data);
    if let Err(e) = config::load_with(&path, &[], LoadOptions::default()) {
        assert!(
            !e.field.is_empty() || e.pos.is_some() || e.message.starts_with("cannot read"),
            "a load error without a field or position: {e}"
        );
    }
});

//! Fuzz target `loader`: see `mcrender_formats::fuzzing`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    mcrender_formats::fuzzing::run("loader", data);
});

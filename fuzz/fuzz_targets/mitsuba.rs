//! Fuzz target `mitsuba`: see `mcrender_scene::fuzzing`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    mcrender_scene::fuzzing::run("mitsuba", data);
});

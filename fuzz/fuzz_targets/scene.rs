#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| timbre_fuzz::scene(data));

//! libFuzzer entry point of the `scene_parse` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::scene_parse(data) {
        panic!("scene_parse: violation\n{report}");
    }
});

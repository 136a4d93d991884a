//! libFuzzer entry point of the `field_bounds` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::field_bounds(data) {
        panic!("field_bounds: soundness violation\n{report}");
    }
});

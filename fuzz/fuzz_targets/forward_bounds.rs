//! libFuzzer entry point of the `forward_bounds` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::forward_bounds(data) {
        panic!("forward_bounds: soundness violation\n{report}");
    }
});

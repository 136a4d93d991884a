//! libFuzzer entry point of the `tracer_first_hit` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::tracer_first_hit(data) {
        panic!("tracer_first_hit: soundness violation\n{report}");
    }
});

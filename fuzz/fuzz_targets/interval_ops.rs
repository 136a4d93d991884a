//! libFuzzer entry point of the `interval_ops` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::interval_ops(data) {
        panic!("interval_ops: soundness violation\n{report}");
    }
});

//! libFuzzer entry point of the `affine_ops` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::affine_ops(data) {
        panic!("affine_ops: soundness violation\n{report}");
    }
});

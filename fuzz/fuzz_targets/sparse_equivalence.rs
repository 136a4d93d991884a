//! libFuzzer entry point of the `sparse_equivalence` target (see `fuzz/README.md`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(report) = boundtrace_fuzz::sparse_equivalence(data) {
        panic!("sparse_equivalence: soundness violation\n{report}");
    }
});

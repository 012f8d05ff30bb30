//! Runs one test case on both backends.

/// `#[test]` wrappers `<case>_cpu` and `<case>_gpu` for each `fn case(&Backend)`; the GPU one is
/// skipped without an adapter unless `SURFTRACK_REQUIRE_GPU=1`.
#[macro_export]
macro_rules! on_both_backends {
    ($($case:ident => $cpu:ident, $gpu:ident;)*) => {$(
        #[test]
        fn $cpu() {
            $case(&surftrack::compute::Backend::Cpu);
        }

        #[test]
        fn $gpu() {
            surftrack::compute::parity::run_on_gpu($case);
        }
    )*};
}

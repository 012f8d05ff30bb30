//! The GPU context on its own: buffers round-trip, and misuse comes back as an error value.

use surftrack::compute::parity::run_on_gpu;
use surftrack::compute::{Backend, ComputeError, GpuContext};
use surftrack::kernels::TRIANGLE_BOUNDS;
use surftrack::kernels::shared::Aabb;

fn context(backend: &Backend) -> &GpuContext {
    backend.gpu().expect("run_on_gpu passes a GPU backend")
}

#[test]
fn upload_then_read_back_round_trips_any_length() {
    run_on_gpu(|backend| {
        let gpu = context(backend);
        for len in [0usize, 1, 3, 1000] {
            let bytes: Vec<u8> = (0..len).map(|i| (i * 37 % 251) as u8).collect();
            let buffer = gpu.upload("bytes", &bytes).unwrap();
            assert_eq!(gpu.read_back::<u8>(&buffer, len).unwrap(), bytes);
            let words: Vec<u16> = (0..len).map(|i| (i * 7919) as u16).collect();
            let buffer = gpu.upload("words", &words).unwrap();
            assert_eq!(gpu.read_back::<u16>(&buffer, len).unwrap(), words);
        }
    });
}

#[test]
fn misuse_is_an_error_not_a_panic() {
    run_on_gpu(|backend| {
        let gpu = context(backend);
        let small = gpu.upload("small", &[1u32, 2]).unwrap();
        assert!(matches!(
            gpu.read_back::<u32>(&small, 3),
            Err(ComputeError::Gpu(_))
        ));
        assert_eq!(
            gpu.dispatch(&TRIANGLE_BOUNDS, &[&small], 1),
            Err(ComputeError::BindingCount {
                kernel: "triangle_bounds",
                expected: 3,
                got: 1
            })
        );
        // A 4-byte buffer cannot hold even one 32-byte box: wgpu's validation error comes back
        // as a value instead of reaching the device's panicking default handler.
        let positions = gpu.upload("positions", &[[0.0f32; 3]]).unwrap();
        let triangles = gpu.upload("triangles", &[[0u32; 3]]).unwrap();
        let result = gpu.dispatch(&TRIANGLE_BOUNDS, &[&positions, &triangles, &small], 1);
        assert!(matches!(result, Err(ComputeError::Gpu(_))), "{result:?}");
        let too_many = gpu.max_binding_len::<Aabb>() + 1;
        assert!(matches!(
            gpu.output::<Aabb>("huge", too_many),
            Err(ComputeError::BufferTooLarge { .. })
        ));
    });
}

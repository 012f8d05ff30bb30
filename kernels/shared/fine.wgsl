// The fine stage's solve on the device (register::fine_solve): its parameters, the state of its
// conjugate-gradient iteration and one vertex's correspondence, with the f64 vector and 3×3 matrix
// arithmetic of glam's DVec3 and DMat3 written out in glam's order of operations, so each kernel
// rounds as its CPU twin does. Vectors and matrices live in flat `array<f64>` buffers, 3 and 9
// values per element, matrices by column (glam's layout).
// Mirrored by `surftrack::kernels::shared::FineParams`, `CgState` and `FineTarget`
// (src/kernels/shared/fine.rs); a test compares the layouts.

// The weights of the fine energy and the sizes of one solve.
struct FineParams {
    disp_weight: f64,
    edge_weight: f64,
    plane_weight: f64,
    point_weight: f64,
    // Conjugate gradients stop once |r| / |b| is at most this.
    tolerance: f64,
    vertices: u32,
    // Cover pairs.
    pairs: u32,
    // Chunks of REDUCE_CHUNK vertices, each summed in order by one invocation of fine_reduce.
    chunks: u32,
    max_iterations: u32,
}

// The scalars of one conjugate-gradient solve, kept on the device between its kernels.
struct CgState {
    b_norm: f64,
    rz: f64,
    alpha: f64,
    beta: f64,
    // |r| / |b| after the last iteration.
    residual: f64,
    iterations: u32,
    // Non-zero once the solve has ended: every kernel of an iteration then leaves its outputs alone.
    done: u32,
}

// A vertex's correspondence: the target point and unit normal (solver coordinates); `found` is 0
// where the vertex has none.
struct FineTarget {
    point: array<f64, 3>,
    normal: array<f64, 3>,
    found: u32,
    pad: u32,
}

// Terms summed in order per chunk: the length of `ordered_sum`'s chunks on the CPU.
const REDUCE_CHUNK: u32 = 1024u;

// Phases of fine_scalars.
const PHASE_NORM: u32 = 0u;
const PHASE_BEGIN: u32 = 1u;
const PHASE_ALPHA: u32 = 2u;
const PHASE_BETA: u32 = 3u;

// glam's `DVec3::dot`.
fn dot3(a: vec3<f64>, b: vec3<f64>) -> f64 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's `DVec3::cross`.
fn cross3(a: vec3<f64>, b: vec3<f64>) -> vec3<f64> {
    return vec3<f64>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// glam's `DMat3 * DVec3`.
fn mat_vec(m: mat3x3<f64>, v: vec3<f64>) -> vec3<f64> {
    return m[0] * v.x + m[1] * v.y + m[2] * v.z;
}

// `v vᵀ`, as `register::fine::outer`.
fn outer(v: vec3<f64>) -> mat3x3<f64> {
    return mat3x3<f64>(v * v.x, v * v.y, v * v.z);
}

// glam's `DMat3::IDENTITY * s`.
fn identity_times(s: f64) -> mat3x3<f64> {
    let one = f64(1.0);
    let zero = f64(0.0);
    return mat3x3<f64>(
        vec3<f64>(one, zero, zero) * s,
        vec3<f64>(zero, one, zero) * s,
        vec3<f64>(zero, zero, one) * s,
    );
}

// glam's `DMat3::determinant`.
fn determinant3(m: mat3x3<f64>) -> f64 {
    return dot3(m[0], cross3(m[1], m[2]));
}

// glam's `DMat3::inverse`.
fn inverse3(m: mat3x3<f64>) -> mat3x3<f64> {
    let tmp0 = cross3(m[1], m[2]);
    let tmp1 = cross3(m[2], m[0]);
    let tmp2 = cross3(m[0], m[1]);
    let inv_det = f64(1.0) / dot3(m[0], tmp0);
    let a = tmp0 * inv_det;
    let b = tmp1 * inv_det;
    let c = tmp2 * inv_det;
    return mat3x3<f64>(vec3<f64>(a.x, b.x, c.x), vec3<f64>(a.y, b.y, c.y), vec3<f64>(a.z, b.z, c.z));
}

// The fine stage's system for one round of correspondences (register::fine): per vertex v its fit
// matrix M_v = α_plane n nᵀ + α_point I (zero without a correspondence), its right-hand side
// b_v = M_v (c_v − p_v) plus the cover pulls w M_p (t_p − Σ_k w_k p_k) of the pairs touching it,
// the inverse of A's 3×3 diagonal block as the Jacobi preconditioner (the identity where the block
// is singular), and the term |b_v|² of |b|.
// CPU twin: src/register/cpu/fine_system.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> start: array<f64>;
@group(0) @binding(2) var<storage, read> targets: array<FineTarget>;
@group(0) @binding(3) var<storage, read> offsets: array<u32>;
@group(0) @binding(4) var<storage, read> directions: array<f64>;
@group(0) @binding(5) var<storage, read> cover_offsets: array<u32>;
@group(0) @binding(6) var<storage, read> cover_entries: array<u32>;
@group(0) @binding(7) var<storage, read> cover_weights: array<f64>;
@group(0) @binding(8) var<storage, read> cover_matrices: array<f64>;
@group(0) @binding(9) var<storage, read> cover_pulls: array<f64>;
@group(0) @binding(10) var<storage, read_write> fit: array<f64>;
@group(0) @binding(11) var<storage, read_write> b: array<f64>;
@group(0) @binding(12) var<storage, read_write> preconditioner: array<f64>;
@group(0) @binding(13) var<storage, read_write> terms: array<f64>;

const WORKGROUP_SIZE: u32 = 64u;

fn direction(k: u32) -> vec3<f64> {
    return vec3<f64>(directions[3u * k], directions[3u * k + 1u], directions[3u * k + 2u]);
}

fn cover_matrix(p: u32) -> mat3x3<f64> {
    let m = 9u * p;
    return mat3x3<f64>(
        vec3<f64>(cover_matrices[m], cover_matrices[m + 1u], cover_matrices[m + 2u]),
        vec3<f64>(cover_matrices[m + 3u], cover_matrices[m + 4u], cover_matrices[m + 5u]),
        vec3<f64>(cover_matrices[m + 6u], cover_matrices[m + 7u], cover_matrices[m + 8u]),
    );
}

fn cover_pull(p: u32) -> vec3<f64> {
    return vec3<f64>(cover_pulls[3u * p], cover_pulls[3u * p + 1u], cover_pulls[3u * p + 2u]);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let v = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if v >= params.vertices {
        return;
    }
    let target_v = targets[v];
    var m = identity_times(f64(0.0));
    var rhs = vec3<f64>(f64(0.0), f64(0.0), f64(0.0));
    if target_v.found != 0u {
        let n = vec3<f64>(target_v.normal[0], target_v.normal[1], target_v.normal[2]);
        let c = vec3<f64>(target_v.point[0], target_v.point[1], target_v.point[2]);
        let p = vec3<f64>(start[3u * v], start[3u * v + 1u], start[3u * v + 2u]);
        m = outer(n) * params.plane_weight + identity_times(params.point_weight);
        rhs = mat_vec(m, c - p);
    }
    var diagonal = identity_times(f64(0.0));
    for (var i = cover_offsets[v]; i < cover_offsets[v + 1u]; i += 1u) {
        let pair = cover_entries[i] >> 2u;
        let w = cover_weights[3u * pair + (cover_entries[i] & 3u)];
        rhs = rhs + cover_pull(pair) * w;
        diagonal = diagonal + cover_matrix(pair) * (w * w);
    }
    var block = m + diagonal;
    for (var k = offsets[v]; k < offsets[v + 1u]; k += 1u) {
        let e = direction(k);
        block = block + (identity_times(params.disp_weight) + outer(e) * params.edge_weight);
    }
    var inverse = identity_times(f64(1.0));
    if abs(determinant3(block)) > f64(1e-300) {
        inverse = inverse3(block);
    }
    for (var col = 0u; col < 3u; col += 1u) {
        for (var row = 0u; row < 3u; row += 1u) {
            fit[9u * v + 3u * col + row] = m[col][row];
            preconditioner[9u * v + 3u * col + row] = inverse[col][row];
        }
        b[3u * v + col] = rhs[col];
    }
    terms[2u * v] = dot3(rhs, rhs);
    terms[2u * v + 1u] = f64(0.0);
}

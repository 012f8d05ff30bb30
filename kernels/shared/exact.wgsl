// Exact integer arithmetic wider than 32 bits, for the rasterization predicates that
// src/grid/predicates.rs evaluates with i64 and i128. WGSL has no 64-bit integers: a signed 64-bit
// value is vec2<u32>(low, high) and a signed 128-bit value vec4<u32> (limb 0 lowest), both two's
// complement. Every operation is exact, so both backends take the same branch on every sign.

// The full 64-bit product of two u32, from four 16-bit partial products.
fn mul_wide_u32(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let lo = (p00 & 0xffffu) | (mid << 16u);
    let hi = p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(lo, hi);
}

fn neg64(x: vec2<u32>) -> vec2<u32> {
    let lo = ~x.x + 1u;
    return vec2<u32>(lo, ~x.y + select(0u, 1u, lo == 0u));
}

fn add64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let lo = a.x + b.x;
    return vec2<u32>(lo, a.y + b.y + select(0u, 1u, lo < a.x));
}

fn sub64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    return add64(a, neg64(b));
}

fn sign64(x: vec2<u32>) -> i32 {
    if (x.y & 0x80000000u) != 0u {
        return -1;
    }
    return select(0, 1, (x.x | x.y) != 0u);
}

// a * b for any i32 (abs of the most negative i32 is itself, whose bits read as u32 are 2^31).
fn mul_i32(a: i32, b: i32) -> vec2<u32> {
    let p = mul_wide_u32(bitcast<u32>(abs(a)), bitcast<u32>(abs(b)));
    return select(p, neg64(p), (a < 0) != (b < 0));
}

fn add128(a: vec4<u32>, b: vec4<u32>) -> vec4<u32> {
    var out = vec4<u32>(0u);
    var carry = 0u;
    for (var i = 0u; i < 4u; i += 1u) {
        let s = a[i] + b[i];
        let r = s + carry;
        carry = select(0u, 1u, s < a[i]) + select(0u, 1u, r < s);
        out[i] = r;
    }
    return out;
}

fn neg128(x: vec4<u32>) -> vec4<u32> {
    return add128(~x, vec4<u32>(1u, 0u, 0u, 0u));
}

fn sign128(x: vec4<u32>) -> i32 {
    if (x.w & 0x80000000u) != 0u {
        return -1;
    }
    return select(0, 1, (x.x | x.y | x.z | x.w) != 0u);
}

// a * b for |a| < 2^63.
fn mul64_i32(a: vec2<u32>, b: i32) -> vec4<u32> {
    let negative_a = sign64(a) < 0;
    let ma = select(a, neg64(a), negative_a);
    let mb = bitcast<u32>(abs(b));
    let p0 = mul_wide_u32(ma.x, mb);
    let p1 = mul_wide_u32(ma.y, mb);
    let l1 = p0.y + p1.x;
    let m = vec4<u32>(p0.x, l1, p1.y + select(0u, 1u, l1 < p0.y), 0u);
    return select(m, neg128(m), negative_a != (b < 0));
}

// Nearest f32, up to a few rounding steps.
fn f32_from_64(x: vec2<u32>) -> f32 {
    let negative = sign64(x) < 0;
    let m = select(x, neg64(x), negative);
    let f = f32(m.y) * 4294967296.0 + f32(m.x);
    return select(f, -f, negative);
}

fn f32_from_128(x: vec4<u32>) -> f32 {
    let negative = sign128(x) < 0;
    let m = select(x, neg128(x), negative);
    let f = ((f32(m.w) * 4294967296.0 + f32(m.z)) * 4294967296.0 + f32(m.y)) * 4294967296.0
        + f32(m.x);
    return select(f, -f, negative);
}

// The rasterizer of `surftrack render` (src/render/gpu.rs): one triangle list of corners, each
// with its position, normal and colour (src/render/mesh.rs builds them), drawn with a depth
// test and lit by a headlight, or unlit to show the colours exactly.

struct View {
    view_proj: mat4x4<f32>,
    // Unit direction from the surface toward the light, in world space.
    light: vec4<f32>,
    // x: 1 lit, 0 unlit.
    mode: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;

struct Corner {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) colour: vec4<f32>,
}

struct Varying {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) colour: vec3<f32>,
}

@vertex
fn vs_main(corner: Corner) -> Varying {
    var out: Varying;
    out.clip = view.view_proj * vec4<f32>(corner.position.xyz, 1.0);
    out.normal = corner.normal.xyz;
    out.colour = corner.colour.rgb;
    return out;
}

@fragment
fn fs_main(in: Varying) -> @location(0) vec4<f32> {
    if view.mode.x < 0.5 {
        return vec4<f32>(in.colour, 1.0);
    }
    let n = normalize(in.normal);
    // Two-sided, so an inward-facing normal still reads as lit.
    let diffuse = abs(dot(n, view.light.xyz));
    return vec4<f32>(in.colour * (0.25 + 0.75 * diffuse), 1.0);
}

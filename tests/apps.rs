//! The applications of paper §5 end to end, through the binary: waves started by a merge, the
//! forward/backward blend of a morph, the evaluation chart, and rendered pictures (on any Vulkan
//! adapter, lavapipe included; skipped without one unless `SURFTRACK_REQUIRE_GPU=1`).

mod propagate_support;

use glam::Vec3;
use propagate_support::{channel, ok, surftrack};
use std::path::Path;
use surftrack::compute::parity::test_gpu;
use surftrack::io::{ReadOptions, read_frame_with, write_ply};
use surftrack::mesh::{Attribute, IndexedMesh};
use surftrack::render::{Camera, Renderer, Shading, corners};

fn read(path: &Path) -> IndexedMesh {
    let options = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    read_frame_with(path, &options).unwrap().mesh
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Generates synth `scene` and tracks it; returns the tracked folder.
fn tracked(dir: &Path, scene: &str, resolution: &str, frames: &str) -> std::path::PathBuf {
    let (input, out) = (dir.join("input"), dir.join("tracked"));
    ok(&surftrack(&[
        "synth",
        scene,
        "-o",
        text(&input),
        "--resolution",
        resolution,
        "--frames",
        frames,
    ]));
    ok(&surftrack(&[
        "track",
        text(&input),
        "-o",
        text(&out),
        "--backend",
        "cpu",
    ]));
    out
}

#[test]
fn waves_start_at_the_merge_and_the_chart_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let tracked = tracked(dir.path(), "merge", "48", "16");
    let waves = dir.path().join("waves");
    ok(&surftrack(&["waves", text(&tracked), "-o", text(&waves)]));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(waves.join("waves.json")).unwrap()).unwrap();
    let frames = summary["frames"].as_array().unwrap();
    let unit = summary["unit"].as_f64().unwrap() as f32;
    let merge = frames
        .iter()
        .position(|f| f["seeded"].as_u64().unwrap() > 0)
        .expect("the merge seeds waves");
    assert!(
        frames[..merge]
            .iter()
            .all(|f| f["max_height"].as_f64() == Some(0.0)),
        "no waves before the merge"
    );
    // The spheres meet near x = 0.05 (src/synth/scenes/merge.rs). A wave of speed 1 Δ per frame
    // has not reached the vertices more than 8 Δ from every vertex the merge seeded two frames on.
    let start = read(&waves.join(format!("frame_{merge:04}.ply")));
    let (_, height) = channel(&start, "height");
    let seeded: std::collections::HashSet<u64> = start
        .ids
        .as_ref()
        .unwrap()
        .iter()
        .zip(&height)
        .filter(|(_, h)| h[0] != 0.0)
        .map(|(&id, _)| id)
        .collect();
    for frame in merge..merge + 3 {
        let mesh = read(&waves.join(format!("frame_{frame:04}.ply")));
        let (_, height) = channel(&mesh, "height");
        let ids = mesh.ids.as_ref().unwrap();
        let sources: Vec<glam::Vec3> = ids
            .iter()
            .zip(&mesh.positions)
            .filter(|(id, _)| seeded.contains(id))
            .map(|(_, &p)| p)
            .collect();
        let (mut near, mut far, mut far_count) = (0.0f32, 0.0f32, 0usize);
        for (p, h) in mesh.positions.iter().zip(&height) {
            let h = h[0].abs() / unit;
            let reach = sources
                .iter()
                .map(|s| s.distance(*p))
                .fold(f32::MAX, f32::min);
            if (p.x - 0.05).abs() < 0.1 {
                near = near.max(h);
            } else if reach > 8.0 * unit {
                far = far.max(h);
                far_count += 1;
            }
        }
        println!(
            "frame {frame}: largest |h| near the merge {near:.3} Δ, on {far_count} vertices far from it {far:.2e} Δ"
        );
        assert!(near > 0.1, "frame {frame}: {near} near the merge");
        assert!(far_count > 100, "frame {frame}: {far_count} far vertices");
        assert!(far < 1e-3, "frame {frame}: {far} far from the merge");
    }

    for chart in ["eval.png", "eval.svg"] {
        let path = dir.path().join(chart);
        ok(&surftrack(&["eval", text(&tracked), "--plot", text(&path)]));
        let bytes = std::fs::read(&path).unwrap();
        if chart.ends_with(".svg") {
            let svg = String::from_utf8(bytes).unwrap();
            assert!(
                svg.starts_with("<svg") && svg.contains("Coherence"),
                "{chart}"
            );
        } else {
            let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
            let mut reader = decoder.read_info().unwrap();
            let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut pixels).unwrap();
            assert_eq!((info.width, info.height), (1200, 800));
            let white = pixels.iter().filter(|&&b| b == 255).count();
            assert!(white < pixels.len() * 99 / 100, "the chart is blank");
        }
        let again = surftrack(&["eval", text(&tracked), "--plot", text(&path)]);
        assert!(
            !again.status.success(),
            "{chart} was overwritten without --force"
        );
    }
}

#[test]
fn a_blend_starts_with_the_forward_colours_and_ends_with_the_backward_ones() {
    let dir = tempfile::tempdir().unwrap();
    let tracked = tracked(dir.path(), "morph", "32", "8");
    let run = |direction: &str, name: &str| {
        let out = dir.path().join(name);
        ok(&surftrack(&[
            "propagate",
            text(&tracked),
            direction,
            "--checker",
            "-o",
            text(&out),
        ]));
        out
    };
    let (forward, backward, blend) = (
        run("--forward", "forward"),
        run("--backward", "backward"),
        run("--blend", "blend"),
    );
    let colours = |dir: &Path, frame: usize| {
        let mesh = read(&dir.join(format!("frame_{frame:04}.ply")));
        channel(&mesh, "color").0.values.clone()
    };
    assert_eq!(colours(&blend, 0), colours(&forward, 0));
    assert_eq!(colours(&blend, 7), colours(&backward, 7));
    let (mixed, ahead, behind) = (
        colours(&blend, 4),
        colours(&forward, 4),
        colours(&backward, 4),
    );
    for ((m, a), b) in mixed.iter().zip(&ahead).zip(&behind) {
        assert!(
            (m - (3.0 * a + 4.0 * b) / 7.0).abs() < 1e-5,
            "{m} from {a} and {b}"
        );
    }
}

/// A sphere of `radius` at the origin, every vertex coloured `rgb`.
fn coloured_sphere(radius: f32, rgb: [f32; 3]) -> IndexedMesh {
    let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, radius, 4);
    let n = mesh.positions.len();
    mesh.attributes.push(Attribute {
        name: "color".to_string(),
        components: 3,
        values: rgb.repeat(n),
    });
    mesh
}

#[test]
fn a_rendered_sphere_fills_its_analytic_disc_in_its_colour_and_renders_identically_twice() {
    let backend = match test_gpu() {
        Ok(Some(backend)) => backend,
        Ok(None) => return,
        Err(error) => panic!("SURFTRACK_REQUIRE_GPU=1 but no GPU backend is available: {error}"),
    };
    let context = backend.gpu().unwrap();
    let size = 256u32;
    let renderer = Renderer::new(context, size, size).unwrap();
    let rgb = [51.0 / 255.0, 153.0 / 255.0, 204.0 / 255.0];
    let mesh = coloured_sphere(1.0, rgb);
    let colours = vec![rgb; mesh.positions.len()];
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_degrees: 30.0,
    };
    let unlit = corners(&mesh, &colours, Shading::Unlit);
    let image = renderer
        .draw(&unlit, &camera, Shading::Unlit, [1.0, 1.0, 1.0])
        .unwrap();
    let covered: Vec<[u8; 4]> = (0..size)
        .flat_map(|y| (0..size).map(move |x| (x, y)))
        .map(|(x, y)| image.pixel(x, y))
        .filter(|p| *p != [255, 255, 255, 255])
        .collect();
    let angular = (1.0f64 / 5.0).asin();
    let radius = angular.tan() / 15f64.to_radians().tan() * f64::from(size) / 2.0;
    let disc = std::f64::consts::PI * radius * radius;
    let error = (covered.len() as f64 - disc).abs() / disc;
    println!(
        "covered {} pixels, analytic disc {disc:.0}: {:.2}% off ({})",
        covered.len(),
        100.0 * error,
        context.adapter_info().name
    );
    assert!(error < 0.02, "coverage off by {error}");
    assert!(
        covered.iter().all(|p| *p == [51, 153, 204, 255]),
        "the flat colour is not reproduced"
    );
    let smooth = corners(&mesh, &colours, Shading::Smooth);
    let first = renderer
        .draw(&smooth, &camera, Shading::Smooth, [0.1, 0.1, 0.1])
        .unwrap();
    let second = renderer
        .draw(&smooth, &camera, Shading::Smooth, [0.1, 0.1, 0.1])
        .unwrap();
    assert!(first == second, "two renders differ");
}

#[test]
fn render_writes_every_frame_a_sheet_and_an_animation() {
    if test_gpu().map(|b| b.is_none()).unwrap_or(false) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    for k in 0..3 {
        let mut mesh = coloured_sphere(0.5 + 0.1 * k as f32, [0.8, 0.3, 0.2]);
        mesh.ids = Some((0..mesh.positions.len() as u64).collect());
        write_ply(&frames.join(format!("frame_{k:04}.ply")), &mesh).unwrap();
    }
    let out = dir.path().join("previews");
    let args = [
        "render",
        text(dir.path()),
        "-o",
        text(&out),
        "--width",
        "160",
        "--height",
        "120",
    ];
    ok(&surftrack(&args));
    for name in [
        "frame_0000.png",
        "frame_0001.png",
        "frame_0002.png",
        "sheet.png",
    ] {
        let bytes = std::fs::read(out.join(name)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{name}");
    }
    let gif = std::fs::read(out.join("animation.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a"));
    let again = surftrack(&args);
    assert!(
        !again.status.success(),
        "an existing output was overwritten without --force"
    );
}

#[test]
fn render_without_an_adapter_says_how_to_get_one() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    let mut mesh = coloured_sphere(1.0, [0.5; 3]);
    mesh.ids = Some((0..mesh.positions.len() as u64).collect());
    write_ply(&frames.join("frame_0000.ply"), &mesh).unwrap();
    let out = dir.path().join("previews");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_surftrack"))
        .args(["render", text(dir.path()), "-o", text(&out)])
        .env("WGPU_BACKEND", "dx12")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("lavapipe") && stderr.contains("mesa-vulkan-drivers"),
        "{stderr}"
    );
    assert!(!out.exists(), "an output folder was created for nothing");
}

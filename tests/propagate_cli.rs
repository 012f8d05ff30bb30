//! `surftrack propagate` end to end on a hand-built tracked sequence: the files Blender and Houdini
//! import, every source, the output-directory rules and clean failures.

mod propagate_support;

use glam::Vec3;
use propagate_support::{Ops, channel, ok, surftrack, write_sequence};
use std::path::Path;
use surftrack::io::{read_frame, write_ply};
use surftrack::mesh::Attribute;
use surftrack::propagate::{Bounds, Checker, LIGHT, Projection, Texture};

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn checker_and_uv_as_ply_properties_and_obj_texture_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 3, Ops::All, 60, 21);
    let stdout = ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--uv",
        "--projection",
        "planar-z",
        "--format",
        "both",
    ]));
    assert!(stdout.contains("color (3), uv (2)"), "{stdout}");
    let out = dir.path().join("propagated");
    for (k, frame) in frames.iter().enumerate() {
        let ply = read_frame(&out.join(format!("frame_{k:04}.ply")))
            .unwrap()
            .mesh;
        assert_eq!(ply.ids, frame.ids);
        assert_eq!(ply.positions, frame.positions);
        let (colour, _) = channel(&ply, "color");
        let (uv, _) = channel(&ply, "uv");
        assert_eq!((colour.components, uv.components), (3, 2));
        let obj = std::fs::read_to_string(out.join(format!("frame_{k:04}.obj"))).unwrap();
        let vt = obj.lines().filter(|l| l.starts_with("vt ")).count();
        assert_eq!(vt, frame.positions.len());
        let coloured = obj.lines().find(|l| l.starts_with("v ")).unwrap();
        assert_eq!(coloured.split_whitespace().count(), 7, "{coloured}");
        assert!(obj.lines().any(|l| l.starts_with("f ") && l.contains('/')));
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("propagate.json")).unwrap()).unwrap();
    assert_eq!(summary["direction"], "Forward");
    assert_eq!(summary["vertices"].as_array().unwrap().len(), 3);

    let again = surftrack(&["propagate", path(dir.path()), "--forward"]);
    assert!(!again.status.success());
    let message = String::from_utf8_lossy(&again.stderr);
    assert!(message.contains("propagated"), "{message}");
    ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--backward",
        "--force",
    ]));
    let both = surftrack(&["propagate", path(dir.path()), "--forward", "--backward"]);
    assert!(!both.status.success());
    let neither = surftrack(&["propagate", path(dir.path())]);
    assert!(!neither.status.success());
}

#[test]
fn an_image_through_a_planar_projection_colours_the_start_frame() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 2, Ops::Refine, 30, 4);
    // A 2×2 image: red, green on top; blue, white below.
    let pixels: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    let png_path = dir.path().join("tex.png");
    {
        let file = std::fs::File::create(&png_path).unwrap();
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 2, 2);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(pixels.as_flattened()).unwrap();
    }
    let texture = Texture::read_png(&png_path).unwrap();
    assert_eq!((texture.width(), texture.height()), (2, 2));
    let out = dir.path().join("img");
    ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--image",
        path(&png_path),
        "--projection",
        "planar-z",
        "-o",
        path(&out),
    ]));
    let first = read_frame(&out.join("frame_0000.ply")).unwrap().mesh;
    let bounds = Bounds::of(&frames[0].positions).unwrap();
    let (_, colours) = channel(&first, "color");
    for (p, c) in frames[0].positions.iter().zip(&colours) {
        let want =
            texture.sample(Projection::Planar(surftrack::propagate::Axis::Z).uv(*p, &bounds));
        for i in 0..3 {
            assert!((c[i] - want[i]).abs() < 1e-6);
        }
    }
    let corner = frames[0]
        .positions
        .iter()
        .position(|p| p.x < bounds.min.x + 0.2 && p.y > bounds.max.y - 0.6)
        .unwrap();
    assert!(
        colours[corner][0] > 0.5 && colours[corner][2] < 0.5,
        "{:?}",
        colours[corner]
    );

    let missing = surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--image",
        "nope.png",
    ]);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("nope.png"));
}

#[test]
fn a_painted_attribute_is_matched_by_id_or_by_closest_point() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 3, Ops::All, 50, 8);
    let mut painted = frames[0].clone();
    let heights: Vec<f32> = painted.positions.iter().map(|p| p.y).collect();
    painted.attributes = vec![Attribute {
        name: "height".to_string(),
        components: 1,
        values: heights.clone(),
    }];
    let with_ids = dir.path().join("painted.ply");
    write_ply(&with_ids, &painted).unwrap();
    painted.ids = None;
    let centre = Vec3::new(0.2, -0.1, 0.3);
    painted
        .positions
        .iter_mut()
        .for_each(|p| *p = centre + (*p - centre) * 1.02);
    let without_ids = dir.path().join("nearby.ply");
    write_ply(&without_ids, &painted).unwrap();

    let out = dir.path().join("by_id");
    ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--attribute",
        "height",
        "--from",
        path(&with_ids),
        "-o",
        path(&out),
    ]));
    let first = read_frame(&out.join("frame_0000.ply")).unwrap().mesh;
    assert_eq!(
        first.attributes.len(),
        1,
        "only the painted channel is carried"
    );
    assert_eq!(channel(&first, "height").0.values, heights);

    let out = dir.path().join("by_position");
    ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--attribute",
        "height",
        "--from",
        path(&without_ids),
        "-o",
        path(&out),
    ]));
    let first = read_frame(&out.join("frame_0000.ply")).unwrap().mesh;
    for (got, want) in channel(&first, "height").0.values.iter().zip(&heights) {
        assert!((got - want).abs() < 5e-3, "{got} vs {want}");
    }

    let wrong = surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--attribute",
        "paint",
        "--from",
        path(&with_ids),
        "-o",
        path(&dir.path().join("wrong")),
    ]);
    assert!(!wrong.status.success());
    let message = String::from_utf8_lossy(&wrong.stderr);
    assert!(
        message.contains("'paint'") && message.contains("height"),
        "{message}"
    );
}

#[test]
fn displacement_moves_light_checker_cells_out_along_the_normal() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 2, Ops::Refine, 20, 2);
    let out = dir.path().join("displaced");
    ok(&surftrack(&[
        "propagate",
        path(dir.path()),
        "--forward",
        "--checker-size",
        "6",
        "--displace",
        "0.5",
        "-o",
        path(&out),
    ]));
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("propagate.json")).unwrap()).unwrap();
    let delta = summary["start"]["mean_edge_length"].as_f64().unwrap() as f32;
    let checker: Checker = Checker {
        origin: Vec3::from_array(
            serde_json::from_value(summary["checker"]["origin"].clone()).unwrap(),
        ),
        cell: summary["checker"]["cell"].as_f64().unwrap() as f32,
    };
    assert!((checker.cell - 6.0 * delta).abs() < 1e-6);
    let first = read_frame(&out.join("frame_0000.ply")).unwrap().mesh;
    let centre = Vec3::new(0.2, -0.1, 0.3);
    let light = 0.2126 * LIGHT[0] + 0.7152 * LIGHT[1] + 0.0722 * LIGHT[2];
    let mut moved_light = 0;
    for (before, after) in frames[0].positions.iter().zip(&first.positions) {
        let lift = (after - centre).length() - (before - centre).length();
        if checker.is_light(*before) {
            assert!((lift - 0.5 * delta * light).abs() < 0.05 * delta, "{lift}");
            moved_light += 1;
        } else {
            assert!(lift > 0.0 && lift < 0.5 * delta * light, "{lift}");
        }
    }
    assert!(moved_light > 0);
}

//! The third-party dam-break frames (Blender `.bobj.gz`) load unrepaired and match the vertex,
//! face and topology counts of their manifest.

mod data_support;
use surftrack::io::{discover_sequence, read_frame};

#[test]
fn every_dambreak_frame_loads_clean_and_matches_its_manifest() {
    let Some(dir) = data_support::dambreak() else {
        return;
    };
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("manifest.json")).unwrap()).unwrap();
    let expected = manifest["frames"].as_array().unwrap();
    let sequence = discover_sequence(&dir).unwrap();
    assert_eq!(sequence.frames.len(), expected.len());
    for ((_, path), truth) in sequence.frames.iter().zip(expected) {
        let name = path.file_name().unwrap().to_str().unwrap();
        assert_eq!(name, truth["file"].as_str().unwrap());
        let frame = read_frame(path).unwrap();
        assert!(frame.repairs.is_clean(), "{name}: {:?}", frame.repairs);
        let mesh = &frame.mesh;
        assert_eq!(
            mesh.positions.len() as u64,
            truth["vertices"].as_u64().unwrap(),
            "{name}"
        );
        assert_eq!(
            mesh.triangles.len() as u64,
            truth["faces"].as_u64().unwrap(),
            "{name}"
        );
        mesh.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let topology = mesh.topology();
        assert_eq!(
            topology.components.len() as u64,
            truth["components"].as_u64().unwrap(),
            "{name}"
        );
        assert_eq!(
            topology.euler(),
            truth["euler_characteristic"].as_i64().unwrap(),
            "{name}"
        );
    }
}

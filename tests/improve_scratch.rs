use surftrack::synth::{Scene, SynthOptions, generate};
use std::io::Write;

#[test]
fn dump() {
    let res: usize = std::env::var("RES").ok().and_then(|s| s.parse().ok()).unwrap_or(80);
    std::fs::create_dir_all("/tmp/scratch/frames").unwrap();
    for scene in Scene::ALL {
        let opts = SynthOptions { resolution: res, frames: 32 };
        for (i, frame) in generate(scene, &opts).unwrap().enumerate() {
            let m = frame.unwrap().mesh;
            let mut f = std::fs::File::create(format!("/tmp/scratch/frames/{scene}_{res}_{i:02}.bin")).unwrap();
            f.write_all(&(m.positions.len() as u32).to_le_bytes()).unwrap();
            for p in &m.positions { for c in p.to_array() { f.write_all(&c.to_le_bytes()).unwrap(); } }
            f.write_all(&(m.triangles.len() as u32).to_le_bytes()).unwrap();
            for t in &m.triangles { for c in t { f.write_all(&c.to_le_bytes()).unwrap(); } }
        }
    }
}

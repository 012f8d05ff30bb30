use surftrack::events::EventList;
use surftrack::improve::{ImproveParams, assess, improve, one_sided_hausdorff};
use surftrack::mesh::Mesh;
use surftrack::synth::{Scene, SynthOptions, generate};

#[test]
fn scratch() {
    let res: usize = std::env::var("RES").ok().and_then(|s| s.parse().ok()).unwrap_or(80);
    let step: usize = std::env::var("STEP").ok().and_then(|s| s.parse().ok()).unwrap_or(4);
    for scene in Scene::ALL {
        let opts = SynthOptions { resolution: res, frames: 32 };
        let mut worst_band = 1.0f64;
        let (mut worst_pass, mut worst_hd, mut tot_unf, mut tot_t, mut tot_ops, mut second) = (1.0f64, 0.0f32, std::collections::BTreeMap::new(), 0.0, 0, 0);
        let mut nv = 0;
        let mut ttime = std::time::Duration::ZERO;
        for frame in generate(scene, &opts).unwrap().step_by(step) {
            let frame = frame.unwrap();
            let mesh = frame.mesh;
            nv = nv.max(mesh.positions.len());
            let l = mesh.mean_edge_length();
            let params = ImproveParams::new(l);
            let mut m = Mesh::from_indexed(&mesh).unwrap();
            m.record_mutations();
            let t = std::time::Instant::now();
            let report = improve(&mut m, &params).unwrap();
            ttime += t.elapsed();
            let _events = EventList::drain(&mut m);
            m.validate().unwrap();
            let out = m.to_indexed();
            let after = assess(&out, &params);
            let hd = one_sided_hausdorff(&out, &mesh) / l;
            worst_pass = worst_pass.min(after.passing_fraction());
            worst_hd = worst_hd.max(hd);
            worst_band = worst_band.min(1.0 - after.edge_out_of_band as f64 / after.triangles as f64);
            tot_t += after.triangles as f64;
            tot_ops += report.operations();
            for u in &report.unfixed { *tot_unf.entry(format!("{:?} {:?}", u.problem, u.refusals)).or_insert(0) += 1; }
            let mut again = Mesh::from_indexed(&out).unwrap();
            let r2 = improve(&mut again, &params).unwrap();
            second += r2.operations();
        }
        println!("{scene} maxverts {nv}: worst pass {worst_pass:.4} band {worst_band:.4} worst hd {worst_hd:.4} ops {tot_ops} second {second} time {ttime:?}");
        if std::env::var("V").is_ok() { for (k, v) in tot_unf { println!("  {v:5} {k}"); } }
        let _ = tot_t;
    }
}

#[test]
fn diag() {
    use std::collections::HashMap;
    let opts = SynthOptions { resolution: 80, frames: 32 };
    let scene: Scene = std::env::var("SCENE").unwrap_or("rigid".into()).parse().unwrap();
    let frame = generate(scene, &opts).unwrap().nth(8).unwrap().unwrap();
    let mesh = frame.mesh;
    let l = mesh.mean_edge_length();
    let params = ImproveParams::new(l);
    let mut m = Mesh::from_indexed(&mesh).unwrap();
    let report = improve(&mut m, &params).unwrap();
    let out = m.to_indexed();
    let a = assess(&out, &params);
    // normals of original mesh near each failing triangle: max normal angle among original triangles within 1.5L of centroid
    let n = |t: &[u32; 3], p: &[glam::Vec3]| { let [a, b, c] = t.map(|v| p[v as usize]); (b - a).cross(c - a).normalize() };
    let cent = |t: &[u32; 3], p: &[glam::Vec3]| { let [a, b, c] = t.map(|v| p[v as usize]); (a + b + c) / 3.0 };
    let mut spread_hist = [0usize; 8];
    for w in &a.worst {
        let t = &out.triangles[w.triangle];
        let c = cent(t, &out.positions);
        let nt = n(t, &out.positions);
        let mut spread = 0.0f32;
        for o in &mesh.triangles { if cent(o, &mesh.positions).distance(c) < 1.5 * l { spread = spread.max(nt.angle_between(n(o, &mesh.positions)).to_degrees()); } }
        spread_hist[((spread / 10.0) as usize).min(7)] += 1;
    }
    println!("triangles {} failing {} small {} ratio {}; spread hist (10deg) {:?}", a.triangles, a.failing, a.small_angle, a.ratio_exceeded, spread_hist);
    let mut c: HashMap<String, usize> = HashMap::new();
    for u in &report.unfixed { *c.entry(format!("{:?} {:?}", u.problem, u.refusals)).or_insert(0) += 1; }
    let mut c: Vec<_> = c.into_iter().collect(); c.sort();
    for (k, v) in c { println!("  {v:5} {k}"); }
    let (mut caps, mut needles, mut ratio_only) = (0, 0, 0);
    for w in &a.worst {
        let [p0, p1, p2] = out.triangles[w.triangle].map(|v| out.positions[v as usize]);
        let maxang = [(p1 - p0).angle_between(p2 - p0), (p0 - p1).angle_between(p2 - p1), (p0 - p2).angle_between(p1 - p2)].into_iter().fold(0.0f32, f32::max).to_degrees();
        if w.min_angle < 10.0 && maxang > 120.0 { caps += 1 } else if w.min_angle < 10.0 { needles += 1 } else { ratio_only += 1 }
    }
    println!("caps {caps} needles {needles} ratio_only {ratio_only}");

}

#[test]
fn lh() {
    for scene in Scene::ALL {
        let opts = SynthOptions { resolution: 80, frames: 32 };
        let f = generate(scene, &opts).unwrap().next().unwrap().unwrap();
        println!("{scene}: L/h = {:.3} verts {}", f.mesh.mean_edge_length() / f.truth.grid.spacing, f.mesh.positions.len());
    }
}

use std::time::Instant;
use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::grid::*;

fn metaballs() -> (surftrack::mesh::IndexedMesh, GridFrame) {
    let n = 128usize;
    let centers = [Vec3::new(-0.4, -0.2, 0.0), Vec3::new(0.45, 0.05, 0.1), Vec3::new(0.0, 0.45, -0.3)];
    let width = 0.57f32;
    let spacing = 2.0 / n as f32;
    let origin = Vec3::splat(-1.0);
    let grid = ScalarGrid::from_fn(origin, spacing, [n + 1; 3], |p| {
        0.5 - centers.iter().map(|c| (-(p - *c).length_squared() / (width * width)).exp()).sum::<f32>()
    }).unwrap();
    let mesh = marching_cubes(&grid, 0.0);
    (mesh, GridFrame::new(origin, spacing).unwrap())
}

#[test]
fn timing() {
    let (mesh, frame) = metaballs();
    eprintln!("tris {} mean edge {} spacing {}", mesh.triangles.len(), mesh.mean_edge_length(), frame.spacing());
    let gpu = Backend::select(surftrack::compute::BackendChoice::Gpu).unwrap();
    let backend = if std::env::var("GPU").is_ok() { &gpu } else { &Backend::Cpu };
    if std::env::var("BANDONLY").is_ok() {
        let lattice = LatticeMesh::new(frame, &mesh).unwrap();
        let crossings = rasterize(backend, &lattice).unwrap();
        let windings = sweep(backend, &crossings).unwrap();
        let faces = edge_faces(&lattice);
        let cells = footprint(&lattice, &crossings, &faces);
        let t = Instant::now();
        let n: usize = std::env::var("BANDONLY").unwrap().parse().unwrap();
        for _ in 0..n {
            signed_distance(backend, &lattice, &cells, &windings, 3.0).unwrap();
        }
        eprintln!("band x10 {:?}", t.elapsed());
        return;
    }
    for _ in 0..5 {
        let t = Instant::now();
        let lattice = LatticeMesh::new(frame, &mesh).unwrap();
        let t1 = t.elapsed();
        let crossings = rasterize(backend, &lattice).unwrap();
        let t2 = t.elapsed();
        let windings = sweep(backend, &crossings).unwrap();
        let t3 = t.elapsed();
        let dense = windings.fill_box([0; 3], [129; 3]);
        let t4 = t.elapsed();
        let faces = edge_faces(&lattice);
        let t5 = t.elapsed();
        let cells = footprint(&lattice, &crossings, &faces);
        let t6 = t.elapsed();
        let band = signed_distance(backend, &lattice, &cells, &windings, 3.0).unwrap();
        let t7 = t.elapsed();
        eprintln!("lattice {t1:?} raster {:?} sweep {:?} fill {:?} faces {:?} footprint {:?} band {:?} | crossings {} inside {} cells {} band {} ",
            t2-t1, t3-t2, t4-t3, t5-t4, t6-t5, t7-t6, crossings.len(), dense.iter().filter(|&&w| w > 0).count(), cells.len(), band.len());
    }
}

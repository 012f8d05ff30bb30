#[cfg(test)]
mod stats_probe {
    use std::sync::atomic::Ordering;
    use glam::Vec3;
    use crate::project::*;
    use crate::project::cpu::project::{NODES, TRIS};
    use crate::grid::{ScalarGrid, marching_cubes};
    fn metaballs(cells: usize, phase: f32, shift: f32) -> crate::mesh::IndexedMesh {
        let balls = [
            (Vec3::new(-0.35 + 0.1 * phase.cos(), 0.05, 0.0), 0.42),
            (Vec3::new(0.35, -0.1 + 0.1 * phase.sin(), 0.1), 0.36),
            (Vec3::new(0.0, 0.4, -0.2 + 0.05 * phase), 0.3),
            (Vec3::new(0.1, -0.45, -0.3), 0.22),
        ];
        let size = 2.4f32;
        let spacing = size / cells as f32;
        let origin = Vec3::splat(-size / 2.0) + Vec3::splat(shift * spacing);
        let grid = ScalarGrid::from_fn(origin, spacing, [cells + 1; 3], |p| {
            let sum: f32 = balls.iter().map(|&(c, r)| r * r / (p - c).length_squared().max(1e-12)).sum();
            1.0 - sum
        }).unwrap();
        marching_cubes(&grid, 0.0)
    }
    #[test]
    fn stats() {
        let target = metaballs(176, 0.0, 0.0);
        let source = metaballs(250, 0.3, 0.37);
        let normals = source.vertex_normals(crate::mesh::NormalWeighting::Max);
        let points = source.positions;
        let mut build = f64::MAX;
        let mut bvh = Bvh::build(&target).unwrap();
        for _ in 0..5 {
            let t = std::time::Instant::now();
            bvh = Bvh::build(&target).unwrap();
            build = build.min(t.elapsed().as_secs_f64());
        }
        let leaves = bvh.nodes().iter().filter(|n| n.is_leaf()).count();
        println!("build {:.1} ms nodes {} leaves {} avg leaf {:.2} depth {}", build * 1e3, bvh.nodes().len(), leaves, target.triangles.len() as f64 / leaves as f64, bvh.depth());
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let mut best = f64::MAX;
        for _ in 0..7 {
            NODES.store(0, Ordering::Relaxed);
            TRIS.store(0, Ordering::Relaxed);
            let t = std::time::Instant::now();
            let _ = pool.install(|| project(&crate::compute::Backend::Cpu, &bvh, &points, &normals, &ProjectOptions::default()).unwrap());
            best = best.min(t.elapsed().as_secs_f64());
        }
        let n = points.len() as f64;
        println!("per query: nodes {:.2} tris {:.2}", NODES.load(Ordering::Relaxed) as f64 / n, TRIS.load(Ordering::Relaxed) as f64 / n);
        println!("best {:.2} ms = {:.2} Mrays/s", best * 1e3, 2.0 * n / best / 1e6);
    }
}

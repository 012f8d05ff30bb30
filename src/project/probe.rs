#[cfg(test)]
mod stats_probe {
    use crate::grid::{ScalarGrid, marching_cubes};
    use crate::project::*;
    use glam::Vec3;
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
            let sum: f32 = balls
                .iter()
                .map(|&(c, r)| r * r / (p - c).length_squared().max(1e-12))
                .sum();
            1.0 - sum
        })
        .unwrap();
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
        let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let mut b1 = f64::MAX;
        for _ in 0..10 { let t = std::time::Instant::now(); single.install(|| Bvh::build(&target).unwrap()); b1 = b1.min(t.elapsed().as_secs_f64()); }
        println!("build 1 thread {:.1} ms", b1 * 1e3);
        let time = |name: &str, f: &(dyn Fn() + Sync)| { let mut b = f64::MAX; for _ in 0..10 { let t = std::time::Instant::now(); single.install(|| f()); b = b.min(t.elapsed().as_secs_f64()); } println!("  {name}: {:.2} ms", b * 1e3); };
        let boxes = crate::compute::triangle_bounds(&crate::compute::Backend::Cpu, &target.positions, &target.triangles).unwrap();
        time("bounds", &|| { crate::compute::triangle_bounds(&crate::compute::Backend::Cpu, &target.positions, &target.triangles).unwrap(); });
        time("tree", &|| { crate::project::build::build(&boxes); });
        time("shading", &|| { crate::project::shading::Shading::new(&target); });
        let tree = crate::project::build::build(&boxes);
        let sh = crate::project::shading::Shading::new(&target);
        time("leaf order", &|| { sh.in_leaf_order(&target, &tree.order); });
        time("adjacency", &|| { crate::project::adjacency::VertexFaces::new(target.positions.len(), &target.triangles); });
        for _ in 0..10 {
            let t = std::time::Instant::now();
            bvh = Bvh::build(&target).unwrap();
            build = build.min(t.elapsed().as_secs_f64());
        }
        let leaves = bvh
            .nodes()
            .iter()
            .flat_map(|n| n.children())
            .filter(|(_, c)| matches!(c, BvhChild::Leaf { .. }))
            .count();
        println!(
            "build {:.1} ms nodes {} leaves {} avg leaf {:.2} depth {}",
            build * 1e3,
            bvh.nodes().len(),
            leaves,
            target.triangles.len() as f64 / leaves as f64,
            bvh.depth()
        );
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let mut best = f64::MAX;
        fn cpu_ns() -> f64 {
            let s = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap();
            s.split_whitespace().next().unwrap().parse::<f64>().unwrap()
        }
        let n0 = points.len();
        let mut shuffled: Vec<usize> = (0..n0).collect();
        let mut state = 12345u64;
        for i in (1..n0).rev() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let j = (state >> 33) as usize % (i + 1);
            shuffled.swap(i, j);
        }
        let lo = points.iter().fold(Vec3::splat(f32::MAX), |a, &p| a.min(p));
        let hi = points.iter().fold(Vec3::splat(f32::MIN), |a, &p| a.max(p));
        let morton = |p: Vec3| -> u64 {
            let q = ((p - lo) / (hi - lo) * 1023.0).as_uvec3();
            let mut m = 0u64;
            for b in 0..10 {
                m |= (((q.x >> b) & 1) as u64) << (3 * b)
                    | (((q.y >> b) & 1) as u64) << (3 * b + 1)
                    | (((q.z >> b) & 1) as u64) << (3 * b + 2);
            }
            m
        };
        let mut sorted: Vec<usize> = (0..n0).collect();
        sorted.sort_by_key(|&i| morton(points[i]));
        let orders = [
            ("original", (0..n0).collect::<Vec<_>>()),
            ("shuffled", shuffled),
            ("morton", sorted),
        ];
        let sets: Vec<(&str, Vec<Vec3>, Vec<Vec3>)> = orders
            .iter()
            .map(|(name, o)| {
                (
                    *name,
                    o.iter().map(|&i| points[i]).collect(),
                    o.iter().map(|&i| normals[i]).collect(),
                )
            })
            .collect();
        let mut bests = vec![f64::MAX; 3];
        for _ in 0..7 {
            for (k, (_, p, nn)) in sets.iter().enumerate() {
                let c = pool.install(|| {
                    let a = cpu_ns();
                    let _ = project(
                        &crate::compute::Backend::Cpu,
                        &bvh,
                        p,
                        nn,
                        &ProjectOptions::default(),
                    )
                    .unwrap();
                    cpu_ns() - a
                });
                bests[k] = bests[k].min(c * 1e-9);
            }
        }
        let mut cp = f64::MAX;
        for _ in 0..7 { let t = std::time::Instant::now(); pool.install(|| closest_points(&crate::compute::Backend::Cpu, &bvh, &points, f32::INFINITY).unwrap()); cp = cp.min(t.elapsed().as_secs_f64()); }
        println!("closest: {:.2} ms = {:.2} M/s", cp * 1e3, n0 as f64 / cp / 1e6);
        for (k, (name, _, _)) in sets.iter().enumerate() {
            println!(
                "{name}: best cpu {:.2} ms = {:.2} Mrays/s",
                bests[k] * 1e3,
                2.0 * n0 as f64 / bests[k] / 1e6
            );
        }
        let _ = best;
    }
}

//! Properties of mesh improvement that hold on any input: a mesh that meets the criteria is left alone
//! (no mutation at all), the result does not depend on the thread count or on the mesh's scale, the
//! deviation limit really stops collapses that would move the surface, and the Hausdorff tool measures
//! what it claims.

use glam::Vec3;
use surftrack::improve::{
    ImproveError, ImproveParams, Operation, Problem, Refusal, SurfaceDistance, assess, improve,
    one_sided_hausdorff, point_triangle_distance, unfixed,
};
use surftrack::mesh::{IndexedMesh, Mesh, Mutation};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

/// A raw marching-cubes frame, small enough for quick tests.
fn raw_frame(scene: Scene) -> IndexedMesh {
    let options = SynthOptions {
        resolution: 40,
        frames: 4,
    };
    extract(&plan(scene, &options).expect("plan")[1]).expect("extract")
}

/// Improves `input` and returns the result with the recorded journal's length.
fn improved(input: &IndexedMesh, params: &ImproveParams) -> (IndexedMesh, usize) {
    let mut mesh = Mesh::from_indexed(input).expect("valid input");
    mesh.record_mutations();
    improve(&mut mesh, params).expect("improve");
    let journal = mesh.take_journal().len();
    (mesh.to_indexed(), journal)
}

#[test]
fn meshes_meeting_the_criteria_are_left_untouched() {
    let meshes = [
        IndexedMesh::icosphere(Vec3::new(1.0, 2.0, 3.0), 2.0, 3),
        IndexedMesh::torus(1.0, 0.35, 48, 18),
    ];
    for input in meshes {
        let params = ImproveParams::new(input.mean_edge_length());
        let before = assess(&input, &params);
        assert_eq!(before.failing, 0, "the test mesh itself must pass");
        assert_eq!(before.edge_out_of_band, 0);
        let (output, journal) = improved(&input, &params);
        assert_eq!(journal, 0, "a good mesh records no mutation");
        assert_eq!(output.positions, input.positions);
        assert_eq!(output.triangles, input.triangles);
    }
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let input = raw_frame(Scene::Blobs);
    let params = ImproveParams::new(input.mean_edge_length());
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| {
                let mut mesh = Mesh::from_indexed(&input).expect("valid input");
                mesh.record_mutations();
                let report = improve(&mut mesh, &params).expect("improve");
                (mesh.to_indexed(), mesh.take_journal(), report)
            })
    };
    let (one, journal_one, report_one) = run(1);
    let (three, journal_three, report_three) = run(3);
    assert!(report_one.collapses > 0, "the frame needed work");
    assert_eq!(one, three);
    assert_eq!(journal_one, journal_three);
    assert_eq!(report_one, report_three);
}

#[test]
fn scaling_the_mesh_and_the_target_length_scales_the_result() {
    let input = raw_frame(Scene::Rigid);
    let l = input.mean_edge_length();
    // A power of two scales every float exactly, so every decision must come out the same.
    let s = 1024.0;
    let mut scaled = input.clone();
    for p in &mut scaled.positions {
        *p *= s;
    }
    let (small, small_journal) = improved(&input, &ImproveParams::new(l));
    let (large, large_journal) = improved(&scaled, &ImproveParams::new(l * s));
    assert!(small_journal > 0);
    assert_eq!(small_journal, large_journal);
    assert_eq!(small.triangles, large.triangles);
    assert_eq!(small.ids, large.ids);
    for (a, b) in small.positions.iter().zip(&large.positions) {
        assert_eq!(*a * s, *b);
    }
}

#[test]
fn the_deviation_limit_stops_collapses_that_would_move_the_surface() {
    // A sphere with one edge split close to an end and the new vertex raised a little: the short
    // edge lies on a bump, so collapsing or merging it (or its end along another edge) moves the
    // surface a little.
    let input = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
    let l = input.mean_edge_length();
    let mut mesh = Mesh::from_indexed(&input).expect("valid");
    let h = mesh.edges().next().expect("an edge");
    let m = mesh.split_edge(h, 0.1).expect("split");
    let p = mesh.position(m);
    mesh.set_position(m, p + p.normalize() * 0.01 * l);
    let with_short_edge = mesh.to_indexed();

    let mut strict = ImproveParams::new(l);
    strict.max_deviation = 0.0;
    let mut mesh = Mesh::from_indexed(&with_short_edge).expect("valid");
    let report = improve(&mut mesh, &strict).expect("improve");
    assert_eq!(report.collapses + report.merges, 0);
    let left = unfixed(&mesh, &strict).expect("unfixed");
    let short = left
        .iter()
        .find(|u| u.problem == Problem::ShortEdge)
        .expect("the short edge is reported");
    for operation in [Operation::Merge, Operation::Collapse] {
        assert!(short.refusals.contains(&(operation, Refusal::Deviation)));
    }

    let mut mesh = Mesh::from_indexed(&with_short_edge).expect("valid");
    let params = ImproveParams::new(l);
    let report = improve(&mut mesh, &params).expect("improve");
    assert!(
        report.collapses + report.merges >= 1,
        "the default limit allows the fix"
    );
    let left = unfixed(&mesh, &params).expect("unfixed");
    assert!(left.is_empty(), "{left:?}");
    let moved = one_sided_hausdorff(&mesh.to_indexed(), &with_short_edge);
    assert!(moved > 0.0 && moved <= 2.0 * 0.0225 * l, "moved {moved}");
}

/// An icosphere with one vertex pushed most of the way towards a neighbour along the surface.
fn pushed_vertex() -> (Mesh, f32) {
    let input = IndexedMesh::icosphere(Vec3::new(0.5, -1.0, 2.0), 1.5, 3);
    let l = input.mean_edge_length();
    let mut mesh = Mesh::from_indexed(&input).expect("valid");
    let h = mesh.edges().nth(40).expect("an edge");
    let (v, w) = (mesh.origin(h), mesh.target(h));
    let p = mesh.position(v) + 0.6 * (mesh.position(w) - mesh.position(v));
    mesh.set_position(v, p);
    (mesh, l)
}

#[test]
fn a_carried_vertex_pushed_against_a_neighbour_is_moved_back_instead_of_removed() {
    // Registration can bunch vertices; a vertex from an earlier frame is then moved along the
    // surface, keeping every id, where a merge would re-sample it.
    let (mut mesh, l) = pushed_vertex();
    let before: Vec<u64> = mesh.vertices().map(|v| mesh.id(v)).collect();
    mesh.record_mutations();
    let params = ImproveParams {
        relax_below: mesh.next_id(),
        ..ImproveParams::new(l)
    };
    let report = improve(&mut mesh, &params).expect("improve");
    assert!(report.relaxes >= 1, "{report:?}");
    assert_eq!((report.merges, report.collapses, report.splits), (0, 0, 0));
    let left = unfixed(&mesh, &params).expect("unfixed");
    assert!(left.is_empty(), "{left:?}");
    assert!(mesh.take_journal().is_empty(), "a move is no mutation");
    let after: Vec<u64> = mesh.vertices().map(|v| mesh.id(v)).collect();
    assert_eq!(before, after);
    let shortest = mesh
        .edges()
        .map(|e| {
            mesh.position(mesh.origin(e))
                .distance(mesh.position(mesh.target(e)))
        })
        .fold(f32::INFINITY, f32::min);
    assert!(
        shortest >= params.min_edge_length(),
        "shortest edge {shortest}"
    );
}

#[test]
fn collapses_and_merges_keep_their_older_end_where_that_end_was_carried_over() {
    // A raw marching-cubes frame needs many collapses. With every vertex carried over, each keeps
    // its older end (moved to the midpoint): no vertex is created but by splits, and no merge
    // removes the older of its two ends.
    let input = raw_frame(Scene::Blobs);
    let l = input.mean_edge_length() * 1.5;
    let improve_with = |relax_below: u64| {
        let mut mesh = Mesh::from_indexed(&input).expect("valid input");
        mesh.record_mutations();
        let params = ImproveParams {
            relax_below,
            ..ImproveParams::new(l)
        };
        let report = improve(&mut mesh, &params).expect("improve");
        (report, mesh.take_journal(), mesh.next_id())
    };
    let (paper, journal, _) = improve_with(0);
    assert!(paper.collapses > 0, "{paper:?}");
    assert!(
        journal
            .iter()
            .any(|m| matches!(m, Mutation::Collapse { .. }))
    );
    let (carried, journal, _) = improve_with(u64::MAX);
    assert_eq!(carried.collapses, 0, "{carried:?}");
    assert!(carried.merges > paper.merges);
    assert!(
        !journal
            .iter()
            .any(|m| matches!(m, Mutation::Collapse { .. }))
    );
    // Every merge, the collapses' and those into the newer end alike, keeps the older end.
    for m in &journal {
        if let Mutation::Merge { kept, removed } = m {
            assert!(kept < removed, "merge kept {kept}, removed {removed}");
        }
    }
}

#[test]
fn a_vertex_new_in_this_frame_is_removed_as_before() {
    // The same mesh with no vertex carried over: the short edge goes by a merge, as in the paper's
    // improvement of a frame's new surface.
    let (mut mesh, l) = pushed_vertex();
    let vertices = mesh.vertex_count();
    let report = improve(&mut mesh, &ImproveParams::new(l)).expect("improve");
    assert_eq!(report.relaxes, 0);
    assert!(report.merges + report.collapses >= 1, "{report:?}");
    assert!(mesh.vertex_count() < vertices);
}

#[test]
fn a_vertex_split_off_near_an_end_is_merged_back_into_the_older_end() {
    // Splitting an edge of a good mesh at a tenth leaves one short edge; merging its new end into
    // the old one restores the mesh exactly, re-sampling nothing the input had.
    let input = IndexedMesh::icosphere(Vec3::new(0.5, -1.0, 2.0), 1.5, 2);
    let l = input.mean_edge_length();
    let mut mesh = Mesh::from_indexed(&input).expect("valid");
    let h = mesh.edges().nth(7).expect("an edge");
    mesh.split_edge(h, 0.1).expect("split");
    mesh.record_mutations();
    let params = ImproveParams::new(l);
    let report = improve(&mut mesh, &params).expect("improve");
    assert_eq!((report.merges, report.collapses, report.splits), (1, 0, 0));
    let left = unfixed(&mesh, &params).expect("unfixed");
    assert!(left.is_empty(), "{left:?}");
    let mut output = mesh.to_indexed();
    output.ids = None;
    let mut expected = input.clone();
    expected.ids = None;
    assert_eq!(output.positions, expected.positions);
    let sorted = |m: &IndexedMesh| {
        let mut t: Vec<[u32; 3]> = m
            .triangles
            .iter()
            .map(|&[a, b, c]| {
                let k = [a, b, c]
                    .iter()
                    .position(|&x| x == a.min(b).min(c))
                    .unwrap_or(0);
                [[a, b, c][k], [a, b, c][(k + 1) % 3], [a, b, c][(k + 2) % 3]]
            })
            .collect();
        t.sort_unstable();
        t
    };
    assert_eq!(sorted(&output), sorted(&expected));
}

#[test]
fn bad_parameters_are_refused_before_any_work() {
    let input = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1);
    let mut mesh = Mesh::from_indexed(&input).expect("valid");
    mesh.record_mutations();
    type Spoil = fn(&mut ImproveParams);
    let cases: [(&str, Spoil); 4] = [
        ("edge_length", |p| p.edge_length = 0.0),
        ("min_angle_degrees", |p| p.min_angle_degrees = 75.0),
        ("edge_ratio", |p| p.edge_ratio = 1.5),
        ("max_deviation", |p| p.max_deviation = f32::NAN),
    ];
    for (name, spoil) in cases {
        let mut params = ImproveParams::new(1.0);
        spoil(&mut params);
        match improve(&mut mesh, &params) {
            Err(ImproveError::Parameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("{name}: {other:?}"),
        }
    }
    assert!(mesh.take_journal().is_empty());
}

#[test]
fn surface_distance_matches_brute_force_and_hausdorff_sees_a_shift() {
    let sphere = raw_frame(Scene::Merge);
    let grid = SurfaceDistance::new(&sphere);
    let brute = |p: Vec3| {
        sphere
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| sphere.positions[v as usize]);
                point_triangle_distance(p, a, b, c)
            })
            .fold(f32::INFINITY, f32::min)
    };
    let l = sphere.mean_edge_length();
    for k in 0..200 {
        let v = sphere.positions[(k * 97) % sphere.positions.len()];
        let offset = Vec3::new(
            ((k * 13) % 7) as f32 - 3.0,
            ((k * 5) % 9) as f32 - 4.0,
            ((k * 11) % 5) as f32 - 2.0,
        ) * (0.4 * l);
        let p = v + offset * (k % 4) as f32;
        assert!((grid.distance(p) - brute(p)).abs() <= 1e-6 * (1.0 + brute(p)));
    }
    let itself = one_sided_hausdorff(&sphere, &sphere);
    assert!(itself <= 1e-5 * l, "a mesh is {itself} from itself");
    let mut shifted = sphere.clone();
    let d = 0.3 * l;
    for p in &mut shifted.positions {
        p.x += d;
    }
    let h = one_sided_hausdorff(&shifted, &sphere);
    assert!(h > 0.5 * d && h <= d * 1.0001, "{h} vs shift {d}");
}

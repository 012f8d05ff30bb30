//! Mesh core: validation verdicts, topology, normals and quality on meshes with known answers.

use glam::Vec3;
use surftrack::mesh::{IndexedMesh, Mesh, MeshError, NormalWeighting};

fn tetrahedron() -> IndexedMesh {
    IndexedMesh::new(
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

#[test]
fn closed_meshes_validate_with_the_right_topology() {
    let tet = tetrahedron();
    assert_eq!(tet.validate(), Ok(()));
    assert!(tet.signed_volume() > 0.0);
    let sphere = IndexedMesh::icosphere(Vec3::ZERO, 2.0, 3);
    assert_eq!(sphere.validate(), Ok(()));
    let t = sphere.topology();
    assert_eq!((t.components.len(), t.euler(), t.total_genus()), (1, 2, 0));
    let torus = IndexedMesh::torus(3.0, 1.0, 32, 16);
    assert_eq!(torus.validate(), Ok(()));
    let t = torus.topology();
    assert_eq!((t.components.len(), t.euler(), t.total_genus()), (1, 0, 1));
}

#[test]
fn two_components_are_counted_separately() {
    let mut t = IndexedMesh::torus(3.0, 1.0, 12, 8);
    t.positions.iter_mut().for_each(|p| *p += Vec3::X * 10.0);
    let m = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1).joined(&t);
    assert_eq!(m.validate(), Ok(()));
    let topo = m.topology();
    let genus: Vec<i64> = topo.components.iter().map(|c| c.genus).collect();
    assert_eq!(genus, vec![0, 1]);
}

#[test]
fn each_defect_has_its_own_error() {
    let mut open = tetrahedron();
    open.triangles.pop();
    assert!(matches!(
        open.validate(),
        Err(MeshError::OpenBoundary { .. })
    ));

    let mut flipped = tetrahedron();
    flipped.triangles[3] = [1, 3, 2];
    assert!(matches!(
        flipped.validate(),
        Err(MeshError::InconsistentOrientation { .. })
    ));

    let mut nan = tetrahedron();
    nan.positions[2].y = f32::NAN;
    assert!(matches!(
        nan.validate(),
        Err(MeshError::NonFiniteCoordinate { vertex: 2, .. })
    ));

    let mut range = tetrahedron();
    range.triangles[0][1] = 9;
    assert!(matches!(
        range.validate(),
        Err(MeshError::IndexOutOfRange { vertex: 9, .. })
    ));

    let mut flat = tetrahedron();
    flat.positions[3] = Vec3::new(0.5, 0.5, 0.0);
    flat.positions[2] = Vec3::new(1.0, 1.0, 0.0);
    flat.positions[1] = Vec3::new(0.5, 0.5, 0.0);
    assert!(matches!(
        flat.validate(),
        Err(MeshError::DegenerateFace { .. })
    ));

    // Two tetrahedra sharing vertex 0: a bow-tie.
    let mut bowtie = tetrahedron();
    bowtie.positions.extend([
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(0.0, 0.0, -1.0),
    ]);
    bowtie
        .triangles
        .extend([[0, 5, 4], [0, 4, 6], [0, 6, 5], [4, 5, 6]]);
    assert!(matches!(
        bowtie.validate(),
        Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 })
    ));

    // A fin: a third triangle on edge (0, 1) plus its closing faces.
    let mut fin = tetrahedron();
    fin.positions.push(Vec3::new(0.5, -1.0, 0.0));
    fin.triangles.push([0, 1, 4]);
    assert!(matches!(
        fin.validate(),
        Err(MeshError::NonManifoldEdge { count: 3, .. })
    ));

    let mut isolated = tetrahedron();
    isolated.positions.push(Vec3::ONE);
    assert!(matches!(
        isolated.validate(),
        Err(MeshError::IsolatedVertex { vertex: 4 })
    ));

    assert_eq!(IndexedMesh::default().validate(), Err(MeshError::Empty));
}

#[test]
fn normals_of_a_sphere_are_radial() {
    let sphere = IndexedMesh::icosphere(Vec3::new(1.0, 2.0, 3.0), 5.0, 3);
    for weighting in [
        NormalWeighting::Area,
        NormalWeighting::Angle,
        NormalWeighting::Max,
    ] {
        let normals = sphere.vertex_normals(weighting);
        for (p, n) in sphere.positions.iter().zip(&normals) {
            let radial = (*p - Vec3::new(1.0, 2.0, 3.0)).normalize();
            let tol = if weighting == NormalWeighting::Max {
                1e-5
            } else {
                2e-2
            };
            assert!(n.dot(radial) > 1.0 - tol, "{weighting:?}: {n} vs {radial}");
        }
    }
}

#[test]
fn quality_of_an_equilateral_triangle_mesh() {
    let tet = IndexedMesh::new(
        vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ],
        vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    );
    assert_eq!(tet.validate(), Ok(()));
    let q = tet.quality();
    assert!((q.min_angle - 60.0).abs() < 1e-3);
    assert!((q.max_aspect - 1.0).abs() < 1e-5);
    assert!((q.edge_mean - 8.0f32.sqrt()).abs() < 1e-5);
    assert_eq!(q.min_angle_histogram[5], 4);
}

#[test]
fn half_edge_round_trip_keeps_ids_and_attributes() {
    let mut m = IndexedMesh::torus(3.0, 1.0, 16, 8);
    m.ids = Some(
        (0..m.positions.len() as u64)
            .map(|i| 1000 + 3 * i)
            .collect(),
    );
    let back = Mesh::from_indexed(&m).unwrap().to_indexed();
    assert_eq!(back.positions, m.positions);
    assert_eq!(back.ids, m.ids);
    assert_eq!(back.triangles.len(), m.triangles.len());
    let mut sorted_in: Vec<[u32; 3]> = m.triangles.iter().map(|t| canonical(*t)).collect();
    let mut sorted_out: Vec<[u32; 3]> = back.triangles.iter().map(|t| canonical(*t)).collect();
    sorted_in.sort();
    sorted_out.sort();
    assert_eq!(sorted_in, sorted_out);
}

/// Rotates a triangle so its smallest index comes first (orientation kept).
fn canonical(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

//! Memory follows the surface's area, never the box's volume (issue 6, bar 3): a thin, tilted,
//! closed sheet between two small markers that span a box of 1000³ or 10 000³ cells. Every stored
//! array (crossings, swept lines and their runs, footprint cells, narrow-band corners) is counted:
//! the counts do not change when the box grows a thousandfold, and grow fourfold with the sheet's
//! area. Run with `--nocapture` to see the counts.

pub mod grid_support;

use glam::{Quat, Vec3};
use grid_support::grid_box;
use surftrack::compute::Backend;
use surftrack::grid::{
    GridFrame, LatticeMesh, edge_faces, footprint, rasterize, signed_distance, sweep,
};
use surftrack::mesh::IndexedMesh;

/// Half-width of the narrow band, in cells.
const BAND: f32 = 3.0;

/// What the grid stores for one mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Stored {
    crossings: usize,
    lines: usize,
    runs: usize,
    cells: usize,
    band: usize,
}

impl Stored {
    fn total(&self) -> usize {
        self.crossings + self.lines + self.runs + self.cells + self.band
    }
}

/// A closed sheet of `side × side × 1` cells through the origin, tilted so grid lines cross it
/// obliquely, between markers at `±reach` cells on the diagonal (the box they span has `2 reach`
/// cells a side).
fn sheet_in_box(frame: &GridFrame, side: i32, reach: f32) -> IndexedMesh {
    let half = side / 2;
    let mut sheet = grid_box(frame, [-half, -half, 0], [half, half, 1]);
    let tilt = Quat::from_rotation_x(0.3) * Quat::from_rotation_y(0.2);
    for p in &mut sheet.positions {
        *p = tilt * *p;
    }
    let marker = |at: f32| IndexedMesh::icosphere(Vec3::splat(at * frame.spacing()), 1.5, 1);
    let parts = [sheet, marker(-reach), marker(reach)];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for m in &parts {
        let first = positions.len() as u32;
        positions.extend_from_slice(&m.positions);
        triangles.extend(m.triangles.iter().map(|t| t.map(|v| v + first)));
    }
    IndexedMesh::new(positions, triangles)
}

fn stored(frame: GridFrame, mesh: &IndexedMesh) -> Stored {
    let backend = Backend::Cpu;
    let lattice = LatticeMesh::new(frame, mesh).unwrap();
    let crossings = rasterize(&backend, &lattice).unwrap();
    let windings = sweep(&backend, &crossings).unwrap();
    assert!(windings.unbalanced_lines().is_empty());
    let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
    let band = signed_distance(&backend, &lattice, &cells, &windings, BAND).unwrap();
    Stored {
        crossings: crossings.len(),
        lines: windings.index().len(),
        runs: windings.runs().len(),
        cells: cells.len(),
        band: band.len(),
    }
}

#[test]
fn thin_sheet_in_a_huge_box_stores_its_area() {
    let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
    let small = sheet_in_box(&frame, 48, 500.0);
    let large = sheet_in_box(&frame, 96, 500.0);
    let small_huge = stored(frame, &sheet_in_box(&frame, 48, 5000.0));
    let small_counts = stored(frame, &small);
    let large_counts = stored(frame, &large);
    for (what, mesh, counts) in [
        ("48² sheet, 1000³ box", &small, small_counts),
        ("48² sheet, 10000³ box", &small, small_huge),
        ("96² sheet, 1000³ box", &large, large_counts),
    ] {
        println!("{what}: {} triangles, {counts:?}", mesh.triangles.len());
    }

    // The box is irrelevant: a thousandfold volume stores exactly the same.
    assert_eq!(small_counts, small_huge);

    // Fourfold area, about fourfold storage in every array (the rim adds a perimeter term).
    for (what, s, l) in [
        ("crossings", small_counts.crossings, large_counts.crossings),
        ("lines", small_counts.lines, large_counts.lines),
        ("runs", small_counts.runs, large_counts.runs),
        ("cells", small_counts.cells, large_counts.cells),
        ("band", small_counts.band, large_counts.band),
    ] {
        let ratio = l as f64 / s as f64;
        assert!(
            (3.5..=4.2).contains(&ratio),
            "{what}: {s} → {l}, ratio {ratio}"
        );
    }

    // A few stored items per cell² of area (two faces of 96² cells), nowhere near the 10⁹ corners
    // of the box.
    let area = 2.0 * 96.0 * 96.0;
    let per_area = large_counts.total() as f64 / area;
    println!("{per_area:.1} stored items per cell² of surface");
    assert!(per_area < 40.0, "{per_area}");
    assert!(large_counts.band as f64 <= 2.0 * (2.0 * f64::from(BAND) + 2.0) * area / 2.0);
}

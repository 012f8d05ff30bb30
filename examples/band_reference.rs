//! The grid benchmark's narrow-band case (`benches/grid.rs`: three metaballs, about 100k
//! triangles, a 128³ box, a band of 3 cells) timed on the CPU and written out for a reference
//! implementation to time on the same queries, side by side (`benches/reference/libigl_band.py`).
//!
//! `cargo run --release --example band_reference -- DIR [RUNS]` writes, little-endian:
//! `vertices.f64` (x y z per vertex), `triangles.i32` (three indices per triangle) and
//! `band.f64` (x y z and our signed distance per band corner), then prints one line per run with
//! the time of `signed_distance`.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use surftrack::compute::Backend;
use surftrack::grid::{LatticeMesh, edge_faces, footprint, rasterize, signed_distance, sweep};

#[path = "../benches/support/metaballs.rs"]
mod metaballs;

fn write(path: &Path, values: impl Iterator<Item = [u8; 8]>) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for v in values {
        out.write_all(&v)?;
    }
    out.flush()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = args.next().ok_or("usage: band_reference DIR [RUNS]")?;
    let runs: usize = args.next().map_or(Ok(5), |r| r.parse())?;
    let (mesh, frame) = metaballs::metaballs();
    let lattice = LatticeMesh::new(frame, &mesh)?;
    let crossings = rasterize(&Backend::Cpu, &lattice)?;
    let windings = sweep(&Backend::Cpu, &crossings)?;
    let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
    let mut band = signed_distance(&Backend::Cpu, &lattice, &cells, &windings, 3.0)?;
    for _ in 0..runs {
        let start = Instant::now();
        band = signed_distance(&Backend::Cpu, &lattice, &cells, &windings, 3.0)?;
        println!(
            "surftrack signed_distance: {:.1} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
    }
    let dir = Path::new(&dir);
    std::fs::create_dir_all(dir)?;
    write(
        &dir.join("vertices.f64"),
        mesh.positions
            .iter()
            .flat_map(|p| p.to_array())
            .map(|x| f64::from(x).to_le_bytes()),
    )?;
    let mut indices = std::io::BufWriter::new(std::fs::File::create(dir.join("triangles.i32"))?);
    for t in &mesh.triangles {
        for &v in t {
            indices.write_all(&(v as i32).to_le_bytes())?;
        }
    }
    indices.flush()?;
    write(
        &dir.join("band.f64"),
        band.corners()
            .iter()
            .zip(band.values())
            .flat_map(|(c, v)| {
                let p = frame.corner_position(*c);
                [p.x, p.y, p.z, *v]
            })
            .map(|x| f64::from(x).to_le_bytes()),
    )?;
    Ok(())
}

//! Random adversarial cases for `constrain_topology` and the check of every guarantee on one case,
//! shared by the stress test and `examples/topology_stress.rs`.

use std::collections::{HashMap, HashSet};

use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::events::{EventKind, EventList, VertexValues, backward, forward};
use surftrack::grid::{GridFrame, ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::topology::{Field, Resampling, TopologyOptions, constrain_topology};

/// SplitMix64: small, seedable, reproducible.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next_u64() >> 40) as f32 / (1u64 << 24) as f32)
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
    pub fn chance(&mut self, p: f32) -> bool {
        self.range(0.0, 1.0) < p
    }
    pub fn vec(&mut self, r: f32) -> Vec3 {
        Vec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
}

/// Blended Gaussian blobs: `threshold − Σ exp(−|p − c|² / width²)`, in grid units around the origin.
#[derive(Debug, Clone)]
pub struct Blobs {
    pub centers: Vec<Vec3>,
    pub widths: Vec<f32>,
    pub threshold: f32,
}

impl Blobs {
    pub fn value(&self, p: Vec3) -> f32 {
        let sum: f32 = self
            .centers
            .iter()
            .zip(&self.widths)
            .map(|(c, w)| (-(p - *c).length_squared() / (w * w)).exp())
            .sum();
        self.threshold - sum
    }

    pub fn random(rng: &mut Rng, spacing: f32) -> Self {
        let n = 1 + rng.below(4) as usize;
        Self {
            centers: (0..n).map(|_| rng.vec(3.5 * spacing)).collect(),
            widths: (0..n).map(|_| rng.range(1.6, 3.2) * spacing).collect(),
            threshold: rng.range(0.35, 0.6),
        }
    }

    /// The same blobs moved and resized a little, one blob sometimes removed or added (merges,
    /// splits, droplets appearing and vanishing).
    pub fn perturbed(&self, rng: &mut Rng, spacing: f32, amount: f32) -> Self {
        let mut out = self.clone();
        for c in &mut out.centers {
            *c += rng.vec(amount * spacing);
        }
        for w in &mut out.widths {
            *w *= rng.range(0.85, 1.15);
        }
        if out.centers.len() > 1 && rng.chance(0.2) {
            let k = rng.below(out.centers.len() as u64) as usize;
            out.centers.remove(k);
            out.widths.remove(k);
        }
        if rng.chance(0.3) {
            out.centers.push(rng.vec(5.0 * spacing));
            out.widths.push(rng.range(0.9, 1.8) * spacing);
        }
        out
    }
}

/// What one case exercises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Θ sampled from a perturbed field: merges, splits, droplets.
    Target,
    /// Θ = Φ(T) for the perturbed field's marching-cubes surface T.
    TargetMesh,
    /// Θ = Φ(M) of a clean mesh.
    SelfClean,
    /// Θ = Φ(M) of a mesh deformed until it intersects itself.
    SelfIntersecting,
    /// Vertices snapped onto grid planes, grid lines and grid corners, Θ from a perturbed field.
    Snapped,
}

pub const KINDS: [Kind; 5] = [
    Kind::Target,
    Kind::TargetMesh,
    Kind::SelfClean,
    Kind::SelfIntersecting,
    Kind::Snapped,
];

pub struct Case {
    pub kind: Kind,
    pub mesh: IndexedMesh,
    pub theta: Field,
}

/// Marching cubes of `f` on a grid of spacing `h` with a random origin, covering ±9 units.
fn extract(f: &(dyn Fn(Vec3) -> f32 + Sync), rng: &mut Rng, h: f32) -> IndexedMesh {
    let n = (18.0 / h).ceil() as usize + 3;
    let origin = Vec3::splat(-9.0 - h) + rng.vec(0.5 * h);
    let grid = ScalarGrid::from_fn(origin, h, [n; 3], f).unwrap();
    marching_cubes(&grid, 0.0)
}

/// Smooth random displacement of amplitude `amplitude`.
fn deform(mesh: &mut IndexedMesh, rng: &mut Rng, amplitude: f32) {
    let waves: Vec<(Vec3, Vec3, f32)> = (0..3)
        .map(|_| (rng.vec(0.6), rng.vec(amplitude), rng.range(0.0, 6.3)))
        .collect();
    for p in &mut mesh.positions {
        let q = *p;
        for (k, a, phase) in &waves {
            *p += *a * (k.dot(q) + phase).sin();
        }
    }
}

/// Snaps a random share of coordinates onto grid planes (and so some vertices onto grid lines and
/// corners), keeping the mesh only if it stays non-degenerate.
fn snap(mesh: &IndexedMesh, rng: &mut Rng, frame: &GridFrame) -> Option<IndexedMesh> {
    let mut out = mesh.clone();
    let share = rng.range(0.1, 0.9);
    let h = frame.spacing();
    let o = frame.origin();
    for p in &mut out.positions {
        for a in 0..3 {
            if rng.chance(share) {
                p[a] = o[a] + h * ((p[a] - o[a]) / h).round();
            }
        }
    }
    out.validate().ok().map(|_| out)
}

/// The case of seed `seed` (deterministic).
pub fn case(seed: u64) -> Case {
    let mut rng = Rng::new(seed);
    let kind = KINDS[(seed % KINDS.len() as u64) as usize];
    loop {
        let spacing = 1.0;
        let origin = if kind == Kind::Snapped && rng.chance(0.5) {
            Vec3::ZERO
        } else {
            rng.vec(1.0)
        };
        let frame = GridFrame::new(origin, spacing).unwrap();
        let a = Blobs::random(&mut rng, spacing);
        let h = rng.range(0.6, 1.4) * spacing;
        let mut mesh = extract(&|p| a.value(p), &mut rng, h);
        if mesh.triangles.is_empty() && rng.chance(0.7) {
            continue;
        }
        let amount = rng.range(0.2, 1.5);
        let b = a.perturbed(&mut rng, spacing, amount);
        let lo = [-12; 3];
        let hi = [12; 3];
        let theta = match kind {
            Kind::Target => Field::from_fn(frame, lo, hi, |p| b.value(p)).unwrap(),
            Kind::TargetMesh => {
                let ht = rng.range(0.6, 1.4) * spacing;
                let t = extract(&|p| b.value(p), &mut rng, ht);
                Field::signed_distance(&Backend::Cpu, frame, &t).unwrap()
            }
            Kind::SelfClean => Field::signed_distance(&Backend::Cpu, frame, &mesh).unwrap(),
            Kind::SelfIntersecting => {
                let amplitude = rng.range(0.5, 3.0) * spacing;
                deform(&mut mesh, &mut rng, amplitude);
                if mesh.validate().is_err() {
                    continue;
                }
                Field::signed_distance(&Backend::Cpu, frame, &mesh).unwrap()
            }
            Kind::Snapped => {
                let Some(snapped) = snap(&mesh, &mut rng, &frame) else {
                    continue;
                };
                mesh = snapped;
                if rng.chance(0.5) {
                    Field::signed_distance(&Backend::Cpu, frame, &mesh).unwrap()
                } else {
                    Field::from_fn(frame, lo, hi, |p| b.value(p)).unwrap()
                }
            }
        };
        if !mesh.triangles.is_empty() && mesh.validate().is_err() {
            continue;
        }
        return Case { kind, mesh, theta };
    }
}

/// Sorted Euler characteristics of the components.
pub fn euler_list(mesh: &IndexedMesh) -> Vec<i64> {
    let mut e: Vec<i64> = mesh.topology().components.iter().map(|c| c.euler).collect();
    e.sort_unstable();
    e
}

/// Θ's isosurface extracted independently: dense samples of `theta` over a box holding both the
/// mesh and Θ's surface, then the grid's marching cubes.
pub fn reference(theta: &Field, mesh: &IndexedMesh) -> IndexedMesh {
    let frame = theta.frame();
    let mut lo = [-14i32; 3];
    let mut hi = [14i32; 3];
    for p in &mesh.positions {
        let g = (*p - frame.origin()) / frame.spacing();
        for a in 0..3 {
            lo[a] = lo[a].min(g[a].floor() as i32 - 3);
            hi[a] = hi[a].max(g[a].ceil() as i32 + 3);
        }
    }
    let dims: [usize; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1) as usize);
    let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                values.push(theta.value([i, j, k]));
            }
        }
    }
    let grid = ScalarGrid::new(frame.corner_position(lo), frame.spacing(), dims, values).unwrap();
    marching_cubes(&grid, 0.0)
}

/// Θ by trilinear interpolation at grid coordinates `g`, and its gradient in grid units.
fn trilinear(theta: &Field, g: [f64; 3]) -> (f64, [f64; 3]) {
    let cell = g.map(|x| x.floor() as i32);
    let local: [f64; 3] = std::array::from_fn(|a| g[a] - f64::from(cell[a]));
    let mut value = 0.0;
    let mut gradient = [0.0f64; 3];
    for c in 0..8usize {
        let o = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
        let corner: [i32; 3] = std::array::from_fn(|a| cell[a] + o[a] as i32);
        let v = f64::from(theta.value(corner));
        let w: [f64; 3] =
            std::array::from_fn(|a| if o[a] == 1 { local[a] } else { 1.0 - local[a] });
        let s: [f64; 3] = std::array::from_fn(|a| if o[a] == 1 { 1.0 } else { -1.0 });
        value += v * w[0] * w[1] * w[2];
        gradient[0] += v * s[0] * w[1] * w[2];
        gradient[1] += v * w[0] * s[1] * w[2];
        gradient[2] += v * w[0] * w[1] * s[2];
    }
    (value, gradient)
}

/// Distance in cells from `p` to Θ's zero set (the zero set of its trilinear interpolant). Where
/// the first-order estimate (value over gradient length) says the point is within 0.05 cell, that
/// estimate; otherwise the distance to the nearest sign change on a lattice of 16 steps per cell
/// over the 3 × 3 × 3 cells around the point (a point whose zero set lies farther counts as 1.5
/// cells away).
pub fn level_distance(theta: &Field, p: Vec3) -> f64 {
    let frame = theta.frame();
    let g = ((p.as_dvec3() - frame.origin().as_dvec3()) / f64::from(frame.spacing())).to_array();
    let (value, gradient) = trilinear(theta, g);
    let norm = gradient.iter().map(|x| x * x).sum::<f64>().sqrt();
    let estimate = if norm > 0.0 {
        value.abs() / norm
    } else {
        f64::INFINITY
    };
    if estimate <= 0.05 {
        return estimate;
    }
    const STEPS: i32 = 16;
    let lo: [i32; 3] = std::array::from_fn(|a| (g[a].floor() as i32 - 1) * STEPS);
    let at = |i: [i32; 3]| i.map(|k| f64::from(k) / f64::from(STEPS));
    let mut best = 1.5f64;
    for x in 0..=3 * STEPS {
        for y in 0..=3 * STEPS {
            for z in 0..=3 * STEPS {
                let i = [lo[0] + x, lo[1] + y, lo[2] + z];
                let a = trilinear(theta, at(i)).0;
                for axis in 0..3 {
                    let mut j = i;
                    j[axis] += 1;
                    if j[axis] > lo[axis] + 3 * STEPS {
                        continue;
                    }
                    let b = trilinear(theta, at(j)).0;
                    if (a < 0.0) == (b < 0.0) {
                        continue;
                    }
                    let t = (a / (a - b)).clamp(0.0, 1.0);
                    let (pi, pj) = (at(i), at(j));
                    let d = (0..3)
                        .map(|k| (pi[k] + t * (pj[k] - pi[k]) - g[k]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    best = best.min(d);
                }
            }
        }
    }
    best
}

/// What one checked case showed.
#[derive(Debug, Clone, Copy, Default)]
pub struct Outcome {
    pub changed: bool,
    pub whole: bool,
    pub attempt: usize,
    /// Largest distance of a new fill vertex from Θ's zero set, in cells.
    pub fill_error: f64,
    pub replaced: f64,
}

/// Runs `constrain_topology` on the case and checks every guarantee; the error names what broke.
pub fn check(case: &Case) -> Result<Outcome, String> {
    let input = &case.mesh;
    let mut mesh = if input.triangles.is_empty() {
        return Ok(Outcome::default());
    } else {
        Mesh::from_indexed(input).map_err(|e| format!("input: {e}"))?
    };
    mesh.add_attribute("one", 1, 1.0);
    let next_id = mesh.next_id();
    mesh.record_mutations();
    let options = TopologyOptions::default();
    let reach = options.continue_within * case.theta.frame().spacing();
    let report = constrain_topology(&mut mesh, &case.theta, &options)
        .map_err(|e| format!("constrain_topology failed: {e}"))?;
    let events = EventList::drain(&mut mesh);
    let out = mesh.to_indexed();
    if !out.triangles.is_empty() {
        out.validate().map_err(|e| format!("output invalid: {e}"))?;
        mesh.validate()
            .map_err(|e| format!("half-edge mesh invalid: {e}"))?;
    }
    let want = euler_list(&reference(&case.theta, input));
    let got = euler_list(&out);
    if got != want {
        return Err(format!("topology {got:?}, Θ's isosurface has {want:?}"));
    }
    if report.euler != want {
        return Err(format!(
            "report says {:?}, Θ's isosurface has {want:?}",
            report.euler
        ));
    }
    let ids = out.ids.as_ref().ok_or("no ids")?;
    let input_ids: Vec<u64> = input
        .ids
        .clone()
        .unwrap_or_else(|| (0..input.positions.len() as u64).collect());
    let index: std::collections::HashMap<u64, usize> = input_ids
        .iter()
        .enumerate()
        .map(|(i, &id)| (id, i))
        .collect();
    for (i, &id) in ids.iter().enumerate() {
        if id < next_id {
            let Some(&v) = index.get(&id) else {
                return Err(format!("kept id {id} is not an input id"));
            };
            // A vertex keeps its place, unless a patch vertex that stood on it continues it.
            let moved = out.positions[i].distance(input.positions[v]);
            if moved > reach {
                return Err(format!("kept vertex {id} moved by {moved} > {reach}"));
            }
        } else if id >= mesh.next_id() {
            return Err(format!("id {id} not below the mesh's next id"));
        }
    }
    let mut sorted = ids.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() != ids.len() {
        return Err("duplicate ids".into());
    }
    match report.resampling {
        Resampling::None => {
            if out.positions != input.positions
                || out.triangles != input.triangles
                || out.ids.as_deref() != Some(&input_ids[..])
            {
                return Err("unchanged, yet the mesh differs from the input".into());
            }
        }
        Resampling::Local { .. } => {
            untouched_outside(input, &input_ids, &out, &case.theta, &report.region)?
        }
        Resampling::Whole => {}
    }
    events.check().map_err(|e| format!("events: {e}"))?;
    // A constant carried forward and backward stays constant wherever it arrives.
    let ones = vec![1.0f32; input_ids.len()];
    let mut values = VertexValues::from_parts(1, &input_ids, &ones).map_err(|e| e.to_string())?;
    forward(&events, &mut values).map_err(|e| format!("forward: {e}"))?;
    for &id in ids {
        if let Some(v) = values.get(id)
            && (v[0] - 1.0).abs() > 1e-4
        {
            return Err(format!("forward constant became {} at {id}", v[0]));
        }
    }
    let out_ones = vec![1.0f32; ids.len()];
    let mut values = VertexValues::from_parts(1, ids, &out_ones).map_err(|e| e.to_string())?;
    backward(&events, &mut values).map_err(|e| format!("backward: {e}"))?;
    for &id in &input_ids {
        if let Some(v) = values.get(id)
            && (v[0] - 1.0).abs() > 1e-4
        {
            return Err(format!("backward constant became {} at {id}", v[0]));
        }
    }
    let attribute = &out.attributes[0];
    if attribute
        .values
        .iter()
        .any(|&v| (v - 1.0).abs() > 1e-4 && v != 0.0)
    {
        return Err("carried attribute is not constant".into());
    }
    let created: Vec<u64> = events
        .events
        .iter()
        .filter(|e| e.kind == EventKind::PatchCreated)
        .flat_map(|e| {
            e.outputs
                .iter()
                .copied()
                .filter(|id| !e.inputs.contains(id))
        })
        .collect();
    let mut created = created;
    created.sort_unstable();
    let mut fill_error = 0.0f64;
    for (i, id) in ids.iter().enumerate() {
        if created.binary_search(id).is_ok() {
            fill_error = fill_error.max(level_distance(&case.theta, out.positions[i]));
        }
    }
    if fill_error > 0.5 {
        return Err(format!(
            "a fill vertex lies {fill_error:.4} cells from Θ's zero set"
        ));
    }
    Ok(Outcome {
        changed: report.changed(),
        whole: report.resampling == Resampling::Whole,
        attempt: match report.resampling {
            Resampling::Local { attempt } => attempt,
            _ => 0,
        },
        fill_error,
        replaced: report.replaced_fraction(),
    })
}

/// Cells whose closure may hold a point within `slack` cells of the box `lo..=hi` (grid units).
fn cells_near(lo: [f64; 3], hi: [f64; 3], slack: f64) -> impl Iterator<Item = [i32; 3]> {
    let a: [i32; 3] = std::array::from_fn(|k| (lo[k] - slack).floor() as i32);
    let b: [i32; 3] = std::array::from_fn(|k| (hi[k] + slack).floor() as i32);
    (a[2]..=b[2])
        .flat_map(move |z| (a[1]..=b[1]).flat_map(move |y| (a[0]..=b[0]).map(move |x| [x, y, z])))
}

/// Outside the complex region the mesh is untouched: every input vertex in no region cell keeps its
/// id and position, and every input triangle that neither meets a region cell nor shares a side
/// with one that does is in the output with the same ids. Cells are read with a thousandth of a
/// cell of slack, so the test's own rounding cannot excuse a change.
fn untouched_outside(
    input: &IndexedMesh,
    input_ids: &[u64],
    out: &IndexedMesh,
    theta: &Field,
    region: &[[i32; 3]],
) -> Result<(), String> {
    const SLACK: f64 = 1e-3;
    if region.is_empty() {
        return Err("local re-sampling with an empty region".into());
    }
    let region: HashSet<[i32; 3]> = region.iter().copied().collect();
    let frame = theta.frame();
    let grid = |p: Vec3| -> [f64; 3] {
        let g = (p.as_dvec3() - frame.origin().as_dvec3()) / f64::from(frame.spacing());
        g.to_array()
    };
    let out_ids = out.ids.as_ref().ok_or("no ids")?;
    let kept: HashMap<u64, Vec3> = out_ids
        .iter()
        .copied()
        .zip(out.positions.iter().copied())
        .collect();
    for (v, p) in input.positions.iter().enumerate() {
        let g = grid(*p);
        if cells_near(g, g, SLACK).any(|c| region.contains(&c)) {
            continue;
        }
        if kept.get(&input_ids[v]) != Some(p) {
            return Err(format!(
                "vertex {} outside the region was removed or moved",
                input_ids[v]
            ));
        }
    }
    let meets: Vec<bool> = input
        .triangles
        .iter()
        .map(|t| {
            let g = t.map(|v| grid(input.positions[v as usize]));
            let lo = std::array::from_fn(|k| g.iter().map(|x| x[k]).fold(f64::INFINITY, f64::min));
            let hi =
                std::array::from_fn(|k| g.iter().map(|x| x[k]).fold(f64::NEG_INFINITY, f64::max));
            cells_near(lo, hi, SLACK).any(|c| region.contains(&c))
        })
        .collect();
    let mut sides: HashMap<[u32; 2], Vec<usize>> = HashMap::new();
    for (t, tri) in input.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            sides.entry([a.min(b), a.max(b)]).or_default().push(t);
        }
    }
    let rotated = |t: [u64; 3]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
    };
    let output: HashSet<[u64; 3]> = out
        .triangles
        .iter()
        .map(|t| rotated(t.map(|v| out_ids[v as usize])))
        .collect();
    for (t, tri) in input.triangles.iter().enumerate() {
        let near = (0..3).any(|k| {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            sides[&[a.min(b), a.max(b)]].iter().any(|&n| meets[n])
        });
        if !near && !output.contains(&rotated(tri.map(|v| input_ids[v as usize]))) {
            return Err(format!("triangle {t} away from the region was changed"));
        }
    }
    Ok(())
}

//! Closest-point transfer across a re-sampled patch (paper §4.4, sharpened).
//!
//! The paper gives a new patch vertex the average of its neighbours marched in from the patch's
//! boundary, and a deleted vertex likewise going backward. On a fluid, whose surface is
//! re-sampled somewhere every frame, those averages blur a texture a little more each time. Here
//! a vertex a patch creates takes its data from the surface the patch replaces at its closest
//! point, and a vertex the patch deletes takes, going backward, the data of the new surface at its
//! own closest point: by default the value of the closest triangle's corner nearest that point,
//! whole, or, with [`Carry::Blend`], the barycentric combination of its corners, which is exact
//! for data linear over the surface (UVs) but blurs a texture across one triangle each time the
//! same place is re-sampled (see [`Carry`]).

use std::borrow::Cow;
use std::sync::OnceLock;

use glam::{IVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashSet;
use serde::{Deserialize, Serialize};

use super::nearest::Survivors;

use crate::compute::Backend;
use crate::grid::CellBox;
use crate::mesh::IndexedMesh;
use crate::project::{Bvh, ProjectError, closest_points};

/// Triangles to take data from at closest points. Their tree is built by the first query, so a
/// topology step that re-samples nothing builds none, and its attempts share one.
pub(crate) struct Transfer<'a> {
    positions: &'a [Vec3],
    triangles: Cow<'a, [[u32; 3]]>,
    bvh: OnceLock<Option<Bvh>>,
}

impl<'a> Transfer<'a> {
    /// Over `triangles`, whose corners index `positions`; with no triangles every query answers
    /// nothing.
    pub fn new(positions: &'a [Vec3], triangles: impl Into<Cow<'a, [[u32; 3]]>>) -> Self {
        Self {
            positions,
            triangles: triangles.into(),
            bvh: OnceLock::new(),
        }
    }

    /// The triangles' tree, built the first time; none without triangles.
    fn tree(&self) -> Result<Option<&Bvh>, ProjectError> {
        if let Some(tree) = self.bvh.get() {
            return Ok(tree.as_ref());
        }
        let built = tree_of(self.positions, &self.triangles)?;
        Ok(self.bvh.get_or_init(|| built).as_ref())
    }

    /// Runs `meanwhile` on this thread while the tree, if not built yet, is built on the thread
    /// pool: a caller about to query overlaps the build with the work before its first query. A
    /// build that fails is left to that query, which then reports it.
    pub fn prepare_while<R>(&self, meanwhile: impl FnOnce() -> R) -> R {
        if self.bvh.get().is_some() {
            return meanwhile();
        }
        let (positions, triangles) = (self.positions, &*self.triangles);
        let mut built = None;
        let result = rayon::in_place_scope(|scope| {
            scope.spawn(|_| built = Some(tree_of(positions, triangles)));
            meanwhile()
        });
        if let Some(Ok(tree)) = built {
            self.bvh.get_or_init(|| tree);
        }
        result
    }

    /// For each of `points`, the corners of the nearest triangle with their barycentric weights at
    /// the closest point (corners of weight 0 left out; the weights sum to 1), or nothing when
    /// there are no triangles.
    pub fn terms(&self, points: &[Vec3]) -> Result<Vec<Vec<(u32, f32)>>, ProjectError> {
        let Some(bvh) = self.tree()? else {
            return Ok(vec![Vec::new(); points.len()]);
        };
        let hits = closest_points(&Backend::Cpu, bvh, points, f32::INFINITY)?;
        Ok(hits
            .iter()
            .map(|hit| match hit.hit_triangle() {
                Some(t) => self.triangles[t as usize]
                    .into_iter()
                    .zip(hit.barycentric.to_array())
                    .filter(|&(_, w)| w > 0.0)
                    .collect(),
                None => Vec::new(),
            })
            .collect())
    }

    /// A transfer over the triangles of `triangles` that may hold the closest point of one of
    /// `points` ([`triangles_around`]), which queries of those points answer as the whole
    /// surface would. The tree over a re-sampled region's surroundings costs a fraction of one
    /// over the whole surface.
    pub fn around(
        positions: &'a [Vec3],
        triangles: &[[u32; 3]],
        points: &[Vec3],
        cell: f32,
    ) -> Self {
        let kept = triangles_around((positions, triangles), points, cell, f32::INFINITY);
        Self::new(positions, kept)
    }

    /// For each of `points`, what a vertex there takes from the triangles under `carry`: the
    /// corners of the nearest triangle with their weights at the closest point, or the one corner
    /// of largest weight (see [`Carry`]); nothing when there are no triangles.
    pub fn read(
        &self,
        points: &[Vec3],
        carry: Carry,
    ) -> Result<Vec<Vec<(u32, f32)>>, ProjectError> {
        Ok(self
            .terms(points)?
            .into_iter()
            .map(|terms| carry.terms(terms))
            .collect())
    }
}

/// How a vertex that re-sampling creates (or, going backward, deletes) takes its data from the
/// surface at its closest point. Both read the triangle holding the closest point, so a vertex
/// just off a sheet thinner than an edge reads its own side, where the vertex nearest in space
/// may lie on the other.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Carry {
    /// The value of the triangle's corner nearest the closest point (the largest barycentric
    /// weight, the lowest index among equals), whole. A fluid's splash is re-sampled frame after
    /// frame; a value taken whole each time stays crisp (a carried checker on the SPH dam break
    /// is 83.9% crisp at the last frame, 72.8% blended), at the price of moving by up to half an
    /// edge where it is re-sampled.
    #[default]
    Corner,
    /// The corners' barycentric blend at the closest point: exact for data linear over the
    /// surface (UVs, rest positions, smooth fields), a blur for data that changes within a
    /// triangle, which grows each time the same place is re-sampled.
    Blend,
}

impl Carry {
    /// What a vertex takes from the closest point's barycentric `terms`.
    pub fn terms(self, terms: Vec<(u32, f32)>) -> Vec<(u32, f32)> {
        match self {
            Carry::Blend => terms,
            Carry::Corner => terms
                .into_iter()
                .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
                .map(|(v, _)| vec![(v, 1.0)])
                .unwrap_or_default(),
        }
    }
}

/// The triangles of `triangles` (over `positions`) that may hold the closest point, within
/// `reach`, of one of `points`: a point's closest point lies no farther than its nearest corner,
/// at distance `r`, so the triangle holding it has a bounding box meeting the cube of half-side
/// `min(r, reach)` around the point (a triangle beyond `reach` is no answer either). Boxes and
/// cubes are compared by the cells of spacing `cell` they cover. Where a cube spans more than
/// [`AROUND_CELLS`] cells, every triangle is kept.
pub(crate) fn triangles_around(
    (positions, triangles): (&[Vec3], &[[u32; 3]]),
    points: &[Vec3],
    cell: f32,
    reach: f32,
) -> Vec<[u32; 3]> {
    // The corners in increasing order, marked rather than sorted: a linear pass.
    let mut used = vec![false; positions.len()];
    for &v in triangles.iter().flatten() {
        used[v as usize] = true;
    }
    let corners = (0..positions.len() as u32).filter(|&v| used[v as usize]);
    let nearest = Survivors::new(corners.map(|v| (v, positions[v as usize])), cell);
    let half: Vec<Option<f32>> = nearest
        .nearest_each(points.par_iter().copied())
        .into_iter()
        .zip(points)
        .map(|(v, p)| v.map(|v| positions[v as usize].distance(*p).min(reach)))
        .collect();
    let key = |p: Vec3| (p / cell).floor().as_ivec3();
    let mut cubes: Vec<(IVec3, IVec3)> = Vec::with_capacity(points.len());
    for (p, r) in points.iter().zip(&half) {
        let Some(r) = *r else { continue };
        let (low, high) = (key(*p - Vec3::splat(r)), key(*p + Vec3::splat(r)));
        if (high - low).max_element() > AROUND_CELLS {
            return triangles.to_vec();
        }
        cubes.push((low, high));
    }
    let near = NearCells::new(&cubes);
    triangles
        .par_iter()
        .filter(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            near.meets(key(a.min(b).min(c)), key(a.max(b).max(c)))
        })
        .copied()
        .collect()
}

/// The cells of some cubes, for asking whether a box of cells meets any of them: marked in an
/// array over the cubes' bounding box where that box is small enough to list (most are: the
/// points of one re-sampling lie in one part of the mesh), else in a hash set. Every triangle of
/// the surface asks, and most lie outside that box.
enum NearCells {
    Listed { cells: CellBox, marked: Vec<bool> },
    Hashed(FxHashSet<IVec3>),
}

/// Bounding boxes of at most this many cells are listed.
const LISTED_CELLS: usize = 1 << 22;

impl NearCells {
    fn new(cubes: &[(IVec3, IVec3)]) -> Self {
        let (low, high) = cubes.iter().fold((IVec3::MAX, IVec3::MIN), |(l, h), c| {
            (l.min(c.0), h.max(c.1))
        });
        let every = || {
            cubes.iter().flat_map(|&(l, h)| {
                (l.z..=h.z).flat_map(move |z| {
                    (l.y..=h.y).flat_map(move |y| (l.x..=h.x).map(move |x| IVec3::new(x, y, z)))
                })
            })
        };
        match CellBox::spanning(low, high, LISTED_CELLS) {
            Some(cells) => {
                let mut marked = vec![false; cells.volume()];
                for i in every().filter_map(|c| cells.index(c)) {
                    marked[i] = true;
                }
                NearCells::Listed { cells, marked }
            }
            None => NearCells::Hashed(every().collect()),
        }
    }

    /// Whether the box of cells from `low` to `high` holds a marked cell.
    fn meets(&self, low: IVec3, high: IVec3) -> bool {
        match self {
            NearCells::Listed { cells, marked } => {
                let (low, high) = (low.max(cells.low()), high.min(cells.high()));
                (low.z..=high.z).any(|z| {
                    (low.y..=high.y).any(|y| {
                        (low.x..=high.x)
                            .any(|x| cells.index(IVec3::new(x, y, z)).is_some_and(|i| marked[i]))
                    })
                })
            }
            NearCells::Hashed(set) => (low.x..=high.x).any(|x| {
                (low.y..=high.y)
                    .any(|y| (low.z..=high.z).any(|z| set.contains(&IVec3::new(x, y, z))))
            }),
        }
    }
}

/// How many cells across the cube around a point [`triangles_around`] keeps triangles in may
/// span before it keeps them all.
const AROUND_CELLS: i32 = 16;

/// The tree of `triangles` over `positions`; none without triangles.
fn tree_of(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<Option<Bvh>, ProjectError> {
    if triangles.is_empty() {
        return Ok(None);
    }
    Ok(Some(Bvh::build_unsigned(&IndexedMesh::new(
        positions.to_vec(),
        triangles.to_vec(),
    ))?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cubes spread too wide to list are hashed, and a box of cells meets them as it meets the
    /// listed ones.
    #[test]
    fn listed_and_hashed_cells_agree() {
        let near: Vec<(IVec3, IVec3)> = (0..40)
            .map(|k| {
                let low = IVec3::new(k % 7 * 3, k % 5 * 2 - 4, k / 3);
                (low, low + IVec3::new(k % 3, 1, k % 2))
            })
            .collect();
        let mut wide = near.clone();
        wide.push((IVec3::splat(100_000), IVec3::splat(100_001)));
        let (listed, hashed) = (NearCells::new(&near), NearCells::new(&wide));
        assert!(matches!(listed, NearCells::Listed { .. }));
        assert!(matches!(hashed, NearCells::Hashed(_)));
        let mut met = 0;
        for x in -3..24 {
            for y in -7..8 {
                for z in -2..16 {
                    let low = IVec3::new(x, y, z);
                    let high = low + IVec3::new(x.rem_euclid(2), 0, z.rem_euclid(3));
                    let meets = listed.meets(low, high);
                    assert_eq!(meets, hashed.meets(low, high), "box {low} {high}");
                    met += usize::from(meets);
                }
            }
        }
        assert!(met > 100 && met < 27 * 15 * 18);
        assert!(hashed.meets(IVec3::splat(100_001), IVec3::splat(100_003)));
        assert!(!listed.meets(IVec3::splat(100_001), IVec3::splat(100_003)));
    }

    /// Around a few points, on and off a bumpy sphere and beside each other, the triangles kept
    /// answer as the whole surface does, and are fewer; a point far from every corner keeps them
    /// all.
    #[test]
    fn the_triangles_around_points_answer_as_the_whole_surface() {
        let mut sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
        for p in &mut sphere.positions {
            *p *= 1.0 + 0.05 * (7.0 * p.x).sin() * (5.0 * p.y).cos();
        }
        let points: Vec<Vec3> = (0..40)
            .map(|i| {
                let a = i as f32 * 0.37;
                Vec3::new(a.cos(), a.sin() * 0.3, a.sin()).normalize() * (0.9 + 0.005 * i as f32)
            })
            .collect();
        let whole = Transfer::new(&sphere.positions, &sphere.triangles[..]);
        let around = Transfer::around(&sphere.positions, &sphere.triangles, &points, 0.1);
        assert!(around.triangles.len() < sphere.triangles.len() / 4);
        let distance = |t: &Transfer, p: Vec3| {
            let hit = &closest_points(
                &Backend::Cpu,
                t.tree().unwrap().unwrap(),
                &[p],
                f32::INFINITY,
            )
            .unwrap()[0];
            hit.distance.abs()
        };
        for &p in &points {
            assert_eq!(distance(&around, p), distance(&whole, p), "{p}");
        }
        let far = [Vec3::new(5.0, 0.0, 0.0)];
        let all = Transfer::around(&sphere.positions, &sphere.triangles, &far, 0.1);
        assert_eq!(all.triangles.len(), sphere.triangles.len());
    }

    /// A slab 0.05 thick: its top one square of two triangles with corners 1 apart, its bottom
    /// split into a fine grid. A point just above the top's middle lies nearest, in space, to a
    /// bottom vertex; it reads the top: its nearest corner whole, or the corners blended.
    #[test]
    fn a_point_off_a_thin_sheet_reads_its_own_side() {
        let mut positions = vec![
            Vec3::new(0.0, 0.0, 0.05),
            Vec3::new(1.0, 0.0, 0.05),
            Vec3::new(1.0, 1.0, 0.05),
            Vec3::new(0.0, 1.0, 0.05),
        ];
        let mut triangles = vec![[0, 1, 2], [0, 2, 3]];
        let n = 10;
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vec3::new(i as f32, j as f32, 0.0) / n as f32);
            }
        }
        let at = |i: u32, j: u32| 4 + j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
                triangles.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
            }
        }
        let transfer = Transfer::new(&positions, triangles);
        let p = Vec3::new(0.45, 0.35, 0.06);
        let nearest_in_space = (0..positions.len())
            .min_by(|&a, &b| {
                p.distance(positions[a])
                    .total_cmp(&p.distance(positions[b]))
            })
            .unwrap();
        assert!(
            nearest_in_space >= 4,
            "the nearest vertex lies on the bottom"
        );
        assert_eq!(
            transfer.read(&[p], Carry::Corner).unwrap(),
            vec![vec![(0, 1.0)]]
        );
        let terms = &transfer.read(&[p], Carry::Blend).unwrap()[0];
        assert!(terms.iter().all(|&(v, _)| v < 4), "{terms:?}");
        let sum: f32 = terms.iter().map(|t| t.1).sum();
        assert!((sum - 1.0).abs() < 1e-6);
    }
}

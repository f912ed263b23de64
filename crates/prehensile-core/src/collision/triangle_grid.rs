//! Exact queries against a closed triangle mesh, accelerated by a uniform grid of triangle buckets.
//!
//! Signs come from angle-weighted pseudo-normals (Bærentzen & Aanæs 2005), which are exact for a
//! closed, manifold, consistently wound mesh — the only kind an [`crate::ObjectModel`] accepts.

use std::collections::HashMap;

use crate::geometry::{
    closest_point_on_triangle, distance_squared_segment_triangle, TriangleFeature,
};
use crate::math::{Point3, Vec3};
use crate::mesh::TriangleMesh;

/// Uniform grid of triangle buckets with the pseudo-normals needed for signed distances.
#[derive(Debug, Clone)]
pub struct TriangleGrid {
    corners: Vec<[Point3; 3]>,
    face_normals: Vec<Vec3>,
    edge_normals: Vec<[Vec3; 3]>,
    vertex_normals: Vec<[Vec3; 3]>,
    origin: Point3,
    cell: f64,
    dims: [usize; 3],
    cell_start: Vec<u32>,
    cell_items: Vec<u32>,
}

impl TriangleGrid {
    /// Builds the grid for a mesh that has passed [`TriangleMesh::report`] without defects.
    pub fn new(mesh: &TriangleMesh) -> Self {
        let n = mesh.triangles.len();
        let corners: Vec<[Point3; 3]> = (0..n).map(|t| mesh.corners(t)).collect();
        let face_normals: Vec<Vec3> = corners
            .iter()
            .map(|[a, b, c]| (b - a).cross(&(c - a)).normalize())
            .collect();
        // Angle-weighted vertex pseudo-normals.
        let mut vertex_acc = vec![Vec3::zeros(); mesh.vertices.len()];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = &corners[t];
            for k in 0..3 {
                let e1 = (p[(k + 1) % 3] - p[k]).normalize();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize();
                let angle = e1.dot(&e2).clamp(-1.0, 1.0).acos();
                vertex_acc[tri[k] as usize] += face_normals[t] * angle;
            }
        }
        let vertex_normals = mesh
            .triangles
            .iter()
            .map(|tri| tri.map(|i| vertex_acc[i as usize].normalize()))
            .collect();
        // Edge pseudo-normals: sum of the two adjacent face normals.
        let mut edge_faces: HashMap<(u32, u32), Vec3> = HashMap::with_capacity(n * 3 / 2);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                *edge_faces
                    .entry((u.min(v), u.max(v)))
                    .or_insert_with(Vec3::zeros) += face_normals[t];
            }
        }
        let edge_normals = mesh
            .triangles
            .iter()
            .map(|tri| {
                std::array::from_fn(|k| {
                    let (u, v) = (tri[k], tri[(k + 1) % 3]);
                    edge_faces[&(u.min(v), u.max(v))].normalize()
                })
            })
            .collect();

        let (lo, hi) = mesh.bounds();
        let extent = hi - lo;
        // About two cells per triangle, at most 128 per axis.
        let volume = extent.x.max(1e-9) * extent.y.max(1e-9) * extent.z.max(1e-9);
        let target_cells = (2 * n).clamp(1, 2_000_000) as f64;
        let mut cell = (volume / target_cells).cbrt();
        cell = cell.max(extent.max() / 128.0).max(1e-9);
        let dims = [0, 1, 2].map(|i| ((extent[i] / cell).ceil() as usize).max(1));
        let mut grid = Self {
            corners,
            face_normals,
            edge_normals,
            vertex_normals,
            origin: lo,
            cell,
            dims,
            cell_start: Vec::new(),
            cell_items: Vec::new(),
        };
        grid.fill_buckets();
        grid
    }

    fn fill_buckets(&mut self) {
        let cells = self.dims[0] * self.dims[1] * self.dims[2];
        let mut counts = vec![0u32; cells + 1];
        let ranges: Vec<([usize; 3], [usize; 3])> = self
            .corners
            .iter()
            .map(|[a, b, c]| {
                let lo = a.inf(b).inf(c);
                let hi = a.sup(b).sup(c);
                (self.cell_of(&lo), self.cell_of(&hi))
            })
            .collect();
        for (lo, hi) in &ranges {
            for_each_cell(*lo, *hi, |c| counts[self.index(c) + 1] += 1);
        }
        for i in 0..cells {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; counts[cells] as usize];
        for (t, (lo, hi)) in ranges.iter().enumerate() {
            for_each_cell(*lo, *hi, |c| {
                let slot = &mut fill[self.index(c)];
                items[*slot as usize] = t as u32;
                *slot += 1;
            });
        }
        self.cell_start = counts;
        self.cell_items = items;
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// The cell containing `p`, clamped to the grid.
    fn cell_of(&self, p: &Point3) -> [usize; 3] {
        std::array::from_fn(|i| {
            let f = ((p[i] - self.origin[i]) / self.cell).floor();
            (f.max(0.0) as usize).min(self.dims[i] - 1)
        })
    }

    fn bucket(&self, c: [usize; 3]) -> &[u32] {
        let i = self.index(c);
        &self.cell_items[self.cell_start[i] as usize..self.cell_start[i + 1] as usize]
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.corners.len()
    }

    /// Exact signed distance from `p` to the surface: positive outside, negative inside.
    pub fn signed_distance(&self, p: &Point3) -> f64 {
        self.signed_distance_within(p, f64::INFINITY)
            .expect("a mesh has triangles, so one is within an infinite distance")
    }

    /// Exact signed distance from `p` if the surface is within `max` of it, else `None`.
    pub fn signed_distance_within(&self, p: &Point3, max: f64) -> Option<f64> {
        let c0 = self.cell_of(p);
        let mut best = f64::INFINITY;
        let mut best_t = usize::MAX;
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for ring in 0..=max_ring {
            // Triangles not yet seen lie in cells at least `ring` cells away, so at least
            // (ring - 1) cell widths from p, whether p is inside the grid or clamped onto it.
            let bound = (ring as f64 - 1.0).max(0.0) * self.cell;
            if best.sqrt() <= bound || bound > max {
                break;
            }
            for_each_ring_cell(c0, ring, self.dims, |c| {
                for &t in self.bucket(c) {
                    let [a, b, cc] = &self.corners[t as usize];
                    let (q, _) = closest_point_on_triangle(p, a, b, cc);
                    let d = (q - p).norm_squared();
                    if d < best {
                        best = d;
                        best_t = t as usize;
                    }
                }
            });
        }
        if best_t == usize::MAX || best.sqrt() > max {
            return None;
        }
        Some(self.signed_distance_to_triangle(p, best_t))
    }

    /// Signed distance from `p` to triangle `t`, signed by the pseudo-normal of the feature
    /// nearest to `p`; equals the mesh's signed distance when `t` is a nearest triangle.
    pub(crate) fn signed_distance_to_triangle(&self, p: &Point3, t: usize) -> f64 {
        let [a, b, c] = &self.corners[t];
        let (q, feature) = closest_point_on_triangle(p, a, b, c);
        let normal = match feature {
            TriangleFeature::Face => self.face_normals[t],
            TriangleFeature::Edge(k) => self.edge_normals[t][k as usize],
            TriangleFeature::Vertex(k) => self.vertex_normals[t][k as usize],
        };
        let d = (q - p).norm();
        if (p - q).dot(&normal) < 0.0 {
            -d
        } else {
            d
        }
    }

    /// Corners of triangle `t`.
    pub(crate) fn triangle(&self, t: usize) -> &[Point3; 3] {
        &self.corners[t]
    }

    /// True when some triangle lies within `radius` of segment `a–b` (the capsule touches the
    /// surface). Does not detect a capsule wholly inside; see [`TriangleGrid::capsule_touches`].
    pub fn segment_within(&self, a: &Point3, b: &Point3, radius: f64) -> bool {
        let r = Vec3::repeat(radius);
        let lo = self.cell_of(&(a.inf(b) - r));
        let hi = self.cell_of(&(a.sup(b) + r));
        let r2 = radius * radius;
        let mut hit = false;
        for_each_cell_until(lo, hi, |c| {
            hit = self.bucket(c).iter().any(|&t| {
                let [p, q, s] = &self.corners[t as usize];
                distance_squared_segment_triangle(a, b, p, q, s) <= r2
            });
            hit
        });
        hit
    }

    /// Exact distance from segment `a–b` to the surface (zero if it crosses the surface).
    pub fn segment_distance(&self, a: &Point3, b: &Point3) -> f64 {
        (0..self.corners.len())
            .map(|t| {
                let [p, q, s] = &self.corners[t];
                distance_squared_segment_triangle(a, b, p, q, s)
            })
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// Exact test: does the capsule touch the surface or lie inside the object?
    pub fn capsule_touches(&self, a: &Point3, b: &Point3, radius: f64) -> bool {
        self.segment_within(a, b, radius) || self.signed_distance(a) < 0.0
    }
}

fn for_each_cell(lo: [usize; 3], hi: [usize; 3], mut f: impl FnMut([usize; 3])) {
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                f([x, y, z]);
            }
        }
    }
}

fn for_each_cell_until(lo: [usize; 3], hi: [usize; 3], mut f: impl FnMut([usize; 3]) -> bool) {
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                if f([x, y, z]) {
                    return;
                }
            }
        }
    }
}

/// Visits the cells at Chebyshev distance exactly `ring` from `c`, clipped to the grid.
fn for_each_ring_cell(c: [usize; 3], ring: usize, dims: [usize; 3], mut f: impl FnMut([usize; 3])) {
    let r = ring as isize;
    let lo: [isize; 3] = std::array::from_fn(|i| (c[i] as isize - r).max(0));
    let hi: [isize; 3] = std::array::from_fn(|i| (c[i] as isize + r).min(dims[i] as isize - 1));
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            let on_shell_yz = (z - c[2] as isize).abs() == r || (y - c[1] as isize).abs() == r;
            if on_shell_yz {
                for x in lo[0]..=hi[0] {
                    f([x as usize, y as usize, z as usize]);
                }
            } else {
                // Only the two x faces of the shell.
                for x in [c[0] as isize - r, c[0] as isize + r] {
                    if x >= lo[0] && x <= hi[0] && (r > 0 || x == c[0] as isize) {
                        f([x as usize, y as usize, z as usize]);
                    }
                    if r == 0 {
                        break;
                    }
                }
            }
        }
    }
}

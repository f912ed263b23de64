//! An open surface's winding number as a whole number plus a small fan's: what lets the inside
//! volume of an open scan count crossings instead of querying the winding tree along each line.
//!
//! Only a surface's boundary Γ (its unbalanced edges) keeps its generalized winding number from
//! being a whole number. A fan F of triangles from a point of each connected part of Γ over that
//! part's edges has the same boundary, so S − F is closed and w_S − w_F is a whole number off
//! both surfaces. It changes only where a line crosses S (by the crossing's ±1) or F (by minus
//! the fan's), so along a line w_S is that step function plus w_F, and w_F costs one solid angle
//! per boundary edge where w_S costs a walk down the winding tree. Far from the fan, |w_F| is
//! bounded by its triangles' areas over their squared distances.
//!
//! Written by hand: no crate splits a winding number by its boundary.

use std::f64::consts::PI;

use crate::math::Point3;
use crate::TriangleMesh;

use super::fast_winding_number::triangle_solid_angle;
use super::triangle_bvh::vertical_crossing;

/// Vertices closer than this fraction of the mesh's largest side are one vertex of the fan's
/// boundary: scans' seams are 10⁻⁹–10⁻⁸ m apart, real holes millimetres.
pub const SEAM_WIDTH: f64 = 1e-6;

/// Most boundary edges a fan is built over: summing its solid angles then costs about one
/// winding-tree query.
pub const MAX_FAN_TRIANGLES: usize = 256;

/// One fan triangle: its corners, how many times it counts, and its area and (x, y) bounds for
/// the far-field bound.
#[derive(Debug, Clone, Copy)]
struct FanTriangle {
    corners: [Point3; 3],
    weight: i32,
    area: f64,
    lo: [f64; 2],
    hi: [f64; 2],
}

/// The fan over a surface's boundary.
#[derive(Debug, Clone, Default)]
pub struct BoundaryFan {
    triangles: Vec<FanTriangle>,
}

impl BoundaryFan {
    /// The fan over `mesh`'s [unbalanced edges](TriangleMesh::unbalanced_edges): for each
    /// connected part of them, triangles from the mean of its vertices over each of its edges.
    /// Vertices within `SEAM_WIDTH` of the mesh's size are welded first, so that the two
    /// edges of a seam a hair apart cancel instead of making a fan each: S − F is then closed
    /// but for strips that narrow, which a line meets only by chance. `None` when the boundary
    /// has more than `MAX_FAN_TRIANGLES` edges (a triangle soup): the fan would cost more
    /// than the winding tree.
    pub fn new(mesh: &TriangleMesh) -> Option<Self> {
        // Welding copies the mesh: not for one without a boundary (overlapping closed parts).
        if mesh.unbalanced_edges().is_empty() {
            return Some(Self::default());
        }
        let (lo, hi) = mesh.bounds();
        let (mesh, _) = mesh.weld_within(SEAM_WIDTH * (hi - lo).max());
        let mesh = &mesh;
        let edges = mesh.unbalanced_edges();
        if edges.len() > MAX_FAN_TRIANGLES {
            return None;
        }
        // Connected parts by union–find over the edges' vertices.
        let mut parent: std::collections::BTreeMap<u32, u32> = edges
            .iter()
            .flat_map(|(ends, _)| ends.iter().map(|&v| (v, v)))
            .collect();
        fn root(parent: &mut std::collections::BTreeMap<u32, u32>, mut v: u32) -> u32 {
            while parent[&v] != v {
                let up = parent[&parent[&v]];
                parent.insert(v, up);
                v = up;
            }
            v
        }
        for ([u, v], _) in &edges {
            let (ru, rv) = (root(&mut parent, *u), root(&mut parent, *v));
            parent.insert(ru.max(rv), ru.min(rv));
        }
        let mut sums: std::collections::BTreeMap<u32, (nalgebra::Vector3<f64>, f64)> =
            Default::default();
        let vertices: Vec<u32> = parent.keys().copied().collect();
        for v in vertices {
            let r = root(&mut parent, v);
            let sum = sums.entry(r).or_insert((nalgebra::Vector3::zeros(), 0.0));
            sum.0 += mesh.vertices[v as usize].coords;
            sum.1 += 1.0;
        }
        let triangles = edges
            .iter()
            .map(|([u, v], imbalance)| {
                let (sum, count) = sums[&root(&mut parent, *u)];
                let corners = [
                    Point3::from(sum / count),
                    mesh.vertices[*u as usize],
                    mesh.vertices[*v as usize],
                ];
                let [a, b, c] = corners;
                FanTriangle {
                    corners,
                    weight: *imbalance as i32,
                    area: 0.5 * (b - a).cross(&(c - a)).norm(),
                    lo: [a.x.min(b.x).min(c.x), a.y.min(b.y).min(c.y)],
                    hi: [a.x.max(b.x).max(c.x), a.y.max(b.y).max(c.y)],
                }
            })
            .collect();
        Some(Self { triangles })
    }

    /// Has the surface no boundary (its winding number a whole number off it)?
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// How many triangles the fan has (one per unbalanced edge).
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// The fan's winding number at `p`, summed exactly.
    pub fn winding_number(&self, p: &Point3) -> f64 {
        self.triangles
            .iter()
            .map(|t| f64::from(t.weight) * triangle_solid_angle(&t.corners, p))
            .sum::<f64>()
            / (4.0 * PI)
    }

    /// Appends where the vertical line through `(x, y)` crosses the fan to `out`: the height,
    /// and how w_S − w_F changes going up through it (minus the fan's own change). A line
    /// through an edge may report it twice or not at all, as
    /// [`super::TriangleBvh::vertical_crossings`] may.
    pub fn vertical_crossings(&self, x: f64, y: f64, out: &mut Vec<(f64, i32)>) {
        for t in &self.triangles {
            if x < t.lo[0] || x > t.hi[0] || y < t.lo[1] || y > t.hi[1] {
                continue;
            }
            if let Some((z, change)) = vertical_crossing(&t.corners, x, y) {
                out.push((z, -change * t.weight));
            }
        }
    }

    /// An upper bound on |w_F| at every point of the vertical line through `(x, y)`: each
    /// triangle subtends at most its area over its squared distance, which is at least the
    /// horizontal distance to its (x, y) bounds. Infinite where the line meets those bounds.
    pub fn winding_bound(&self, x: f64, y: f64) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let dx = (t.lo[0] - x).max(x - t.hi[0]).max(0.0);
                let dy = (t.lo[1] - y).max(y - t.hi[1]).max(0.0);
                f64::from(t.weight.unsigned_abs()) * t.area / (dx * dx + dy * dy)
            })
            .sum::<f64>()
            / (4.0 * PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::TriangleBvh;

    /// A 4 cm cube without its top face (two triangles), so its rim is a square.
    fn open_box() -> TriangleMesh {
        let mut mesh = crate::shapes::cuboid(crate::math::Vec3::new(0.04, 0.04, 0.04));
        let vertices = mesh.vertices.clone();
        mesh.triangles
            .retain(|t| !t.iter().all(|&v| vertices[v as usize].z > 0.019));
        assert_eq!(mesh.triangles.len(), 10);
        mesh
    }

    #[test]
    fn the_surface_minus_its_fan_winds_a_whole_number_of_times_and_the_bound_holds() {
        let mesh = open_box();
        let fan = BoundaryFan::new(&mesh).unwrap();
        assert_eq!(fan.len(), 4);
        let exact = TriangleBvh::new(&mesh);
        let mut fractions = 0;
        for i in 0..7 {
            for k in 0..40 {
                let p = Point3::new(
                    -0.035 + 0.01 * i as f64 + 1e-4,
                    0.003,
                    -0.05 + 0.0026 * k as f64,
                );
                let (surface, fan_w) = (exact.winding_number(&p), fan.winding_number(&p));
                let whole = surface - fan_w;
                assert!(
                    (whole - whole.round()).abs() < 1e-9,
                    "{p}: {surface} − {fan_w}"
                );
                if (surface - surface.round()).abs() > 0.05 {
                    fractions += 1;
                }
                assert!(fan_w.abs() <= fan.winding_bound(p.x, p.y) + 1e-12, "{p}");
            }
        }
        // Near the open top the surface's own winding number is far from whole.
        assert!(fractions > 10, "{fractions}");
    }

    #[test]
    fn crossings_of_surface_and_fan_give_the_whole_part_along_a_line() {
        let mesh = open_box();
        let fan = BoundaryFan::new(&mesh).unwrap();
        let exact = TriangleBvh::new(&mesh);
        let (x, y) = (0.0031, -0.0047);
        let mut crossings = Vec::new();
        exact.vertical_crossings(x, y, &mut crossings);
        fan.vertical_crossings(x, y, &mut crossings);
        crossings.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        // Bottom, the fan across the open top: two crossings whose changes cancel.
        assert_eq!(crossings.len(), 2, "{crossings:?}");
        assert_eq!(crossings.iter().map(|c| c.1).sum::<i32>(), 0);
        let whole_at = |z: f64| {
            let p = Point3::new(x, y, z);
            (exact.winding_number(&p) - fan.winding_number(&p)).round() as i32
        };
        assert_eq!(whole_at(-0.03), 0);
        assert_eq!(whole_at(0.0), crossings[0].1);
        assert_eq!(whole_at(0.03), 0);
        assert!(fan.winding_bound(x, y).is_infinite());
        assert!(fan.winding_bound(0.5, 0.0) < 1e-3);
        let closed = crate::shapes::cuboid(crate::math::Vec3::new(0.04, 0.04, 0.04));
        assert!(BoundaryFan::new(&closed).unwrap().is_empty());
    }

    #[test]
    fn a_triangle_soup_gets_no_fan() {
        // 100 separate triangles: 300 boundary edges, more than a fan is worth.
        let mut mesh = TriangleMesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        for i in 0..100u32 {
            let x = f64::from(i) * 0.001;
            mesh.vertices.extend([
                Point3::new(x, 0.0, 0.0),
                Point3::new(x, 0.01, 0.0),
                Point3::new(x, 0.0, 0.01),
            ]);
            mesh.triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        assert_eq!(mesh.unbalanced_edges().len(), 300);
        assert!(BoundaryFan::new(&mesh).is_none());
        mesh.triangles.truncate(80);
        assert_eq!(BoundaryFan::new(&mesh).map(|f| f.len()), Some(240));
    }
}

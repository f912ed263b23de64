//! Whether a mesh's winding numbers are affordable to query.
//!
//! The winding tree's far-field expansion replaces a node's triangles only at points farther
//! than a few of its radii. A mesh whose triangles all crowd near every point (a "book" of
//! thousands of pages sharing one edge, a dense soup) opens every node at every query: each
//! inside test then sums every triangle, and setting up 100,000 such pages took two minutes
//! before a grasp search even began. Probing a few points first tells such a mesh apart at a
//! bounded cost. Real scans and shapes need at most about 2,000 terms per query (see
//! `MOST_WINDING_TERMS`).

use rayon::prelude::*;

use crate::math::Point3;
use crate::TriangleMesh;

use super::TriangleBvh;

/// Most terms (expansions and triangles' solid angles) a probe's winding number may take. The
/// real scans in `assets/objects` and a 259k-triangle torus with holes take at most 512 at
/// points in their box and 1,024 beside their surface; a 15k-triangle subdivided can 2,048.
/// A query at this cap costs about 0.3 ms.
pub const MOST_WINDING_TERMS: usize = 8192;
/// Probe points along each side of the box's grid: 4³ of them.
const GRID_PROBES: usize = 4;
/// Probe points just off the surface, at triangles evenly spaced in the mesh's order.
const SURFACE_PROBES: usize = 64;
/// How far off the surface a surface probe lies, as a fraction of the box's largest side.
const SURFACE_OFFSET: f64 = 0.01;

/// What probing a mesh's winding numbers found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindingCost {
    /// How many points were probed.
    pub probes: usize,
    /// How many of them needed more than [`MOST_WINDING_TERMS`] terms.
    pub costly: usize,
}

impl WindingCost {
    /// Probes `exact` (built with winding numbers over `mesh`) at the centres of a 4 × 4 × 4
    /// grid over its box and just off 64 of its triangles, each query stopped after
    /// [`MOST_WINDING_TERMS`] terms: at most about 130 × 8,192 solid angles in all.
    pub fn probe(exact: &TriangleBvh, mesh: &TriangleMesh) -> Self {
        let (lo, hi) = exact.bounds();
        let size = hi - lo;
        let grid = (0..GRID_PROBES.pow(3)).map(|k| {
            let fraction = |i: usize| {
                (((k / GRID_PROBES.pow(i as u32)) % GRID_PROBES) as f64 + 0.5) / GRID_PROBES as f64
            };
            lo + size.component_mul(&nalgebra::Vector3::from_fn(|i, _| fraction(i)))
        });
        let n = mesh.triangles.len();
        let offset = SURFACE_OFFSET * size.max();
        let surface = (0..SURFACE_PROBES.min(n)).filter_map(|s| {
            let [a, b, c] = mesh.corners(s * n / SURFACE_PROBES.min(n));
            let normal = (b - a).cross(&(c - a)).try_normalize(0.0)?;
            Some(Point3::from((a.coords + b.coords + c.coords) / 3.0) + normal * offset)
        });
        let points: Vec<Point3> = grid.chain(surface).collect();
        let costly = points
            .par_iter()
            .filter(|p| exact.winding_number_within(p, MOST_WINDING_TERMS).is_none())
            .count();
        Self {
            probes: points.len(),
            costly,
        }
    }

    /// Are queries cheap enough: at most a quarter of the probes over the cap?
    pub fn affordable(&self) -> bool {
        4 * self.costly <= self.probes
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// `pages` triangles sharing the edge from (0, 0, 0) to (0, 0, 0.05), fanned around it.
    fn book(pages: usize) -> TriangleMesh {
        let mut vertices = vec![Point3::origin(), Point3::new(0.0, 0.0, 0.05)];
        vertices.extend((0..pages).map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / pages as f64;
            Point3::new(0.05 * angle.cos(), 0.05 * angle.sin(), 0.02)
        }));
        let triangles = (0..pages as u32).map(|i| [0, 1, i + 2]).collect();
        TriangleMesh {
            vertices,
            triangles,
        }
    }

    #[test]
    fn a_book_of_pages_or_a_fanned_polygon_is_too_costly_and_a_holed_torus_is_not() {
        let pages = book(3 * MOST_WINDING_TERMS);
        let cost = WindingCost::probe(&TriangleBvh::with_winding_numbers(&pages), &pages);
        assert_eq!(cost.costly, cost.probes, "{cost:?}");
        assert!(!cost.affordable());
        // A polygon of as many sides fanned from one corner (as an OBJ face of that many
        // vertices is read), tilted: slivers that all meet at that corner.
        let sides = 3 * MOST_WINDING_TERMS as u32;
        let polygon = TriangleMesh {
            vertices: (0..sides)
                .map(|i| {
                    let angle = std::f64::consts::TAU * f64::from(i) / f64::from(sides);
                    let (x, y) = (0.05 * angle.cos(), 0.05 * angle.sin());
                    Point3::new(x, y, 0.3 * x)
                })
                .collect(),
            triangles: (1..sides - 1).map(|i| [0, i, i + 1]).collect(),
        };
        let cost = WindingCost::probe(&TriangleBvh::with_winding_numbers(&polygon), &polygon);
        assert!(!cost.affordable(), "{cost:?}");
        // A torus of 32k triangles with every seventh removed: a real scan's kind of holes.
        let torus = shapes::torus(0.045, 0.014, 256, 64);
        let holed = TriangleMesh {
            vertices: torus.vertices.clone(),
            triangles: (torus.triangles.iter().enumerate())
                .filter(|(t, _)| t % 7 != 0)
                .map(|(_, &triangle)| triangle)
                .collect(),
        };
        let cost = WindingCost::probe(&TriangleBvh::with_winding_numbers(&holed), &holed);
        assert_eq!(cost.probes, 128);
        assert_eq!(cost.costly, 0, "{cost:?}");
        assert!(cost.affordable());
    }
}

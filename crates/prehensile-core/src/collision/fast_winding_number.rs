//! Generalized winding numbers (Jacobson, Kavan & Sorkine-Hornung 2013) with the tree-based
//! far-field approximation of Barill et al. 2018 ("Fast Winding Numbers for Soups and Clouds").
//!
//! The winding number of a point is the signed solid angle the triangles subtend there, divided
//! by 4π: 1 inside a closed, outward-wound surface, 0 outside, 2 where two closed parts overlap,
//! and a smooth value between 0 and 1 across the holes of an open surface. "Inside" is
//! `|w| > ½` (see [`super::TriangleBvh::inside`]), which gives every mesh — open, non-manifold, inconsistently wound, self-intersecting
//! or made of overlapping parts — a well-defined solid.
//!
//! Far from a node of the triangle hierarchy, the node's triangles are replaced by the first two
//! terms of a Taylor expansion about their area-weighted centre (Barill's first and second
//! order: the summed area vector, and the tensor of area vectors times offsets). Nearer than `β`
//! times the node's radius the node is opened; leaves are summed exactly with the
//! Van Oosterom–Strackee solid angle. Written by hand because no maintained crate
//! offers winding numbers over our own hierarchy; it shares the [`super::TriangleBvh`]'s nodes.

use std::f64::consts::PI;

use crate::math::{Point3, Vec3};

type Mat3 = nalgebra::Matrix3<f64>;

/// Nodes farther than this many radii from the query use the expansion. Barill et al. use 2
/// with one more term (the Hessian, from each triangle's second moments); with the two terms
/// here, 3 keeps the error within 0.015 of libigl's exact sum on `tests/integration/winding_oracle.rs`
/// (libigl's own fast path: 0.003), far from mattering to an inside test at ½ on closed parts.
const BETA: f64 = 3.0;
/// Traversal stack depth, as for the hierarchy's other queries.
const STACK: usize = 64;

/// A node of the triangle hierarchy as the winding tree needs it.
#[derive(Debug, Clone, Copy)]
pub(super) struct TreeNode {
    /// Leaf: first index into the triangle order; inner node: index of the left child.
    pub first: u32,
    /// Triangles in a leaf, 0 for an inner node.
    pub count: u32,
}

/// One node's far-field expansion.
#[derive(Debug, Clone, Copy)]
struct Dipole {
    /// Area-weighted centre of the node's triangles.
    centre: Point3,
    /// Sum of the triangles' area vectors (½ (b−a)×(c−a)).
    area_normal: Vec3,
    /// Σ aₜ nₜ (cₜ − centre)ᵀ over the node's triangles (area vector times centroid offset).
    second_order: Mat3,
    /// Distance from `centre` to the farthest corner of the node's triangles.
    radius: f64,
}

/// Far-field expansions of every node of a triangle hierarchy.
#[derive(Debug, Clone)]
pub struct WindingNumberTree {
    nodes: Vec<TreeNode>,
    dipoles: Vec<Dipole>,
}

impl WindingNumberTree {
    /// Expansions for the hierarchy `nodes` over `corners`, stored in leaf order (node 0 is the
    /// root; a leaf holds `corners[first..first + count]`; an inner node's children are `first`
    /// and `first + 1`).
    pub(super) fn new(nodes: Vec<TreeNode>, corners: &[[Point3; 3]]) -> Self {
        let mut dipoles = vec![
            Dipole {
                centre: Point3::origin(),
                area_normal: Vec3::zeros(),
                second_order: Mat3::zeros(),
                radius: 0.0,
            };
            nodes.len()
        ];
        // Σ aₜ nₜ cₜᵀ, additive over children; the tensor about a centre P is this − N Pᵀ.
        let mut moment = vec![Mat3::zeros(); nodes.len()];
        // Children come after their parents, so a reverse sweep sees children first.
        let mut area_sum = vec![0.0f64; nodes.len()];
        let mut centre_sum = vec![Vec3::zeros(); nodes.len()];
        for i in (0..nodes.len()).rev() {
            let node = nodes[i];
            if node.count > 0 {
                for [a, b, c] in &corners[node.first as usize..(node.first + node.count) as usize] {
                    let area_vector = (b - a).cross(&(c - a)) * 0.5;
                    let area = area_vector.norm();
                    let centroid = (a.coords + b.coords + c.coords) / 3.0;
                    dipoles[i].area_normal += area_vector;
                    area_sum[i] += area;
                    centre_sum[i] += centroid * area;
                    moment[i] += area_vector * centroid.transpose();
                }
            } else {
                for child in [node.first as usize, node.first as usize + 1] {
                    let (normal, area, centre) = (
                        dipoles[child].area_normal,
                        area_sum[child],
                        centre_sum[child],
                    );
                    dipoles[i].area_normal += normal;
                    area_sum[i] += area;
                    centre_sum[i] += centre;
                    let child_moment = moment[child];
                    moment[i] += child_moment;
                }
            }
            dipoles[i].centre = if area_sum[i] > 0.0 {
                Point3::from(centre_sum[i] / area_sum[i])
            } else {
                // Only zero-area triangles below: any corner will do, the dipole is zero.
                first_corner(&nodes, corners, i)
            };
            dipoles[i].second_order =
                moment[i] - dipoles[i].area_normal * dipoles[i].centre.coords.transpose();
        }
        // Radii need the centres, and a node's radius is bounded by its children's.
        for i in (0..nodes.len()).rev() {
            let node = nodes[i];
            let centre = dipoles[i].centre;
            dipoles[i].radius = if node.count > 0 {
                corners[node.first as usize..(node.first + node.count) as usize]
                    .iter()
                    .flatten()
                    .map(|p| (p - centre).norm())
                    .fold(0.0, f64::max)
            } else {
                [node.first as usize, node.first as usize + 1]
                    .iter()
                    .map(|&c| (dipoles[c].centre - centre).norm() + dipoles[c].radius)
                    .fold(0.0, f64::max)
            };
        }
        Self { nodes, dipoles }
    }

    /// The winding number at `p` (`corners` as the tree was built from).
    pub(super) fn winding_number(&self, corners: &[[Point3; 3]], p: &Point3) -> f64 {
        self.solid_angle_sum(corners, p, usize::MAX).0 / (4.0 * PI)
    }

    /// The winding number at `p` if it takes at most `most_terms` terms (expansions and
    /// triangles' solid angles), else `None` after that many: what bounds the work of a probe.
    pub(super) fn winding_number_within(
        &self,
        corners: &[[Point3; 3]],
        p: &Point3,
        most_terms: usize,
    ) -> Option<f64> {
        let (solid_angle, terms) = self.solid_angle_sum(corners, p, most_terms);
        (terms <= most_terms).then_some(solid_angle / (4.0 * PI))
    }

    /// The solid angle at `p` and how many terms it took, stopping once more than `most_terms`.
    fn solid_angle_sum(
        &self,
        corners: &[[Point3; 3]],
        p: &Point3,
        most_terms: usize,
    ) -> (f64, usize) {
        let mut solid_angle = 0.0;
        let mut terms = 0usize;
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 && terms <= most_terms {
            top -= 1;
            let i = stack[top] as usize;
            let dipole = &self.dipoles[i];
            let r = dipole.centre - p;
            let distance = r.norm();
            if distance > BETA * dipole.radius {
                // ∫ n·g dA with g(x) = (x − p)/|x − p|³ expanded about the centre: g·N plus
                // Σᵢⱼ ∂ⱼgᵢ Mᵢⱼ, where ∂ⱼgᵢ = δᵢⱼ/|r|³ − 3 rᵢ rⱼ/|r|⁵.
                let d3 = distance * distance * distance;
                let m = &dipole.second_order;
                solid_angle += r.dot(&dipole.area_normal) / d3 + m.trace() / d3
                    - 3.0 * r.dot(&(m * r)) / (d3 * distance * distance);
                terms += 1;
                continue;
            }
            let node = self.nodes[i];
            if node.count > 0 {
                for triangle in &corners[node.first as usize..(node.first + node.count) as usize] {
                    solid_angle += triangle_solid_angle(triangle, p);
                }
                terms += node.count as usize;
            } else {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            }
        }
        (solid_angle, terms)
    }
}

/// A corner of the first triangle under node `i`.
fn first_corner(nodes: &[TreeNode], corners: &[[Point3; 3]], i: usize) -> Point3 {
    let mut node = nodes[i];
    while node.count == 0 {
        node = nodes[node.first as usize];
    }
    corners[node.first as usize][0]
}

/// Signed solid angle of triangle `abc` seen from `p` (Van Oosterom & Strackee 1983): positive
/// when `p` is behind the triangle (on the side its counter-clockwise normal points away from).
pub fn triangle_solid_angle([a, b, c]: &[Point3; 3], p: &Point3) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let numerator = a.dot(&b.cross(&c));
    let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
    2.0 * numerator.atan2(denominator)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_seen_from_behind_its_centre_fills_a_known_angle() {
        // A point on the axis of an equilateral triangle, behind it: positive; in front: negative.
        let tri = [
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(-0.5, 0.75f64.sqrt(), 0.0),
            Point3::new(-0.5, -(0.75f64.sqrt()), 0.0),
        ];
        let behind = triangle_solid_angle(&tri, &Point3::new(0.0, 0.0, -1e-9));
        assert!((behind - 2.0 * PI).abs() < 1e-6, "{behind}");
        let front = triangle_solid_angle(&tri, &Point3::new(0.0, 0.0, 1e-9));
        assert!((front + 2.0 * PI).abs() < 1e-6, "{front}");
    }
}

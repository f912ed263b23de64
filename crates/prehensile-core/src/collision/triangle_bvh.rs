//! Exact queries against a closed triangle mesh, accelerated by a bounding-volume hierarchy.
//!
//! Signs come from angle-weighted pseudo-normals (Bærentzen & Aanæs 2005), which are exact for a
//! closed, manifold, consistently wound mesh. Any other mesh (open, non-manifold, inconsistently
//! wound, overlapping parts) is built [`TriangleBvh::with_winding_numbers`]: its inside is where
//! the generalized winding number exceeds ½ in magnitude, and signs and normals follow it.
//! Written by hand rather than with parry3d's BVH so that the leaf tests are our checked kernels
//! and the traversal uses a fixed stack: queries take `&self` and never allocate.

use rayon::prelude::*;

use crate::edge_groups::EdgeGroups;
use crate::geometry::{
    closest_point_on_triangle, closest_segment_triangle, distance_squared_segment_triangle,
    segment_within_triangle, TriangleFeature,
};
use crate::math::{Point3, Vec3};
use crate::mesh::TriangleMesh;

use super::fast_winding_number::{triangle_solid_angle, TreeNode, WindingNumberTree};
use super::node_slab::{area_normal, Slab, SLAB_MOST_TRIANGLES};

/// A point on the surface with its outward pseudo-normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The surface point.
    pub point: Point3,
    /// Outward unit pseudo-normal of the feature (face, edge or vertex) the point lies on.
    pub normal: Vec3,
    /// Signed distance from the query point: positive outside, negative inside.
    pub signed_distance: f64,
}

/// Triangles per leaf at most.
const LEAF_SIZE: usize = 4;
/// Sine of the corner angle below which a triangle counts as a sliver for the plane test.
const SLIVER_SINE: f64 = 1e-3;
/// Traversal stack depth; a median-split tree over 20 million triangles is about 24 deep.
const STACK: usize = 64;
/// Below this depth nodes split at the median, so that no traversal's stack overflows.
const MAX_SAH_DEPTH: usize = 32;
/// Bins of the surface area heuristic's split.
const SAH_BINS: usize = 16;
/// Triangles in a node above which its two subtrees are built on two threads (each then pays
/// for its own node list and the graft).
const PARALLEL_ITEMS: usize = 2048;
/// Depth from which subtrees are built on one thread whatever their size: 16 subtrees keep
/// the cores busy, and each level built in parallel copies its nodes once more in the graft.
const PARALLEL_DEPTH: usize = 4;

#[derive(Debug, Clone, Copy)]
struct Node {
    min: Point3,
    max: Point3,
    /// Leaf: its first triangle (the triangles are stored in leaf order); inner node: index of
    /// the left child (right = left + 1).
    first: u32,
    /// Triangles in a leaf, 0 for an inner node.
    count: u32,
    /// Half the box's diagonal (a hair more, for rounding): the radius of the sphere around
    /// the box's centre through its corners.
    reach: f64,
}

impl Node {
    /// A node around box `bounds`, its children or triangles not set yet.
    fn around(bounds: &Aabb) -> Self {
        Self {
            min: Point3::from(bounds.0),
            max: Point3::from(bounds.1),
            first: 0,
            count: 0,
            reach: half_diagonal(bounds),
        }
    }
}

/// A bounding-volume hierarchy over a mesh's triangles with the pseudo-normals needed for signed
/// distances.
#[derive(Debug, Clone)]
pub struct TriangleBvh {
    corners: Vec<[Point3; 3]>,
    /// Bounding sphere (centre, radius) of each triangle, to skip exact tests cheaply.
    spheres: Vec<(Point3, f64)>,
    face_normals: Vec<Vec3>,
    /// Unit normal of each well-shaped triangle, to skip triangles whose plane is already
    /// farther than the best distance; zero for slivers (corner angles below about 0.06°), whose
    /// computed normal is too inaccurate to bound anything.
    plane_normals: Vec<Vec3>,
    edge_normals: Vec<[Vec3; 3]>,
    vertex_normals: Vec<[Vec3; 3]>,
    nodes: Vec<Node>,
    /// Each node's slab ([`Slab`]), tightening its box's distance bounds.
    slabs: Vec<Slab>,
    /// Present when the inside is given by winding numbers instead of pseudo-normals.
    winding: Option<WindingNumberTree>,
    /// The winding number is a whole number off the surface (every edge balanced), so the
    /// inside changes only across triangles ([`TriangleBvh::into_whole_winding_numbers`]).
    whole_winding: bool,
}

impl TriangleBvh {
    /// Builds the hierarchy for a closed, manifold, consistently wound mesh (one that passed
    /// [`TriangleMesh::report`] without defects): signs from pseudo-normals.
    pub fn new(mesh: &TriangleMesh) -> Self {
        // The tree and the pseudo-normals need nothing of each other: they are built side by
        // side. Every per-triangle array is then gathered once in leaf order, so that a query
        // reads a leaf's corners and normals from neighbouring memory (fewer cache misses on
        // scans of tens of thousands of triangles) without an index table; the geometry's
        // arrays and the normals' are gathered side by side too.
        let ((nodes, order), normals) = rayon::join(
            || {
                let mut items: Vec<BuildItem> = (0..mesh.triangles.len())
                    .map(|t| BuildItem::new(&mesh.corners(t), t as u32))
                    .collect();
                let (bounds, centres) = boxes_of(&items);
                let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
                nodes.push(Node::around(&bounds));
                build(&mut nodes, &mut items, 0, 0, 0, centres);
                let order: Vec<usize> = items.iter().map(|item| item.triangle as usize).collect();
                (nodes, order)
            },
            || PseudoNormals::new(mesh),
        );
        let ((corners, plane_normals, spheres), (face_normals, edge_normals, vertex_normals)) =
            rayon::join(
                || gathered_geometry(mesh, &order),
                || normals.gathered(mesh, &order),
            );
        let slabs = node_slabs(&nodes, &corners);
        Self {
            corners,
            spheres,
            face_normals,
            plane_normals,
            edge_normals,
            vertex_normals,
            nodes,
            slabs,
            winding: None,
            whole_winding: false,
        }
    }

    /// Builds the hierarchy for any mesh: the inside is where the generalized winding number
    /// exceeds ½ in magnitude (within the mesh's bounding box); signs and outward normals follow
    /// it.
    pub fn with_winding_numbers(mesh: &TriangleMesh) -> Self {
        Self::new(mesh).into_winding_numbers()
    }

    /// This hierarchy with its inside from winding numbers (see
    /// [`TriangleBvh::with_winding_numbers`]).
    pub fn into_winding_numbers(mut self) -> Self {
        let links = self
            .nodes
            .iter()
            .map(|n| TreeNode {
                first: n.first,
                count: n.count,
            })
            .collect();
        self.winding = Some(WindingNumberTree::new(links, &self.corners));
        self
    }

    /// [`TriangleBvh::into_winding_numbers`] for a surface whose every edge is balanced (no
    /// [unbalanced edges](TriangleMesh::unbalanced_edges): closed parts that overlap or touch
    /// along an edge, a face pushed through another). Its winding number is then a whole number
    /// off the surface and the inside changes only across triangles, so the signed distance
    /// stays 1-Lipschitz and the distance grids apply
    /// ([`TriangleBvh::signs_change_only_at_the_surface`]).
    pub fn into_whole_winding_numbers(self) -> Self {
        Self {
            whole_winding: true,
            ..self.into_winding_numbers()
        }
    }

    /// Does the sign of the signed distance change only across the surface, so that the signed
    /// distance is 1-Lipschitz, as the distance grids' bounds need? Yes for pseudo-normal signs
    /// and [whole winding numbers](TriangleBvh::into_whole_winding_numbers); no across the holes
    /// of an open surface, where the winding number passes ½ away from any triangle.
    pub fn signs_change_only_at_the_surface(&self) -> bool {
        self.winding.is_none() || self.whole_winding
    }

    /// Is the inside given by winding numbers (the mesh is not a clean closed manifold)?
    pub fn uses_winding_numbers(&self) -> bool {
        self.winding.is_some()
    }

    /// The generalized winding number at `p`: 1 inside a closed part, 0 outside, fractional
    /// near holes. Tree-approximated when built [`TriangleBvh::with_winding_numbers`], else
    /// summed exactly over every triangle.
    pub fn winding_number(&self, p: &Point3) -> f64 {
        match &self.winding {
            Some(tree) => tree.winding_number(&self.corners, p),
            None => {
                self.corners
                    .iter()
                    .map(|t| triangle_solid_angle(t, p))
                    .sum::<f64>()
                    / (4.0 * std::f64::consts::PI)
            }
        }
    }

    /// [`TriangleBvh::winding_number`] at `p` if it takes at most `most_terms` terms (the
    /// tree's expansions and triangles' solid angles; every triangle without a tree), else
    /// `None`, after at most that much work.
    pub fn winding_number_within(&self, p: &Point3, most_terms: usize) -> Option<f64> {
        match &self.winding {
            Some(tree) => tree.winding_number_within(&self.corners, p, most_terms),
            None => (self.corners.len() <= most_terms).then(|| self.winding_number(p)),
        }
    }

    /// Is `p` inside the object? Winding number above ½ in magnitude (so a part wound inside
    /// out still counts, and a cavity wound inward is empty), within the bounding box, for a mesh
    /// built with winding numbers, negative signed distance otherwise.
    pub fn inside(&self, p: &Point3) -> bool {
        match &self.winding {
            Some(tree) => {
                let root = &self.nodes[0];
                (0..3).all(|i| p[i] >= root.min[i] && p[i] <= root.max[i])
                    && tree.winding_number(&self.corners, p).abs() > 0.5
            }
            None => self.signed_distance(p) < 0.0,
        }
    }

    /// Where the vertical line through `(x, y)` crosses a triangle, unsorted, into `out`
    /// (cleared first): the height, and how the winding number changes going up through it (+1
    /// entering through a downward-facing triangle, −1 leaving). A line through an edge may
    /// report it twice or not at all.
    pub fn vertical_crossings(&self, x: f64, y: f64, out: &mut Vec<(f64, i32)>) {
        out.clear();
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if x < node.min.x || x > node.max.x || y < node.min.y || y > node.max.y {
                continue;
            }
            if node.count > 0 {
                for triangle in
                    &self.corners[node.first as usize..(node.first + node.count) as usize]
                {
                    if let Some(crossing) = vertical_crossing(triangle, x, y) {
                        out.push(crossing);
                    }
                }
            } else {
                stack[top] = node.first;
                stack[top + 1] = node.first + 1;
                top += 2;
            }
        }
    }

    /// The mesh's bounding box (lower and upper corners).
    pub fn bounds(&self) -> (Point3, Point3) {
        (self.nodes[0].min, self.nodes[0].max)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.corners.len()
    }

    /// Exact signed distance from `p` to the surface: positive outside, negative inside; NaN
    /// for a point with a NaN coordinate (no triangle is at any distance from it).
    pub fn signed_distance(&self, p: &Point3) -> f64 {
        self.signed_distance_within(p, f64::INFINITY)
            .unwrap_or(f64::NAN)
    }

    /// Exact signed distance from `p` if the surface is within `max` of it, else `None`.
    pub fn signed_distance_within(&self, p: &Point3, max: f64) -> Option<f64> {
        self.nearest_triangle(p, max)
            .map(|t| self.signed_distance_to_triangle(p, t))
    }

    /// The surface point nearest to `p` if it is within `max`, with the pseudo-normal of the
    /// feature it lies on (outward) and the signed distance from `p`.
    pub fn closest_point_within(&self, p: &Point3, max: f64) -> Option<SurfacePoint> {
        self.nearest_triangle(p, max)
            .map(|t| self.surface_point_on_triangle(p, t))
    }

    /// Index of a triangle nearest to `p` if one is within `max`.
    fn nearest_triangle(&self, p: &Point3, max: f64) -> Option<usize> {
        let mut best = if max.is_finite() {
            max * max
        } else {
            f64::INFINITY
        };
        let mut best_t = usize::MAX;
        // Each entry carries its box's squared distance, computed once when it was pushed.
        let mut stack = [(0u32, 0.0f64); STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (index, gap) = stack[top];
            if gap > best {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count > 0 {
                for t in node.first as usize..(node.first + node.count) as usize {
                    let [a, b, c] = &self.corners[t];
                    // A triangle is no nearer than its plane.
                    let height = (p - a).dot(&self.plane_normals[t]);
                    if height * height > best {
                        continue;
                    }
                    let d = (closest_point_on_triangle(p, a, b, c).0 - p).norm_squared();
                    if d <= best {
                        best = d;
                        best_t = t;
                    }
                }
            } else {
                // Visit the nearer child first: push it last.
                let (l, r) = (node.first, node.first + 1);
                let (dl, dr) = (
                    box_distance_squared(&self.nodes[l as usize], p),
                    box_distance_squared(&self.nodes[r as usize], p),
                );
                let (near, far) = if dl <= dr {
                    ((l, dl), (r, dr))
                } else {
                    ((r, dr), (l, dl))
                };
                if far.1 <= best {
                    stack[top] = far;
                    top += 1;
                }
                if near.1 <= best {
                    stack[top] = near;
                    top += 1;
                }
            }
        }
        (best_t != usize::MAX).then_some(best_t)
    }

    /// The point of segment `a–b` nearest the surface, as a fraction along the segment, with
    /// the surface point nearest it (pseudo-normal, signed distance), if the surface comes within
    /// `max` of the segment. Exact: the minimum over the triangles of their distance to the
    /// segment, whose nearest triangle is also the nearest to that point. Where the segment
    /// crosses the surface, a crossing point (signed distance 0).
    pub fn closest_point_to_segment_within(
        &self,
        a: &Point3,
        b: &Point3,
        max: f64,
    ) -> Option<(f64, SurfacePoint)> {
        let (mut best, mut best_squared) = (max, max * max);
        let mut found: Option<(usize, f64)> = None;
        let middle = nalgebra::center(a, b);
        let segment = QuerySegment::new(a, b);
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if self.segment_nearness(&segment, stack[top], best).is_none() {
                continue;
            }
            if node.count > 0 {
                for t in node.first as usize..(node.first + node.count) as usize {
                    let (centre, reach) = self.spheres[t];
                    if segment.distance_squared_to(&centre) > (best + reach).powi(2) {
                        continue;
                    }
                    // A triangle is no nearer than its plane.
                    let corners = &self.corners[t];
                    let normal = &self.plane_normals[t];
                    let (ha, hb) = (normal.dot(&(a - corners[0])), normal.dot(&(b - corners[0])));
                    if (ha > best && hb > best) || (ha < -best && hb < -best) {
                        continue;
                    }
                    let (d, s) =
                        closest_segment_triangle(a, b, &corners[0], &corners[1], &corners[2]);
                    if d <= best_squared {
                        best_squared = d;
                        best = d.sqrt();
                        found = Some((t, s));
                    }
                }
            } else {
                // The child nearer the segment's middle is visited first: pushed last.
                let (l, r) = (node.first, node.first + 1);
                let near_left = box_distance_squared(&self.nodes[l as usize], &middle)
                    <= box_distance_squared(&self.nodes[r as usize], &middle);
                let (near, far) = if near_left { (l, r) } else { (r, l) };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        found.map(|(t, s)| (s, self.surface_point_on_triangle(&(a + (b - a) * s), t)))
    }

    /// Signed distance from `p` to triangle `t`, signed by the pseudo-normal of the feature
    /// nearest to `p`; equals the mesh's signed distance when `t` is a nearest triangle.
    pub(crate) fn signed_distance_to_triangle(&self, p: &Point3, t: usize) -> f64 {
        self.surface_point_on_triangle(p, t).signed_distance
    }

    /// The point of triangle `t` nearest to `p`, with the pseudo-normal of its feature.
    fn surface_point_on_triangle(&self, p: &Point3, t: usize) -> SurfacePoint {
        let [a, b, c] = &self.corners[t];
        let (point, feature) = closest_point_on_triangle(p, a, b, c);
        let normal = match feature {
            TriangleFeature::Face => self.face_normals[t],
            TriangleFeature::Edge(k) => self.edge_normals[t][k as usize],
            TriangleFeature::Vertex(k) => self.vertex_normals[t][k as usize],
        };
        let d = (point - p).norm();
        let (signed_distance, normal) = match &self.winding {
            None if (p - point).dot(&normal) < 0.0 => (-d, normal),
            None => (d, normal),
            Some(_) => {
                // The pseudo-normal of an open or inconsistent mesh may face either way: turn
                // it away from the inside.
                let inside = self.inside(p);
                let facing_p = (p - point).dot(&normal) >= 0.0;
                let normal = if inside == facing_p { -normal } else { normal };
                (if inside { -d } else { d }, normal)
            }
        };
        SurfacePoint {
            point,
            normal,
            signed_distance,
        }
    }

    /// True when some triangle lies within `radius` of segment `a–b` (the capsule touches the
    /// surface). Does not detect a capsule wholly inside; see [`TriangleBvh::capsule_touches`].
    pub fn segment_within(&self, a: &Point3, b: &Point3, radius: f64) -> bool {
        let segment = QuerySegment::new(a, b);
        if self.segment_nearness(&segment, 0, radius).is_none() {
            return false;
        }
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if node.count > 0 {
                for t in node.first as usize..(node.first + node.count) as usize {
                    let (centre, reach) = self.spheres[t];
                    let near = radius + reach;
                    if segment.distance_squared_to(&centre) > near * near {
                        continue;
                    }
                    if segment_within_triangle(
                        a,
                        b,
                        &self.corners[t],
                        &self.plane_normals[t],
                        radius,
                    ) {
                        return true;
                    }
                }
                continue;
            }
            // The children the capsule may meet, the one whose centre is nearer the segment
            // visited first: a capsule that touches is proven sooner.
            let (left, right) = (node.first, node.first + 1);
            let near_left = self.segment_nearness(&segment, left, radius);
            let near_right = self.segment_nearness(&segment, right, radius);
            match (near_left, near_right) {
                (Some(l), Some(r)) => {
                    let (first, second) = if l <= r { (left, right) } else { (right, left) };
                    stack[top] = second;
                    stack[top + 1] = first;
                    top += 2;
                }
                (Some(_), None) => {
                    stack[top] = left;
                    top += 1;
                }
                (None, Some(_)) => {
                    stack[top] = right;
                    top += 1;
                }
                (None, None) => {}
            }
        }
        false
    }

    /// The squared distance from the segment to node `index`'s centre when the capsule of
    /// radius `r` around it may meet the node's triangles, `None` when it cannot. It must meet
    /// the node's box grown by `r` on every side ([`QuerySegment::meets_box`]), come within `r`
    /// of the node's slab ([`Slab`]) and within `r` of the sphere through the box's corners:
    /// on a fine mesh a finger's capsule is many times a leaf's size, and the grown box's
    /// corners, which the sphere cuts off, hold most of the leaves the box test alone lets
    /// through (on a 15k-triangle can, 60% of the node visits).
    #[inline]
    fn segment_nearness(&self, segment: &QuerySegment, index: u32, r: f64) -> Option<f64> {
        // The sphere first: the walk needs its distance to order the children anyway, and it
        // turns away more nodes than the box for its cost (1% fewer instructions in a 16k
        // grasp than box, sphere, slab).
        let node = &self.nodes[index as usize];
        let reach = r + node.reach;
        let d2 = segment.distance_squared_to(&nalgebra::center(&node.min, &node.max));
        let near_sphere = d2 <= reach * reach;
        if !near_sphere || !segment.meets_box(&node.min, &node.max, r) {
            return None;
        }
        (self.slabs[index as usize].segment_gap(&segment.a, &segment.b) <= r).then_some(d2)
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
    ///
    /// A capsule clear of the surface is wholly inside or wholly outside a closed mesh, so one
    /// end decides. The inside of an open mesh also ends across its holes, so there both ends are
    /// asked.
    pub fn capsule_touches(&self, a: &Point3, b: &Point3, radius: f64) -> bool {
        self.segment_within(a, b, radius)
            || self.inside(a)
            || (self.winding.is_some() && self.inside(b))
    }
}

/// A mesh's pseudo-normals in mesh order (Bærentzen & Aanæs 2005), summed in mesh order so that
/// every sum is the same bit for bit whatever the tree.
struct PseudoNormals {
    /// Each triangle's unit normal (+z for a collapsed triangle).
    face: Vec<Vec3>,
    /// Each triangle's edges' pseudo-normals: the sums of the face normals on each edge.
    edge: Vec<[Vec3; 3]>,
    /// Each vertex's angle-weighted sum of its triangles' normals, not normalized.
    vertex_sums: Vec<Vec3>,
}

impl PseudoNormals {
    fn new(mesh: &TriangleMesh) -> Self {
        let n = mesh.triangles.len();
        let mut face = Vec::with_capacity(n);
        let mut vertex_sums = vec![Vec3::zeros(); mesh.vertices.len()];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = mesh.corners(t);
            let normal = unit_or((p[1] - p[0]).cross(&(p[2] - p[0])), Vec3::z());
            face.push(normal);
            for k in 0..3 {
                let e1 = (p[(k + 1) % 3] - p[k]).normalize();
                let e2 = (p[(k + 2) % 3] - p[k]).normalize();
                let angle = e1.dot(&e2).clamp(-1.0, 1.0).acos();
                vertex_sums[tri[k] as usize] += normal * angle;
            }
        }
        let mut edge = vec![[Vec3::zeros(); 3]; n];
        for (_, corners) in EdgeGroups::new(&mesh.triangles).iter() {
            let sum = corners
                .iter()
                .fold(Vec3::zeros(), |sum, (t, _)| sum + face[t]);
            for (t, k) in corners.iter() {
                edge[t][k] = unit_or(sum, face[t]);
            }
        }
        Self {
            face,
            edge,
            vertex_sums,
        }
    }

    /// Each triangle's face normal, edge normals and unit vertex normals, in the tree's `order`.
    fn gathered(&self, mesh: &TriangleMesh, order: &[usize]) -> Normals {
        let face = order.iter().map(|&t| self.face[t]).collect();
        let edge = order.iter().map(|&t| self.edge[t]).collect();
        let vertex = order
            .iter()
            .map(|&t| {
                mesh.triangles[t].map(|i| unit_or(self.vertex_sums[i as usize], self.face[t]))
            })
            .collect();
        (face, edge, vertex)
    }
}

/// Each triangle's corners, unit plane normal (zero for a sliver) and bounding sphere, in the
/// tree's `order`.
fn gathered_geometry(mesh: &TriangleMesh, order: &[usize]) -> Geometry {
    let corners: Vec<[Point3; 3]> = order.iter().map(|&t| mesh.corners(t)).collect();
    let plane_normals = corners
        .iter()
        .map(|[a, b, c]| {
            let (ab, ac) = (b - a, c - a);
            let cross = ab.cross(&ac);
            if cross.norm() > SLIVER_SINE * ab.norm() * ac.norm() {
                cross.normalize()
            } else {
                Vec3::zeros()
            }
        })
        .collect();
    let spheres = corners
        .iter()
        .map(|[a, b, c]| {
            let centre = Point3::from(triangle_centre(a, b, c));
            let radius = (a - centre)
                .norm()
                .max((b - centre).norm())
                .max((c - centre).norm());
            (centre, radius)
        })
        .collect();
    (corners, plane_normals, spheres)
}

/// Per-triangle corners, plane normals and bounding spheres (see [`gathered_geometry`]).
type Geometry = (Vec<[Point3; 3]>, Vec<Vec3>, Vec<(Point3, f64)>);

/// Per-triangle face, edge and vertex pseudo-normals (see [`PseudoNormals::gathered`]).
type Normals = (Vec<Vec3>, Vec<[Vec3; 3]>, Vec<[Vec3; 3]>);

/// A triangle as the tree's build moves it: its centre (the split key), its box and its index.
/// The build reorders these, not indices into per-triangle arrays, so that each level reads
/// its range of them in order instead of at random.
#[derive(Debug, Clone, Copy)]
struct BuildItem {
    centre: Vec3,
    bounds: Aabb,
    triangle: u32,
    /// The item's bin in the split being made (kept from binning to partitioning).
    bin: u8,
}

impl BuildItem {
    fn new([a, b, c]: &[Point3; 3], triangle: u32) -> Self {
        Self {
            centre: triangle_centre(a, b, c),
            bounds: (
                a.coords.inf(&b.coords).inf(&c.coords),
                a.coords.sup(&b.coords).sup(&c.coords),
            ),
            triangle,
            bin: 0,
        }
    }
}

/// The centroid of triangle `abc` (the centre of its bounding sphere and its split key).
fn triangle_centre(a: &Point3, b: &Point3, c: &Point3) -> Vec3 {
    (a.coords + b.coords + c.coords) / 3.0
}

/// Builds node `index` of `nodes` (its box already set) at `depth` over `items`, which start at
/// position `start` of the whole build's, with `centres` the box of their centres: both
/// children pushed, then the left child's subtree built, then the right's; leaves refer to
/// positions in the build's order. A node of more than [`PARALLEL_ITEMS`] above
/// [`PARALLEL_DEPTH`] builds its two subtrees side by side and grafts them in that order: the
/// same tree as one thread builds.
fn build(
    nodes: &mut Vec<Node>,
    items: &mut [BuildItem],
    index: usize,
    start: usize,
    depth: usize,
    centres: Aabb,
) {
    if items.len() <= LEAF_SIZE {
        nodes[index].first = start as u32;
        nodes[index].count = items.len() as u32;
        return;
    }
    let bounds = (nodes[index].min.coords, nodes[index].max.coords);
    let (mid, left, right) = split(items, bounds, depth, centres);
    let first = nodes.len();
    nodes.push(Node::around(&left.0));
    nodes.push(Node::around(&right.0));
    nodes[index].first = first as u32;
    let parallel = items.len() > PARALLEL_ITEMS && depth < PARALLEL_DEPTH;
    let (left_items, right_items) = items.split_at_mut(mid);
    if parallel {
        let (left_tree, right_tree) = rayon::join(
            || subtree(left, left_items, start, depth + 1),
            || subtree(right, right_items, start + mid, depth + 1),
        );
        graft(nodes, &left_tree, first);
        graft(nodes, &right_tree, first + 1);
    } else {
        build(nodes, left_items, first, start, depth + 1, left.1);
        build(
            nodes,
            right_items,
            first + 1,
            start + mid,
            depth + 1,
            right.1,
        );
    }
}

/// Each node's [`Slab`] around its triangles (`corners` in leaf order, so a node's triangles are
/// one run of them); [`Slab::EVERYWHERE`] above [`SLAB_MOST_TRIANGLES`].
fn node_slabs(nodes: &[Node], corners: &[[Point3; 3]]) -> Vec<Slab> {
    // Children come after their parent: runs and normal sums fill from the leaves up.
    let mut runs = vec![(0..0, Vec3::zeros()); nodes.len()];
    for (index, node) in nodes.iter().enumerate().rev() {
        runs[index] = if node.count > 0 {
            let run = node.first as usize..(node.first + node.count) as usize;
            let sum = corners[run.clone()].iter().map(area_normal).sum();
            (run, sum)
        } else {
            let (left, right) = (&runs[node.first as usize], &runs[node.first as usize + 1]);
            (
                left.0.start.min(right.0.start)..left.0.end.max(right.0.end),
                left.1 + right.1,
            )
        };
    }
    runs.into_par_iter()
        .map(|(run, sum)| {
            if run.len() <= SLAB_MOST_TRIANGLES {
                Slab::around(sum, &corners[run])
            } else {
                Slab::EVERYWHERE
            }
        })
        .collect()
}

/// The tree over `items` (their boxes `(bounds, centres)`) at `depth`, its root at index 0 and
/// its inner nodes' child indices its own.
fn subtree(
    (bounds, centres): BoxPair,
    items: &mut [BuildItem],
    start: usize,
    depth: usize,
) -> Vec<Node> {
    let mut nodes = vec![Node::around(&bounds)];
    build(&mut nodes, items, 0, start, depth, centres);
    nodes
}

/// Puts `tree` (from [`subtree`]) under the tree in `nodes`: its root in place of the node at
/// `root`, the rest appended, child indices moved along.
fn graft(nodes: &mut Vec<Node>, tree: &[Node], root: usize) {
    let (offset, appended) = ((nodes.len() - 1) as u32, nodes.len());
    nodes[root] = tree[0];
    nodes.extend_from_slice(&tree[1..]);
    for index in std::iter::once(root).chain(appended..nodes.len()) {
        let node = &mut nodes[index];
        if node.count == 0 {
            node.first += offset;
        }
    }
}

/// Splits `items` (their box `bounds`, their centres' box `centres`) of a node at `depth`:
/// where the surface area heuristic says ([`sah_split`]), at the median of the node's longest
/// axis where it finds no split or the tree is deep. Returns the left side's length and both
/// sides' boxes.
fn split(
    items: &mut [BuildItem],
    bounds: Aabb,
    depth: usize,
    centres: Aabb,
) -> (usize, BoxPair, BoxPair) {
    let by_area = (depth < MAX_SAH_DEPTH)
        .then(|| sah_split(items, centres))
        .flatten();
    by_area.unwrap_or_else(|| {
        let axis = (bounds.1 - bounds.0).imax();
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |x, y| x.centre[axis].total_cmp(&y.centre[axis]));
        (mid, boxes_of(&items[..mid]), boxes_of(&items[mid..]))
    })
}

/// Where to split `items` by the surface area heuristic: the triangles binned by their
/// centres along the centres' longest axis, the split between bins that minimizes each side's
/// box area times its count. Reorders `items` to put the left side first and returns its
/// length and both sides' boxes (of their triangles, of their centres), or `None` when every
/// centre falls in one bin. `(lo, hi)` is the box of the items' centres.
fn sah_split(items: &mut [BuildItem], (lo, hi): Aabb) -> Option<(usize, BoxPair, BoxPair)> {
    let axis = (hi - lo).imax();
    let extent = hi[axis] - lo[axis];
    if extent.is_nan() || extent <= 0.0 {
        return None;
    }
    let scale = SAH_BINS as f64 / extent;
    let mut bins = [EMPTY_BOX; SAH_BINS];
    let mut bin_centres = [EMPTY_BOX; SAH_BINS];
    let mut counts = [0usize; SAH_BINS];
    for item in items.iter_mut() {
        let k = (((item.centre[axis] - lo[axis]) * scale) as usize).min(SAH_BINS - 1);
        item.bin = k as u8;
        counts[k] += 1;
        bins[k] = grown(bins[k], item.bounds);
        bin_centres[k] = grown(bin_centres[k], (item.centre, item.centre));
    }
    // Half the box's area (the factor 2 is common to every split).
    let area = |(lo, hi): Aabb| {
        let d = (hi - lo).map(|x| x.max(0.0));
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    // Cost of the right side of each split, swept from the right.
    let mut right_cost = [0.0; SAH_BINS];
    let (mut right, mut n) = (EMPTY_BOX, 0);
    for k in (1..SAH_BINS).rev() {
        right = grown(right, bins[k]);
        n += counts[k];
        right_cost[k] = area(right) * n as f64;
    }
    let (mut left, mut n) = (EMPTY_BOX, 0);
    let mut best: Option<(f64, usize)> = None;
    for k in 1..SAH_BINS {
        left = grown(left, bins[k - 1]);
        n += counts[k - 1];
        let cost = area(left) * n as f64 + right_cost[k];
        if n > 0 && n < items.len() && best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, k));
        }
    }
    let (_, split) = best?;
    let mut left_len = 0;
    for i in 0..items.len() {
        if usize::from(items[i].bin) < split {
            items.swap(i, left_len);
            left_len += 1;
        }
    }
    let side = |range: std::ops::Range<usize>| {
        let union = |boxes: &[Aabb]| boxes.iter().fold(EMPTY_BOX, |a, &b| grown(a, b));
        (union(&bins[range.clone()]), union(&bin_centres[range]))
    };
    Some((left_len, side(0..split), side(split..SAH_BINS)))
}

/// The box around the boxes of `items`, and the box around their centres.
fn boxes_of(items: &[BuildItem]) -> BoxPair {
    items.iter().fold((EMPTY_BOX, EMPTY_BOX), |(b, c), item| {
        (grown(b, item.bounds), grown(c, (item.centre, item.centre)))
    })
}

/// A set of triangles' boxes: around the triangles, around their centres.
type BoxPair = (Aabb, Aabb);

/// An axis-aligned box: its lower and upper corners.
type Aabb = (Vec3, Vec3);

/// Half the diagonal of box `b`, rounded up by a relative 1e-12 so that the sphere through its
/// corners contains them whatever the rounding.
fn half_diagonal(b: &Aabb) -> f64 {
    0.5 * (b.1 - b.0).norm() * (1.0 + 1e-12)
}

/// The box around nothing, which any box grows from.
const EMPTY_BOX: Aabb = (
    Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
    Vec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY),
);

/// The box around boxes `a` and `b`.
#[inline]
fn grown(a: Aabb, b: Aabb) -> Aabb {
    let lo = |x: f64, y: f64| if y < x { y } else { x };
    let hi = |x: f64, y: f64| if y > x { y } else { x };
    (
        Vec3::new(lo(a.0.x, b.0.x), lo(a.0.y, b.0.y), lo(a.0.z, b.0.z)),
        Vec3::new(hi(a.1.x, b.1.x), hi(a.1.y, b.1.y), hi(a.1.z, b.1.z)),
    )
}

/// `v` normalized, or `fallback` when it has no direction (a collapsed triangle, or normals
/// of an inconsistent mesh that cancel).
fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    v.try_normalize(1e-300).unwrap_or(fallback)
}

/// Height where the vertical line through `(x, y)` crosses triangle `abc`, if it does, and the
/// change of winding number going up through it.
pub(super) fn vertical_crossing([a, b, c]: &[Point3; 3], x: f64, y: f64) -> Option<(f64, i32)> {
    // Barycentric coordinates of (x, y) in the triangle's projection on the xy plane.
    let det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if det.abs() < 1e-300 {
        return None;
    }
    let u = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
    let v = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
    let change = if det > 0.0 { -1 } else { 1 };
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0)
        .then(|| (a.z + u * (b.z - a.z) + v * (c.z - a.z), change))
}

/// Squared distance from `p` to a node's box.
fn box_distance_squared(node: &Node, p: &Point3) -> f64 {
    let d = Vec3::from_fn(|i, _| (node.min[i] - p[i]).max(p[i] - node.max[i]).max(0.0));
    d.norm_squared()
}

/// A query segment `a–b` with what every box and triangle test of one traversal would
/// otherwise compute again: its direction, the direction's reciprocals and its squared length's.
struct QuerySegment {
    a: Point3,
    b: Point3,
    direction: Vec3,
    /// 1 / direction, per axis; `None` along an axis the segment does not move along.
    reciprocal: [Option<f64>; 3],
    /// 1 / |direction|², 0 for a point.
    reciprocal_length_squared: f64,
}

impl QuerySegment {
    fn new(a: &Point3, b: &Point3) -> Self {
        let direction = b - a;
        let length_squared = direction.norm_squared();
        Self {
            a: *a,
            b: *b,
            direction,
            reciprocal: std::array::from_fn(|i| {
                (direction[i].abs() >= 1e-300).then(|| 1.0 / direction[i])
            }),
            reciprocal_length_squared: if length_squared > 0.0 {
                1.0 / length_squared
            } else {
                0.0
            },
        }
    }

    /// Squared distance from `p` to the segment.
    #[inline]
    fn distance_squared_to(&self, p: &Point3) -> f64 {
        let t =
            ((p - self.a).dot(&self.direction) * self.reciprocal_length_squared).clamp(0.0, 1.0);
        (self.a + self.direction * t - p).norm_squared()
    }

    /// Does the segment meet the box grown by `r` on every side? (slab test; a superset of "the
    /// capsule meets the box", which is all the traversal needs)
    #[inline]
    fn meets_box(&self, min: &Point3, max: &Point3, r: f64) -> bool {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for i in 0..3 {
            let (lo, hi) = (min[i] - r, max[i] + r);
            match self.reciprocal[i] {
                None => {
                    if self.a[i] < lo || self.a[i] > hi {
                        return false;
                    }
                }
                Some(inv) => {
                    let (mut ta, mut tb) = ((lo - self.a[i]) * inv, (hi - self.a[i]) * inv);
                    if ta > tb {
                        std::mem::swap(&mut ta, &mut tb);
                    }
                    // Plain comparisons, not `f64::max`/`min`, which also order NaNs: this runs
                    // on every node a capsule test visits. A NaN (a NaN capsule or box) leaves
                    // the interval as it was, and such a box is still met.
                    if ta > t0 {
                        t0 = ta;
                    }
                    if tb < t1 {
                        t1 = tb;
                    }
                    if t0 > t1 {
                        return false;
                    }
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A collapsed triangle (its corners on one line) has no plane: the nearest-point query
    /// must not skip it by the plane of its fallback normal.
    #[test]
    fn a_collapsed_triangle_is_found_at_its_distance() {
        let mesh = TriangleMesh {
            vertices: vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 1.0),
                Point3::new(2.0, 0.0, 2.0),
            ],
            triangles: vec![[0, 1, 2]],
        };
        let bvh = TriangleBvh::new(&mesh);
        // √2 from the line x = z; 2 from the plane z = 0 of the fallback normal.
        let found = bvh
            .closest_point_within(&Point3::new(0.0, 0.0, 2.0), 1.5)
            .expect("the triangle is within 1.5");
        assert!((found.signed_distance.abs() - 2f64.sqrt()).abs() < 1e-12);
    }

    /// The queries against every triangle, on a mesh the split heuristic builds a lopsided tree
    /// for: beside a sphere of even triangles, a row of triangles each half the size of the last
    /// and half as far from the row's end. The heuristic peels them off a few at a time, past its
    /// depth limit, below which the median must take over so that no traversal's stack
    /// overflows.
    #[test]
    fn queries_agree_with_every_triangle_on_a_lopsided_tree() {
        let mut mesh = crate::shapes::sphere(0.05, 24, 12);
        for k in 0..300 {
            let x = 0.1 + 0.2 * 0.5f64.powi(k);
            let base = mesh.vertices.len() as u32;
            let w = 0.01 * 0.5f64.powi(k);
            mesh.vertices.extend([
                Point3::new(x, 0.0, 0.0),
                Point3::new(x + w, w, 0.0),
                Point3::new(x, 0.0, w),
            ]);
            mesh.triangles.push([base, base + 1, base + 2]);
        }
        let bvh = TriangleBvh::new(&mesh);
        fn depth(bvh: &TriangleBvh, node: usize) -> usize {
            let n = bvh.nodes[node];
            if n.count > 0 {
                1
            } else {
                1 + depth(bvh, n.first as usize).max(depth(bvh, n.first as usize + 1))
            }
        }
        // Past the heuristic's limit (88 levels without it), within the traversals' stacks.
        let levels = depth(&bvh, 0);
        assert!(levels > MAX_SAH_DEPTH && levels < STACK, "{levels} levels");
        let mut rng = crate::random::SplitMix64::new(5);
        let mut point = || {
            Point3::new(
                rng.uniform(-0.08, 0.35),
                rng.uniform(-0.08, 0.08),
                rng.uniform(-0.08, 0.08),
            )
        };
        for _ in 0..300 {
            let (p, q) = (point(), point());
            let every = (0..mesh.triangles.len())
                .map(|t| {
                    let [a, b, c] = mesh.corners(t);
                    (crate::geometry::closest_point_on_triangle(&p, &a, &b, &c).0 - p).norm()
                })
                .fold(f64::INFINITY, f64::min);
            let found = bvh.closest_point_within(&p, 1.0).expect("within a metre");
            assert!((found.signed_distance.abs() - every).abs() < 1e-12);
            let d = bvh.segment_distance(&p, &q);
            for r in [0.5 * d, 0.999 * d, 1.001 * d + 1e-12] {
                assert_eq!(
                    bvh.segment_within(&p, &q, r),
                    d <= r,
                    "radius {r}, distance {d}"
                );
            }
            let (_, near) = bvh
                .closest_point_to_segment_within(&p, &q, 1.0)
                .expect("within a metre");
            assert!((near.signed_distance.abs() - d).abs() < 1e-12 || d == 0.0);
        }
    }

    /// A tree whose top is built on two threads and grafted is laid out as one thread builds
    /// it: walked left before right, its leaves hold consecutive runs of triangles covering
    /// each once; every child lies after its parent and inside its box.
    #[test]
    fn a_tree_built_side_by_side_covers_every_triangle_once_in_leaf_order() {
        let mesh = crate::shapes::torus(0.045, 0.014, 128, 64);
        assert!(mesh.triangles.len() > 4 * PARALLEL_ITEMS);
        let bvh = TriangleBvh::new(&mesh);
        let contains = |outer: &Node, inner_min: &Point3, inner_max: &Point3| {
            (0..3).all(|i| outer.min[i] <= inner_min[i] && inner_max[i] <= outer.max[i])
        };
        let (mut next, mut stack) = (0u32, vec![0usize]);
        while let Some(index) = stack.pop() {
            let node = bvh.nodes[index];
            if node.count > 0 {
                assert_eq!(node.first, next, "leaf {index} out of order");
                next += node.count;
                for corners in &bvh.corners[node.first as usize..next as usize] {
                    for p in corners {
                        assert!(contains(&node, p, p), "leaf {index} misses a corner");
                    }
                }
                continue;
            }
            let first = node.first as usize;
            assert!(first > index);
            for child in [first, first + 1] {
                let c = bvh.nodes[child];
                assert!(
                    contains(&node, &c.min, &c.max),
                    "node {child} outside {index}"
                );
            }
            stack.extend([first + 1, first]);
        }
        assert_eq!(next as usize, mesh.triangles.len());
    }

    /// Capsules many times a leaf's size, near a fine mesh, where the nodes' spheres cut off
    /// most of the leaves the grown boxes let through: the capsule test and the nearest point
    /// to a segment agree with every triangle, with radii just either side of the distance.
    #[test]
    fn capsules_near_a_fine_mesh_agree_with_every_triangle() {
        let mesh = crate::shapes::torus(0.045, 0.014, 128, 64);
        let bvh = TriangleBvh::new(&mesh);
        let mut rng = crate::random::SplitMix64::new(17);
        let mut unit = || {
            Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .normalize()
        };
        let mut touching = 0;
        for k in 0..200 {
            let [a, b, c] = mesh.corners(k * 73 % mesh.triangles.len());
            let on_surface = Point3::from((a.coords + b.coords + c.coords) / 3.0);
            let p = on_surface + unit() * (0.005 + 0.0001 * (k % 100) as f64);
            let q = p + unit() * (0.01 + 0.0003 * (k % 100) as f64);
            let d = bvh.segment_distance(&p, &q);
            for r in [0.999 * d, 1.001 * d + 1e-12] {
                let within = bvh.segment_within(&p, &q, r);
                assert_eq!(within, d <= r, "radius {r}, distance {d}");
                touching += usize::from(within);
            }
            if let Some((_, near)) = bvh.closest_point_to_segment_within(&p, &q, 0.03) {
                assert!((near.signed_distance.abs() - d).abs() < 1e-12 || d == 0.0);
            } else {
                assert!(d > 0.03, "distance {d} within the bound, not found");
            }
        }
        assert!(touching > 100, "{touching} touching");
    }

    /// Every node's slab holds all the corners of its triangles, and on a fine torus the
    /// leaves' slabs are thin beside their boxes (what makes them prune).
    #[test]
    fn each_node_slab_holds_its_triangles_and_a_fine_mesh_leaf_slab_is_thin() {
        let mesh = crate::shapes::torus(0.045, 0.014, 128, 64);
        let bvh = TriangleBvh::new(&mesh);
        // Each node's run of triangles, from its leaves (walked left before right).
        fn run(bvh: &TriangleBvh, index: usize) -> std::ops::Range<usize> {
            let node = bvh.nodes[index];
            if node.count > 0 {
                node.first as usize..(node.first + node.count) as usize
            } else {
                let first = node.first as usize;
                run(bvh, first).start..run(bvh, first + 1).end
            }
        }
        let (mut thin_leaves, mut leaves) = (0, 0);
        for (index, node) in bvh.nodes.iter().enumerate() {
            let slab = &bvh.slabs[index];
            let corners = &bvh.corners[run(&bvh, index)];
            if corners.len() > SLAB_MOST_TRIANGLES {
                assert!(
                    slab.segment_gap(&Point3::origin(), &Point3::origin()) == f64::NEG_INFINITY
                );
                continue;
            }
            for p in corners.iter().flatten() {
                assert!(
                    slab.segment_gap(p, p) <= 0.0,
                    "node {index}: a corner outside"
                );
            }
            if node.count > 0 {
                leaves += 1;
                // The slab's thickness: how far apart its two planes are.
                let centre = nalgebra::center(&node.min, &node.max);
                let thickness = -slab.segment_gap(&centre, &centre) * 2.0;
                thin_leaves += usize::from(thickness < 0.2 * 2.0 * node.reach);
            }
        }
        assert!(
            thin_leaves * 10 > leaves * 9,
            "{thin_leaves} of {leaves} leaves thin"
        );
    }

    /// Capsules lying along a fine mesh just clear of it or just touching, where the slabs end
    /// most visits: the capsule test agrees with every triangle.
    #[test]
    fn capsules_along_a_fine_mesh_agree_with_every_triangle() {
        let mesh = crate::shapes::torus(0.045, 0.014, 128, 64);
        let bvh = TriangleBvh::new(&mesh);
        let mut touching = 0;
        for k in 0..200 {
            let t = k * 97 % mesh.triangles.len();
            let [a, b, c] = mesh.corners(t);
            let normal = (b - a).cross(&(c - a)).normalize();
            let along = (b - a).normalize();
            let radius = 0.006 + 0.00002 * (k % 100) as f64;
            let on_surface = Point3::from((a.coords + b.coords + c.coords) / 3.0);
            let p = on_surface + normal * (radius + 0.0005) - along * 0.01;
            let q = p + along * 0.02;
            let d = bvh.segment_distance(&p, &q);
            for r in [0.999 * d, 1.001 * d + 1e-12, radius] {
                let within = bvh.segment_within(&p, &q, r);
                assert_eq!(within, d <= r, "radius {r}, distance {d}");
                touching += usize::from(within);
            }
        }
        assert!(touching > 200, "{touching} touching");
    }

    /// Nor may the capsule test: a capsule 0.1 from the collapsed triangle's line but 2 from the
    /// plane of its fallback normal touches it.
    #[test]
    fn a_capsule_touches_a_collapsed_triangle() {
        let mesh = TriangleMesh {
            vertices: vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(0.0, 0.0, 1.0),
                Point3::new(0.0, 0.0, 2.0),
            ],
            triangles: vec![[0, 1, 2]],
        };
        let bvh = TriangleBvh::new(&mesh);
        let (a, b) = (Point3::new(0.1, 0.0, 1.5), Point3::new(0.1, 0.5, 1.5));
        assert!(bvh.segment_within(&a, &b, 0.11));
        assert!(!bvh.segment_within(&a, &b, 0.09));
    }
}

//! Triangle meshes: welding by position, topology checks and mass properties.

use foldhash::{HashMap, HashMapExt};

use crate::edge_groups::{sorted_in_vertex_buckets, EdgeGroups};
use crate::math::{Point3, Vec3};

/// Largest number of triangles a mesh may have; larger inputs are refused rather than exhausting
/// memory.
pub const MAX_TRIANGLES: usize = 20_000_000;
/// Largest coordinate accepted, metres (1000 km): beyond it the units or scale are wrong, and
/// squared distances would lose all precision.
pub const MAX_COORDINATE: f64 = 1e6;

/// A triangle soup welded into an indexed mesh: vertices, and triangles as index triples.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions in metres.
    pub vertices: Vec<Point3>,
    /// Triangles as counter-clockwise (seen from outside) index triples into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// What is wrong with a mesh that is not a valid closed object.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The mesh has no triangles.
    #[error("the mesh has no triangles")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate {value:?}; fix or remove it in the source file")]
    NonFinite {
        /// Index of the vertex in the input.
        vertex: usize,
        /// The offending position.
        value: [f64; 3],
    },
    /// A coordinate lies farther than [`MAX_COORDINATE`] from the origin: no object is that far
    /// or that big; the units or the scale are wrong.
    #[error("vertex {vertex} lies at {value:?}, more than {MAX_COORDINATE} m from the origin; check the units (--units mm|cm|m) or --scale")]
    TooFar {
        /// Index of the vertex in the input.
        vertex: usize,
        /// The offending position.
        value: [f64; 3],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {index}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Triangle index.
        triangle: usize,
        /// The bad vertex index.
        index: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// More triangles than [`MAX_TRIANGLES`].
    #[error(
        "{count} triangles is more than the limit of {MAX_TRIANGLES}; decimate the mesh first"
    )]
    TooLarge {
        /// Number of triangles given.
        count: usize,
    },
}

/// The result of checking a welded mesh. A mesh is usable as a graspable object only when
/// [`MeshReport::defects`] is empty.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MeshReport {
    /// Number of triangles after welding.
    pub triangles: usize,
    /// Number of distinct vertices after welding.
    pub vertices: usize,
    /// Edges used by exactly one triangle (holes).
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges whose two triangles traverse them in the same direction (flipped winding).
    pub inconsistent_edges: usize,
    /// Edges traversed more often one way than the other. With none, the surface is closed and
    /// oriented as a whole — even if non-manifold or of overlapping parts — and its winding
    /// number is an integer everywhere off the surface.
    pub unbalanced_edges: usize,
    /// Triangles with (near) zero area.
    pub degenerate_triangles: usize,
    /// Enclosed volume in cubic metres (meaningful only for closed meshes; negative = inside out).
    pub volume: f64,
    /// Axis-aligned size in metres.
    pub size: [f64; 3],
    /// Lower corner of the bounding box.
    pub min: [f64; 3],
    /// Upper corner of the bounding box.
    pub max: [f64; 3],
    /// Each defect, with where it is (its message says how to fix it).
    pub defects: Vec<MeshDefect>,
}

impl std::fmt::Display for MeshReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.defects.is_empty() {
            return write!(f, "closed mesh");
        }
        for (i, d) in self.defects.iter().enumerate() {
            write!(f, "{}{d}", if i > 0 { "; " } else { "" })?;
        }
        Ok(())
    }
}

/// A defect that keeps a mesh from being one clean closed surface. Written to JSON as its
/// message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshDefect {
    /// Edges used by one triangle only: the mesh has holes.
    #[error("{edges} boundary edges (the mesh has holes), first at vertices {}–{}; close the holes (e.g. Blender: Select > All by Trait > Non Manifold, then Face > Fill)", first[0], first[1])]
    Holes {
        /// How many.
        edges: usize,
        /// The first one's vertices.
        first: [u32; 2],
    },
    /// Edges shared by more than two triangles.
    #[error("{edges} non-manifold edges (shared by more than two triangles), first at vertices {}–{}; split or remove the extra faces", first[0], first[1])]
    NonManifold {
        /// How many.
        edges: usize,
        /// The first one's vertices.
        first: [u32; 2],
    },
    /// Edges whose two triangles face opposite ways.
    #[error("{edges} edges with inconsistent winding (neighbouring triangles face opposite ways), first at vertices {}–{}; recalculate normals outside", first[0], first[1])]
    InconsistentWinding {
        /// How many.
        edges: usize,
        /// The first one's vertices.
        first: [u32; 2],
    },
    /// Triangles of (near) zero area.
    #[error("{triangles} degenerate (zero-area) triangles, first is triangle {first}; remove them in your modeller (prehensile grasp removes them itself by splitting neighbours, shape unchanged)")]
    Degenerate {
        /// How many.
        triangles: usize,
        /// The first one.
        first: usize,
    },
    /// A closed mesh wound inside out.
    #[error("the mesh is inside out (volume {volume:.3e} m³); flip all normals")]
    InsideOut {
        /// Its (negative) volume, m³.
        volume: f64,
    },
}

impl MeshDefect {
    /// The defect in a few words, without where or how to fix it.
    pub fn summary(&self) -> String {
        match self {
            Self::Holes { edges, .. } => format!("{edges} boundary edges (the mesh has holes)"),
            Self::NonManifold { edges, .. } => format!("{edges} non-manifold edges"),
            Self::InconsistentWinding { edges, .. } => {
                format!("{edges} edges with inconsistent winding")
            }
            Self::Degenerate { triangles, .. } => {
                format!("{triangles} degenerate (zero-area) triangles")
            }
            Self::InsideOut { .. } => "the mesh is inside out".to_string(),
        }
    }
}

impl serde::Serialize for MeshDefect {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// What [`TriangleMesh::drop_cancelling_triangles`] dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DroppedTriangles {
    /// Triangles with a vertex repeated.
    pub collapsed: usize,
    /// Pairs of coincident triangles wound opposite ways.
    pub cancelling_pairs: usize,
    /// Copies of a triangle wound the same way as one kept.
    pub duplicates: usize,
}

impl TriangleMesh {
    /// Welds a triangle list by exact position (coincident vertices become one), checks numbers and
    /// indices, and drops nothing. Use [`TriangleMesh::report`] to check topology.
    pub fn weld(positions: &[Point3], triangles: &[[usize; 3]]) -> Result<Self, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(MeshError::TooLarge {
                count: triangles.len(),
            });
        }
        for (i, p) in positions.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinite {
                    vertex: i,
                    value: [p.x, p.y, p.z],
                });
            }
            if p.iter().any(|c| c.abs() > MAX_COORDINATE) {
                return Err(MeshError::TooFar {
                    vertex: i,
                    value: [p.x, p.y, p.z],
                });
            }
        }
        let mut remap = Vec::with_capacity(positions.len());
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
        let mut vertices = Vec::new();
        for p in positions {
            // +0.0 and -0.0 weld together.
            let key = [p.x + 0.0, p.y + 0.0, p.z + 0.0].map(f64::to_bits);
            let id = *seen.entry(key).or_insert_with(|| {
                vertices.push(*p);
                (vertices.len() - 1) as u32
            });
            remap.push(id);
        }
        let mut out = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let mut welded = [0u32; 3];
            for (k, &i) in tri.iter().enumerate() {
                welded[k] = *remap.get(i).ok_or(MeshError::IndexOutOfRange {
                    triangle: t,
                    index: i,
                    vertex_count: positions.len(),
                })?;
            }
            out.push(welded);
        }
        Ok(Self {
            vertices,
            triangles: out,
        })
    }

    /// Merges vertices closer than `tolerance` metres (each joins the first vertex within reach,
    /// found through a hash grid of cell `tolerance`) and drops triangles that collapse. An
    /// explicit repair for scans whose seams are a hair apart; returns the mesh and how many
    /// vertices were merged.
    pub fn weld_within(&self, tolerance: f64) -> (Self, usize) {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return (self.clone(), 0);
        }
        let cell = |p: &Point3| [p.x, p.y, p.z].map(|c| (c / tolerance).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut vertices: Vec<Point3> = Vec::new();
        let mut remap = Vec::with_capacity(self.vertices.len());
        for p in &self.vertices {
            let c = cell(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                            if let Some(&k) = list
                                .iter()
                                .find(|&&k| (vertices[k as usize] - p).norm() <= tolerance)
                            {
                                found = Some(k);
                                break 'search;
                            }
                        }
                    }
                }
            }
            let id = found.unwrap_or_else(|| {
                vertices.push(*p);
                let id = (vertices.len() - 1) as u32;
                grid.entry(c).or_default().push(id);
                id
            });
            remap.push(id);
        }
        let merged = self.vertices.len() - vertices.len();
        let triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        (
            Self {
                vertices,
                triangles,
            },
            merged,
        )
    }

    /// Returns a copy with every vertex multiplied by `factor`.
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            vertices: self.vertices.iter().map(|p| p * factor).collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [Point3; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Point3, Point3) {
        let mut lo = Point3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = Point3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
        for t in &self.triangles {
            for &i in t {
                let p = self.vertices[i as usize];
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        (lo, hi)
    }

    /// Signed enclosed volume and centre of mass (uniform density) by the divergence theorem.
    pub fn volume_and_centroid(&self) -> (f64, Point3) {
        let (volume, moment) = self.volume_and_moment(0..self.triangles.len());
        let centroid = if volume.abs() > 0.0 {
            Point3::from(moment / volume)
        } else {
            let (lo, hi) = self.bounds();
            nalgebra::center(&lo, &hi)
        };
        (volume, centroid)
    }

    /// Signed volume and its first moment over the triangles `triangles` (indices).
    fn volume_and_moment(&self, triangles: impl IntoIterator<Item = usize>) -> (f64, Vec3) {
        let mut volume = 0.0;
        let mut moment = Vec3::zeros();
        for t in triangles {
            let [a, b, c] = self.corners(t);
            let v = a.coords.dot(&b.coords.cross(&c.coords)) / 6.0;
            volume += v;
            moment += (a.coords + b.coords + c.coords) * (v / 4.0);
        }
        (volume, moment)
    }

    /// The connected parts (triangles sharing vertices), each as its triangle indices, largest
    /// volume first.
    pub fn components(&self) -> Vec<Vec<usize>> {
        // Union–find over vertices.
        let mut parent: Vec<u32> = (0..self.vertices.len() as u32).collect();
        fn find(parent: &mut [u32], mut v: u32) -> u32 {
            while parent[v as usize] != v {
                parent[v as usize] = parent[parent[v as usize] as usize];
                v = parent[v as usize];
            }
            v
        }
        for tri in &self.triangles {
            let a = find(&mut parent, tri[0]);
            for &v in &tri[1..] {
                let b = find(&mut parent, v);
                parent[b as usize] = a;
            }
        }
        let mut by_root: HashMap<u32, Vec<usize>> = HashMap::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            by_root
                .entry(find(&mut parent, tri[0]))
                .or_default()
                .push(t);
        }
        let mut parts: Vec<(f64, Vec<usize>)> = by_root
            .into_values()
            // Each part's volume from its own triangles: a copy of the vertices per part made
            // a soup of 100,000 triangles take minutes.
            .map(|ts| (self.volume_and_moment(ts.iter().copied()).0, ts))
            .collect();
        parts.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1[0].cmp(&b.1[0])));
        parts.into_iter().map(|(_, ts)| ts).collect()
    }

    /// Indices of (near) zero-area triangles: area below 1e-12 of the squared bounding diagonal or
    /// 1e-9 of the squared longest edge.
    pub fn degenerate_triangles(&self) -> Vec<usize> {
        let (lo, hi) = self.bounds();
        let diag = (hi - lo).norm();
        (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = self.corners(t);
                let area2 = (b - a).cross(&(c - a)).norm();
                let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
                area2 <= 1e-12 * diag * diag || area2 <= 1e-9 * longest * longest
            })
            .collect()
    }

    /// Drops triangles that add nothing to the surface: collapsed triangles (a vertex repeated),
    /// pairs of coincident triangles wound opposite ways (they cancel; scans have them as slivers
    /// of a fraction of a square millimetre), and copies of a triangle wound the same way as one
    /// kept (the surface counted once: each copy would add the triangle's solid angle to the
    /// winding number again, and a crafted file of millions of copies of one face made every
    /// inside test visit all of them). Returns the mesh and what was dropped.
    pub fn drop_cancelling_triangles(&self) -> (Self, DroppedTriangles) {
        let mut dead = vec![false; self.triangles.len()];
        let mut collapsed = 0;
        for (t, &[a, b, c]) in self.triangles.iter().enumerate() {
            if a == b || b == c || c == a {
                dead[t] = true;
                collapsed += 1;
            }
        }
        // Each other triangle under its sorted vertex set, with its winding's parity, bucketed
        // by its lowest vertex and sorted, so that the triangles on one vertex set lie together
        // in their order (buckets, not a map of lists: a million small lists were a quarter of
        // a million-triangle setup; nor one sort of all).
        let (by_set, _) = sorted_in_vertex_buckets(&self.triangles, |t, tri| {
            let [a, b, c] = tri;
            let mut key = tri;
            key.sort_unstable();
            // Even permutations of the sorted order keep the winding.
            let rotation = [[a, b, c], [b, c, a], [c, a, b]];
            let kept = !dead[t];
            kept.then_some((key[0], (key, t, rotation.contains(&key))))
                .into_iter()
        });
        let (mut pairs, mut duplicates) = (0, 0);
        for list in by_set.chunk_by(|x, y| x.0 == y.0) {
            // The k-th triangle wound one way cancels the k-th wound the other way, in mesh
            // order: one pass, so a crafted mesh of many copies of one triangle stays linear.
            let up = list.iter().filter(|x| x.2).map(|x| x.1);
            let down = list.iter().filter(|x| !x.2).map(|x| x.1);
            for (u, d) in up.clone().zip(down.clone()) {
                dead[u] = true;
                dead[d] = true;
                pairs += 1;
            }
            // Of those left over (all wound the way more of them are), the first stays.
            let (ups, downs) = (up.count(), down.count());
            let left_over = list
                .iter()
                .filter(|x| x.2 == (ups > downs))
                .skip(ups.min(downs) + 1);
            for x in left_over {
                dead[x.1] = true;
                duplicates += 1;
            }
        }
        let triangles = self
            .triangles
            .iter()
            .zip(&dead)
            .filter(|(_, d)| !**d)
            .map(|(t, _)| *t)
            .collect();
        (
            Self {
                vertices: self.vertices.clone(),
                triangles,
            },
            DroppedTriangles {
                collapsed,
                cancelling_pairs: pairs,
                duplicates,
            },
        )
    }

    /// Removes zero-area triangles without changing the shape: a triangle with a repeated vertex
    /// is dropped (its two neighbours then share the edge); a sliver whose middle vertex lies on
    /// its longest edge is dropped and the neighbour across that edge is split at the middle
    /// vertex. A closed, manifold, consistently wound mesh stays so. Returns the repaired mesh
    /// and how many triangles were removed.
    pub fn remove_degenerate_triangles(&self) -> (Self, usize) {
        let mut mesh = self.clone();
        let mut removed = 0;
        for _pass in 0..8 {
            let bad = mesh.degenerate_triangles();
            if bad.is_empty() {
                break;
            }
            let mut dead = vec![false; mesh.triangles.len()];
            let mut added: Vec<[u32; 3]> = Vec::new();
            let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
            for (t, tri) in mesh.triangles.iter().enumerate() {
                for k in 0..3 {
                    directed.insert((tri[k], tri[(k + 1) % 3]), t);
                }
            }
            for t in bad {
                if dead[t] {
                    continue;
                }
                let tri = mesh.triangles[t];
                if tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] {
                    dead[t] = true;
                    removed += 1;
                    continue;
                }
                // Longest edge (a, b) and the middle vertex c.
                let k = (0..3)
                    .max_by(|&i, &j| {
                        let len = |e: usize| {
                            (mesh.vertices[tri[e] as usize]
                                - mesh.vertices[tri[(e + 1) % 3] as usize])
                                .norm()
                        };
                        len(i).total_cmp(&len(j))
                    })
                    .expect("three edges");
                let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let Some(&n) = directed.get(&(b, a)) else {
                    continue;
                };
                if dead[n] || n == t {
                    continue;
                }
                let nt = mesh.triangles[n];
                // A neighbour collapsed onto the edge has no third vertex: leave it to the check.
                let Some(&x) = nt.iter().find(|&&v| v != a && v != b) else {
                    continue;
                };
                dead[t] = true;
                dead[n] = true;
                added.push([b, c, x]);
                added.push([c, a, x]);
                removed += 1;
            }
            let mut kept: Vec<[u32; 3]> = mesh
                .triangles
                .iter()
                .enumerate()
                .filter(|(t, _)| !dead[*t])
                .map(|(_, tri)| *tri)
                .collect();
            kept.extend(added);
            mesh.triangles = kept;
        }
        (mesh, removed)
    }

    /// The same mesh with every triangle wound the other way (an inside-out mesh turned out).
    pub fn flipped(&self) -> Self {
        Self {
            vertices: self.vertices.clone(),
            triangles: self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
        }
    }

    /// Turns the triangles that disagree with their neighbours, so that every edge is traversed
    /// once each way: the exact repair of "recalculate normals" for a closed manifold mesh. In
    /// each connected part the majority's winding is kept (so an inward-wound cavity stays a
    /// cavity). Returns the mesh and how many triangles were turned, or `None` when some edge is
    /// not shared by exactly two triangles or the surface cannot be oriented (a Möbius strip).
    pub fn oriented(&self) -> Option<(Self, usize)> {
        let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                edges.entry((u.min(v), u.max(v))).or_default().push(t);
            }
        }
        if edges.values().any(|faces| faces.len() != 2) {
            return None;
        }
        // Does triangle t run along edge (u, v) from u to v?
        let forward = |t: usize, u: u32, v: u32| {
            let tri = self.triangles[t];
            (0..3).any(|k| tri[k] == u && tri[(k + 1) % 3] == v)
        };
        let mut flip: Vec<Option<bool>> = vec![None; self.triangles.len()];
        let mut turned = 0;
        for seed in 0..self.triangles.len() {
            if flip[seed].is_some() {
                continue;
            }
            flip[seed] = Some(false);
            let mut part = vec![seed];
            let mut queue = std::collections::VecDeque::from([seed]);
            while let Some(t) = queue.pop_front() {
                let tri = self.triangles[t];
                for k in 0..3 {
                    let (u, v) = (tri[k], tri[(k + 1) % 3]);
                    let faces = &edges[&(u.min(v), u.max(v))];
                    let other = if faces[0] == t { faces[1] } else { faces[0] };
                    // The neighbour must run the edge the other way once both are turned.
                    let t_runs_u_to_v = !flip[t]?;
                    let wanted = forward(other, u, v) == t_runs_u_to_v;
                    match flip[other] {
                        None => {
                            flip[other] = Some(wanted);
                            part.push(other);
                            queue.push_back(other);
                        }
                        Some(f) if f != wanted => return None,
                        Some(_) => {}
                    }
                }
            }
            let flipped = part.iter().filter(|&&t| flip[t] == Some(true)).count();
            if 2 * flipped > part.len() {
                for &t in &part {
                    flip[t] = flip[t].map(|f| !f);
                }
            }
            turned += flipped.min(part.len() - flipped);
        }
        let triangles = (self.triangles.iter().zip(&flip))
            .map(|(&[a, b, c], f)| {
                if *f == Some(true) {
                    [a, c, b]
                } else {
                    [a, b, c]
                }
            })
            .collect();
        let mesh = Self {
            vertices: self.vertices.clone(),
            triangles,
        };
        Some((mesh, turned))
    }

    /// The mesh without the vertices no triangle uses, the others kept in their order, and how
    /// many were dropped. A stray vertex far from the surface changes no triangle, but it would
    /// stretch everything taken over the vertices: the simulation's convex hull of the object,
    /// the search's widths, a picture's frame.
    pub fn without_unused_vertices(self) -> (Self, usize) {
        let mut used = vec![false; self.vertices.len()];
        for &i in self.triangles.iter().flatten() {
            used[i as usize] = true;
        }
        let unused = used.iter().filter(|&&u| !u).count();
        if unused == 0 {
            return (self, 0);
        }
        let mut index = vec![u32::MAX; self.vertices.len()];
        let mut vertices = Vec::with_capacity(self.vertices.len() - unused);
        for (i, p) in self.vertices.iter().enumerate() {
            if used[i] {
                index[i] = vertices.len() as u32;
                vertices.push(*p);
            }
        }
        let triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|i| index[i as usize]))
            .collect();
        (
            Self {
                vertices,
                triangles,
            },
            unused,
        )
    }

    /// The mesh without its (near) zero-area triangles, and how many were dropped. Unlike
    /// [`TriangleMesh::remove_degenerate_triangles`] it does not mend the neighbours, so a closed
    /// mesh may open: for meshes whose inside comes from winding numbers, which a zero-area
    /// triangle does not change.
    pub fn without_degenerate_triangles(&self) -> (Self, usize) {
        let degenerate = self.degenerate_triangles();
        let mut dead = vec![false; self.triangles.len()];
        for &t in &degenerate {
            dead[t] = true;
        }
        let triangles = (self.triangles.iter().zip(&dead))
            .filter(|(_, &d)| !d)
            .map(|(t, _)| *t)
            .collect();
        let mesh = Self {
            vertices: self.vertices.clone(),
            triangles,
        };
        (mesh, degenerate.len())
    }

    /// Every edge (lower vertex index first), in order, with how many triangles run along it from
    /// the lower index to the higher and how many the other way. A collapsed triangle's edge from
    /// a vertex to itself is no edge.
    fn edge_uses(&self) -> Vec<((u32, u32), (u32, u32))> {
        EdgeGroups::new(&self.triangles)
            .iter()
            .filter(|((u, v), _)| u != v)
            .map(|(ends, corners)| {
                let forward = corners.forward() as u32;
                (ends, (forward, corners.len() as u32 - forward))
            })
            .collect()
    }

    /// The edges along which the triangles do not cancel (a hole's rim, a non-manifold or a
    /// flipped edge): the boundary of the surface, which alone keeps its winding number from
    /// being a whole number. Each edge runs the way more triangles run along it, with how many
    /// more; sorted, so the same mesh gives the same list.
    pub fn unbalanced_edges(&self) -> Vec<([u32; 2], u32)> {
        let mut edges: Vec<_> = self
            .edge_uses()
            .into_iter()
            .filter(|(_, (fwd, back))| fwd != back)
            .map(|((u, v), (fwd, back))| {
                let ends = if fwd > back { [u, v] } else { [v, u] };
                (ends, fwd.abs_diff(back))
            })
            .collect();
        edges.sort_unstable();
        edges
    }

    /// Checks topology and geometry: closed, manifold, consistently wound, no degenerate
    /// triangles, positive volume. Every defect names where it is and how to fix it.
    pub fn report(&self) -> MeshReport {
        let (lo, hi) = self.bounds();
        let size = hi - lo;
        // To find boundary, non-manifold and flipped edges.
        let edges = self.edge_uses();
        let degenerate = self.degenerate_triangles();
        let mut boundary = Vec::new();
        let mut non_manifold = Vec::new();
        let mut inconsistent = Vec::new();
        let unbalanced_edges = edges.iter().filter(|(_, (fwd, back))| fwd != back).count();
        for &((u, v), (fwd, back)) in &edges {
            match fwd + back {
                1 => boundary.push((u, v)),
                2 if fwd != 1 => inconsistent.push((u, v)),
                2 => {}
                _ => non_manifold.push((u, v)),
            }
        }
        boundary.sort_unstable();
        non_manifold.sort_unstable();
        inconsistent.sort_unstable();
        let (volume, _) = self.volume_and_centroid();
        let mut defects = Vec::new();
        let first = |v: &[(u32, u32)]| [v[0].0, v[0].1];
        if !boundary.is_empty() {
            defects.push(MeshDefect::Holes {
                edges: boundary.len(),
                first: first(&boundary),
            });
        }
        if !non_manifold.is_empty() {
            defects.push(MeshDefect::NonManifold {
                edges: non_manifold.len(),
                first: first(&non_manifold),
            });
        }
        if !inconsistent.is_empty() {
            defects.push(MeshDefect::InconsistentWinding {
                edges: inconsistent.len(),
                first: first(&inconsistent),
            });
        }
        if !degenerate.is_empty() {
            defects.push(MeshDefect::Degenerate {
                triangles: degenerate.len(),
                first: degenerate[0],
            });
        }
        if defects.is_empty() && volume <= 0.0 {
            defects.push(MeshDefect::InsideOut { volume });
        }
        MeshReport {
            triangles: self.triangles.len(),
            vertices: self.vertices.len(),
            boundary_edges: boundary.len(),
            non_manifold_edges: non_manifold.len(),
            inconsistent_edges: inconsistent.len(),
            unbalanced_edges,
            degenerate_triangles: degenerate.len(),
            volume,
            size: [size.x, size.y, size.z],
            min: [lo.x, lo.y, lo.z],
            max: [hi.x, hi.y, hi.z],
            defects,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> (Vec<Point3>, Vec<[usize; 3]>) {
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        (v, t)
    }

    #[test]
    fn tetrahedron_is_closed_with_known_volume() {
        let (v, t) = tetra();
        let m = TriangleMesh::weld(&v, &t).unwrap();
        let r = m.report();
        assert!(r.defects.is_empty(), "{:?}", r.defects);
        assert!((r.volume - 1.0 / 6.0).abs() < 1e-12);
        let (_, c) = m.volume_and_centroid();
        assert!((c - Point3::new(0.25, 0.25, 0.25)).norm() < 1e-12);
    }

    #[test]
    fn welding_joins_duplicate_positions() {
        let (v, t) = tetra();
        // Unshare every vertex: 12 positions, 4 triangles.
        let mut soup = Vec::new();
        let mut tris = Vec::new();
        for tri in &t {
            tris.push([soup.len(), soup.len() + 1, soup.len() + 2]);
            soup.extend(tri.iter().map(|&i| v[i]));
        }
        let m = TriangleMesh::weld(&soup, &tris).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert!(m.report().defects.is_empty());
    }

    #[test]
    fn open_mesh_names_boundary_edges() {
        let (v, mut t) = tetra();
        t.pop();
        let r = TriangleMesh::weld(&v, &t).unwrap().report();
        assert_eq!(r.boundary_edges, 3);
        assert!(
            r.defects[0].to_string().contains("3 boundary edges"),
            "{}",
            r.defects[0]
        );
    }

    #[test]
    fn flipped_triangle_is_inconsistent() {
        let (v, mut t) = tetra();
        t[3] = [1, 3, 2];
        let r = TriangleMesh::weld(&v, &t).unwrap().report();
        assert_eq!(r.inconsistent_edges, 3);
    }

    #[test]
    fn non_manifold_and_degenerate_are_found() {
        let (mut v, mut t) = tetra();
        t.push([0, 1, 3]);
        let r = TriangleMesh::weld(&v, &t).unwrap().report();
        assert!(r.non_manifold_edges >= 1);
        v.push(Point3::new(2.0, 0.0, 0.0));
        let (v2, _) = tetra();
        let mut t2 = vec![[0usize, 1, 4]];
        t2.extend(tetra().1);
        let mut v3 = v2.clone();
        v3.push(Point3::new(0.5, 0.0, 0.0));
        let r = TriangleMesh::weld(&v3, &t2).unwrap().report();
        assert_eq!(r.degenerate_triangles, 1);
    }

    #[test]
    fn slivers_are_removed_and_the_mesh_stays_closed() {
        // A square pyramid whose base edge 0-1 carries a sliver (0, 1, 5) with vertex 5 on it:
        // the base triangle (1, 0, 2)... built as a closed mesh by hand.
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.5, 0.5, 1.0),
            Point3::new(0.5, 0.0, 0.0),
        ];
        // Side 0-1 is split at 5 on the side face, but the base still uses edge 1-0 whole, and the
        // sliver (0, 5, 1) seen from below closes the crack.
        let t = vec![
            [0, 5, 4],
            [5, 1, 4],
            [1, 2, 4],
            [2, 3, 4],
            [3, 0, 4],
            [0, 2, 1],
            [0, 3, 2],
            [0, 1, 5],
        ];
        let m = TriangleMesh::weld(&v, &t).unwrap();
        let r = m.report();
        assert_eq!(r.degenerate_triangles, 1, "{:?}", r.defects);
        assert_eq!(
            r.boundary_edges + r.non_manifold_edges + r.inconsistent_edges,
            0,
            "{:?}",
            r.defects
        );
        let (fixed, removed) = m.remove_degenerate_triangles();
        assert_eq!(removed, 1);
        let r2 = fixed.report();
        assert!(r2.defects.is_empty(), "{:?}", r2.defects);
        assert!((r2.volume - r.volume).abs() < 1e-12);
    }

    #[test]
    fn collapsed_triangles_and_cancelling_pairs_are_dropped_exactly() {
        // The tetrahedron with, as a scan has them, a collapsed triangle and a coincident pair
        // wound opposite ways.
        let (mut p, mut t) = tetra();
        p.push(Point3::new(0.3, 0.3, 0.0));
        let extra = p.len() - 1;
        t.push([0, 0, 1]);
        t.push([0, 1, extra]);
        t.push([1, 0, extra]);
        let mesh = TriangleMesh::weld(&p, &t).unwrap();
        assert!(!mesh.report().defects.is_empty());
        let (fixed, dropped) = mesh.drop_cancelling_triangles();
        assert_eq!((dropped.collapsed, dropped.cancelling_pairs), (1, 1));
        let clean = TriangleMesh::weld(&tetra().0, &tetra().1).unwrap();
        assert_eq!(fixed.triangles, clean.triangles);
        assert!(fixed.report().defects.is_empty());
        // Two copies wound the same way do not cancel: one stays.
        let (mut p, mut t) = tetra();
        t.push(t[0]);
        p.push(Point3::origin());
        let (fixed, dropped) = TriangleMesh::weld(&p, &t)
            .unwrap()
            .drop_cancelling_triangles();
        assert_eq!((dropped.cancelling_pairs, dropped.duplicates), (0, 1));
        assert_eq!(fixed.triangles, clean.triangles);
        // A crafted mesh of 200,000 copies of one face, wound both ways in turn plus one more
        // one way: every pair cancels, in one pass over them (the pairing used to rescan the
        // copies for every pair, quadratic in their number).
        // The tetrahedron and `n` more copies of its first face, copy k turned if `turned(k)`.
        let with_copies = |n: usize, turned: &dyn Fn(usize) -> bool| {
            let (p, mut t) = tetra();
            let face = t[0];
            for k in 0..n {
                t.push(if turned(k) {
                    [face[0], face[2], face[1]]
                } else {
                    face
                });
            }
            TriangleMesh::weld(&p, &t)
                .unwrap()
                .drop_cancelling_triangles()
        };
        let (fixed, dropped) = with_copies(200_001, &|k| k % 2 == 0);
        assert_eq!(dropped.cancelling_pairs, 100_001);
        assert_eq!(dropped.duplicates, 0);
        assert_eq!(fixed.triangles.len(), 4 - 1 + 200_001 - 2 * 100_001 + 1);
        // 200,000 copies wound one way and 3 the other: 3 pairs cancel, one copy stays.
        let (fixed, dropped) = with_copies(200_003, &|k| k < 3);
        assert_eq!(dropped.cancelling_pairs, 3);
        assert_eq!(dropped.duplicates, 200_000 + 1 - 3 - 1);
        let sorted = |mut t: Vec<[u32; 3]>| {
            t.sort_unstable();
            t
        };
        assert_eq!(
            sorted(fixed.triangles.clone()),
            sorted(clean.triangles.clone())
        );
        assert!(fixed.report().defects.is_empty());
    }

    #[test]
    fn nan_and_bad_index_are_errors() {
        let (mut v, t) = tetra();
        v[2].y = f64::NAN;
        assert!(matches!(
            TriangleMesh::weld(&v, &t),
            Err(MeshError::NonFinite { vertex: 2, .. })
        ));
        let (v, mut t) = tetra();
        t[1][2] = 9;
        assert!(matches!(
            TriangleMesh::weld(&v, &t),
            Err(MeshError::IndexOutOfRange {
                triangle: 1,
                index: 9,
                ..
            })
        ));
        assert_eq!(TriangleMesh::weld(&v, &[]), Err(MeshError::Empty));
    }

    #[test]
    fn inside_out_mesh_is_reported() {
        let (v, t) = tetra();
        let flipped: Vec<[usize; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let r = TriangleMesh::weld(&v, &flipped).unwrap().report();
        assert!(r
            .defects
            .iter()
            .any(|d| matches!(d, MeshDefect::InsideOut { .. })));
    }
}

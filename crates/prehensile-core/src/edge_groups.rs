//! A triangle mesh's edges, each with the triangle corners that run along it, grouped by a
//! counting sort on the lower vertex.
//!
//! Written by hand because the mesh report and the pseudo-normals both need every edge's triangles
//! in mesh order, and the general tools cost several times more on a scan: a hash map of edges (a
//! third of a million-triangle setup once went to one) or a sort of all `3n` corners (an eighth of
//! a 16k-triangle setup's instructions). Bucketing by the lower vertex is linear; each bucket holds
//! about a vertex's valence of corners, sorted where it lies. The bucketing,
//! [`sorted_in_vertex_buckets`], also groups the triangles on one vertex set for
//! [`TriangleMesh::drop_cancelling_triangles`](crate::TriangleMesh::drop_cancelling_triangles).

/// Every edge of a list of triangles with the corners (`3 · triangle + k`, the edge from corner
/// `k` to corner `k + 1`) that run along it either way, in mesh order.
pub(crate) struct EdgeGroups {
    /// `(higher vertex, 2 · corner + 1 if it runs from the lower vertex to the higher)` of every
    /// corner's edge, in buckets by lower vertex, each bucket sorted: an edge's corners lie
    /// together in mesh order.
    entries: Vec<(u32, u32)>,
    /// Where each lower vertex's bucket starts in `entries`, and where the last one ends.
    starts: Vec<u32>,
}

impl EdgeGroups {
    /// Groups the edges of `triangles`. A collapsed triangle's edge from a vertex to itself is
    /// an edge `(v, v)` of its own.
    pub(crate) fn new(triangles: &[[u32; 3]]) -> Self {
        let (entries, starts) = sorted_in_vertex_buckets(triangles, |t, tri| {
            (0..3).map(move |k| {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                let corner = (3 * t + k) as u32;
                (u.min(v), (u.max(v), 2 * corner + u32::from(u < v)))
            })
        });
        Self { entries, starts }
    }

    /// Every edge once, ordered by its vertices: `(lower, higher)` and its corners in mesh
    /// order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = ((u32, u32), Corners<'_>)> + '_ {
        self.starts
            .windows(2)
            .enumerate()
            .flat_map(|(lower, bucket)| {
                self.entries[bucket[0] as usize..bucket[1] as usize]
                    .chunk_by(|x, y| x.0 == y.0)
                    .map(move |run| ((lower as u32, run[0].0), Corners(run)))
            })
    }
}

/// The corners along one edge (see [`EdgeGroups::iter`]).
#[derive(Clone, Copy)]
pub(crate) struct Corners<'a>(&'a [(u32, u32)]);

impl Corners<'_> {
    /// Each corner as `(triangle, k)`: the triangle's edge from corner `k` to corner `k + 1`.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.0.iter().map(|&(_, code)| {
            let corner = code as usize / 2;
            (corner / 3, corner % 3)
        })
    }

    /// How many of the corners run from the lower vertex to the higher.
    pub(crate) fn forward(&self) -> usize {
        self.0.iter().filter(|&&(_, code)| code % 2 == 1).count()
    }

    /// How many corners run along the edge.
    pub(crate) fn len(&self) -> usize {
        self.0.len()
    }
}

/// The items that `items_of` gives for each triangle (its index and corners), each under a
/// vertex of that triangle: bucketed by the vertex with a counting sort (stable, linear), each
/// bucket then sorted. Returns the items and where each vertex's bucket starts (and the last
/// ends). `items_of` is called again in each pass rather than its items kept in a list: that
/// list cost more than the calls (`EdgeGroups::new` 18 M → 33 M instructions over three setups
/// of the 16k torus).
pub(crate) fn sorted_in_vertex_buckets<T, I>(
    triangles: &[[u32; 3]],
    items_of: impl Fn(usize, [u32; 3]) -> I,
) -> (Vec<T>, Vec<u32>)
where
    T: Ord + Copy,
    I: Iterator<Item = (u32, T)>,
{
    let vertex_count = triangles
        .iter()
        .flatten()
        .max()
        .map_or(0, |&v| v as usize + 1);
    let mut starts = vec![0u32; vertex_count + 1];
    let mut len = 0;
    for (t, &tri) in triangles.iter().enumerate() {
        for (vertex, _) in items_of(t, tri) {
            starts[vertex as usize + 1] += 1;
            len += 1;
        }
    }
    for v in 0..vertex_count {
        starts[v + 1] += starts[v];
    }
    // Any item fills the list before each is written to its place (no `Default` needed).
    let Some((_, filler)) =
        (triangles.iter().enumerate()).find_map(|(t, &tri)| items_of(t, tri).next())
    else {
        return (Vec::new(), starts);
    };
    let mut sorted = vec![filler; len];
    let mut next = starts.clone();
    for (t, &tri) in triangles.iter().enumerate() {
        for (vertex, item) in items_of(t, tri) {
            let at = &mut next[vertex as usize];
            sorted[*at as usize] = item;
            *at += 1;
        }
    }
    for bucket in starts.windows(2) {
        sorted[bucket[0] as usize..bucket[1] as usize].sort_unstable();
    }
    (sorted, starts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_edge_lists_its_corners_in_mesh_order() {
        // Two triangles sharing edge 1–2 (run both ways), a third that repeats vertex 3.
        let groups = EdgeGroups::new(&[[0, 1, 2], [2, 1, 3], [3, 3, 0]]);
        let edges: Vec<(_, Vec<_>)> = groups
            .iter()
            .map(|(ends, corners)| (ends, corners.iter().collect()))
            .collect();
        assert_eq!(
            edges,
            vec![
                ((0, 1), vec![(0, 0)]),
                ((0, 2), vec![(0, 2)]),
                ((0, 3), vec![(2, 1), (2, 2)]),
                ((1, 2), vec![(0, 1), (1, 0)]),
                ((1, 3), vec![(1, 1)]),
                ((2, 3), vec![(1, 2)]),
                ((3, 3), vec![(2, 0)]),
            ]
        );
        let forward: Vec<(usize, usize)> = groups
            .iter()
            .map(|(_, corners)| (corners.forward(), corners.len()))
            .collect();
        assert_eq!(
            forward,
            vec![(1, 1), (0, 1), (1, 2), (1, 2), (1, 1), (0, 1), (0, 1)]
        );
        assert_eq!(EdgeGroups::new(&[]).iter().count(), 0);
    }
}

//! Convex hull of points in `D` dimensions (incremental beneath–beyond with simplicial facets),
//! for the 6-D grasp wrench space.
//!
//! Written by hand because no well-kept pure-Rust crate builds hulls above three dimensions: the
//! `qhull` bindings compile C, capture errors through temporary files and do not build for
//! wasm32, and `chull` supports 2-D and 3-D only. Checked against scipy's Qhull
//! (`tools/oracle/stability_oracle.py`) to 1e-9 on 6-D wrench sets.
//!
//! Each point is added in turn: the facets it sees are removed and every ridge on the border of
//! the removed set (the horizon) is joined to the point. Facets know their neighbours, so the
//! horizon is read off the seen facets' links, and a new facet's plane comes from the pencil of
//! its horizon ridge (a combination of the two old facets' planes that passes through the
//! point), checked against its vertices and solved afresh by elimination when it strays.
//!
//! Wrench sets are full of coplanar points (a friction cone's edges), where rounding can make a
//! point "see" a set of facets with holes and leave a hull that is not convex; so, as Qhull's
//! `QJ` option does, the input is first joggled by 1e-10 of its size (deterministically, far
//! above the 1e-13 within which a point counts as on a facet), and the result is checked
//! (closed, every point inside every facet) and rebuilt with a ten times larger joggle if it
//! fails. Buffers are kept between calls: a warm hull allocates only when it grows larger than
//! before.

/// One facet: `D` vertices (indices into the input, sorted), the unit outward normal and the
/// offset, so that every point `x` of the hull has `normal · x <= offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HullFacet<const D: usize> {
    /// Input indices of the facet's vertices, ascending.
    pub vertices: [u32; D],
    /// Unit outward normal.
    pub normal: [f64; D],
    /// Signed distance of the hyperplane from the origin along `normal`.
    pub offset: f64,
}

/// Why a hull cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum HullError {
    /// Fewer than `D + 1` points.
    #[error("{points} points cannot span {dimension} dimensions")]
    TooFewPoints {
        /// Points given.
        points: usize,
        /// Dimension of the space.
        dimension: usize,
    },
    /// The points lie in an affine subspace of lower dimension.
    #[error("the points span only {span} of {dimension} dimensions")]
    Flat {
        /// Dimension of their affine span.
        span: usize,
        /// Dimension of the space.
        dimension: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("a point has a coordinate that is not finite")]
    NotFinite,
    /// More points than a ridge's packed key can index (2²⁵ in six dimensions).
    #[error("{points} points are more than the hull can index")]
    TooManyPoints {
        /// Points given.
        points: usize,
    },
    /// Rounding defeated the construction even with the input joggled.
    #[error("the hull could not be built reliably in floating point")]
    Numerical,
}

/// No facet: an `assigned` entry of a point inside the hull or already added.
const NONE: u32 = u32::MAX;

/// How much of the hull a build makes.
#[derive(Debug, Clone, Copy)]
enum Extent {
    /// Every facet.
    Whole,
    /// Enough to decide the facet nearest the origin ([`ConvexHull::compute_around_origin`]).
    AroundOrigin,
}

/// Attempts with a joggle ten times larger each (1e-10 to 1e-7 of the input's size).
const JOGGLE_ATTEMPTS: usize = 4;

/// A convex hull with its buffers, reusable across calls.
#[derive(Debug, Clone, Default)]
pub struct ConvexHull<const D: usize> {
    facets: Vec<HullFacet<D>>,
    /// For each facet, the facet across the ridge opposite each of its vertices.
    neighbors: Vec<[u32; D]>,
    /// Per facet: seen from the point being added.
    seen: Vec<bool>,
    /// Per facet: tested and not seen from the point being added.
    unseen: Vec<bool>,
    /// The facets in `unseen`, to clear it.
    probed: Vec<usize>,
    /// Per input point: a live facet it sees, or [`NONE`] (inside, or already added).
    assigned: Vec<u32>,
    /// Per facet: removed, to be dropped.
    dead: Vec<bool>,
    /// Per facet: its index after the dead ones are dropped.
    remap: Vec<u32>,
    /// The horizon: (seen facet, its vertex slot whose opposite ridge borders an unseen facet).
    horizon: Vec<(u32, usize)>,
    /// Ridges of the new facets through the added point: (key, new facet, vertex slot).
    fresh: Vec<(u128, u32, usize)>,
    visible: Vec<usize>,
    ridges: Vec<u128>,
    /// Open-addressing table of [`pair_up`].
    table: Vec<u32>,
    /// The points' coordinates, first every x, then every y, …
    by_axis: Vec<f64>,
    order: Vec<u32>,
    interior: Vec<f64>,
    joggled: Vec<[f64; D]>,
}

impl<const D: usize> ConvexHull<D> {
    /// An empty hull.
    pub fn new() -> Self {
        Self {
            facets: Vec::new(),
            neighbors: Vec::new(),
            seen: Vec::new(),
            unseen: Vec::new(),
            probed: Vec::new(),
            assigned: Vec::new(),
            dead: Vec::new(),
            remap: Vec::new(),
            horizon: Vec::new(),
            fresh: Vec::new(),
            visible: Vec::new(),
            ridges: Vec::new(),
            table: Vec::new(),
            by_axis: Vec::new(),
            order: Vec::new(),
            interior: vec![0.0; D],
            joggled: Vec::new(),
        }
    }

    /// The facets of the last successful [`ConvexHull::compute`].
    pub fn facets(&self) -> &[HullFacet<D>] {
        &self.facets
    }

    /// A point strictly inside the last hull (the centroid of its first simplex).
    pub fn interior_point(&self) -> [f64; D] {
        std::array::from_fn(|k| self.interior.get(k).copied().unwrap_or(0.0))
    }

    /// Builds the hull of `points`, replacing the previous one.
    pub fn compute(&mut self, points: &[[f64; D]]) -> Result<(), HullError> {
        self.compute_with(points, Extent::Whole)
    }

    /// Builds only as much of the hull of `points` as decides its facet nearest the origin:
    /// [`ConvexHull::facets`] are then those of the hull of a subset of the points whose facet
    /// nearest the origin is a facet of the whole hull — the same Ferrari–Canny ε. When the
    /// origin lies outside the points' hull it lies outside this one too (some facet has a
    /// negative offset), though the offsets then differ from the whole hull's. Points are added
    /// farthest beyond the nearest facet first, until none lies beyond it: a power grasp's ~130
    /// wrenches need a fifth to a third of them and make a fifth of the facets
    /// (docs/PERFORMANCE.md).
    ///
    /// Why it is exact: the hull of the subset lies inside the whole hull, so the whole hull's ε
    /// is at least the subset's; and with no point beyond the subset's nearest facet, the whole
    /// hull lies behind that facet's plane, so its ε is at most the same distance.
    pub fn compute_around_origin(&mut self, points: &[[f64; D]]) -> Result<(), HullError> {
        self.compute_with(points, Extent::AroundOrigin)
    }

    /// [`ConvexHull::compute`] of the whole hull or of the part `extent` names.
    fn compute_with(&mut self, points: &[[f64; D]], extent: Extent) -> Result<(), HullError> {
        self.facets.clear();
        if points.len() < D + 1 {
            return Err(HullError::TooFewPoints {
                points: points.len(),
                dimension: D,
            });
        }
        if points.iter().flatten().any(|c| !c.is_finite()) {
            return Err(HullError::NotFinite);
        }
        let limit = 1u128 << key_bits(D).min(32);
        if points.len() as u128 >= limit {
            return Err(HullError::TooManyPoints {
                points: points.len(),
            });
        }
        let scale = points
            .iter()
            .flatten()
            .fold(0.0f64, |m, c| m.max(c.abs()))
            .max(f64::MIN_POSITIVE);
        // Flat input is flat before any joggle.
        initial_simplex(points, 1e-9 * scale)?;
        let mut rng = crate::random::SplitMix64::new(0x6a09e667);
        for attempt in 0..JOGGLE_ATTEMPTS {
            let joggle = scale * 1e-10 * 10f64.powi(attempt as i32);
            let mut joggled = std::mem::take(&mut self.joggled);
            joggled.clear();
            joggled.extend(
                points
                    .iter()
                    .map(|p| std::array::from_fn(|k| p[k] + rng.uniform(-joggle, joggle))),
            );
            let built = self.build(&joggled, scale, extent);
            let tolerance = 1e-9 * scale + 4.0 * joggle;
            let sound = built.is_ok() && self.is_sound(&joggled, tolerance);
            self.joggled = joggled;
            if sound {
                return Ok(());
            }
        }
        self.facets.clear();
        Err(HullError::Numerical)
    }

    /// Every ridge shared by exactly two facets, and every point inside every facet.
    fn is_sound(&mut self, points: &[[f64; D]], tolerance: f64) -> bool {
        self.ridges.clear();
        for f in &self.facets {
            self.ridges
                .extend((0..D).map(|skip| ridge_key(&f.vertices, skip)));
        }
        let ridges = &self.ridges;
        let closed = pair_up(
            ridges.len(),
            |r| ridges[r],
            false,
            &mut self.table,
            |_, _| {},
        );
        if !closed {
            return false;
        }
        // The points' coordinates axis by axis, so that the heights of consecutive points over a
        // facet are computed side by side in vector registers (the same sums in the same order
        // as `dot`): this check took 7% of a whole grasp point by point. Points still assigned
        // to a facet were left out of a partial hull (`Extent::AroundOrigin`) and lie beyond it.
        let assigned = &self.assigned;
        let within = || {
            points
                .iter()
                .zip(assigned)
                .filter(|(_, &a)| a == NONE)
                .map(|(p, _)| p)
        };
        let n = within().count();
        self.by_axis.clear();
        for k in 0..D {
            self.by_axis.extend(within().map(|p| p[k]));
        }
        let axes: [&[f64]; D] = std::array::from_fn(|k| &self.by_axis[k * n..(k + 1) * n]);
        // Point i of axis k: indices both ways are the point of the layout.
        #[allow(clippy::needless_range_loop)]
        self.facets.iter().all(|f| {
            let limit = f.offset + tolerance;
            let mut outside = false;
            for i in 0..n {
                let mut height = 0.0;
                for k in 0..D {
                    height += f.normal[k] * axes[k][i];
                }
                outside |= height > limit;
            }
            !outside
        })
    }

    /// Beneath–beyond over `points` (already joggled into general position), all of them or
    /// those `extent` needs.
    fn build(&mut self, points: &[[f64; D]], scale: f64, extent: Extent) -> Result<(), HullError> {
        self.facets.clear();
        let span_tolerance = 1e-9 * scale;
        let see_tolerance = 1e-13 * scale;
        let simplex = initial_simplex(points, span_tolerance)?;
        self.interior.clear();
        self.interior.resize(D, 0.0);
        for &i in &simplex {
            for (c, p) in self.interior.iter_mut().zip(&points[i as usize]) {
                *c += p / (D + 1) as f64;
            }
        }
        let interior = self.interior_point();
        for skip in 0..=D {
            let mut vertices = [0u32; D];
            let mut n = 0;
            for (j, &v) in simplex.iter().enumerate() {
                if j != skip {
                    vertices[n] = v;
                    n += 1;
                }
            }
            vertices.sort_unstable();
            self.facets.push(facet(points, vertices, &interior));
        }

        // Farthest from the interior first: fewer facets are made and removed again.
        self.order.clear();
        self.order
            .extend((0..points.len() as u32).filter(|i| !simplex.contains(i)));
        let distance = |i: &u32| {
            let p = &points[*i as usize];
            (0..D).map(|k| (p[k] - interior[k]).powi(2)).sum::<f64>()
        };
        self.order
            .sort_by(|a, b| distance(b).total_cmp(&distance(a)).then(a.cmp(b)));

        // Adjacency of the simplex's facets.
        self.neighbors.clear();
        self.neighbors.resize(self.facets.len(), [u32::MAX; D]);
        self.fresh.clear();
        for (f, facet) in self.facets.iter().enumerate() {
            self.fresh
                .extend((0..D).map(|j| (ridge_key(&facet.vertices, j), f as u32, j)));
        }
        link_pairs(&self.fresh, &mut self.table, &mut self.neighbors)?;

        // Each point outside the hull keeps one facet it sees (Quickhull's outside sets,
        // Barber et al. 1996); the others it sees are found from that one across ridges, since
        // they form a connected region, instead of testing every facet.
        let sees = |f: &HullFacet<D>, p: &[f64; D]| dot(&f.normal, p) - f.offset > see_tolerance;
        self.assigned.clear();
        self.assigned.resize(points.len(), NONE);
        for &i in &self.order {
            let p = &points[i as usize];
            if let Some(k) = self.facets.iter().position(|f| sees(f, p)) {
                self.assigned[i as usize] = k as u32;
            }
        }

        // Facets seen from a point are removed: marked dead at once, dropped when the dead
        // outnumber the live ones (and at the end), so neighbours' indices stay put meanwhile.
        self.seen.clear();
        self.seen.resize(self.facets.len(), false);
        self.unseen.clear();
        self.unseen.resize(self.facets.len(), false);
        self.dead.clear();
        self.dead.resize(self.facets.len(), false);
        let mut dead = 0;
        let mut next = 0;
        loop {
            let (i, start) = match extent {
                Extent::Whole => {
                    let Some(&i) = self.order.get(next) else {
                        break;
                    };
                    next += 1;
                    let start = self.assigned[i as usize];
                    if start == NONE {
                        continue;
                    }
                    (i, start)
                }
                Extent::AroundOrigin => match self.beyond_nearest_facet(points, see_tolerance) {
                    Some(pick) => pick,
                    None => break,
                },
            };
            dead += self.add_point(points, i, start, &interior, scale, see_tolerance)?;
            if 2 * dead > self.facets.len() {
                self.drop_dead();
                dead = 0;
            }
        }
        self.drop_dead();
        Ok(())
    }

    /// Adds point `i`, which sees facet `start`: the facets it sees are marked dead, the horizon
    /// joined to it, and the points that saw a dead facet assigned anew. Returns how many
    /// facets died.
    fn add_point(
        &mut self,
        points: &[[f64; D]],
        i: u32,
        start: u32,
        interior: &[f64; D],
        scale: f64,
        see_tolerance: f64,
    ) -> Result<usize, HullError> {
        let sees = |f: &HullFacet<D>, p: &[f64; D]| dot(&f.normal, p) - f.offset > see_tolerance;
        self.assigned[i as usize] = NONE;
        let p = &points[i as usize];
        self.visible.clear();
        self.visible.push(start as usize);
        self.seen[start as usize] = true;
        let mut next = 0;
        while let Some(&k) = self.visible.get(next) {
            next += 1;
            for &across in &self.neighbors[k] {
                let n = across as usize;
                if self.seen[n] || self.unseen[n] {
                    continue;
                }
                if sees(&self.facets[n], p) {
                    self.seen[n] = true;
                    self.visible.push(n);
                } else {
                    self.unseen[n] = true;
                    self.probed.push(n);
                }
            }
        }
        for &n in &self.probed {
            self.unseen[n] = false;
        }
        self.probed.clear();
        // The horizon: ridges between a seen facet and an unseen one.
        self.horizon.clear();
        for &k in &self.visible {
            for (j, &across) in self.neighbors[k].iter().enumerate() {
                if !self.seen[across as usize] {
                    self.horizon.push((k as u32, j));
                }
            }
        }
        // A new facet joins each horizon ridge to the point; its plane is the one of the
        // pencil through that ridge (a combination of the seen and the unseen facet's
        // planes) that passes through the point.
        self.fresh.clear();
        let first_new = self.facets.len();
        for h in 0..self.horizon.len() {
            let (k, j) = self.horizon[h];
            let old = self.facets[k as usize];
            let across = self.neighbors[k as usize][j];
            let mut vertices = old.vertices;
            vertices[j] = i;
            vertices.sort_unstable();
            let new = self.facets.len() as u32;
            let facet = pencil_facet(
                points,
                vertices,
                &old,
                &self.facets[across as usize],
                p,
                interior,
                1e-11 * scale,
            )
            .unwrap_or_else(|| facet(points, vertices, interior));
            self.facets.push(facet);
            self.seen.push(false);
            self.unseen.push(false);
            self.dead.push(false);
            // Across the ridge without the point: the unseen facet, which now borders it.
            let mut links = [u32::MAX; D];
            let apex = vertices
                .iter()
                .position(|&v| v == i)
                .expect("the apex is a vertex");
            links[apex] = across;
            let back = self.neighbors[across as usize]
                .iter()
                .position(|&n| n == k)
                .ok_or(HullError::Numerical)?;
            self.neighbors[across as usize][back] = new;
            self.neighbors.push(links);
            self.fresh.extend(
                (0..D)
                    .filter(|&slot| slot != apex)
                    .map(|slot| (ridge_key(&vertices, slot), new, slot)),
            );
        }
        link_pairs(&self.fresh, &mut self.table, &mut self.neighbors)?;
        // A point that saw a removed facet sees one of the new ones, or is now inside.
        for (assigned, q) in self.assigned.iter_mut().zip(points) {
            if *assigned != NONE && self.seen[*assigned as usize] {
                *assigned = (first_new..self.facets.len())
                    .find(|&k| sees(&self.facets[k], q))
                    .map_or(NONE, |k| k as u32);
            }
        }
        for &k in &self.visible {
            self.seen[k] = false;
            self.dead[k] = true;
        }
        Ok(self.visible.len())
    }

    /// The next point a partial hull around the origin needs (`Extent::AroundOrigin`): the
    /// point farthest beyond the live facet nearest the origin (ties: the lower index), with that
    /// facet; `None` when no point lies beyond it.
    fn beyond_nearest_facet(&self, points: &[[f64; D]], see_tolerance: f64) -> Option<(u32, u32)> {
        let nearest = (0..self.facets.len())
            .filter(|&k| !self.dead[k])
            .min_by(|&a, &b| {
                self.facets[a]
                    .offset
                    .total_cmp(&self.facets[b].offset)
                    .then(a.cmp(&b))
            })?;
        let f = &self.facets[nearest];
        let mut pick: Option<(f64, u32)> = None;
        for (j, p) in points.iter().enumerate() {
            if self.assigned[j] == NONE {
                continue;
            }
            let height = dot(&f.normal, p) - f.offset;
            if height > see_tolerance && pick.is_none_or(|(h, _)| height > h) {
                pick = Some((height, j as u32));
            }
        }
        pick.map(|(_, j)| (j, nearest as u32))
    }

    /// Removes the dead facets, renumbering the others and their neighbours.
    fn drop_dead(&mut self) {
        self.remap.clear();
        let mut kept = 0u32;
        for &dead in &self.dead {
            self.remap.push(kept);
            kept += u32::from(!dead);
        }
        let mut at = 0;
        for k in 0..self.facets.len() {
            if !self.dead[k] {
                self.facets[at] = self.facets[k];
                let links = self.neighbors[k];
                for (slot, n) in self.neighbors[at].iter_mut().zip(links) {
                    *slot = self.remap[n as usize];
                }
                at += 1;
            }
        }
        self.facets.truncate(at);
        self.neighbors.truncate(at);
        self.seen.truncate(at);
        self.unseen.truncate(at);
        // Points are assigned only to live facets.
        for a in self.assigned.iter_mut().filter(|a| **a != NONE) {
            *a = self.remap[*a as usize];
        }
        self.dead.clear();
        self.dead.resize(at, false);
    }
}

/// Links the facets of `ridges` (key, facet, vertex slot) that share a ridge: each key must
/// appear an even number of times, paired in order. (A ridge four new facets share, where
/// rounding pinched the horizon, is linked two and two; such facets are soon removed, and the
/// finished hull is checked with every ridge exactly twice.)
fn link_pairs<const D: usize>(
    ridges: &[(u128, u32, usize)],
    table: &mut Vec<u32>,
    neighbors: &mut [[u32; D]],
) -> Result<(), HullError> {
    let paired = pair_up(
        ridges.len(),
        |r| ridges[r].0,
        true,
        table,
        |a, b| {
            let ((_, fa, ja), (_, fb, jb)) = (ridges[a], ridges[b]);
            neighbors[fa as usize][ja] = fb;
            neighbors[fb as usize][jb] = fa;
        },
    );
    if paired {
        Ok(())
    } else {
        Err(HullError::Numerical)
    }
}

/// Pairs the `count` items by key (`key(i)`), calling `pair(first, second)` for each pair in
/// the order they come; false unless every key appears exactly twice, or with `repeats` an even
/// number of times. Open addressing in `table` (kept between calls) rather than a sort, which
/// took 7% of a whole grasp; std's `HashMap` would allocate and hash with SipHash.
fn pair_up(
    count: usize,
    key: impl Fn(usize) -> u128,
    repeats: bool,
    table: &mut Vec<u32>,
    mut pair: impl FnMut(usize, usize),
) -> bool {
    const EMPTY: u32 = u32::MAX;
    const PAIRED: u32 = 1 << 31;
    if !count.is_multiple_of(2) || count >= PAIRED as usize {
        return false;
    }
    let size = (2 * count).next_power_of_two().max(16);
    let bits = size.trailing_zeros();
    table.clear();
    table.resize(size, EMPTY);
    let mask = size - 1;
    for item in 0..count {
        let k = key(item);
        // Fibonacci hashing of the key folded to 64 bits: the top bits index the table.
        let folded = (k as u64) ^ ((k >> 64) as u64);
        let mut slot = (folded.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> (64 - bits)) as usize;
        loop {
            let entry = table[slot];
            if entry == EMPTY {
                table[slot] = item as u32;
                break;
            }
            let other = (entry & !PAIRED) as usize;
            if key(other) == k {
                if entry & PAIRED == 0 {
                    pair(other, item);
                    table[slot] = entry | PAIRED;
                    break;
                }
                if !repeats {
                    return false; // a third time
                }
            }
            slot = (slot + 1) & mask;
        }
    }
    table.iter().all(|&e| e == EMPTY || e & PAIRED != 0)
}

/// The facet through `vertices` (a ridge of `seen` and of `unseen`, plus `apex`) from the pencil
/// of hyperplanes through that ridge: `−d₂·(n₁, o₁) + d₁·(n₂, o₂)`, where `dᵢ` is the apex's height
/// over each plane, passes through the apex. A few dozen flops against an elimination; `None`
/// when the result is not within `tolerance` of every vertex (old planes' rounding, or planes
/// too close to parallel), so that the caller solves it afresh.
fn pencil_facet<const D: usize>(
    points: &[[f64; D]],
    vertices: [u32; D],
    seen: &HullFacet<D>,
    unseen: &HullFacet<D>,
    apex: &[f64; D],
    interior: &[f64; D],
    tolerance: f64,
) -> Option<HullFacet<D>> {
    let d1 = dot(&seen.normal, apex) - seen.offset;
    let d2 = dot(&unseen.normal, apex) - unseen.offset;
    let mut normal: [f64; D] =
        std::array::from_fn(|k| -d2 * seen.normal[k] + d1 * unseen.normal[k]);
    let length = dot(&normal, &normal).sqrt();
    if length.is_nan() || length <= 0.0 {
        return None;
    }
    normal = normal.map(|c| c / length);
    let heights = vertices.map(|v| dot(&normal, &points[v as usize]));
    let offset = heights.iter().sum::<f64>() / D as f64;
    if heights.iter().any(|h| (h - offset).abs() > tolerance) || dot(&normal, interior) >= offset {
        return None;
    }
    Some(HullFacet {
        vertices,
        normal,
        offset,
    })
}

/// Bits per vertex index in a ridge key: `D − 1` indices share 128 bits.
const fn key_bits(d: usize) -> usize {
    128 / (d - 1)
}

/// The ridge of `vertices` (ascending) without the one at `skip`, packed into one integer (the
/// indices in order, most significant first): ridges compare and sort as single numbers,
/// several times faster than as arrays. Indices fit: [`ConvexHull::compute`] refuses more points.
fn ridge_key<const D: usize>(vertices: &[u32; D], skip: usize) -> u128 {
    let bits = key_bits(D);
    vertices
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != skip)
        .fold(0u128, |key, (_, &v)| {
            key.checked_shl(bits as u32).unwrap_or(0) | u128::from(v)
        })
}

fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    (0..D).map(|k| a[k] * b[k]).sum()
}

/// `D + 1` affinely independent points, each the farthest from the span of those before it.
fn initial_simplex<const D: usize>(
    points: &[[f64; D]],
    tolerance: f64,
) -> Result<Vec<u32>, HullError> {
    // The point with the smallest first coordinate (ties: lowest index) starts.
    let first = (0..points.len())
        .min_by(|&a, &b| points[a][0].total_cmp(&points[b][0]))
        .expect("at least D + 1 points");
    let mut chosen = vec![first as u32];
    let mut basis: Vec<[f64; D]> = Vec::with_capacity(D);
    let origin = points[first];
    while chosen.len() <= D {
        let mut best = (0.0, usize::MAX, [0.0; D]);
        for (i, p) in points.iter().enumerate() {
            let mut r: [f64; D] = std::array::from_fn(|k| p[k] - origin[k]);
            for q in &basis {
                let s = dot(&r, q);
                for k in 0..D {
                    r[k] -= s * q[k];
                }
            }
            let norm = dot(&r, &r).sqrt();
            if norm > best.0 {
                best = (norm, i, r);
            }
        }
        if best.0 <= tolerance {
            return Err(HullError::Flat {
                span: chosen.len() - 1,
                dimension: D,
            });
        }
        let (norm, i, r) = best;
        basis.push(std::array::from_fn(|k| r[k] / norm));
        chosen.push(i as u32);
    }
    Ok(chosen)
}

/// The facet through `vertices`, its normal pointing away from `interior`.
fn facet<const D: usize>(
    points: &[[f64; D]],
    vertices: [u32; D],
    interior: &[f64; D],
) -> HullFacet<D> {
    let base = points[vertices[0] as usize];
    // The normal spans the null space of the facet's D − 1 edge vectors: Gaussian elimination
    // with full pivoting brings them to echelon form, then the first column left without a
    // pivot (the last, unless the edges are degenerate) is set to 1 and the pivot columns are
    // solved back. About a tenth of the work of an orthonormal basis of the edges.
    let mut rows = [[0.0; D]; D];
    for (row, &v) in rows.iter_mut().zip(&vertices[1..]) {
        let p = points[v as usize];
        *row = std::array::from_fn(|k| p[k] - base[k]);
    }
    let edges = D - 1;
    // Columns are swapped in place (`column` remembers which coordinate each now holds), so
    // the inner loops run over contiguous memory.
    let mut column: [usize; D] = std::array::from_fn(|k| k);
    let mut rank = 0;
    while rank < edges {
        let (mut pivot, mut at) = (0.0, (rank, rank));
        for (r, row) in rows.iter().enumerate().take(edges).skip(rank) {
            for (c, x) in row.iter().enumerate().skip(rank) {
                if x.abs() > pivot {
                    pivot = x.abs();
                    at = (r, c);
                }
            }
        }
        if pivot == 0.0 {
            break;
        }
        rows.swap(rank, at.0);
        if at.1 != rank {
            for row in rows.iter_mut().take(edges) {
                row.swap(rank, at.1);
            }
            column.swap(rank, at.1);
        }
        let lead = rows[rank];
        for row in rows.iter_mut().take(edges).skip(rank + 1) {
            let factor = row[rank] / lead[rank];
            for (x, l) in row.iter_mut().zip(&lead).skip(rank) {
                *x -= factor * l;
            }
        }
        rank += 1;
    }
    let mut solved = [0.0; D];
    solved[rank] = 1.0;
    for i in (0..rank).rev() {
        let row = &rows[i];
        let sum: f64 = (i + 1..=rank).map(|c| row[c] * solved[c]).sum();
        solved[i] = -sum / row[i];
    }
    let mut normal = [0.0; D];
    for (c, &x) in solved.iter().enumerate() {
        normal[column[c]] = x;
    }
    let length = dot(&normal, &normal).sqrt();
    normal = normal.map(|c| c / length);
    let mut offset = vertices
        .iter()
        .map(|&v| dot(&normal, &points[v as usize]))
        .sum::<f64>()
        / D as f64;
    if dot(&normal, interior) > offset {
        normal = normal.map(|c| -c);
        offset = -offset;
    }
    HullFacet {
        vertices,
        normal,
        offset,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_facets_sharing_a_ridge_give_it_one_key_and_other_ridges_other_keys() {
        let vertices: [u32; 6] = [3, 17, 40, 41, 1_000_000, (1 << 25) - 1];
        for skip in 0..6 {
            let key = ridge_key(&vertices, skip);
            // The same ridge seen from a facet whose sixth vertex is another point.
            let mut other: Vec<u32> = vertices
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != skip)
                .map(|(_, &v)| v)
                .collect();
            other.push(7);
            other.sort_unstable();
            let other: [u32; 6] = other.try_into().unwrap();
            let at = other.iter().position(|&v| v == 7).unwrap();
            assert_eq!(ridge_key(&other, at), key);
            // Ridges differing in one index differ as keys.
            let mut moved = vertices;
            moved[(skip + 1) % 6] -= 1;
            assert_ne!(ridge_key(&moved, skip), key);
        }
    }

    #[test]
    fn pairing_by_key_finds_each_pair_and_refuses_odd_or_repeated_keys() {
        let mut table = Vec::new();
        let pairs = |keys: &[u128], repeats: bool, table: &mut Vec<u32>| {
            let mut found = Vec::new();
            let ok = pair_up(
                keys.len(),
                |i| keys[i],
                repeats,
                table,
                |a, b| found.push((a, b)),
            );
            ok.then_some(found)
        };
        // 600 keys in a table of 2048 slots collide often; keys differing only in the high
        // half fold together.
        let keys: Vec<u128> = (0..300u128).flat_map(|k| [k << 64, k << 64]).collect();
        let mut shuffled = keys.clone();
        shuffled.rotate_left(1);
        let found = pairs(&shuffled, false, &mut table).unwrap();
        assert_eq!(found.len(), 300);
        assert!(found
            .iter()
            .all(|&(a, b)| a < b && shuffled[a] == shuffled[b]));
        assert!(pairs(&[1, 2, 2, 1], false, &mut table).is_some());
        assert!(pairs(&[1, 1, 2], false, &mut table).is_none());
        assert!(pairs(&[1, 2, 1, 3], false, &mut table).is_none());
        assert!(pairs(&[7, 7, 7, 7], false, &mut table).is_none());
        assert_eq!(
            pairs(&[7, 7, 7, 7], true, &mut table),
            Some(vec![(0, 1), (2, 3)])
        );
        assert!(pairs(&[7, 7, 7, 5, 7, 5], true, &mut table).is_some());
        assert!(pairs(&[7, 7, 7, 5, 5, 5], true, &mut table).is_none());
    }

    #[test]
    fn a_cube_has_its_six_faces_at_distance_one() {
        let mut points = Vec::new();
        for i in 0..8 {
            points.push([
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            ]);
        }
        points.push([0.0, 0.0, 0.0]);
        points.push([0.5, -0.2, 0.9]);
        let mut hull = ConvexHull::<3>::new();
        hull.compute(&points).unwrap();
        // Twelve triangles, each on a face of the cube.
        assert_eq!(hull.facets().len(), 12);
        for f in hull.facets() {
            // Exact to the joggle (1e-10 of the size).
            assert!((f.offset - 1.0).abs() < 1e-8);
            assert!(f.vertices.iter().all(|&v| v < 8));
        }
    }

    #[test]
    fn a_flat_set_is_refused_with_its_span() {
        let points: Vec<[f64; 3]> = (0..10).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
        let mut hull = ConvexHull::<3>::new();
        assert_eq!(
            hull.compute(&points),
            Err(HullError::Flat {
                span: 2,
                dimension: 3
            })
        );
        assert_eq!(
            hull.compute(&points[..3]),
            Err(HullError::TooFewPoints {
                points: 3,
                dimension: 3
            })
        );
    }

    #[test]
    fn every_point_is_inside_every_facet_of_a_random_six_d_hull() {
        let mut rng = crate::random::SplitMix64::new(7);
        let points: Vec<[f64; 6]> = (0..60)
            .map(|_| std::array::from_fn(|_| rng.uniform(-1.0, 1.0)))
            .collect();
        let mut hull = ConvexHull::<6>::new();
        hull.compute(&points).unwrap();
        assert!(hull.facets().len() > 100);
        for f in hull.facets() {
            for p in &points {
                assert!(dot(&f.normal, p) <= f.offset + 1e-9);
            }
            for &v in &f.vertices {
                assert!((dot(&f.normal, &points[v as usize]) - f.offset).abs() < 1e-9);
            }
        }
        // Every ridge is shared by exactly two facets: the hull is closed.
        let mut ridges = std::collections::HashMap::new();
        for f in hull.facets() {
            for skip in 0..6 {
                let ridge: Vec<u32> = (0..6)
                    .filter(|&j| j != skip)
                    .map(|j| f.vertices[j])
                    .collect();
                *ridges.entry(ridge).or_insert(0) += 1;
            }
        }
        assert!(ridges.values().all(|&n| n == 2));
    }

    #[test]
    fn a_six_d_hull_has_exactly_the_facets_a_brute_force_search_finds() {
        // Independent of the construction: a 6-subset of points in general position is a facet
        // exactly when every other point lies on one side of its hyperplane (normal from
        // nalgebra's SVD of the edge vectors, not from `facet`).
        let mut rng = crate::random::SplitMix64::new(11);
        for _ in 0..3 {
            let points: Vec<[f64; 6]> = (0..11)
                .map(|_| std::array::from_fn(|_| rng.uniform(-1.0, 1.0)))
                .collect();
            let mut expected = Vec::new();
            let n = points.len();
            let mut subset = [0usize; 6];
            fn next(subset: &mut [usize; 6], n: usize) -> bool {
                for i in (0..6).rev() {
                    if subset[i] < n - 6 + i {
                        subset[i] += 1;
                        for j in i + 1..6 {
                            subset[j] = subset[j - 1] + 1;
                        }
                        return true;
                    }
                }
                false
            }
            for (i, s) in subset.iter_mut().enumerate() {
                *s = i;
            }
            loop {
                let base = nalgebra::SVector::<f64, 6>::from(points[subset[0]]);
                let edges = nalgebra::DMatrix::from_fn(6, 6, |r, c| {
                    if r < 5 {
                        points[subset[r + 1]][c] - base[c]
                    } else {
                        0.0
                    }
                });
                let svd = edges.svd(false, true);
                let v_t = svd.v_t.expect("asked for V");
                let smallest = (0..6)
                    .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
                    .unwrap();
                let normal: Vec<f64> = v_t.row(smallest).iter().copied().collect();
                let side = |p: &[f64; 6]| (0..6).map(|k| normal[k] * (p[k] - base[k])).sum::<f64>();
                let others: Vec<f64> = (0..n)
                    .filter(|i| !subset.contains(i))
                    .map(|i| side(&points[i]))
                    .collect();
                if others.iter().all(|&d| d < 0.0) || others.iter().all(|&d| d > 0.0) {
                    expected.push(subset.map(|v| v as u32));
                }
                if !next(&mut subset, n) {
                    break;
                }
            }
            let mut hull = ConvexHull::<6>::new();
            hull.compute(&points).unwrap();
            let mut found: Vec<[u32; 6]> = hull.facets().iter().map(|f| f.vertices).collect();
            found.sort_unstable();
            expected.sort_unstable();
            assert!(expected.len() > 20, "{} facets", expected.len());
            assert_eq!(found, expected);
        }
    }

    /// The offset of the facet nearest the origin.
    fn nearest(hull: &ConvexHull<6>) -> f64 {
        hull.facets()
            .iter()
            .map(|f| f.offset)
            .fold(f64::INFINITY, f64::min)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

        /// The partial hull around the origin holds the origin exactly when the whole hull does,
        /// and then has its nearest facet, with fewer facets.
        #[test]
        fn the_hull_around_the_origin_decides_what_the_whole_hull_does(
            seed in 0u64..1_000_000,
            count in 8usize..120,
            shift in proptest::sample::select(vec![0.0, 0.3, 0.9, 2.0]),
            stretch in proptest::sample::select(vec![1.0, 0.1, 10.0]),
        ) {
            let mut rng = crate::random::SplitMix64::new(seed);
            let points: Vec<[f64; 6]> = (0..count)
                .map(|_| {
                    std::array::from_fn(|k| {
                        let scale = if k >= 3 { stretch } else { 1.0 };
                        (rng.uniform(-1.0, 1.0) + if k == 0 { shift } else { 0.0 }) * scale
                    })
                })
                .collect();
            let mut whole = ConvexHull::<6>::new();
            let mut partial = ConvexHull::<6>::new();
            whole.compute(&points).unwrap();
            partial.compute_around_origin(&points).unwrap();
            let (all, near) = (nearest(&whole), nearest(&partial));
            // Outside the hull the origin is beyond some facet of both; inside, ε is the same.
            proptest::prop_assert_eq!(near > 0.0, all > 0.0, "{} against {}", near, all);
            if all > 0.0 {
                proptest::prop_assert!((all - near).abs() < 1e-9, "{} against {}", near, all);
            }
            proptest::prop_assert!(partial.facets().len() <= whole.facets().len());
        }
    }

    #[test]
    fn the_hull_around_the_origin_of_many_points_makes_few_facets() {
        let mut rng = crate::random::SplitMix64::new(5);
        let points: Vec<[f64; 6]> = (0..130)
            .map(|_| std::array::from_fn(|_| rng.uniform(-1.0, 1.0)))
            .collect();
        let (mut whole, mut partial) = (ConvexHull::<6>::new(), ConvexHull::<6>::new());
        whole.compute(&points).unwrap();
        partial.compute_around_origin(&points).unwrap();
        assert!(
            2 * partial.facets().len() < whole.facets().len(),
            "{} facets around the origin, {} in all",
            partial.facets().len(),
            whole.facets().len()
        );
    }
}

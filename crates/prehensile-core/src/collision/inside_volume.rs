//! Volume and centre of mass of a mesh's inside as the winding number defines it, for meshes
//! whose signed tetrahedra would count overlaps twice or leak through holes.
//!
//! Vertical lines through the cells of a grid over the mesh's bounding box are cut at every
//! triangle they cross. Where every edge is balanced (closed parts, overlapping, nested or
//! self-intersecting), the winding number is constant between two crossings and changes by ±1 at
//! each, so counting crossings gives it without a query and the inside length along the line is
//! exact; the same count finds space covered twice ([`overlaps_itself`]). Around the holes or
//! flipped faces of other meshes it changes smoothly between crossings: there it is a whole
//! number, counted from the crossings of the surface and of its [`BoundaryFan`], plus the fan's
//! own winding number, which costs one solid angle per boundary edge. Lines far from the fan are
//! counted alone; on the others each piece between crossings is sampled at up to
//! [`SAMPLES_PER_PIECE`] points and just inside its ends, and each change between neighbouring
//! samples located by regula falsi. A line whose crossings do not add up (through an edge) is
//! sampled with winding-tree queries instead. The inside lengths times the cells' areas sum to
//! the volume (midpoint rule across x and y: within 1% on the shapes of
//! `tests/integration/winding_oracle.rs`).

use rayon::prelude::*;

use crate::math::{Point3, Vec3};

use super::{BoundaryFan, TriangleBvh};

/// Below this bound on the fan's |w| along a line, the inside is where the whole part is not 0.
const FAR_FROM_FAN: f64 = 0.1;
/// Most samples along one piece between crossings when the winding number may vary there.
const SAMPLES_PER_PIECE: usize = 6;
/// Most winding-number queries locating where the inside ends between two samples: as many as
/// bisection needs for 1/256 of their gap.
const ROOT_STEPS: usize = 8;
/// The inside's end is located once |w| is this close to ½: a twentieth of the tree's
/// approximation error ([`crate::collision::TriangleBvh::with_winding_numbers`], within 0.02 of
/// libigl's exact sums), so locating it more closely would refine noise.
const ROOT_WINDING_TOLERANCE: f64 = 1e-3;

/// A grid of vertical lines over the box of a mesh: `cells` along its longer horizontal side,
/// tiling both sides exactly, each line off-centre in its cell by irrational fractions so that
/// lines miss the diagonals of axis-aligned faces.
struct LineGrid {
    lo: Point3,
    counts: [usize; 2],
    spacing: [f64; 2],
}

impl LineGrid {
    fn new(exact: &TriangleBvh, cells: usize) -> Self {
        let (lo, hi) = exact.bounds();
        let size = hi - lo;
        let longer = size.x.max(size.y);
        if longer <= 0.0 || cells == 0 {
            return Self {
                lo,
                counts: [0, 0],
                spacing: [0.0, 0.0],
            };
        }
        let count = |side: f64| ((cells as f64 * side / longer).round() as usize).max(1);
        let counts = [count(size.x), count(size.y)];
        Self {
            lo,
            counts,
            spacing: [size.x / counts[0] as f64, size.y / counts[1] as f64],
        }
    }

    /// How many lines.
    fn len(&self) -> usize {
        self.counts[0] * self.counts[1]
    }

    /// The area of one line's cell.
    fn cell_area(&self) -> f64 {
        self.spacing[0] * self.spacing[1]
    }

    /// Line `k`'s (x, y), rows of constant x in turn.
    fn line(&self, k: usize) -> (f64, f64) {
        let (i, j) = (k / self.counts[1], k % self.counts[1]);
        (
            self.lo.x + (i as f64 + 0.5 + 1e-3 * std::f64::consts::SQRT_2) * self.spacing[0],
            self.lo.y + (j as f64 + 0.5 + 1e-3 * std::f64::consts::LN_2) * self.spacing[1],
        )
    }

    /// Line `k`'s crossings of the mesh, sorted by height, into `out`; returns its (x, y).
    fn crossings(&self, exact: &TriangleBvh, k: usize, out: &mut Vec<(f64, i32)>) -> (f64, f64) {
        let (x, y) = self.line(k);
        exact.vertical_crossings(x, y, out);
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        (x, y)
    }
}

/// Winding numbers along a line from the counts of its crossings (0 below the lowest): the
/// value above each crossing but the last. `None` when the count does not return to 0 (an edge
/// crossed twice or missed), so the line cannot be counted.
fn counted_windings(
    crossings: &[(f64, i32)],
) -> Option<impl Iterator<Item = (f64, f64, i32)> + '_> {
    (crossings.iter().map(|c| c.1).sum::<i32>() == 0).then(|| {
        crossings.windows(2).scan(0, |winding, pair| {
            *winding += pair[0].1;
            Some((pair[0].0, pair[1].0, *winding))
        })
    })
}

/// Does a closed, oriented mesh (no [unbalanced edges](crate::MeshReport::unbalanced_edges))
/// cover some space twice or inside out — overlapping parts, or a self-intersection such as a
/// corner pushed through a face? Scans `cells` lines for a winding number other than 0 and 1; a
/// fold thinner than the line spacing can be missed.
pub fn overlaps_itself(exact: &TriangleBvh, cells: usize) -> bool {
    let lines = LineGrid::new(exact, cells);
    // Lines in parallel: the scan is most of a clean mesh's setup.
    (0..lines.len())
        .into_par_iter()
        .map_init(Vec::new, |crossings, k| {
            lines.crossings(exact, k, crossings);
            counted_windings(crossings)
                .is_some_and(|mut w| w.any(|(z0, z1, w)| z1 > z0 && !(0..=1).contains(&w)))
        })
        .any(|overlapping| overlapping)
}

/// Pieces between crossings that the winding tree may sample, over all lines: 64 × 64 lines of
/// four pieces, an open scan's. A triangle soup crossed 50 times per line would otherwise take
/// minutes.
const TREE_PIECE_BUDGET: usize = 64 * 64 * 4;
/// Fewest lines along the longer side, however many pieces.
const MIN_CELLS: usize = 16;

/// At most `cells` lines along the longer side, fewer when the mesh is crossed so often that
/// sampling every piece with winding-tree queries would exceed [`TREE_PIECE_BUDGET`] (estimated
/// on 16 × 16 lines), but at least [`MIN_CELLS`].
fn cells_within_piece_budget(exact: &TriangleBvh, cells: usize) -> usize {
    let probe = LineGrid::new(exact, MIN_CELLS);
    let mut crossings = Vec::new();
    let pieces: usize = (0..probe.len())
        .map(|k| {
            probe.crossings(exact, k, &mut crossings);
            crossings.len() + 1
        })
        .sum();
    let per_line = pieces as f64 / probe.len().max(1) as f64;
    let affordable = (TREE_PIECE_BUDGET as f64 / per_line).sqrt() as usize;
    affordable.clamp(MIN_CELLS.min(cells), cells)
}

/// What [`inside_volume_and_centroid`] integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InsideVolume {
    /// Volume of the inside, m³.
    pub volume: f64,
    /// Its centroid (the box's centre when it has no volume).
    pub centroid: Point3,
    /// How many lines were integrated.
    pub lines: usize,
    /// How many of them needed winding-tree queries: their crossings did not add up (a line
    /// through an edge), or there was no boundary fan.
    pub lines_from_tree: usize,
}

/// Volume (m³) and centroid of the points of `exact`'s bounding box where the generalized
/// winding number exceeds ½ in magnitude (as [`TriangleBvh::inside`] decides, but summed exactly
/// on the lines the fan splits), integrated on `cells` lines along the longer horizontal side of
/// the box. `fan` is the mesh's [`BoundaryFan`]: where it is empty, every line's crossings are
/// counted alone; without one, every line is sampled with winding-tree queries (the
/// integration the fan replaced).
pub fn inside_volume_and_centroid(
    exact: &TriangleBvh,
    cells: usize,
    fan: Option<&BoundaryFan>,
) -> InsideVolume {
    let (lo, hi) = exact.bounds();
    let longer = (hi.x - lo.x).max(hi.y - lo.y);
    let cells = if fan.is_some() {
        cells
    } else {
        cells_within_piece_budget(exact, cells)
    };
    // Samples along a piece between crossings at about the line spacing.
    let step = longer / cells.max(1) as f64;
    let lines = LineGrid::new(exact, cells);
    // Lines in parallel (with winding-number queries an open scan's lines take most of its
    // setup), summed afterwards in line order: the same sums, bit for bit, on any thread count.
    let per_line: Vec<(f64, f64, f64, f64, bool)> = (0..lines.len())
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new(), Vec::new()),
            |(surface, both, heights), k| {
                let (x, y) = lines.crossings(exact, k, surface);
                let (mut length, mut height_moment) = (0.0, 0.0);
                let mut add = |z0: f64, z1: f64| {
                    length += z1 - z0;
                    height_moment += 0.5 * (z1 * z1 - z0 * z0);
                };
                both.clear();
                both.extend_from_slice(surface);
                if let Some(fan) = fan {
                    fan.vertical_crossings(x, y, both);
                }
                both.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                // S − F is closed and lies within the box, so w_S − w_F is the same whole number
                // all over the plane below the box: 0, as at infinity. It changes by each
                // crossing's count and must come back to 0 above the box.
                let counted = fan.is_some() && both.iter().map(|c| c.1).sum::<i32>() == 0;
                let fan = fan.filter(|_| counted);
                // Each piece between crossings of the surface or the fan, with the whole number
                // w_S − w_F on it; the floor and ceiling bound the first and the last.
                let pieces = || {
                    let (mut from, mut whole) = (lo.z, 0);
                    both.iter()
                        .copied()
                        .chain([(hi.z, 0)])
                        .map(move |(z, change)| {
                            let piece = (from, z, whole);
                            (from, whole) = (z, whole + change);
                            piece
                        })
                };
                let near_fan =
                    fan.filter(|f| !f.is_empty() && f.winding_bound(x, y) > FAR_FROM_FAN);
                if counted && near_fan.is_none() {
                    // |w_F| is small along the whole line: inside wherever the whole part is
                    // not 0.
                    for (z0, z1, whole) in pieces() {
                        if whole != 0 {
                            add(z0, z1);
                        }
                    }
                } else if let Some(fan) = near_fan {
                    for (z0, z1, whole) in pieces() {
                        let beyond_half = |z: f64| {
                            let w = f64::from(whole) + fan.winding_number(&Point3::new(x, y, z));
                            w.abs() - 0.5
                        };
                        inside_parts_of_piece(&beyond_half, z0, z1, step, &mut add);
                    }
                } else {
                    // A line through an edge that crossed it twice or missed it: the winding
                    // tree along the line, between the surface's crossings.
                    heights.clear();
                    heights.extend(surface.iter().map(|c| c.0));
                    heights.extend([lo.z, hi.z]);
                    heights.sort_unstable_by(f64::total_cmp);
                    // Positive inside, as `TriangleBvh::inside` decides it within the box.
                    let beyond_half =
                        |z: f64| exact.winding_number(&Point3::new(x, y, z)).abs() - 0.5;
                    for pair in heights.windows(2) {
                        inside_parts_of_piece(&beyond_half, pair[0], pair[1], step, &mut add);
                    }
                }
                (x, y, length, height_moment, !counted)
            },
        )
        .collect();
    let (mut volume, mut moment) = (0.0, Vec3::zeros());
    let lines_from_tree = per_line.iter().filter(|line| line.4).count();
    for (x, y, length, height_moment, _) in per_line {
        volume += length;
        moment += Vec3::new(x * length, y * length, height_moment);
    }
    let cell_area = lines.cell_area();
    volume *= cell_area;
    moment *= cell_area;
    let centroid = if volume > 0.0 {
        Point3::from(moment / volume)
    } else {
        nalgebra::center(&lo, &hi)
    };
    InsideVolume {
        volume,
        centroid,
        lines: lines.len(),
        lines_from_tree,
    }
}

/// Calls `add(z0, z1)` for the parts of the piece `start..end` of a line where `beyond_half`
/// (|w| − ½, smooth along the piece) is positive: sampled at up to [`SAMPLES_PER_PIECE`] points
/// about `step` apart and, when longer than a step, just inside both ends; each change between
/// neighbouring samples located by [`inside_end`]. The ends matter: where a piece ends at the
/// boundary fan, the inside usually ends just before it.
fn inside_parts_of_piece(
    beyond_half: &impl Fn(f64) -> f64,
    start: f64,
    end: f64,
    step: f64,
    add: &mut impl FnMut(f64, f64),
) {
    if end <= start {
        return;
    }
    let inner = ((end - start) / step)
        .ceil()
        .clamp(1.0, SAMPLES_PER_PIECE as f64) as usize;
    let piece = (end - start) / inner as f64;
    let inset = 1e-3 * piece;
    // A piece shorter than a step (a soup's) is sampled once, at its middle.
    let ends = if inner > 1 { 2 } else { 0 };
    let count = inner + ends;
    let mut samples = [(0.0, 0.0); SAMPLES_PER_PIECE + 2];
    for (k, sample) in samples.iter_mut().enumerate().take(count) {
        let z = match k {
            _ if ends == 0 => start + 0.5 * piece,
            0 => start + inset,
            k if k == count - 1 => end - inset,
            k => start + (k as f64 - 0.5) * piece,
        };
        *sample = (z, beyond_half(z));
    }
    let mut inside = samples[0].1 > 0.0;
    let mut lower = start;
    for pair in samples[..count].windows(2) {
        if (pair[1].1 > 0.0) != inside {
            let upper = inside_end(beyond_half, pair[0], pair[1]);
            if inside {
                add(lower, upper);
            }
            (lower, inside) = (upper, !inside);
        }
    }
    if inside {
        add(lower, end);
    }
}

/// Where `g` (|w| − ½ along a line, smooth between crossings) changes sign between `(a, g(a))`
/// and `(b, g(b))`, whose signs differ: regula falsi with the Illinois halving, which keeps both
/// ends of the bracket moving. Stops once |g| is within [`ROOT_WINDING_TOLERANCE`] or the bracket
/// is 1/256 of its start, after at most [`ROOT_STEPS`] queries (bisection took 8).
fn inside_end(
    g: &impl Fn(f64) -> f64,
    (mut a, mut ga): (f64, f64),
    (mut b, mut gb): (f64, f64),
) -> f64 {
    let narrow = (b - a).abs() / 256.0;
    let secant = |a: f64, ga: f64, b: f64, gb: f64| (a * gb - b * ga) / (gb - ga);
    // Which end moved last: a second move of the same end halves the other's value.
    let mut moved_a_last = None;
    for _ in 0..ROOT_STEPS {
        let z = secant(a, ga, b, gb);
        let gz = g(z);
        if gz.abs() <= ROOT_WINDING_TOLERANCE {
            return z;
        }
        if (gz > 0.0) == (ga > 0.0) {
            (a, ga) = (z, gz);
            if moved_a_last == Some(true) {
                gb *= 0.5;
            }
            moved_a_last = Some(true);
        } else {
            (b, gb) = (z, gz);
            if moved_a_last == Some(false) {
                ga *= 0.5;
            }
            moved_a_last = Some(false);
        }
        if (b - a).abs() <= narrow {
            break;
        }
    }
    secant(a, ga, b, gb)
}

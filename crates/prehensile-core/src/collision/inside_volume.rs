//! Volume and centre of mass of a mesh's inside as the winding number defines it, for meshes
//! whose signed tetrahedra would count overlaps twice or leak through holes.
//!
//! Vertical lines through the cells of a grid over the mesh's bounding box are cut at every
//! triangle they cross. Where every edge is balanced (closed parts, overlapping, nested or
//! self-intersecting), the winding number is constant between two crossings and changes by ±1 at
//! each, so counting crossings gives it without a query and the inside length along the line is
//! exact; the same count finds space covered twice ([`overlaps_itself`]). Around the holes or
//! flipped faces of other meshes it changes smoothly between crossings, so a piece is sampled at
//! up to [`SAMPLES_PER_PIECE`] points and each change between neighbouring samples located by
//! bisection. The inside lengths times the cells' areas sum to the volume (midpoint rule across x
//! and y: within 1% on the shapes of `tests/integration/winding_oracle.rs`).

use rayon::prelude::*;

use crate::math::{Point3, Vec3};

use super::TriangleBvh;

/// Most samples along one piece between crossings when the winding number may vary there.
const SAMPLES_PER_PIECE: usize = 6;
/// Bisection steps locating where the inside ends between two samples (1/256 of their gap).
const BISECTIONS: usize = 8;

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

/// Volume (m³) and centroid of the points of `exact`'s bounding box that [`TriangleBvh::inside`]
/// calls inside, integrated on `cells` lines along the longer horizontal side of the box.
/// `piecewise_constant` says that every edge is balanced, so crossings can be counted.
pub fn inside_volume_and_centroid(
    exact: &TriangleBvh,
    cells: usize,
    piecewise_constant: bool,
) -> (f64, Point3) {
    let (lo, hi) = exact.bounds();
    let longer = (hi.x - lo.x).max(hi.y - lo.y);
    // Samples along a piece between crossings at about the line spacing.
    let step = longer / cells.max(1) as f64;
    let lines = LineGrid::new(exact, cells);
    // Lines in parallel (with winding-number queries an open scan's lines take most of its
    // setup), summed afterwards in line order: the same sums, bit for bit, on any thread count.
    let per_line: Vec<(f64, f64, f64, f64)> = (0..lines.len())
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(crossings, heights), k| {
                let (x, y) = lines.crossings(exact, k, crossings);
                let (mut length, mut height_moment) = (0.0, 0.0);
                let mut add = |z0: f64, z1: f64| {
                    length += z1 - z0;
                    height_moment += 0.5 * (z1 * z1 - z0 * z0);
                };
                match counted_windings(crossings).filter(|_| piecewise_constant) {
                    Some(windings) => {
                        for (z0, z1, winding) in windings {
                            if winding != 0 {
                                add(z0, z1);
                            }
                        }
                    }
                    None => {
                        // The box's floor and ceiling too: over an open cup's mouth the inside
                        // ends without a crossing.
                        heights.clear();
                        heights.extend(crossings.iter().map(|c| c.0));
                        heights.extend([lo.z, hi.z]);
                        heights.sort_unstable_by(f64::total_cmp);
                        for pair in heights.windows(2) {
                            inside_parts_of_piece(exact, x, y, pair[0], pair[1], step, &mut add);
                        }
                    }
                }
                (x, y, length, height_moment)
            },
        )
        .collect();
    let (mut volume, mut moment) = (0.0, Vec3::zeros());
    for (x, y, length, height_moment) in per_line {
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
    (volume, centroid)
}

/// Calls `add(z0, z1)` for the inside parts of the piece `start..end` of the line through
/// `(x, y)`: sampled at up to [`SAMPLES_PER_PIECE`] points about `step` apart, each change
/// between neighbouring samples located by bisection.
fn inside_parts_of_piece(
    exact: &TriangleBvh,
    x: f64,
    y: f64,
    start: f64,
    end: f64,
    step: f64,
    add: &mut impl FnMut(f64, f64),
) {
    if end <= start {
        return;
    }
    let inside_at = |z: f64| exact.inside(&Point3::new(x, y, z));
    let samples = ((end - start) / step)
        .ceil()
        .clamp(1.0, SAMPLES_PER_PIECE as f64) as usize;
    let piece = (end - start) / samples as f64;
    let at = |k: usize| start + (k as f64 + 0.5) * piece;
    let mut flags = [false; SAMPLES_PER_PIECE];
    for (k, flag) in flags.iter_mut().enumerate().take(samples) {
        *flag = inside_at(at(k));
    }
    // Sample k owns [lower, upper]; between two samples that disagree the bound is where the
    // inside ends, found by bisection.
    let mut lower = start;
    for k in 0..samples {
        let upper = if k + 1 == samples {
            end
        } else if flags[k] == flags[k + 1] {
            start + (k + 1) as f64 * piece
        } else {
            let (mut a, mut b) = (at(k), at(k + 1));
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (a + b);
                if inside_at(mid) == flags[k] {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            0.5 * (a + b)
        };
        if flags[k] {
            add(lower, upper);
        }
        lower = upper;
    }
}

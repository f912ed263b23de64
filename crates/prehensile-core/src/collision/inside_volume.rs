//! Volume and centre of mass of a mesh's inside as the winding number defines it, for meshes
//! whose signed tetrahedra would count overlaps twice or leak through holes.
//!
//! Vertical lines through the centres of a grid of cells over the mesh's bounding box are cut at
//! every triangle they cross. Where every part is closed and consistently wound (overlapping or
//! nested parts), the winding number is constant between two crossings and changes by ±1 at
//! each, so counting crossings gives it without a query, and the inside length along the line is
//! exact (a line that does not count back to 0, through an edge counted twice, is asked at the
//! middle of each piece instead). Around the holes
//! or flipped faces of other meshes it changes smoothly between crossings, so a piece is sampled
//! at up to [`SAMPLES_PER_PIECE`] points and each change between neighbouring samples located by
//! bisection. The inside lengths times the cells' areas sum to the volume (midpoint rule across x
//! and y: within 1% on the shapes of `tests/winding_oracle.rs`).

use crate::math::{Point3, Vec3};

use super::TriangleBvh;

/// Most samples along one piece between crossings when the winding number may vary there.
const SAMPLES_PER_PIECE: usize = 6;
/// Bisection steps locating where the inside ends between two samples (1/256 of their gap).
const BISECTIONS: usize = 8;

/// Volume (m³) and centroid of the points of `exact`'s bounding box that [`TriangleBvh::inside`]
/// calls inside, integrated on `cells` lines along the longer horizontal side of the box.
/// `piecewise_constant` says that every part is closed and consistently wound, so one query per
/// piece between crossings is exact.
pub fn inside_volume_and_centroid(
    exact: &TriangleBvh,
    cells: usize,
    piecewise_constant: bool,
) -> (f64, Point3) {
    let (lo, hi) = exact.bounds();
    let size = hi - lo;
    let longer = size.x.max(size.y);
    if longer <= 0.0 || cells == 0 {
        return (0.0, nalgebra::center(&lo, &hi));
    }
    // Cells tile the box exactly on both axes, nearly square.
    let count = |side: f64| ((cells as f64 * side / longer).round() as usize).max(1);
    let (nx, ny) = (count(size.x), count(size.y));
    let (hx, hy) = (size.x / nx as f64, size.y / ny as f64);
    let step = if piecewise_constant {
        f64::INFINITY
    } else {
        hx.max(hy)
    };
    let mut crossings: Vec<(f64, i32)> = Vec::new();
    let mut heights: Vec<f64> = Vec::new();
    let (mut volume, mut moment) = (0.0, Vec3::zeros());
    for i in 0..nx {
        // Off-centre by irrational fractions, so lines miss the diagonals of axis-aligned faces.
        let x = lo.x + (i as f64 + 0.5 + 1e-3 * std::f64::consts::SQRT_2) * hx;
        for j in 0..ny {
            let y = lo.y + (j as f64 + 0.5 + 1e-3 * std::f64::consts::LN_2) * hy;
            exact.vertical_crossings(x, y, &mut crossings);
            crossings.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
            let (mut length, mut height_moment) = (0.0, 0.0);
            let counted = piecewise_constant && crossings.iter().map(|c| c.1).sum::<i32>() == 0;
            if counted {
                let mut winding = 0;
                for pair in crossings.windows(2) {
                    winding += pair[0].1;
                    let (z0, z1) = (pair[0].0, pair[1].0);
                    if winding != 0 {
                        length += z1 - z0;
                        height_moment += 0.5 * (z1 * z1 - z0 * z0);
                    }
                }
                volume += length;
                moment += Vec3::new(x * length, y * length, height_moment);
                continue;
            }
            // The box's floor and ceiling too: over an open cup's mouth the inside ends without
            // a crossing.
            heights.clear();
            heights.extend(crossings.iter().map(|c| c.0));
            heights.extend([lo.z, hi.z]);
            heights.sort_unstable_by(f64::total_cmp);
            for pair in heights.windows(2) {
                let (start, end) = (pair[0], pair[1]);
                if end <= start {
                    continue;
                }
                let inside_at = |z: f64| exact.inside(&Point3::new(x, y, z));
                let mut add = |z0: f64, z1: f64| {
                    length += z1 - z0;
                    height_moment += 0.5 * (z1 * z1 - z0 * z0);
                };
                let samples = ((end - start) / step)
                    .ceil()
                    .clamp(1.0, SAMPLES_PER_PIECE as f64);
                let samples = samples as usize;
                let piece = (end - start) / samples as f64;
                let at = |k: usize| start + (k as f64 + 0.5) * piece;
                let flags: Vec<bool> = (0..samples).map(|k| inside_at(at(k))).collect();
                // Sample k owns [bounds[k], bounds[k + 1]]; between two samples that disagree
                // the bound is where the inside ends, found by bisection.
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
            volume += length;
            moment += Vec3::new(x * length, y * length, height_moment);
        }
    }
    let cell_area = hx * hy;
    volume *= cell_area;
    moment *= cell_area;
    let centroid = if volume > 0.0 {
        Point3::from(moment / volume)
    } else {
        nalgebra::center(&lo, &hi)
    };
    (volume, centroid)
}

//! Built-in procedural objects for defaults and tests: sphere, box, cylinder, torus and a mug with
//! a handle. Every shape is a closed, manifold, outward-wound mesh centred on the origin's axis.

use std::f64::consts::{PI, TAU};

use crate::math::{Point3, Vec3};
use crate::mesh::TriangleMesh;

/// Names of the built-in objects, in the order `prehensile demo` uses them.
pub const BUILTIN_OBJECTS: [&str; 5] = ["sphere", "box", "cylinder", "torus", "mug"];

/// The built-in object with this name at its default size, or `None`.
pub fn builtin_object(name: &str) -> Option<TriangleMesh> {
    Some(match name {
        "sphere" => sphere(0.04, 32, 16),
        "box" => cuboid(Vec3::new(0.06, 0.05, 0.09)),
        "cylinder" => cylinder(0.035, 0.14, 32),
        "torus" => torus(0.045, 0.014, 32, 16),
        "mug" => mug(0.04, 0.1, 0.005, 32),
        _ => return None,
    })
}

/// Surface of revolution about z of a profile `(radius, z)` that starts and ends on the axis.
fn revolve(profile: &[(f64, f64)], segments: usize) -> (Vec<Point3>, Vec<[usize; 3]>) {
    let rings = profile.len();
    let mut vertices = Vec::new();
    let mut index = vec![vec![0usize; segments]; rings];
    for (p, &(r, z)) in profile.iter().enumerate() {
        if r == 0.0 {
            vertices.push(Point3::new(0.0, 0.0, z));
            index[p] = vec![vertices.len() - 1; segments];
        } else {
            for (i, slot) in index[p].iter_mut().enumerate() {
                let t = TAU * i as f64 / segments as f64;
                vertices.push(Point3::new(r * t.cos(), r * t.sin(), z));
                *slot = vertices.len() - 1;
            }
        }
    }
    let mut triangles = Vec::new();
    for p in 0..rings - 1 {
        for i in 0..segments {
            let j = (i + 1) % segments;
            let (a, b, c, d) = (index[p][i], index[p][j], index[p + 1][j], index[p + 1][i]);
            if a != b {
                triangles.push([a, b, c]);
            }
            if c != d {
                triangles.push([a, c, d]);
            }
        }
    }
    (vertices, triangles)
}

fn weld(v: Vec<Point3>, t: Vec<[usize; 3]>) -> TriangleMesh {
    TriangleMesh::weld(&v, &t).expect("procedural shapes are finite and indexed correctly")
}

/// A UV sphere of `radius` centred at the origin.
pub fn sphere(radius: f64, segments: usize, rings: usize) -> TriangleMesh {
    let profile: Vec<(f64, f64)> = (0..=rings)
        .map(|k| {
            let phi = PI * k as f64 / rings as f64;
            let r = if k == 0 || k == rings {
                0.0
            } else {
                radius * phi.sin()
            };
            (r, -radius * phi.cos())
        })
        .collect();
    let (v, t) = revolve(&profile, segments);
    weld(v, t)
}

/// A closed cylinder about z, centred at the origin.
pub fn cylinder(radius: f64, height: f64, segments: usize) -> TriangleMesh {
    let h = height / 2.0;
    let mut profile = vec![(0.0, -h)];
    for k in 0..=4 {
        profile.push((radius, -h + height * k as f64 / 4.0));
    }
    profile.push((0.0, h));
    let (v, t) = revolve(&profile, segments);
    weld(v, t)
}

/// An axis-aligned box with the given full sizes, centred at the origin.
pub fn cuboid(size: Vec3) -> TriangleMesh {
    let h = size / 2.0;
    let v: Vec<Point3> = (0..8)
        .map(|i| {
            Point3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    weld(v, t)
}

/// A torus about z: `major` radius to the tube's centre, `minor` tube radius.
pub fn torus(major: f64, minor: f64, segments: usize, sides: usize) -> TriangleMesh {
    let mut v = Vec::new();
    for i in 0..segments {
        let u = TAU * i as f64 / segments as f64;
        for j in 0..sides {
            let w = TAU * j as f64 / sides as f64;
            let r = major + minor * w.cos();
            v.push(Point3::new(r * u.cos(), r * u.sin(), minor * w.sin()));
        }
    }
    let id = |i: usize, j: usize| (i % segments) * sides + (j % sides);
    let mut t = Vec::new();
    for i in 0..segments {
        for j in 0..sides {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    weld(v, t)
}

/// A mug standing on z = 0: outer `radius`, `height`, wall and bottom `thickness`, and a handle on
/// the +x side stitched into the wall, so the mesh is one closed genus-1 surface with a cavity.
pub fn mug(radius: f64, height: f64, thickness: f64, segments: usize) -> TriangleMesh {
    let wall_rows = 8;
    let mut profile = vec![(0.0, 0.0)];
    for k in 0..=wall_rows {
        profile.push((radius, height * k as f64 / wall_rows as f64));
    }
    let inner = radius - thickness;
    profile.push((inner, height));
    profile.push((inner, thickness));
    profile.push((0.0, thickness));
    // Rotate by half a segment so the handle's wall quad is centred on +x.
    let (mut v, mut t) = revolve(&profile, segments);
    let half = PI / segments as f64;
    let (s, c) = half.sin_cos();
    for p in v.iter_mut() {
        *p = Point3::new(c * p.x + s * p.y, -s * p.x + c * p.y, p.z);
    }
    // Wall quad at segment 0 between profile rings `lo` and `lo + 1` (ring p has vertices
    // 1 + (p - 1) * segments .. for p >= 1).
    let ring_vertex = |p: usize, i: usize| 1 + (p - 1) * segments + (i % segments);
    let (row_a, row_b) = (3, 6);
    let hole = |row: usize| {
        let p = 1 + row;
        [
            ring_vertex(p, 0),
            ring_vertex(p, 1),
            ring_vertex(p + 1, 1),
            ring_vertex(p + 1, 0),
        ]
    };
    let holes = [hole(row_a), hole(row_b)];
    t.retain(|tri| !holes.iter().any(|h| tri.iter().all(|i| h.contains(i))));
    // Tube from hole A to hole B along a half-circle bulging outward (+x).
    let centre = |h: &[usize; 4]| {
        let sum = h.iter().fold(Vec3::zeros(), |a, &i| a + v[i].coords);
        Point3::from(sum / 4.0)
    };
    let (ca, cb) = (centre(&holes[0]), centre(&holes[1]));
    let mid = nalgebra::center(&ca, &cb);
    let rho = (cb.z - ca.z) / 2.0;
    let steps = 12;
    let mut rings: Vec<[usize; 4]> = vec![holes[0]];
    for k in 1..steps {
        let phi = -PI / 2.0 + PI * k as f64 / steps as f64;
        let path = mid + Vec3::new(1.3 * rho * phi.cos(), 0.0, rho * phi.sin());
        // Carry the hole's corners along: offsets from the hole centre, rotated in the xz-plane.
        let ring: [usize; 4] = std::array::from_fn(|c| {
            let off = v[holes[0][c]] - ca;
            let angle = phi + PI / 2.0;
            let (s, co) = angle.sin_cos();
            let rotated = Vec3::new(co * off.x - s * off.z, off.y, s * off.x + co * off.z);
            v.push(path + rotated);
            v.len() - 1
        });
        rings.push(ring);
    }
    // Hole B's corners in the order matching hole A's after a half turn: bottom and top swap.
    let b = holes[1];
    rings.push([b[3], b[2], b[1], b[0]]);
    for k in 0..steps {
        for c in 0..4 {
            let d = (c + 1) % 4;
            let (p, q, r, s) = (rings[k][c], rings[k][d], rings[k + 1][d], rings[k + 1][c]);
            t.push([p, q, r]);
            t.push([p, r, s]);
        }
    }
    weld(v, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_object_is_closed_and_outward() {
        for name in BUILTIN_OBJECTS {
            let mesh = builtin_object(name).unwrap();
            let report = mesh.report();
            assert!(report.defects.is_empty(), "{name}: {:?}", report.defects);
            assert!(report.volume > 0.0, "{name}");
        }
        assert!(builtin_object("teapot").is_none());
    }

    #[test]
    fn volumes_match_closed_forms() {
        let s = sphere(0.04, 64, 32).report().volume;
        let exact = 4.0 / 3.0 * PI * 0.04f64.powi(3);
        assert!((s - exact).abs() / exact < 0.01, "{s} vs {exact}");
        let t = torus(0.045, 0.014, 64, 32).report().volume;
        let exact = 2.0 * PI * PI * 0.045 * 0.014f64.powi(2);
        assert!((t - exact).abs() / exact < 0.01, "{t} vs {exact}");
        let b = cuboid(Vec3::new(0.06, 0.05, 0.09)).report().volume;
        assert!((b - 0.06 * 0.05 * 0.09).abs() < 1e-15);
    }

    #[test]
    fn mug_has_genus_one() {
        let m = builtin_object("mug").unwrap();
        // Euler characteristic V - E + F = 2 - 2g; closed triangle mesh: E = 3F/2.
        let f = m.triangles.len() as i64;
        let chi = m.vertices.len() as i64 - 3 * f / 2 + f;
        assert_eq!(chi, 0, "genus-1 surface has Euler characteristic 0");
    }
}

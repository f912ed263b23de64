//! Closest point on a triangle to a point (Ericson §5.1.5), with the feature it lies on.

use crate::math::{Point3, Vec3};

/// The feature of a triangle on which a closest point lies; used to pick the pseudo-normal that
/// gives the sign of a signed distance (Bærentzen & Aanæs 2005).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TriangleFeature {
    /// A corner: 0, 1 or 2.
    Vertex(u8),
    /// An edge from corner `i` to corner `(i + 1) % 3`.
    Edge(u8),
    /// The interior of the face.
    Face,
}

/// Returns the point of triangle `(a, b, c)` closest to `p`, and the feature it lies on.
pub fn closest_point_on_triangle(
    p: &Point3,
    a: &Point3,
    b: &Point3,
    c: &Point3,
) -> (Point3, TriangleFeature) {
    let ab: Vec3 = b - a;
    let ac: Vec3 = c - a;
    let ap: Vec3 = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (*a, TriangleFeature::Vertex(0));
    }
    let bp: Vec3 = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (*b, TriangleFeature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, TriangleFeature::Edge(0));
    }
    let cp: Vec3 = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (*c, TriangleFeature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, TriangleFeature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, TriangleFeature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, TriangleFeature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> (Point3, Point3, Point3) {
        (
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        )
    }

    #[test]
    fn regions_are_classified() {
        let (a, b, c) = tri();
        let (q, f) = closest_point_on_triangle(&Point3::new(0.2, 0.2, 1.0), &a, &b, &c);
        assert_eq!(f, TriangleFeature::Face);
        assert!((q - Point3::new(0.2, 0.2, 0.0)).norm() < 1e-15);
        let (q, f) = closest_point_on_triangle(&Point3::new(-1.0, -1.0, 0.0), &a, &b, &c);
        assert_eq!(f, TriangleFeature::Vertex(0));
        assert_eq!(q, a);
        let (q, f) = closest_point_on_triangle(&Point3::new(1.0, 1.0, 0.0), &a, &b, &c);
        assert_eq!(f, TriangleFeature::Edge(1));
        assert!((q - Point3::new(0.5, 0.5, 0.0)).norm() < 1e-15);
        let (_, f) = closest_point_on_triangle(&Point3::new(0.5, -1.0, 0.3), &a, &b, &c);
        assert_eq!(f, TriangleFeature::Edge(0));
        let (_, f) = closest_point_on_triangle(&Point3::new(-0.5, 0.5, 0.3), &a, &b, &c);
        assert_eq!(f, TriangleFeature::Edge(2));
    }
}

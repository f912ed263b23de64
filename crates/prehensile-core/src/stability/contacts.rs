//! Contacts of a posed hand with the object: for every capsule within a tolerance of the surface,
//! the points where it touches, with the surface normal, from exact distance queries.
//!
//! A capsule touches where the distance from its axis to the surface, less its radius, has a
//! local minimum within the tolerance. The axis is sampled and each minimum found exactly as the
//! point of the axis between the neighbouring samples nearest the mesh (one segment–mesh query),
//! so a fingertip on a sphere gives one contact and a phalanx lying along a flat face gives a
//! line of them (up to [`MAX_CONTACTS_PER_CAPSULE`], at least a radius apart). An axis that
//! crosses into the object is refined by golden-section search for its deepest point.

use crate::collision::Capsule;
use crate::hand::HandModel;
use crate::math::{Point3, Vec3};
use crate::object::ObjectModel;

/// Samples along each capsule's axis.
const AXIS_SAMPLES: usize = 9;
/// Golden-section iterations refining a minimum (interval shrinks to 0.618^12 ≈ 0.3%).
const REFINE_ITERATIONS: usize = 12;
/// Most contacts kept per capsule.
pub const MAX_CONTACTS_PER_CAPSULE: usize = 3;

/// One contact between a bone's capsule and the object.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Contact {
    /// The bone whose capsule touches.
    pub bone: usize,
    /// Index of the capsule in [`HandModel::capsules`].
    pub capsule: usize,
    /// The contact point on the object's surface, object frame, metres.
    pub point: Point3,
    /// Unit normal at the contact pointing into the object: the direction the hand pushes.
    pub normal: Vec3,
    /// Gap between the capsule and the surface, metres (negative: it enters the object).
    pub gap: f64,
    /// Radius of the touching capsule, metres.
    pub radius: f64,
}

/// Finds the contacts of the world capsules `capsules` (one per hand capsule, as in
/// [`crate::Workspace::capsules`]) within `tolerance` of the object's surface, into `out`.
pub fn find_contacts(
    hand: &HandModel,
    object: &ObjectModel,
    capsules: &[Capsule],
    tolerance: f64,
    out: &mut Vec<Contact>,
) {
    out.clear();
    let exact = object.collider().exact();
    for (index, (capsule, model)) in capsules.iter().zip(hand.capsules()).enumerate() {
        let reach = capsule.radius + tolerance;
        if !exact.segment_within(&capsule.a, &capsule.b, reach) {
            continue;
        }
        // Gap along the axis at parameter s ∈ [0, 1]; far samples count as far.
        let gap = |s: f64| -> f64 {
            let p = capsule.a + (capsule.b - capsule.a) * s;
            exact
                .closest_point_within(&p, reach + capsule.radius)
                .map_or(f64::INFINITY, |q| q.signed_distance - capsule.radius)
        };
        let mut samples = [0.0; AXIS_SAMPLES];
        for (k, g) in samples.iter_mut().enumerate() {
            *g = gap(k as f64 / (AXIS_SAMPLES - 1) as f64);
        }
        let first = out.len();
        // Local minima, lowest first.
        let mut minima = [(f64::INFINITY, 0usize); AXIS_SAMPLES];
        let mut count = 0;
        for k in 0..AXIS_SAMPLES {
            let left = if k > 0 { samples[k - 1] } else { f64::INFINITY };
            let right = samples.get(k + 1).copied().unwrap_or(f64::INFINITY);
            if samples[k] <= left && samples[k] <= right && samples[k].is_finite() {
                minima[count] = (samples[k], k);
                count += 1;
            }
        }
        minima[..count].sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(_, k) in &minima[..count] {
            let step = 1.0 / (AXIS_SAMPLES - 1) as f64;
            let lo = (k as f64 - 1.0).max(0.0) * step;
            let hi = (k as f64 + 1.0).min((AXIS_SAMPLES - 1) as f64) * step;
            let along = |s: f64| capsule.a + (capsule.b - capsule.a) * s;
            // The axis between the neighbouring samples comes nearest the surface where its
            // exact distance to the mesh is least; an axis that crosses into the object (deep
            // penetration) is searched for its deepest point instead.
            let (s, q) = match exact.closest_point_to_segment_within(&along(lo), &along(hi), reach)
            {
                None => continue,
                Some((s, q)) if q.signed_distance > 1e-9 => (lo + (hi - lo) * s, q),
                Some(_) => {
                    let s = golden_section_minimum(&gap, lo, hi);
                    match exact.closest_point_within(&along(s), reach + capsule.radius) {
                        Some(q) => (s, q),
                        None => continue,
                    }
                }
            };
            let p = along(s);
            let gap = q.signed_distance - capsule.radius;
            if gap > tolerance {
                continue;
            }
            if out[first..]
                .iter()
                .any(|c| (c.point - q.point).norm() < capsule.radius)
            {
                continue;
            }
            // From the axis to the surface when the axis is outside; against the outward
            // pseudo-normal when the axis itself is inside (deep penetration).
            let toward = q.point - p;
            let normal = if q.signed_distance > 1e-9 && toward.norm() > 1e-12 {
                toward.normalize()
            } else {
                -q.normal
            };
            out.push(Contact {
                bone: model.bone,
                capsule: index,
                point: q.point,
                normal,
                gap,
                radius: capsule.radius,
            });
            if out.len() - first == MAX_CONTACTS_PER_CAPSULE {
                break;
            }
        }
    }
}

/// The minimum of `f` on `[lo, hi]` by golden-section search, or the better end point.
fn golden_section_minimum(f: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    const INVERSE_PHI: f64 = 0.618_033_988_749_894_9;
    let mut x1 = hi - INVERSE_PHI * (hi - lo);
    let mut x2 = lo + INVERSE_PHI * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..REFINE_ITERATIONS {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - INVERSE_PHI * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + INVERSE_PHI * (hi - lo);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        x1
    } else {
        x2
    }
}

//! Contact generation for a capsule against the object, for a simulation step: the point of the
//! capsule's segment nearest the surface (or deepest inside), its gap and the surface normal
//! there.
//!
//! The signed distance along the segment is minimized in one dimension: regula falsi on its
//! slope (the gradient along the segment), bracketed by the start and the segment end it
//! descends toward. Alternating projections (segment point → nearest surface point → nearest
//! segment point), the textbook way, crawl when the capsule lies along the surface: each round
//! gains about gap/R of the way on a surface of radius R. On a convex surface the search finds
//! the segment's nearest point; on a concave one it may stop in a local dip, which still gives a
//! contact where the capsule touches. A warm start from the fraction the caller found the step
//! before (a resting contact moves little between steps) costs one to three samples; a cold one
//! starts from the lowest of five points along the capsule.
//!
//! The distance field is the object's contact grid (finer than the search's, see
//! [`MeshCollider::contact_grid`]) read by trilinear interpolation
//! ([`SignedDistanceGrid::sample`]: eight node reads, no triangle touched), after the grid's
//! one-lookup test ([`SignedDistanceGrid::proves_clear`]) has skipped the far capsules. A mesh
//! without a grid (its inside from winding numbers) is sampled by exact nearest-point queries
//! instead. This is the narrow phase a reduced-coordinate engine needs (docs/PERFORMANCE.md,
//! "Simulation"): parry's GJK/EPA against the object's hull cost 185–198 µs for the Shadow hand's
//! 24 capsules, this 11 µs warm-started.

use crate::math::{Point3, Vec3};

use super::{Capsule, Decision, MeshCollider};

/// Most samples per capsule after the first.
const MAX_ROUNDS: usize = 16;
/// Where along a capsule a search without a start looks first (segment fractions).
const SPREAD: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
/// How far along the segment the first probe goes (metres).
const NUDGE: f64 = 1e-3;
/// Stop once the distance can fall by less than this (metres): 10 µm, a tenth or less of the
/// grid's interpolation error (measured 0.06–0.26 spacings of 2–3 mm), which bounds what a
/// finer search could learn. At 1 µm the Shadow hand's contacts took a fifth more samples.
const CONVERGED: f64 = 1e-5;

/// One capsule's contact with the object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CapsuleContact {
    /// Where along the segment the nearest point lies, as a fraction from `a` to `b` (pass it
    /// back as the next step's `warm_start`).
    pub fraction: f64,
    /// Distance from the capsule's surface to the object's, negative when they overlap.
    pub gap: f64,
    /// Outward unit normal of the object's surface at the contact.
    pub normal: Vec3,
    /// The contact point on the object's surface.
    pub point: Point3,
}

impl MeshCollider {
    /// The capsule's contact with the object if its gap is at most `margin` metres; `None` when
    /// the capsule is farther. `warm_start` is the segment fraction of the last step's contact.
    /// Without one, a capsule whose nearest point the search found outside the object while
    /// the grid proves it overlapping (a local dip of a concave object) is searched again from
    /// five points along it; a warm start trusts the contact it follows. A capsule with a NaN or
    /// infinite coordinate or radius has no contact. Allocates nothing.
    pub fn capsule_contact(
        &self,
        capsule: &Capsule,
        margin: f64,
        warm_start: Option<f64>,
    ) -> Option<CapsuleContact> {
        let finite = |p: &Point3| p.coords.iter().all(|x| x.is_finite());
        if !(finite(&capsule.a) && finite(&capsule.b) && capsule.radius.is_finite()) {
            return None;
        }
        let reach = capsule.radius + margin.max(0.0);
        let fraction = warm_start.map(|t| t.clamp(0.0, 1.0));
        if let Some(grid) = self.contact_grid() {
            let exact = self.exact();
            if grid.proves_clear(exact, &capsule.a, &capsule.b, reach) {
                return None;
            }
            let sample = |p: &Point3| grid.sample(exact, p);
            let found = nearest_point(capsule, reach, fraction, sample);
            if warm_start.is_none()
                && found.is_none_or(|c| c.gap > 0.0)
                && grid.decide(exact, &capsule.a, &capsule.b, capsule.radius) == Decision::Touches
            {
                // The grid proves an overlap the search missed: it stopped in a local dip of a
                // concave object. Search again from points spread along the capsule.
                return SPREAD
                    .into_iter()
                    .filter_map(|t| nearest_point(capsule, reach, Some(t), sample))
                    .chain(found)
                    .min_by(|x, y| x.gap.total_cmp(&y.gap));
            }
            found
        } else {
            let length = (capsule.b - capsule.a).norm();
            nearest_point(capsule, reach, fraction, |p| {
                // Far enough to sample every point of a segment that comes within reach.
                let s = self.exact().closest_point_within(p, reach + length)?;
                let towards = (p - s.point) * s.signed_distance.signum();
                let normal = towards.try_normalize(1e-12).unwrap_or(s.normal);
                Some((s.signed_distance, normal))
            })
        }
    }
}

/// One sample of the distance along the segment.
#[derive(Clone, Copy)]
struct Sample {
    /// Segment fraction.
    t: f64,
    /// Signed distance there.
    distance: f64,
    /// Its derivative along the segment (per unit fraction).
    slope: f64,
    /// Unit gradient of the distance: the outward surface normal.
    normal: Vec3,
}

/// The segment point where the signed distance is least (module docs; Illinois regula falsi),
/// from `start` or the lowest of five spread points, with `sample` giving the signed distance
/// and its gradient at a point (`None`: too far to say); `None` when no point comes within
/// `reach` of the surface. Keeps the lowest point sampled.
fn nearest_point(
    capsule: &Capsule,
    reach: f64,
    start: Option<f64>,
    sample: impl Fn(&Point3) -> Option<(f64, Vec3)>,
) -> Option<CapsuleContact> {
    let axis = capsule.b - capsule.a;
    let length = axis.norm();
    let at = |t: f64| -> Option<Sample> {
        let (distance, gradient) = sample(&(capsule.a + axis * t))?;
        Some(Sample {
            t,
            distance,
            slope: gradient.dot(&axis),
            normal: gradient.try_normalize(1e-9)?,
        })
    };
    // Without a start (or one too far to sample), the lowest of five points spread along the
    // capsule: on a concave object the lowest dip is then the one searched.
    let mut best = start.and_then(at).or_else(|| {
        SPREAD
            .into_iter()
            .filter_map(at)
            .min_by(|x, y| x.distance.total_cmp(&y.distance))
    })?;
    let mut near = best;
    // The far end of the bracket, first the segment end the distance descends toward; `far` is
    // its sample, `None` until one was taken there (a point too far to sample has none).
    let mut far_t = if near.slope > 0.0 { 0.0 } else { 1.0 };
    let mut far: Option<Sample> = None;
    // First a millimetre along the descent: from a warm start at last step's answer this
    // brackets the minimum at once.
    let nudge = if length > 0.0 { NUDGE / length } else { 1.0 };
    let mut probe_t = if (far_t - near.t).abs() > nudge {
        near.t + nudge.copysign(far_t - near.t)
    } else {
        far_t
    };
    let mut stale = 0;
    for _ in 0..MAX_ROUNDS {
        let width = (far_t - near.t).abs();
        // With the distance convex along the bracket, no point in it is lower than the
        // nearer end by more than |slope|·width.
        let fall = near.slope.abs() * width;
        if near.slope == 0.0 || fall <= CONVERGED || width * length <= CONVERGED {
            break;
        }
        // Nothing in the bracket comes within reach: the distance is 1-Lipschitz, whatever the
        // object's shape.
        if near.distance - width * length > reach {
            return None;
        }
        let Some(next) = at(probe_t) else {
            // Too far to sample: the lowest point is nearer; halve towards it.
            far_t = probe_t;
            probe_t = 0.5 * (near.t + far_t);
            continue;
        };
        if next.distance < best.distance {
            best = next;
        }
        if next.slope * near.slope > 0.0 {
            // Still descending at `next`: it is the new near end, or the minimum is the end.
            if next.t == far_t {
                break;
            }
            near = next;
            stale += 1;
        } else {
            far_t = next.t;
            far = Some(next);
            stale = 0;
        }
        // Regula falsi on the slope between the ends, halving the far end's slope when the same
        // end stays (Illinois) so the bracket keeps shrinking from both sides.
        if let Some(f) = far.as_mut() {
            if stale > 1 {
                f.slope *= 0.5;
            }
        }
        probe_t = match far {
            Some(f) if f.t == far_t => {
                near.t - near.slope * (far_t - near.t) / (f.slope - near.slope)
            }
            _ => far_t,
        };
    }
    (best.distance <= reach).then(|| CapsuleContact {
        fraction: best.t,
        gap: best.distance - capsule.radius,
        normal: best.normal,
        point: capsule.a + axis * best.t - best.normal * best.distance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{Decision, TriangleBvh};
    use crate::shapes::builtin_object;
    use crate::ObjectModel;
    use proptest::prelude::*;

    /// The contact margin the tests ask for (metres).
    const MARGIN: f64 = 0.003;

    /// A capsule near the object's surface: a surface point nearest `seed` (a point of the
    /// object's box), moved out along the normal by the radius plus `offset`, lying at
    /// `at` along a segment of `length` in `direction`.
    fn capsule_near(
        exact: &TriangleBvh,
        seed: [f64; 3],
        offset: f64,
        direction: [f64; 3],
        length: f64,
        at: f64,
    ) -> Option<Capsule> {
        let (lo, hi) = exact.bounds();
        let p = Point3::from(Vec3::from_fn(|i, _| lo[i] + (hi[i] - lo[i]) * seed[i]));
        let surface = exact.closest_point_within(&p, f64::INFINITY)?;
        let radius = 0.009;
        let centre = surface.point + surface.normal * (radius + offset);
        let direction = Vec3::from(direction).try_normalize(1e-6)?;
        Some(Capsule {
            a: centre - direction * (length * at),
            b: centre + direction * (length * (1.0 - at)),
            radius,
        })
    }

    /// Over capsules near an object, the largest amounts by which the contacts understate and
    /// overstate the exact gap (a contact's gap, or the margin for a capsule given none, against
    /// the exact segment distance less the radius), and how many capsules got a contact.
    fn errors(
        collider: &MeshCollider,
        exact: &TriangleBvh,
        cases: &[Capsule],
    ) -> (f64, f64, usize) {
        let (mut shallower, mut deeper, mut found) = (0.0f64, 0.0f64, 0);
        for capsule in cases {
            let distance = exact.segment_distance(&capsule.a, &capsule.b);
            let outside = distance > 0.0 && exact.signed_distance(&capsule.a) > 0.0;
            // A segment crossing the surface or inside is deeper than −radius: compare with that.
            let truth = if outside {
                distance - capsule.radius
            } else {
                -capsule.radius
            };
            let contact = collider.capsule_contact(capsule, MARGIN, None);
            found += contact.is_some() as usize;
            let error = match contact {
                Some(c) => c.gap - truth,
                None => (MARGIN - truth).max(0.0),
            };
            shallower = shallower.max(error);
            if outside {
                deeper = deeper.max(-error);
            }
        }
        (shallower, deeper, found)
    }

    fn cases(exact: &TriangleBvh, raw: &[Raw]) -> Vec<Capsule> {
        raw.iter()
            .filter_map(|&(s, o, d, l, t)| capsule_near(exact, s, o, d, l, t))
            .collect()
    }

    type Raw = ([f64; 3], f64, [f64; 3], f64, f64);

    fn raw_capsules() -> impl Strategy<Value = Vec<Raw>> {
        proptest::collection::vec(
            (
                [0.0..1.0f64, 0.0..1.0, 0.0..1.0],
                -0.004..0.006f64,
                [-1.0..1.0f64, -1.0..1.0, -1.0..1.0],
                0.0..0.04f64,
                0.0..1.0f64,
            ),
            200,
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(8))]

        /// On the built-in objects whose walls are thicker than the grid's spacing, every
        /// capsule near the surface gets its gap to within half a spacing (the interpolation's
        /// error at a sharp edge; about 0.05 spacings on the sphere), and one within the margin
        /// always gets a contact.
        #[test]
        fn grid_contacts_match_the_exact_gap_within_half_a_spacing(raw in raw_capsules()) {
            for name in ["sphere", "box", "cylinder", "torus"] {
                let object = ObjectModel::new(name, builtin_object(name).unwrap(), None).unwrap();
                let collider = object.collider();
                let exact = collider.exact();
                let capsules = cases(exact, &raw);
                let (shallower, deeper, found) = errors(collider, exact, &capsules);
                let spacing = collider.contact_grid().unwrap().spacing();
                prop_assert!(found > capsules.len() / 2, "{name}: {found} contacts");
                prop_assert!(shallower <= 0.5 * spacing, "{name}: understated by {shallower}");
                prop_assert!(deeper <= 0.5 * spacing, "{name}: overstated by {deeper}");
            }
        }

        /// The mug's 4 mm wall is under two grid spacings: interpolation across it can miss a
        /// capsule's overlap by up to a few spacings, but never reports one deeper than it is.
        #[test]
        fn grid_contacts_on_a_thin_wall_never_overstate_the_depth(raw in raw_capsules()) {
            let object = ObjectModel::new("mug", builtin_object("mug").unwrap(), None).unwrap();
            let collider = object.collider();
            let exact = collider.exact();
            let (_, deeper, _) = errors(collider, exact, &cases(exact, &raw));
            prop_assert!(deeper <= 0.5 * collider.contact_grid().unwrap().spacing(), "overstated by {deeper}");
        }

        /// A mesh without a grid (its inside from winding numbers) is sampled exactly, so its
        /// contacts have the exact gap to the search's stop (a tenth of a millimetre at worst,
        /// where the slope jumps across a box's edge).
        #[test]
        fn exact_contacts_have_the_exact_gap(raw in raw_capsules()) {
            for name in ["sphere", "box"] {
                let exact = TriangleBvh::with_winding_numbers(&builtin_object(name).unwrap());
                let collider = MeshCollider::from_exact(exact.clone(), 0.03);
                prop_assert!(collider.grid().is_none() && collider.contact_grid().is_none());
                let (shallower, deeper, _) = errors(&collider, &exact, &cases(&exact, &raw));
                prop_assert!(shallower <= 1e-4 && deeper <= 1e-4, "{name}: {shallower} {deeper}");
            }
        }
    }

    /// A NaN or infinite capsule gets no contact; a NaN one touches nothing, and the grid's
    /// test of it ends (its walk along a NaN segment never did) by leaving it to the exact path.
    #[test]
    fn a_capsule_that_is_not_finite_has_no_contact_and_does_not_hang() {
        let object = ObjectModel::new("sphere", builtin_object("sphere").unwrap(), None).unwrap();
        let origin = Point3::origin();
        let nan = Point3::new(f64::NAN, 0.0, 0.0);
        let far = Point3::new(f64::INFINITY, 0.0, 0.0);
        let capsule = |a, b, radius| Capsule { a, b, radius };
        let not_finite = [
            capsule(nan, origin, 0.01),
            capsule(origin, origin, f64::NAN),
            capsule(origin, nan, f64::INFINITY),
            capsule(far, origin, 0.01),
        ];
        for capsule in &not_finite {
            assert_eq!(
                object.collider().capsule_contact(capsule, MARGIN, None),
                None
            );
            assert_eq!(
                object
                    .collider()
                    .capsule_contact(capsule, MARGIN, Some(0.5)),
                None
            );
        }
        let grid = object.collider().grid().unwrap();
        let exact = object.collider().exact();
        for capsule in &not_finite[..3] {
            let decision = grid.decide(exact, &capsule.a, &capsule.b, capsule.radius);
            let unsure = Decision::Unsure {
                from: 0.0,
                to: 1.0,
                outside: false,
            };
            assert_eq!(decision, unsure);
            assert!(!object.capsule_touches(capsule, &mut Default::default()));
        }
        assert!(exact.signed_distance(&nan).is_nan());
    }

    /// Warm-started from its own answer, a contact is found again at once and unchanged.
    #[test]
    fn a_warm_start_at_the_answer_keeps_it() {
        let object = ObjectModel::new("sphere", builtin_object("sphere").unwrap(), None).unwrap();
        let centre = object.center_of_mass();
        let capsule = Capsule {
            a: centre + Vec3::new(0.048, -0.02, 0.01),
            b: centre + Vec3::new(0.047, 0.02, 0.0),
            radius: 0.009,
        };
        let cold = object
            .collider()
            .capsule_contact(&capsule, MARGIN, None)
            .unwrap();
        assert!(cold.gap < 0.0 && cold.normal.x > 0.9, "{cold:?}");
        let warm = object
            .collider()
            .capsule_contact(&capsule, MARGIN, Some(cold.fraction))
            .unwrap();
        assert!((warm.gap - cold.gap).abs() < 1e-6 && (warm.fraction - cold.fraction).abs() < 1e-3);
        let far = Capsule {
            a: capsule.a + Vec3::x() * 0.02,
            b: capsule.b + Vec3::x() * 0.02,
            ..capsule
        };
        assert_eq!(
            object
                .collider()
                .capsule_contact(&far, MARGIN, Some(cold.fraction)),
            None
        );
    }
}

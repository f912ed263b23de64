//! The grasp wrench space and the stability measures grasp research uses: force closure, the
//! Ferrari–Canny ε (L1) and the largest load the grasp resists along each axis.
//!
//! Each contact pushes inside a Coulomb friction cone of coefficient μ, linearized by
//! `cone_edges` edges `n + μ(cos θ t₁ + sin θ t₂)` with unit normal component, as in GraspIt!.
//! Finger pads are soft: each contact also resists a torsion about its normal up to
//! `μ · patch · f_n`, where the patch radius is `torsion_patch` times the capsule's radius (two
//! more wrenches, `(n, ±μ·patch·n)` in torque). Torques are about the object's centre of mass and
//! divided by the object's size `L` (the largest distance of a vertex from the centre of mass),
//! so forces and torques share one scale.
//!
//! The L1 grasp wrench space is the convex hull of all these wrenches: what the hand can resist
//! when the contacts' normal forces add up to one. The grasp is in force closure when the origin
//! lies strictly inside it; ε is the distance from the origin to the nearest facet (Ferrari &
//! Canny 1992); the load ratio along a direction is how far the hull reaches along the pure
//! force that holds a load there, i.e. the load the grasp holds per newton of total grip.

use crate::math::{Point3, Vec3};
use crate::parameter::{in_range, ParameterError};

use super::contacts::Contact;
use super::force_closure::ForceClosure;
use crate::geometry::ConvexHull;

/// The six load directions of [`Stability::load_ratio`], in the object's frame.
pub const LOAD_DIRECTIONS: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// The force the hand applies to hold a load along each of [`LOAD_DIRECTIONS`]: its opposite.
/// A load ratio is how far the grasp wrench space reaches along it.
const HOLDING_FORCES: [[f64; 6]; 6] = [
    [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, -1.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, -1.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
];

/// The smallest ε counted as force closure (the hull's tolerance is about 1e-9 of its size).
pub const FORCE_CLOSURE_EPSILON: f64 = 1e-7;

/// How contacts resist forces.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactModel {
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Edges of the linearized friction cone (GraspIt! uses 8).
    pub cone_edges: usize,
    /// Soft-contact patch radius as a fraction of the capsule's radius (0: hard point contacts).
    pub torsion_patch: f64,
}

impl Default for ContactModel {
    fn default() -> Self {
        Self {
            friction: Self::DEFAULT_FRICTION,
            cone_edges: 8,
            torsion_patch: 0.5,
        }
    }
}

impl ContactModel {
    /// The friction coefficient the search assumes by default: about half a grippy world's, a
    /// safety factor of two (docs/QUALITY.md).
    pub const DEFAULT_FRICTION: f64 = 0.5;

    /// Why the model is unusable, if it is: μ must be a positive finite number no larger than 10,
    /// the cone needs 3 to 64 edges, and the patch a fraction in [0, 1].
    pub fn check(&self) -> Result<(), ParameterError> {
        in_range(
            "friction",
            self.friction,
            1e-6,
            10.0,
            "rubber on wood is about 0.5-1",
        )?;
        in_range("cone_edges", self.cone_edges as f64, 3.0, 64.0, "")?;
        in_range(
            "torsion_patch",
            self.torsion_patch,
            0.0,
            1.0,
            "a fraction of the capsule radius",
        )?;
        Ok(())
    }
}

/// Stability of one grasp.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Stability {
    /// The origin is strictly inside the grasp wrench space: the contacts can resist any wrench.
    pub force_closure: bool,
    /// Ferrari–Canny ε (L1): the smallest wrench, per unit of total normal force, that the grasp
    /// can just resist in its weakest direction; 0 without force closure.
    pub epsilon: f64,
    /// For a load along each of [`LOAD_DIRECTIONS`] through the centre of mass: the largest load
    /// the grasp holds per unit of total normal force (0 when it cannot hold it at all).
    pub load_ratio: [f64; 6],
    /// The length `L` that torques were divided by, metres.
    pub torque_scale: f64,
    /// Wrenches in the hull (contacts × (edges + 2)).
    pub wrenches: usize,
}

/// Buffers for [`GraspWrenchSpace::evaluate`]; reuse one per thread.
#[derive(Debug, Clone, Default)]
pub struct GraspWrenchSpace {
    wrenches: Vec<[f64; 6]>,
    hull: ConvexHull<6>,
    closure: ForceClosure,
}

impl GraspWrenchSpace {
    /// Empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// The wrenches of the last evaluation: force, then torque divided by `L`.
    pub fn wrenches(&self) -> &[[f64; 6]] {
        &self.wrenches
    }

    /// The force-closure margin of `contacts` (see [`super::force_closure`]): in (0, 1] in force
    /// closure, 0 otherwise. Tens of microseconds, where [`GraspWrenchSpace::evaluate`] takes
    /// milliseconds.
    pub fn closure_margin(
        &mut self,
        contacts: &[Contact],
        model: &ContactModel,
        center: &Point3,
        scale: f64,
    ) -> f64 {
        contact_wrenches(contacts, model, center, scale, &mut self.wrenches);
        self.closure.margin(&self.wrenches)
    }

    /// The Ferrari–Canny ε that [`GraspWrenchSpace::evaluate`] gives (0 without force closure)
    /// alone: for choosing among grasps before the winner's whole stability is computed.
    pub fn epsilon(
        &mut self,
        contacts: &[Contact],
        model: &ContactModel,
        center: &Point3,
        scale: f64,
    ) -> f64 {
        contact_wrenches(contacts, model, center, scale, &mut self.wrenches);
        self.epsilon_of_wrenches().unwrap_or(0.0)
    }

    /// ε of the wrenches in `self.wrenches` from the part of their hull around the origin
    /// ([`ConvexHull::compute_around_origin`]); `None` without force closure (flat or too few
    /// wrenches, the origin outside or too near the boundary, or a hull rounding defeats —
    /// never met on the oracle's or the surveys' wrench sets).
    fn epsilon_of_wrenches(&mut self) -> Option<f64> {
        self.hull.compute_around_origin(&self.wrenches).ok()?;
        let epsilon = self
            .hull
            .facets()
            .iter()
            .map(|f| f.offset)
            .fold(f64::INFINITY, f64::min);
        (epsilon >= FORCE_CLOSURE_EPSILON).then_some(epsilon)
    }

    /// Stability of `contacts` on an object with centre of mass `center` and size `scale` (L):
    /// ε from the hull around the origin, each load ratio from a linear program (how far the
    /// wrenches' hull reaches along the holding force; the same number as the whole hull's facet
    /// on that ray, for a fraction of the cost).
    pub fn evaluate(
        &mut self,
        contacts: &[Contact],
        model: &ContactModel,
        center: &Point3,
        scale: f64,
    ) -> Stability {
        contact_wrenches(contacts, model, center, scale, &mut self.wrenches);
        let mut stability = Stability {
            torque_scale: scale,
            wrenches: self.wrenches.len(),
            ..Default::default()
        };
        let Some(epsilon) = self.epsilon_of_wrenches() else {
            return stability;
        };
        stability.force_closure = true;
        stability.epsilon = epsilon;
        for (ratio, force) in stability.load_ratio.iter_mut().zip(&HOLDING_FORCES) {
            // In force closure the origin is inside and the hull bounded: the program has an
            // optimum, at least ε; rounding that defeats it leaves ε, the reach every way.
            *ratio = self
                .closure
                .reach(&self.wrenches, force)
                .filter(|r| r.is_finite())
                .unwrap_or(epsilon)
                .max(epsilon);
        }
        stability
    }
}

/// The wrenches of every contact's linearized friction cone and soft-contact torsion, into `out`.
pub fn contact_wrenches(
    contacts: &[Contact],
    model: &ContactModel,
    center: &Point3,
    scale: f64,
    out: &mut Vec<[f64; 6]>,
) {
    out.clear();
    let wrench = |p: &Point3, f: &Vec3, torsion: &Vec3| {
        let torque = ((p - center).cross(f) + torsion) / scale;
        [f.x, f.y, f.z, torque.x, torque.y, torque.z]
    };
    for c in contacts {
        let n = c.normal;
        let (t1, t2) = tangents(&n);
        for j in 0..model.cone_edges {
            let angle = std::f64::consts::TAU * j as f64 / model.cone_edges as f64;
            let f = n + (t1 * angle.cos() + t2 * angle.sin()) * model.friction;
            out.push(wrench(&c.point, &f, &Vec3::zeros()));
        }
        if model.torsion_patch > 0.0 {
            let torsion = n * (model.friction * model.torsion_patch * c.radius);
            out.push(wrench(&c.point, &n, &torsion));
            out.push(wrench(&c.point, &n, &-torsion));
        }
    }
}

/// Two unit vectors completing `n` to a right-handed orthonormal frame in which the first
/// points up the surface: `t1` is the object's z axis projected on the tangent plane (or, on a
/// nearly horizontal surface, its x axis), so one edge of each linearized friction cone resists
/// sliding down under gravity with the whole of μ, and the cone does not turn with rounding.
///
/// Every tangent frame jumps somewhere on the sphere; this one only within 1e-6 rad of ±z,
/// where the x axis takes over. (Duff et al.'s branchless frame, used before, jumps on the plane
/// n_z = 0, where the side normals of upright cylinders and boxes lie: rounding of 1e-16 there
/// turned their cones and moved ε by 2%.)
pub fn tangents(n: &Vec3) -> (Vec3, Vec3) {
    let up = Vec3::z() - n * n.z;
    let reference = if up.norm_squared() > 1e-12 {
        up
    } else {
        Vec3::x() - n * n.x
    };
    let t1 = reference.normalize();
    (t1, n.cross(&t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contact(point: [f64; 3], normal: [f64; 3]) -> Contact {
        Contact {
            bone: 0,
            capsule: 0,
            point: Point3::from(point),
            normal: Vec3::from(normal).normalize(),
            gap: 0.0,
            radius: 0.01,
        }
    }

    #[test]
    fn tangents_are_orthonormal() {
        for n in [
            Vec3::z(),
            -Vec3::z(),
            Vec3::new(0.3, -0.8, 0.1).normalize(),
            Vec3::new(1e-9, 0.0, -1.0).normalize(),
            Vec3::new(1.0, 2.0, 3.0).normalize(),
            Vec3::x(),
        ] {
            let (t1, t2) = tangents(&n);
            assert!((t1.norm() - 1.0).abs() < 1e-12 && (t2.norm() - 1.0).abs() < 1e-12);
            assert!(t1.dot(&n).abs() < 1e-12 && t2.dot(&n).abs() < 1e-12);
            assert!(t1.dot(&t2).abs() < 1e-12);
            assert!((t1.cross(&t2) - n).norm() < 1e-12, "right-handed");
        }
    }

    /// Side normals of an upright object get their first edge straight up, whatever rounding
    /// leaves in n_z.
    #[test]
    fn tangents_point_up_the_surface_and_do_not_jump_on_the_equator() {
        for k in 0..16 {
            let angle = std::f64::consts::TAU * k as f64 / 16.0;
            let (x, y) = (angle.cos(), angle.sin());
            let (a1, a2) = tangents(&Vec3::new(x, y, 1e-16).normalize());
            let (b1, b2) = tangents(&Vec3::new(x, y, -1e-16).normalize());
            assert!(
                (a1 - b1).norm() < 1e-12 && (a2 - b2).norm() < 1e-12,
                "at {angle} rad"
            );
            assert!((a1 - Vec3::z()).norm() < 1e-12);
        }
    }

    #[test]
    fn a_hand_lying_flat_on_a_face_is_not_in_force_closure() {
        // Five contacts, all pushing down on the top face of a box.
        let contacts: Vec<Contact> = (0..5)
            .map(|i| contact([0.01 * i as f64 - 0.02, 0.01, 0.03], [0.0, 0.0, -1.0]))
            .collect();
        let mut gws = GraspWrenchSpace::new();
        let s = gws.evaluate(&contacts, &ContactModel::default(), &Point3::origin(), 0.05);
        assert!(!s.force_closure);
        assert_eq!(s.epsilon, 0.0);
    }

    #[test]
    fn an_opposed_pinch_with_soft_pads_is_in_force_closure_and_a_hard_one_is_not() {
        let contacts = [
            contact([0.03, 0.0, 0.0], [-1.0, 0.0, 0.0]),
            contact([-0.03, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ];
        let mut gws = GraspWrenchSpace::new();
        let soft = gws.evaluate(&contacts, &ContactModel::default(), &Point3::origin(), 0.03);
        assert!(soft.force_closure && soft.epsilon > 0.0);
        // Loads across the pinch are held by friction (μ per unit of total grip: 2 × 0.5 μ·½).
        assert!(soft.load_ratio[4] > 0.1 && soft.load_ratio[5] > 0.1);
        let hard = ContactModel {
            torsion_patch: 0.0,
            ..Default::default()
        };
        // Without torsion, nothing resists turning about the line through both contacts.
        assert!(
            !gws.evaluate(&contacts, &hard, &Point3::origin(), 0.03)
                .force_closure
        );
    }

    #[test]
    fn three_contacts_around_a_sphere_hold_loads_in_every_direction() {
        let contacts: Vec<Contact> = (0..3)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 3.0;
                let p = [0.03 * a.cos(), 0.03 * a.sin(), 0.0];
                contact(p, [-p[0], -p[1], 0.0])
            })
            .collect();
        let mut gws = GraspWrenchSpace::new();
        let s = gws.evaluate(&contacts, &ContactModel::default(), &Point3::origin(), 0.03);
        assert!(s.force_closure);
        assert!(s.load_ratio.iter().all(|&r| r > 0.05), "{:?}", s.load_ratio);
        // More friction holds more.
        let grippy = ContactModel {
            friction: 1.0,
            ..Default::default()
        };
        let more = gws.evaluate(&contacts, &grippy, &Point3::origin(), 0.03);
        assert!(more.epsilon > s.epsilon);
        assert!(more.load_ratio[4] > s.load_ratio[4]);
    }
}

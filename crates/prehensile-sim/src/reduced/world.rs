//! The reduced-coordinate engine: hands stepped in their joint angles on the project's own
//! dynamics, with a contact solver of its own, instead of one rigid body per bone held together
//! by rapier's impulse joints (rapier's joints cost more than MuJoCo's whole step; why both
//! engines stay: docs/decisions/002-reduced-engine-beside-rapier.md). One hand's
//! share of the step is [`super::hand`].
//!
//! Each step of `dt`, for every hand under its kinematic palm (the arm is prescribed):
//!
//! 1. the bones placed by forward kinematics, every joint axis in the world;
//! 2. every capsule near the object gives a contact (normal, two tangents, point, gap) from the
//!    object's distance grid ([`prehensile_core::collision::MeshCollider::capsule_contact`],
//!    warm-started from the capsule's contact of the step before), and each of its ends that
//!    touches too gives its own (a bone lying along a face);
//! 3. the bias b(q, q̇) by Newton–Euler with the palm's real motion and gravity
//!    ([`prehensile_control::rnea`]), the controller's compensation τG + τARM by Newton–Euler at
//!    rest ([`prehensile_control::bias_torques`], the paper's Eq. 2; one pass of the velocity
//!    products alone when the two cancel, a palm that does not turn), the mass matrix M(q)
//!    ([`prehensile_control::crba`]);
//! 4. the controller's springs integrated implicitly, as rapier's motors and MuJoCo's servos are:
//!    (M + dt D + dt² K) q̇⁺ = M q̇ + dt (τ − b + K (q* − q) + D q̇*) + impulses, factored block
//!    by block (under the held palm each finger is its own tree, so M is block diagonal);
//! 5. the object's free velocity under gravity; the Delassus matrix of hand and object; the
//!    impulses by projected Gauss–Seidel ([`super::projected_gauss_seidel`]), warm-started from
//!    each capsule's impulses of the step before, friction within Coulomb's cone (the two
//!    tangents solved together), contacts speculative within a millimetre
//!    (a gap may close in one step, no more), penetration pushed out over MuJoCo's 20 ms time
//!    constant, normal rows softened as MuJoCo's, sweeps stopping once the impulses settle;
//! 6. velocities updated, angles and the object integrated (semi-implicit Euler; a ball joint's
//!    rotation composed with its turn).
//!
//! Hands touch each other capsule to capsule (the handshake); a hand never touches itself, and
//! a palm neither a held object nor another palm (neither side could give: rapier likewise
//! leaves kinematic and fixed bodies to pass through each other). Not modelled: the object's
//! gyroscopic term.

use nalgebra::Matrix3;
use prehensile_core::collision::Capsule;
use prehensile_core::geometry::closest_segment_segment;
use prehensile_core::hand::kinematics::forward_kinematics;
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::{HandModel, ObjectModel};

use super::hand::{ReducedHand, CONTACT_SLOTS};
use super::projected_gauss_seidel::{projected_gauss_seidel, ContactProblem};
use crate::error::{Divergence, SimError};
use crate::world::contacts::Contacts;
use crate::world::engine::{bone_ran_away, runaway, HandDrive, PhysicsEngine};
use crate::world::object_mass::solid_mass_properties;
use crate::world::settings::{ReducedSettings, Settings};

/// Hands and at most one object, stepped in reduced coordinates.
pub(crate) struct ReducedWorld {
    dt: f64,
    /// The contact solver's settings.
    solver: ReducedSettings,
    gravity: Vec3,
    friction: f64,
    density: f64,
    hands: Vec<ReducedHand>,
    object: Option<FreeObject>,
    contact: ContactWorkspace,
}

/// The object as a free rigid body.
struct FreeObject {
    object: ObjectModel,
    /// The mesh frame's pose.
    pose: Transform,
    /// Centre of mass in the mesh frame.
    center: Point3,
    mass: f64,
    /// Inertia about the centre of mass, mesh frame.
    inertia: Matrix3<f64>,
    velocity: Vec3,
    spin: Vec3,
    fixed: bool,
}

impl FreeObject {
    fn center_world(&self) -> Point3 {
        self.pose * self.center
    }

    /// The world-frame inverse inertia, or zero while it is held fixed.
    fn inverse_inertia(&self) -> Matrix3<f64> {
        if self.fixed {
            return Matrix3::zeros();
        }
        let r = self.pose.rotation.to_rotation_matrix().into_inner();
        let inverse = self.inertia.try_inverse().unwrap_or_else(Matrix3::zeros);
        r * inverse * r.transpose()
    }

    fn inverse_mass(&self) -> f64 {
        if self.fixed {
            0.0
        } else {
            1.0 / self.mass
        }
    }
}

impl ReducedWorld {
    /// An empty world with `settings`' step, gravity, friction and density.
    pub fn new(settings: &Settings) -> Self {
        Self {
            dt: settings.dt,
            solver: settings.reduced,
            gravity: settings.gravity,
            friction: settings.friction,
            density: settings.object_density,
            hands: Vec::new(),
            object: None,
            contact: ContactWorkspace::default(),
        }
    }
}

/// One side of a contact: a capsule of a hand's bone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CapsuleOf {
    hand: usize,
    capsule: usize,
    bone: usize,
}

/// One contact of this step: a hand's capsule against the object or another hand's capsule.
struct ContactPoint {
    /// The side the normal leaves.
    from: CapsuleOf,
    /// Which of the capsule's contacts with the object (0 the nearest point, 1 and 2 its ends;
    /// always 0 between hands): where its warm start is kept.
    slot: usize,
    /// The side it enters: another hand's capsule, or the object.
    into: Option<CapsuleOf>,
    point: Point3,
    /// The normal, then the two tangents.
    directions: [Vec3; 3],
    gap: f64,
}

/// The contact rows of a step and the solver's buffers.
#[derive(Default)]
struct ContactWorkspace {
    points: Vec<ContactPoint>,
    delassus: Vec<f64>,
    /// The object's angular part of each row, (point − centre of mass) × direction; zero for
    /// rows between hands.
    levers: Vec<Vec3>,
    free: Vec<f64>,
    target: Vec<f64>,
    lambda: Vec<f64>,
    /// The impulses of the last step's contacts between hands (the solver's warm start).
    between_hands: Vec<(CapsuleOf, CapsuleOf, [f64; 3])>,
}

/// A contact frame around `normal`: the normal and two tangents, chosen the same way each
/// step so that warm-started tangent impulses keep their meaning while the normal turns slowly.
fn contact_frame(normal: Vec3) -> [Vec3; 3] {
    let first = normal
        .cross(&Vec3::x())
        .try_normalize(1e-6)
        .unwrap_or_else(|| normal.cross(&Vec3::y()).normalize());
    [normal, first, normal.cross(&first)]
}

/// Every hand capsule's contacts with the object, within the solver's margin: its point nearest
/// the object, and each end that touches too.
fn object_contacts(
    object: &FreeObject,
    hands: &mut [ReducedHand],
    solver: &ReducedSettings,
    points: &mut Vec<ContactPoint>,
) {
    let to_mesh = object.pose.inverse();
    for (h, hand) in hands.iter_mut().enumerate() {
        for (capsule, c) in hand.hand.capsules().iter().enumerate() {
            // A capsule without a contact needs no clearing of its warm start: the solve
            // keeps only this step's impulses.
            if object.fixed && hand.movers[c.bone].is_empty() {
                continue;
            }
            let frame = &hand.frames[c.bone];
            let local = Capsule {
                a: to_mesh * (frame * c.a),
                b: to_mesh * (frame * c.b),
                radius: c.radius,
            };
            let collider = object.object.collider();
            let found = collider.capsule_contact(&local, solver.followed, hand.fractions[capsule]);
            hand.fractions[capsule] = found.map(|f| f.fraction);
            let Some(nearest) = found.filter(|f| f.gap <= solver.margin) else {
                continue;
            };
            let from = CapsuleOf {
                hand: h,
                capsule,
                bone: c.bone,
            };
            // An end sphere's own contact: the search from a warm start at the point
            // itself, on a segment of no length, samples it once.
            let end = |t: f64, p: Point3| {
                let apart = (t - nearest.fraction).abs() >= solver.ends_apart;
                let sphere = Capsule {
                    a: p,
                    b: p,
                    radius: c.radius,
                };
                apart
                    .then(|| collider.capsule_contact(&sphere, solver.margin, Some(0.0)))
                    .flatten()
                    .filter(|f| f.gap <= solver.margin)
            };
            let found = [Some(nearest), end(0.0, local.a), end(1.0, local.b)];
            for (slot, contact) in found.into_iter().enumerate() {
                let Some(contact) = contact else { continue };
                points.push(ContactPoint {
                    from,
                    slot,
                    into: None,
                    point: object.pose * contact.point,
                    directions: contact_frame(-(object.pose.rotation * contact.normal)),
                    gap: contact.gap,
                });
            }
        }
    }
}

/// Contacts between capsules of different hands, within `margin`.
fn hand_contacts(hands: &[ReducedHand], margin: f64, points: &mut Vec<ContactPoint>) {
    for a in 0..hands.len() {
        for b in a + 1..hands.len() {
            let (first, second) = (&hands[a], &hands[b]);
            for (i, ci) in first.hand.capsules().iter().enumerate() {
                let (pa, qa) = (first.frames[ci.bone] * ci.a, first.frames[ci.bone] * ci.b);
                for (j, cj) in second.hand.capsules().iter().enumerate() {
                    if first.movers[ci.bone].is_empty() && second.movers[cj.bone].is_empty() {
                        continue;
                    }
                    let (pb, qb) = (second.frames[cj.bone] * cj.a, second.frames[cj.bone] * cj.b);
                    let reach = ci.radius + cj.radius + margin;
                    // Bounding spheres first: most pairs are far apart.
                    let (ma, mb) = (nalgebra::center(&pa, &qa), nalgebra::center(&pb, &qb));
                    let spread = 0.5 * ((qa - pa).norm() + (qb - pb).norm());
                    if (ma - mb).norm() > reach + spread {
                        continue;
                    }
                    let (squared, s, t) = closest_segment_segment(&pa, &qa, &pb, &qb);
                    let distance = squared.sqrt();
                    let gap = distance - ci.radius - cj.radius;
                    if gap > margin {
                        continue;
                    }
                    let (on_a, on_b) = (pa + (qa - pa) * s, pb + (qb - pb) * t);
                    let Some(normal) = (on_b - on_a).try_normalize(1e-12) else {
                        continue;
                    };
                    points.push(ContactPoint {
                        from: CapsuleOf {
                            hand: a,
                            capsule: i,
                            bone: ci.bone,
                        },
                        slot: 0,
                        into: Some(CapsuleOf {
                            hand: b,
                            capsule: j,
                            bone: cj.bone,
                        }),
                        // Midway between the two surfaces.
                        point: on_a + normal * (ci.radius + 0.5 * gap),
                        directions: contact_frame(normal),
                        gap,
                    });
                }
            }
        }
    }
}

impl ReducedWorld {
    /// This step's contacts: every hand's capsules within the margin of the object, and of
    /// every other hand's capsules.
    fn find_contacts(&mut self) {
        let points = &mut self.contact.points;
        points.clear();
        if let Some(object) = &self.object {
            object_contacts(object, &mut self.hands, &self.solver, points);
        }
        hand_contacts(&self.hands, self.solver.margin, points);
    }

    /// The contact rows, their Delassus matrix and free velocities, the impulses, and the
    /// velocities after them.
    fn solve_contacts(&mut self) {
        let dt = self.dt;
        let ws = &mut self.contact;
        let rows = 3 * ws.points.len();
        for hand in &mut self.hands {
            hand.clear_rows();
        }
        ws.free.clear();
        ws.target.clear();
        ws.lambda.clear();
        ws.levers.clear();
        ws.delassus.clear();
        ws.delassus.resize(rows * rows, 0.0);
        let (center, inverse_mass, inverse_inertia) = match &self.object {
            Some(o) => (o.center_world(), o.inverse_mass(), o.inverse_inertia()),
            None => (Point3::origin(), 0.0, Matrix3::zeros()),
        };
        for (c, p) in ws.points.iter().enumerate() {
            let warm = match p.into {
                None => self.hands[p.from.hand].impulses[p.from.capsule][p.slot],
                Some(into) => ws
                    .between_hands
                    .iter()
                    .find(|(a, b, _)| *a == p.from && *b == into)
                    .map_or([0.0; 3], |w| w.2),
            };
            for (k, d) in p.directions.iter().enumerate() {
                let row = 3 * c + k;
                let from = self.hands[p.from.hand].add_row(row, p.from.bone, &p.point, d, -1.0);
                let (into, lever) = match (p.into, &self.object) {
                    (Some(into), _) => (
                        self.hands[into.hand].add_row(row, into.bone, &p.point, d, 1.0),
                        Vec3::zeros(),
                    ),
                    (None, Some(object)) => {
                        let lever = (p.point - center).cross(d);
                        (object.velocity.dot(d) + object.spin.dot(&lever), lever)
                    }
                    (None, None) => (0.0, Vec3::zeros()),
                };
                ws.levers.push(lever);
                ws.free.push(into + from);
                ws.target.push(match k {
                    0 if p.gap > 0.0 => -p.gap / dt,
                    0 => -p.gap / self.solver.push_out_time.max(2.0 * dt),
                    _ => 0.0,
                });
                ws.lambda.push(warm[k]);
            }
        }
        // The object's part, for the rows against it.
        let against_object = |r: usize| ws.points[r / 3].into.is_none();
        for i in (0..rows).filter(|&i| against_object(i)) {
            let direction = ws.points[i / 3].directions[i % 3];
            let spun = inverse_inertia * ws.levers[i];
            for j in (0..rows).filter(|&j| against_object(j)) {
                let other = ws.points[j / 3].directions[j % 3];
                ws.delassus[i * rows + j] =
                    direction.dot(&other) * inverse_mass + ws.levers[j].dot(&spun);
            }
        }
        for hand in &mut self.hands {
            hand.add_delassus(rows, &mut ws.delassus);
        }
        projected_gauss_seidel(
            &ContactProblem {
                delassus: &ws.delassus,
                free: &ws.free,
                target: &ws.target,
                friction: self.friction,
                softness: self.solver.softness,
                converged: self.solver.converged,
            },
            self.solver.sweeps,
            &mut ws.lambda,
        );
        for hand in &mut self.hands {
            hand.apply_impulses(&ws.lambda);
            hand.impulses
                .iter_mut()
                .for_each(|i| *i = [[0.0; 3]; CONTACT_SLOTS]);
        }
        ws.between_hands.clear();
        for (c, p) in ws.points.iter().enumerate() {
            let impulse = [0, 1, 2].map(|k| ws.lambda[3 * c + k]);
            match p.into {
                Some(into) => ws.between_hands.push((p.from, into, impulse)),
                None => {
                    self.hands[p.from.hand].impulses[p.from.capsule][p.slot] = impulse;
                    if let Some(object) = &mut self.object {
                        for (k, l) in impulse.iter().enumerate() {
                            object.velocity += p.directions[k] * (l * inverse_mass);
                            object.spin += inverse_inertia * (ws.levers[3 * c + k] * *l);
                        }
                    }
                }
            }
        }
    }

    /// What touched in this step, for [`PhysicsEngine::contacts`].
    fn report(&mut self) {
        for hand in &mut self.hands {
            let report = &mut hand.report;
            report.force = 0.0;
            report.penetration = 0.0;
            report.touching = 0;
            report.bone_forces.iter_mut().for_each(|f| *f = 0.0);
        }
        // A capsule touches a thing when a normal impulse between them pushes; its contacts
        // with the object (its nearest point and ends) are consecutive and count once.
        let mut counted: Option<(CapsuleOf, Option<CapsuleOf>)> = None;
        for (c, p) in self.contact.points.iter().enumerate() {
            let force = self.contact.lambda[3 * c] / self.dt;
            let pair = Some((p.from, p.into));
            let new_pair = force > 0.0 && counted != pair;
            if new_pair {
                counted = pair;
            }
            for side in std::iter::once(p.from).chain(p.into) {
                let report = &mut self.hands[side.hand].report;
                report.penetration = report.penetration.max(-p.gap);
                if force > 0.0 {
                    report.force += force;
                    report.bone_forces[side.bone] += force;
                    report.touching += usize::from(new_pair);
                }
            }
        }
    }
}

impl PhysicsEngine for ReducedWorld {
    fn add_hand(
        &mut self,
        hand: &HandModel,
        root: &Transform,
        start: &[f64],
    ) -> Result<(), SimError> {
        self.hands.push(ReducedHand::new(hand, root, start)?);
        Ok(())
    }

    fn add_object(
        &mut self,
        object: &ObjectModel,
        pose: &Transform,
        fixed: bool,
    ) -> Result<f64, SimError> {
        let props = solid_mass_properties(object, self.density)?;
        let inertia = props.reconstruct_inertia_matrix().to_cols_array();
        let com = props.local_com;
        let free = FreeObject {
            object: object.clone(),
            pose: *pose,
            center: Point3::new(com.x, com.y, com.z),
            mass: props.mass(),
            inertia: Matrix3::from_column_slice(&inertia),
            velocity: Vec3::zeros(),
            spin: Vec3::zeros(),
            fixed,
        };
        Ok(self.object.insert(free).mass)
    }

    fn let_go_object(&mut self) {
        if let Some(o) = self.object.as_mut().filter(|o| o.fixed) {
            o.fixed = false;
            // Impulses against an immovable object say nothing about a free one.
            for h in &mut self.hands {
                h.impulses
                    .iter_mut()
                    .for_each(|i| *i = [[0.0; 3]; CONTACT_SLOTS]);
            }
        }
    }

    fn object_pose(&self) -> Option<Transform> {
        self.object.as_ref().map(|o| o.pose)
    }

    fn palm(&self, i: usize) -> Transform {
        let h = &self.hands[i];
        h.palm_at(&h.root)
    }

    fn joint_state(&self, i: usize, q: &mut [f64], qd: &mut [f64]) {
        q.copy_from_slice(&self.hands[i].q);
        qd.copy_from_slice(&self.hands[i].qd);
    }

    fn drive(&mut self, i: usize, drive: &HandDrive) -> Result<(), SimError> {
        let h = &mut self.hands[i];
        h.springs.copy_from_slice(drive.springs);
        h.coupling.copy_from_slice(drive.coupling);
        h.palm_motion = drive.palm;
        h.compensate = (drive.compensate_gravity, drive.compensate_arm);
        h.next_root = drive.next_root;
        Ok(())
    }

    fn step(&mut self) -> Result<(), SimError> {
        let dt = self.dt;
        for h in &mut self.hands {
            h.place(dt);
        }
        self.find_contacts();
        for h in &mut self.hands {
            h.free_velocity(dt, &self.gravity)?;
        }
        if let Some(o) = self.object.as_mut().filter(|o| !o.fixed) {
            o.velocity += self.gravity * dt;
        }
        self.solve_contacts();
        self.report();
        for h in &mut self.hands {
            h.integrate(dt);
        }
        if let Some(o) = self.object.as_mut().filter(|o| !o.fixed) {
            // Semi-implicit Euler about the centre of mass.
            let center = o.center_world() + o.velocity * dt;
            let rotation = Rotation::from_scaled_axis(o.spin * dt) * o.pose.rotation;
            let rotation = Rotation::new_normalize(rotation.into_inner());
            o.pose = Transform::from_parts(
                (center - rotation * o.center.coords).coords.into(),
                rotation,
            );
        }
        Ok(())
    }

    fn contacts(&self, i: usize) -> Contacts {
        self.hands[i].report.clone()
    }

    fn penetration(&self, i: usize) -> f64 {
        self.hands[i].report.penetration
    }

    fn diverged(&self) -> Option<Divergence> {
        for (i, h) in self.hands.iter().enumerate() {
            for (k, bone) in h.hand.bones().iter().enumerate() {
                let range = bone.first_dof..bone.first_dof + bone.joint.dofs();
                let finite = h.q[range.clone()]
                    .iter()
                    .chain(&h.qd[range.clone()])
                    .all(|x| x.is_finite());
                // A joint's fastest rate, held to the angular limit of a body.
                let rates = h.qd[range].iter().fold(0.0f64, |m, x| m.max(x.abs()));
                if runaway(finite, &Vec3::zeros(), &Vec3::new(rates, 0.0, 0.0)) {
                    return Some(bone_ran_away(&h.hand, i, k));
                }
            }
        }
        match &self.object {
            Some(o) => {
                let finite = o.pose.translation.vector.iter().all(|x| x.is_finite())
                    && o.pose.rotation.coords.iter().all(|x| x.is_finite());
                runaway(finite, &o.velocity, &o.spin).then_some(Divergence::Object)
            }
            None => None,
        }
    }

    fn bone_frames(&self, i: usize, out: &mut Vec<Transform>) {
        let h = &self.hands[i];
        let mut rotations = vec![Rotation::identity(); h.hand.bones().len()];
        h.hand.joint_rotations(&h.q, &mut rotations);
        out.resize(h.hand.bones().len(), Transform::identity());
        forward_kinematics(&h.hand, &h.root, &rotations, out);
    }
}

#[cfg(test)]
mod tests {
    use prehensile_control::{forward_dynamics, BaseMotion, DynamicsModel, JointSpring};
    use prehensile_core::hand::Joint;

    use super::*;
    use crate::reduced::hand::tests::hands;
    use crate::world::holding_wrench::FrameMotion;

    /// The contacts of capsule `k` of a human hand with a flat 20 cm slab whose top face lies
    /// 0.3 mm under the capsule along its whole length, the slab then tilted about the
    /// capsule's end `a` by `tilt` radians (its end `b` lifts off the face).
    fn contacts_on_a_face(k: usize, tilt: f64) -> Vec<(usize, Point3, Point3, Point3)> {
        let hand = prehensile_formats::builtin_hand("human").unwrap();
        let mut world = ReducedWorld::new(&Settings::default());
        let start = vec![0.0; hand.dof_count()];
        world
            .add_hand(&hand, &Transform::identity(), &start)
            .unwrap();
        world.hands[0].place(1e-3);
        let c = &hand.capsules()[k];
        let frame = world.hands[0].frames[c.bone];
        let (a, b) = (frame * c.a, frame * c.b);
        let along = (b - a).normalize();
        let up = along.cross(&Vec3::z()).cross(&along).normalize();
        let thickness = 0.02;
        // The slab's frame: x along the capsule, z out of its top face.
        let turn = Rotation::from_matrix(&nalgebra::Matrix3::from_columns(&[
            along,
            up.cross(&along),
            up,
        ]));
        let below = a - up * (c.radius + 3e-4 + 0.5 * thickness) + along * (0.5 * (b - a).norm());
        let tilted =
            Rotation::from_axis_angle(&nalgebra::Unit::new_normalize(up.cross(&along)), tilt);
        let pose = Transform::from_parts((a.coords + tilted * (below - a)).into(), tilted * turn);
        let mesh = prehensile_core::shapes::cuboid(Vec3::new(0.2, 0.2, thickness));
        let slab = ObjectModel::new("slab", mesh, None).unwrap();
        world.add_object(&slab, &pose, true).unwrap();
        world.find_contacts();
        world
            .contact
            .points
            .iter()
            .filter(|p| p.from.capsule == k)
            .map(|p| (p.slot, p.point, a, b))
            .collect()
    }

    /// A finger bone lying along a face touches it at its nearest point and at both ends, so
    /// that the face cannot pivot about one point of the bone; tilted so that one end lifts
    /// off, that end has no contact.
    #[test]
    fn a_bone_lying_along_a_face_touches_it_at_both_ends() {
        let hand = prehensile_formats::builtin_hand("human").unwrap();
        let k = (0..hand.capsules().len())
            .rev()
            .find(|&k| {
                let c = &hand.capsules()[k];
                (c.b - c.a).norm() > 0.015
            })
            .unwrap();
        let radius = hand.capsules()[k].radius;
        let flat = contacts_on_a_face(k, 0.0);
        let (a, b) = (flat[0].2, flat[0].3);
        let along = |p: &Point3| (p - a).dot(&(b - a)) / (b - a).norm_squared();
        // The nearest point lies anywhere along a flat bone; an end within a quarter of the
        // bone from it is that contact already.
        let span = flat.iter().map(|c| along(&c.1)).fold(0.0, f64::max)
            - flat.iter().map(|c| along(&c.1)).fold(1.0, f64::min);
        assert!(
            flat.len() >= 2 && span > 0.95,
            "contacts span {span} of the bone: {flat:?}"
        );
        for (slot, point, ..) in &flat[1..] {
            let end = if *slot == 1 { a } else { b };
            let off = (point - end).norm() - radius;
            assert!(
                off.abs() < 1e-3,
                "end {slot}: contact {off} m off the end's foot"
            );
        }
        let tilted = contacts_on_a_face(k, 0.3);
        assert!(
            tilted.iter().all(|c| c.0 != 2),
            "end b lifted off: {tilted:?}"
        );
        assert!(
            along(&tilted[0].1) < 0.05,
            "the nearest point is end a: {tilted:?}"
        );
    }

    /// The hand's free motion (no springs, no contact, no compensation) under gravity, with
    /// the palm accelerating sideways, against [`prehensile_control::forward_dynamics`]
    /// integrated at a twentieth of the step (a ball joint's rates are its bone's angular
    /// velocity in its own frame, so its rotation turns by them on the right): the engine
    /// integrates the same equations of motion, ball joints and the moving base included.
    #[test]
    fn the_free_hand_moves_as_forward_dynamics_says() {
        for (name, hand) in hands() {
            let n = hand.dof_count();
            let (dt, steps) = (1e-4, 500);
            let gravity = Vec3::new(0.0, -3.0, -9.81);
            let push = Vec3::new(4.0, 0.0, 1.0);
            let root_at =
                |t: f64| Transform::from_parts((push * (0.5 * t * t)).into(), Rotation::identity());
            let settings = Settings {
                gravity,
                ..Settings::for_step(dt)
            };
            let mut world = ReducedWorld::new(&settings);
            let start: Vec<f64> = (0..n).map(|k| 0.1 * ((k % 5) as f64 - 2.0)).collect();
            world.add_hand(&hand, &root_at(0.0), &start).unwrap();
            let still = JointSpring::SLACK;
            let springs = vec![still; n];
            let zeros = vec![0.0; n];
            for step in 0..steps {
                let t = step as f64 * dt;
                let origin = (root_at(t) * hand.bones()[0].rest).translation.vector;
                let drive = HandDrive {
                    q: &zeros,
                    springs: &springs,
                    coupling: &zeros,
                    palm: FrameMotion {
                        linear_acceleration: push,
                        ..FrameMotion::at_rest(Point3::from(origin))
                    },
                    compensate_gravity: false,
                    compensate_arm: false,
                    next_root: root_at(t + dt),
                };
                world.drive(0, &drive).unwrap();
                world.step().unwrap();
            }
            let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
            world.joint_state(0, &mut q, &mut qd);

            // The reference, in the palm's frame (the root does not turn).
            let to_palm = hand.bones()[0].rest.rotation.inverse();
            let base = BaseMotion {
                linear_acceleration_minus_gravity: to_palm * (push - gravity),
                ..BaseMotion::at_rest(Vec3::zeros())
            };
            let model = DynamicsModel::new(&hand);
            let mut data = model.data();
            let mut acceleration = |q: &[f64], qd: &[f64]| {
                forward_dynamics(&model, &mut data, q, qd, &zeros, &base)
                    .unwrap()
                    .as_slice()
                    .to_vec()
            };
            let (mut rq, mut rqd) = (start.clone(), vec![0.0; n]);
            let h = dt / 20.0;
            for _ in 0..steps * 20 {
                let a = acceleration(&rq, &rqd);
                for k in 0..n {
                    rqd[k] += h * a[k];
                }
                for bone in hand.bones() {
                    let range = bone.first_dof..bone.first_dof + bone.joint.dofs();
                    if let Joint::Ball { .. } = bone.joint {
                        let w = Vec3::from_column_slice(&rqd[range.clone()]);
                        let turned = bone.joint.rotation(&rq[range.clone()])
                            * Rotation::from_scaled_axis(w * h);
                        bone.joint.angles(&turned, &mut rq[range]);
                    } else {
                        for k in range {
                            rq[k] += h * rqd[k];
                        }
                    }
                }
            }
            let moved = start
                .iter()
                .zip(&rq)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let error = q
                .iter()
                .zip(&rq)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            eprintln!("{name}: moved {moved} rad, off by {error} rad");
            assert!(moved > 0.05, "{name}: the fingers must swing ({moved} rad)");
            assert!(
                error < 0.02 * moved,
                "{name}: {error} rad off after {moved} rad"
            );
        }
    }
}

//! The reduced-coordinate engine: a hand stepped in its joint angles on the project's own
//! dynamics, with a contact solver of its own, instead of one rigid body per bone held together
//! by rapier's impulse joints (issue 15: rapier's joints cost more than MuJoCo's whole step; a
//! prototype of this step ran 1.35–2.2× MuJoCo's speed, docs/PERFORMANCE.md).
//!
//! Each step of `dt`, for the hand under its kinematic palm (the arm is prescribed):
//!
//! 1. the bones placed by forward kinematics, every joint axis in the world;
//! 2. every capsule near the object gives a contact (normal, two tangents, point, gap) from the
//!    object's distance grid ([`prehensile_core::collision::MeshCollider::capsule_contact`],
//!    warm-started from the capsule's contact of the step before);
//! 3. the bias b(q, q̇) by Newton–Euler with the palm's real motion and gravity
//!    ([`prehensile_control::rnea`]), the controller's compensation τG + τARM by Newton–Euler at
//!    rest ([`prehensile_control::bias_torques`], the paper's Eq. 2), the mass matrix M(q)
//!    ([`prehensile_control::crba`]);
//! 4. the controller's springs integrated implicitly, as rapier's motors and MuJoCo's servos are:
//!    (M + dt D + dt² K) q̇⁺ = M q̇ + dt (τ − b + K (q* − q) + D q̇*) + impulses, factored block
//!    by block (under the held palm each finger is its own tree, so M is block diagonal);
//! 5. the object's free velocity under gravity; the Delassus matrix of hand and object; the
//!    impulses by projected Gauss–Seidel ([`crate::projected_gauss_seidel`]), warm-started from
//!    each capsule's impulses of the step before, contacts speculative within a millimetre
//!    (a gap may close in one step, no more) and penetration pushed out by a fifth a step;
//! 6. velocities updated, angles and the object integrated (semi-implicit Euler; a ball joint's
//!    rotation composed with its turn).
//!
//! Not modelled yet: hand–hand contact (one hand per world), the object's gyroscopic term.

use nalgebra::{Cholesky, DMatrix, DMatrixViewMut, Dyn, Matrix3};
use prehensile_control::JointSpring;
use prehensile_control::{bias_torques, crba, rnea, BaseMotion, DynamicsData, DynamicsModel};
use prehensile_core::collision::Capsule;
use prehensile_core::hand::Joint;
use prehensile_core::kinematics::forward_kinematics;
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::{HandModel, ObjectModel};

use crate::holding_wrench::FrameMotion;
use crate::object_body::solid_mass_properties;
use crate::physics_engine::{runaway, HandDrive, PhysicsEngine};
use crate::projected_gauss_seidel::{projected_gauss_seidel, ContactProblem};
use crate::rapier_world::bone_ran_away;
use crate::simulation::{Contacts, Settings};
use crate::SimError;

/// Gauss–Seidel sweeps a step (warm-started, so few are needed).
const SWEEPS: usize = 10;
/// Contacts are made this far out, so that a resting contact stays one (metres).
const MARGIN: f64 = 0.001;
/// Share of a penetration pushed out per step.
const BAUMGARTE: f64 = 0.2;
/// Contact compliance as a share of each row's Delassus diagonal: MuJoCo's default impedance
/// (d = 0.95 at depth) gives (1 − d) / d ≈ 0.05.
const SOFTNESS: f64 = 0.05;

/// A hand and at most one object, stepped in reduced coordinates.
pub(crate) struct ReducedWorld {
    dt: f64,
    gravity: Vec3,
    friction: f64,
    density: f64,
    hands: Vec<ReducedHand>,
    object: Option<FreeObject>,
    contact: ContactWorkspace,
}

/// A hand: its model, state and drive, and the buffers of its step.
struct ReducedHand {
    hand: HandModel,
    dynamics: DynamicsModel,
    data: DynamicsData,
    q: Vec<f64>,
    qd: Vec<f64>,
    /// The root placement now.
    root: Transform,
    /// What drives it over the next step (set by [`PhysicsEngine::drive`]).
    springs: Vec<JointSpring>,
    coupling: Vec<f64>,
    palm_motion: FrameMotion,
    compensate: (bool, bool),
    next_root: Transform,
    /// The blocks of M: dofs that share a moving ancestor.
    blocks: Vec<Block>,
    /// Per bone, every degree of freedom that moves it (its own and its ancestors').
    movers: Vec<Vec<usize>>,
    rotations: Vec<Rotation>,
    frames: Vec<Transform>,
    /// Per degree of freedom, its joint's origin and axis in the world this step.
    axes: Vec<(Point3, Vec3)>,
    /// Per capsule, the contact fraction of the step before (the narrow phase's warm start)
    /// and the impulses (normal, two tangents) of the step before (the solver's).
    fractions: Vec<Option<f64>>,
    impulses: Vec<[f64; 3]>,
    /// The generalized forces of this step and the velocity before contact.
    bias: Vec<f64>,
    force: Vec<f64>,
    free: Vec<f64>,
    /// The contacts of the last step.
    report: Contacts,
}

/// One block of the mass matrix and its share of this step's contact rows.
struct Block {
    dofs: Vec<usize>,
    /// M + dt D + dt² K for the block, factored (its storage reused every step).
    factor: Option<Cholesky<f64, Dyn>>,
    /// The matrix's storage before the first factorization.
    spare: DMatrix<f64>,
    /// Contact rows that move a dof of the block.
    rows: Vec<usize>,
    /// (M + dt D + dt² K)⁻¹ Hᵀ for those rows, dofs × rows, column-major.
    response: Vec<f64>,
    /// One column of the block's size.
    scratch: Vec<f64>,
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

/// One contact of this step: a capsule of a bone against the object.
struct ContactPoint {
    capsule: usize,
    bone: usize,
    point: Point3,
    /// From the hand into the object, then the two tangents.
    directions: [Vec3; 3],
    gap: f64,
}

/// The contact rows of a step and the solver's buffers.
#[derive(Default)]
struct ContactWorkspace {
    points: Vec<ContactPoint>,
    /// The hand's Jacobian, one row of `dof_count` per contact row.
    jacobian: Vec<f64>,
    delassus: Vec<f64>,
    free: Vec<f64>,
    target: Vec<f64>,
    lambda: Vec<f64>,
}

impl ReducedWorld {
    /// An empty world with `settings`' step, gravity, friction and density.
    pub fn new(settings: &Settings) -> Self {
        Self {
            dt: settings.dt,
            gravity: settings.gravity,
            friction: settings.friction,
            density: settings.object_density,
            hands: Vec::new(),
            object: None,
            contact: ContactWorkspace::default(),
        }
    }
}

impl ReducedHand {
    fn new(hand: &HandModel, root: &Transform, start: &[f64]) -> Result<Self, SimError> {
        if hand.bones()[0].joint.dofs() > 0 {
            return Err(SimError::Hand(format!(
                "hand '{}': the reduced engine holds the root bone '{}' as the palm, and it has \
                 a joint; use the rapier engine",
                hand.name(),
                hand.bones()[0].name
            )));
        }
        let n = hand.dof_count();
        let bones = hand.bones();
        // Every dof that moves each bone, and each moving bone's top-most moving ancestor.
        let mut movers: Vec<Vec<usize>> = Vec::with_capacity(bones.len());
        let mut top: Vec<Option<usize>> = Vec::with_capacity(bones.len());
        for (k, bone) in bones.iter().enumerate() {
            let own = bone.first_dof..bone.first_dof + bone.joint.dofs();
            let (mut list, above) = match bone.parent {
                Some(p) => (movers[p].clone(), top[p]),
                None => (Vec::new(), None),
            };
            list.extend(own.clone());
            movers.push(list);
            top.push(above.or((!own.is_empty()).then_some(k)));
        }
        let mut blocks: Vec<Block> = Vec::new();
        let mut block_of_top: Vec<Option<usize>> = vec![None; bones.len()];
        for (k, bone) in bones.iter().enumerate() {
            let Some(t) = top[k] else { continue };
            let b = *block_of_top[t].get_or_insert_with(|| {
                blocks.push(Block {
                    dofs: Vec::new(),
                    factor: None,
                    spare: DMatrix::zeros(0, 0),
                    rows: Vec::new(),
                    response: Vec::new(),
                    scratch: Vec::new(),
                });
                blocks.len() - 1
            });
            blocks[b]
                .dofs
                .extend(bone.first_dof..bone.first_dof + bone.joint.dofs());
        }
        for block in &mut blocks {
            let size = block.dofs.len();
            block.spare = DMatrix::zeros(size, size);
            block.scratch = vec![0.0; size];
        }
        let dynamics = DynamicsModel::new(hand);
        let spring = JointSpring {
            stiffness: 0.0,
            damping: 0.0,
            target: 0.0,
            target_velocity: 0.0,
        };
        let capsules = hand.capsules().len();
        Ok(Self {
            hand: hand.clone(),
            data: dynamics.data(),
            dynamics,
            q: start.to_vec(),
            qd: vec![0.0; n],
            root: *root,
            springs: vec![spring; n],
            coupling: vec![0.0; n],
            palm_motion: FrameMotion::at_rest(Point3::from(
                (root * bones[0].rest).translation.vector,
            )),
            compensate: (false, false),
            next_root: *root,
            blocks,
            movers,
            rotations: vec![Rotation::identity(); bones.len()],
            frames: vec![Transform::identity(); bones.len()],
            axes: vec![(Point3::origin(), Vec3::zeros()); n],
            fractions: vec![None; capsules],
            impulses: vec![[0.0; 3]; capsules],
            bias: vec![0.0; n],
            force: vec![0.0; n],
            free: vec![0.0; n],
            report: Contacts {
                bone_forces: vec![0.0; bones.len()],
                ..Contacts::default()
            },
        })
    }

    /// The palm (root bone) frame at root placement `root`.
    fn palm_at(&self, root: &Transform) -> Transform {
        root * self.hand.bones()[0].rest
    }

    /// Places the bones at the current angles and root, and every joint axis in the world.
    fn place(&mut self) {
        self.hand.joint_rotations(&self.q, &mut self.rotations);
        forward_kinematics(&self.hand, &self.root, &self.rotations, &mut self.frames);
        for (k, bone) in self.hand.bones().iter().enumerate() {
            let Some(parent) = bone.parent else { continue };
            let frame = self.frames[parent] * bone.rest;
            let origin = Point3::from(frame.translation.vector);
            let first = bone.first_dof;
            match &bone.joint {
                Joint::Fixed => {}
                Joint::Hinge(a) => {
                    self.axes[first] = (origin, frame.rotation * a.axis.into_inner())
                }
                Joint::TwoAxis { flexion, abduction } => {
                    let outer = Rotation::from_axis_angle(&abduction.axis, self.q[first + 1]);
                    self.axes[first + 1] = (origin, frame.rotation * abduction.axis.into_inner());
                    self.axes[first] =
                        (origin, frame.rotation * (outer * flexion.axis.into_inner()));
                }
                Joint::Ball { .. } => {
                    // Its rates are the bone's angular velocity in the bone's own frame.
                    let turned = frame.rotation * self.rotations[k];
                    for (k, axis) in [Vec3::x(), Vec3::y(), Vec3::z()].into_iter().enumerate() {
                        self.axes[first + k] = (origin, turned * axis);
                    }
                }
            }
        }
    }

    /// The palm's velocity over this step: the velocity of its origin and its spin.
    fn palm_velocity(&self, dt: f64) -> (Point3, Vec3, Vec3) {
        let (now, next) = (self.palm_at(&self.root), self.palm_at(&self.next_root));
        let spin = (next.rotation * now.rotation.inverse()).scaled_axis() / dt;
        let velocity = (next.translation.vector - now.translation.vector) / dt;
        (Point3::from(now.translation.vector), velocity, spin)
    }

    /// The generalized forces (bias, explicit torques) and the velocity each block reaches with
    /// its springs integrated implicitly and no contact; factors every block.
    fn free_velocity(&mut self, dt: f64, gravity: &Vec3) -> Result<(), SimError> {
        let palm = self.palm_at(&self.root);
        let to_palm = palm.rotation.inverse();
        let m = &self.palm_motion;
        let real = BaseMotion {
            angular_velocity: to_palm * m.angular_velocity,
            angular_acceleration: to_palm * m.angular_acceleration,
            linear_acceleration_minus_gravity: to_palm * (m.linear_acceleration - gravity),
        };
        let (gravity_held, arm_held) = self.compensate;
        let held = BaseMotion {
            angular_velocity: if arm_held {
                real.angular_velocity
            } else {
                Vec3::zeros()
            },
            angular_acceleration: if arm_held {
                real.angular_acceleration
            } else {
                Vec3::zeros()
            },
            linear_acceleration_minus_gravity: to_palm
                * (if arm_held {
                    m.linear_acceleration
                } else {
                    Vec3::zeros()
                } - if gravity_held {
                    *gravity
                } else {
                    Vec3::zeros()
                }),
        };
        let failed = |e: prehensile_control::DynamicsError| SimError::Hand(e.to_string());
        self.free.iter_mut().for_each(|v| *v = 0.0);
        self.force.copy_from_slice(&self.coupling);
        if gravity_held || arm_held {
            let compensation =
                bias_torques(&self.dynamics, &mut self.data, &self.q, &held).map_err(failed)?;
            for (f, c) in self.force.iter_mut().zip(compensation) {
                *f += c;
            }
        }
        let zeros = &self.free;
        let bias = rnea(
            &self.dynamics,
            &mut self.data,
            &self.q,
            &self.qd,
            zeros,
            &real,
        )
        .map_err(failed)?;
        self.bias.copy_from_slice(bias);
        let mass = crba(&self.dynamics, &mut self.data, &self.q).map_err(failed)?;
        for block in &mut self.blocks {
            let size = block.dofs.len();
            let mut effective = match block.factor.take() {
                Some(factor) => factor.unpack_dirty(),
                None => std::mem::replace(&mut block.spare, DMatrix::zeros(0, 0)),
            };
            for (i, &k) in block.dofs.iter().enumerate() {
                for (j, &l) in block.dofs.iter().enumerate() {
                    effective[(i, j)] = mass[(k, l)];
                }
                let s = &self.springs[k];
                effective[(i, i)] += dt * s.damping + dt * dt * s.stiffness;
            }
            for &k in &block.dofs {
                let s = &self.springs[k];
                let momentum: f64 = block.dofs.iter().map(|&l| mass[(k, l)] * self.qd[l]).sum();
                self.free[k] = momentum
                    + dt * (self.force[k] - self.bias[k]
                        + s.stiffness * (s.target - self.q[k])
                        + s.damping * s.target_velocity);
            }
            let factor = Cholesky::new(effective).ok_or_else(|| {
                SimError::Hand(format!(
                    "hand '{}': the mass matrix is not positive definite",
                    self.hand.name()
                ))
            })?;
            for (i, &k) in block.dofs.iter().enumerate() {
                block.scratch[i] = self.free[k];
            }
            factor.solve_mut(&mut DMatrixViewMut::from_slice(&mut block.scratch, size, 1));
            for (i, &k) in block.dofs.iter().enumerate() {
                self.free[k] = block.scratch[i];
            }
            block.factor = Some(factor);
        }
        Ok(())
    }

    /// Integrates the angles over `dt` at the new rates and moves the root on.
    fn integrate(&mut self, dt: f64) {
        for bone in self.hand.bones() {
            let range = bone.first_dof..bone.first_dof + bone.joint.dofs();
            match &bone.joint {
                Joint::Fixed => {}
                Joint::Ball { .. } => {
                    let rates = &self.qd[range.clone()];
                    let turn =
                        Rotation::from_scaled_axis(Vec3::new(rates[0], rates[1], rates[2]) * dt);
                    let rotation = bone.joint.rotation(&self.q[range.clone()]) * turn;
                    bone.joint.angles(&rotation, &mut self.q[range]);
                }
                _ => {
                    for k in range {
                        self.q[k] += dt * self.qd[k];
                    }
                }
            }
        }
        self.root = self.next_root;
    }
}

impl ReducedWorld {
    /// This step's contacts: every capsule of the hand within the margin of the object.
    fn find_contacts(&mut self) {
        let points = &mut self.contact.points;
        points.clear();
        let (Some(hand), Some(object)) = (self.hands.first_mut(), &self.object) else {
            return;
        };
        let to_mesh = object.pose.inverse();
        for (capsule, c) in hand.hand.capsules().iter().enumerate() {
            // A palm capsule against the held object: neither side can give (rapier likewise
            // leaves a kinematic body and a fixed one to pass through each other).
            if object.fixed && hand.movers[c.bone].is_empty() {
                hand.impulses[capsule] = [0.0; 3];
                continue;
            }
            let frame = &hand.frames[c.bone];
            let local = Capsule {
                a: to_mesh * (frame * c.a),
                b: to_mesh * (frame * c.b),
                radius: c.radius,
            };
            let found =
                object
                    .object
                    .collider()
                    .capsule_contact(&local, MARGIN, hand.fractions[capsule]);
            hand.fractions[capsule] = found.map(|f| f.fraction);
            let Some(contact) = found.filter(|f| f.gap <= MARGIN) else {
                hand.impulses[capsule] = [0.0; 3];
                continue;
            };
            let normal = -(object.pose.rotation * contact.normal);
            let first = normal
                .cross(&Vec3::x())
                .try_normalize(1e-6)
                .unwrap_or_else(|| normal.cross(&Vec3::y()).normalize());
            points.push(ContactPoint {
                capsule,
                bone: c.bone,
                point: object.pose * contact.point,
                directions: [normal, first, normal.cross(&first)],
                gap: contact.gap,
            });
        }
    }

    /// The contact rows, their Delassus matrix and free velocities, the impulses, and the
    /// velocities after them.
    fn solve_contacts(&mut self) {
        let dt = self.dt;
        let ws = &mut self.contact;
        let rows = 3 * ws.points.len();
        let (Some(hand), Some(object)) = (self.hands.first_mut(), &mut self.object) else {
            return;
        };
        if rows == 0 {
            for block in &mut hand.blocks {
                block.rows.clear();
            }
            hand.qd.copy_from_slice(&hand.free);
            return;
        }
        let n = hand.q.len();
        ws.jacobian.clear();
        ws.jacobian.resize(rows * n, 0.0);
        ws.free.resize(rows, 0.0);
        ws.target.resize(rows, 0.0);
        ws.lambda.resize(rows, 0.0);
        ws.delassus.clear();
        ws.delassus.resize(rows * rows, 0.0);
        let (palm_origin, palm_velocity, palm_spin) = hand.palm_velocity(dt);
        let center = object.center_world();
        let (inverse_mass, inverse_inertia) = (object.inverse_mass(), object.inverse_inertia());
        // The object's side of each row: its linear and angular parts.
        let mut angular = Vec::with_capacity(rows);
        for (c, p) in ws.points.iter().enumerate() {
            for (k, d) in p.directions.iter().enumerate() {
                let r = 3 * c + k;
                let row = &mut ws.jacobian[r * n..(r + 1) * n];
                let mut hand_velocity =
                    (palm_velocity + palm_spin.cross(&(p.point - palm_origin))).dot(d);
                for &dof in &hand.movers[p.bone] {
                    let (origin, axis) = hand.axes[dof];
                    row[dof] = axis.cross(&(p.point - origin)).dot(d);
                    hand_velocity += row[dof] * hand.free[dof];
                }
                let lever = (p.point - center).cross(d);
                angular.push(lever);
                ws.free[r] = object.velocity.dot(d) + object.spin.dot(&lever) - hand_velocity;
                ws.target[r] = match k {
                    0 if p.gap > 0.0 => -p.gap / dt,
                    0 => -p.gap * BAUMGARTE / dt,
                    _ => 0.0,
                };
                ws.lambda[r] = hand.impulses[p.capsule][k];
            }
        }
        let direction = |r: usize| ws.points[r / 3].directions[r % 3];
        for (i, lever) in angular.iter().enumerate() {
            let spun = inverse_inertia * lever;
            for (j, other) in angular.iter().enumerate() {
                ws.delassus[i * rows + j] =
                    direction(i).dot(&direction(j)) * inverse_mass + other.dot(&spun);
            }
        }
        for block in &mut hand.blocks {
            let size = block.dofs.len();
            block.rows.clear();
            block.rows.extend(
                (0..rows).filter(|&r| block.dofs.iter().any(|&k| ws.jacobian[r * n + k] != 0.0)),
            );
            let count = block.rows.len();
            block.response.clear();
            block.response.resize(size * count, 0.0);
            for (c, &r) in block.rows.iter().enumerate() {
                let column = &mut block.response[c * size..(c + 1) * size];
                for (i, &k) in block.dofs.iter().enumerate() {
                    column[i] = ws.jacobian[r * n + k];
                }
            }
            if let Some(factor) = &block.factor {
                factor.solve_mut(&mut DMatrixViewMut::from_slice(
                    &mut block.response,
                    size,
                    count,
                ));
            }
            for &ra in &block.rows {
                for (b, &rb) in block.rows.iter().enumerate() {
                    let response = &block.response[b * size..(b + 1) * size];
                    let coupling: f64 = block
                        .dofs
                        .iter()
                        .zip(response)
                        .map(|(&k, x)| ws.jacobian[ra * n + k] * x)
                        .sum();
                    ws.delassus[ra * rows + rb] += coupling;
                }
            }
        }
        projected_gauss_seidel(
            &ContactProblem {
                delassus: &ws.delassus,
                free: &ws.free,
                target: &ws.target,
                friction: self.friction,
                softness: SOFTNESS,
            },
            SWEEPS,
            &mut ws.lambda,
        );
        // The hand is pushed back by −Hᵀλ, the object on by its rows.
        hand.qd.copy_from_slice(&hand.free);
        for block in &hand.blocks {
            let size = block.dofs.len();
            for (c, &r) in block.rows.iter().enumerate() {
                let response = &block.response[c * size..(c + 1) * size];
                for (i, &k) in block.dofs.iter().enumerate() {
                    hand.qd[k] -= response[i] * ws.lambda[r];
                }
            }
        }
        for impulse in &mut hand.impulses {
            *impulse = [0.0; 3];
        }
        for (c, p) in ws.points.iter().enumerate() {
            for k in 0..3 {
                let (r, l) = (3 * c + k, ws.lambda[3 * c + k]);
                hand.impulses[p.capsule][k] = l;
                object.velocity += p.directions[k] * (l * inverse_mass);
                object.spin += inverse_inertia * (angular[r] * l);
            }
        }
    }

    /// What touched in this step, for [`PhysicsEngine::contacts`].
    fn report(&mut self) {
        let Some(hand) = self.hands.first_mut() else {
            return;
        };
        let report = &mut hand.report;
        report.force = 0.0;
        report.penetration = 0.0;
        report.touching = 0;
        report.bone_forces.iter_mut().for_each(|f| *f = 0.0);
        // One contact per capsule: a capsule touches when its normal impulse pushes.
        for (c, p) in self.contact.points.iter().enumerate() {
            report.penetration = report.penetration.max(-p.gap);
            let force = self.contact.lambda[3 * c] / self.dt;
            if force > 0.0 {
                report.force += force;
                report.bone_forces[p.bone] += force;
                report.touching += 1;
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
        if !self.hands.is_empty() {
            return Err(SimError::Settings(
                "the reduced engine simulates one hand (hand–hand contact is not built yet); \
                 use the rapier engine for two"
                    .into(),
            ));
        }
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
                h.impulses.iter_mut().for_each(|i| *i = [0.0; 3]);
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
        if let Some(h) = self.hands.first_mut() {
            h.place();
        }
        self.find_contacts();
        if let Some(h) = self.hands.first_mut() {
            h.free_velocity(dt, &self.gravity)?;
        }
        if let Some(o) = self.object.as_mut().filter(|o| !o.fixed) {
            o.velocity += self.gravity * dt;
        }
        if self.object.is_some() {
            self.solve_contacts();
        } else if let Some(h) = self.hands.first_mut() {
            h.qd.copy_from_slice(&h.free);
        }
        self.report();
        if let Some(h) = self.hands.first_mut() {
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

    fn diverged(&self) -> Option<String> {
        for (i, h) in self.hands.iter().enumerate() {
            for (k, bone) in h.hand.bones().iter().enumerate() {
                let range = bone.first_dof..bone.first_dof + bone.joint.dofs();
                let angles_finite = h.q[range.clone()].iter().all(|x| x.is_finite());
                let rates = h.qd[range].iter().fold(0.0f64, |m, x| m.max(x.abs()));
                if runaway(angles_finite, &Vec3::zeros(), &Vec3::new(rates, 0.0, 0.0))
                    || rates.is_nan()
                {
                    return Some(bone_ran_away(&h.hand, i, k));
                }
            }
        }
        match &self.object {
            Some(o) => {
                let finite = o.pose.translation.vector.iter().all(|x| x.is_finite())
                    && o.pose.rotation.coords.iter().all(|x| x.is_finite());
                runaway(finite, &o.velocity, &o.spin).then(|| "the object ran away".into())
            }
            None => None,
        }
    }

    fn bone_frames(&self, i: usize, out: &mut Vec<Transform>) {
        let h = &self.hands[i];
        out.resize(h.hand.bones().len(), Transform::identity());
        forward_kinematics_into(h, out);
    }
}

/// Hand `h`'s bone frames at its angles and root now.
fn forward_kinematics_into(h: &ReducedHand, out: &mut [Transform]) {
    let mut rotations = vec![Rotation::identity(); h.hand.bones().len()];
    h.hand.joint_rotations(&h.q, &mut rotations);
    forward_kinematics(&h.hand, &h.root, &rotations, out);
}

#[cfg(test)]
mod tests {
    use prehensile_control::{forward_dynamics, BaseMotion, DynamicsModel, JointSpring};
    use prehensile_core::math::{Point3, Transform, Vec3};

    use super::*;

    /// Hands with every kind of joint: hinges, two-axis joints (human), ball joints.
    fn hands() -> Vec<(&'static str, HandModel)> {
        let ball = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/hands/robot3_ball.toml"
        );
        vec![
            ("human", prehensile_formats::builtin_hand("human").unwrap()),
            (
                "robot3",
                prehensile_formats::builtin_hand("robot3").unwrap(),
            ),
            (
                "robot3_ball",
                prehensile_formats::load_hand(std::path::Path::new(ball)).unwrap(),
            ),
        ]
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
            let still = JointSpring {
                stiffness: 0.0,
                damping: 0.0,
                target: 0.0,
                target_velocity: 0.0,
            };
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

    /// The joint axes the contact rows are built from move every capsule's end as forward
    /// kinematics does: a finite difference of the bone frames along random rates.
    #[test]
    fn the_contact_jacobian_is_the_derivative_of_forward_kinematics() {
        for (name, hand) in hands() {
            let n = hand.dof_count();
            let root = Transform::from_parts(
                Vec3::new(0.01, -0.02, 0.03).into(),
                Rotation::from_euler_angles(0.3, -0.5, 0.9),
            );
            let q: Vec<f64> = (0..n)
                .map(|k| 0.37 * ((k * 7 % 5) as f64 - 2.0) / 2.0)
                .collect();
            let rates: Vec<f64> = (0..n).map(|k| ((k * 3 % 7) as f64 - 3.0) / 3.0).collect();
            let mut placed = ReducedHand::new(&hand, &root, &q).unwrap();
            placed.place();
            let h = 1e-6;
            let mut moved = ReducedHand::new(&hand, &root, &q).unwrap();
            moved.qd.copy_from_slice(&rates);
            moved.next_root = root;
            moved.integrate(h);
            moved.place();
            for c in hand.capsules() {
                let (before, after) = (placed.frames[c.bone] * c.b, moved.frames[c.bone] * c.b);
                let numeric = (after - before) / h;
                let mut analytic = Vec3::zeros();
                for &dof in &placed.movers[c.bone] {
                    let (origin, axis) = placed.axes[dof];
                    analytic += axis.cross(&(before - origin)) * rates[dof];
                }
                assert!(
                    (numeric - analytic).norm() < 1e-4 * (1.0 + analytic.norm()),
                    "{name}, bone {}: {numeric} against {analytic}",
                    hand.bones()[c.bone].name
                );
            }
        }
    }
}

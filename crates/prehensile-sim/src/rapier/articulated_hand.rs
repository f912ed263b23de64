//! A hand model as rapier rigid bodies: one dynamic body per bone with the bone's mass and
//! inertia and its capsules as colliders, joined by impulse joints; the root (palm) is a
//! kinematic body that follows the arm.
//!
//! Design (measured against the alternatives, see docs/PERFORMANCE.md): impulse joints rather
//! than rapier's reduced-coordinate multibody joints (3–4× faster a step on the Shadow hand
//! holding a sphere in rapier 0.36, whatever the number of solver sweeps); every degree of freedom is a joint motor that carries the
//! controller's τP + τA as an implicit spring ([`prehensile_control::joint_springs`]), so the
//! stiff limit springs integrate stably at millisecond steps; τG + τARM are applied as the
//! equivalent wrench on each body ([`crate::holding_wrench`]). A hinge is a revolute joint; a
//! two-axis bone becomes two revolute joints in series through a small intermediate body
//! (R = R(abduction)·R(flexion), as in the model); a ball joint is a spherical joint with a motor
//! about each of the bone's axes, the cross terms of its 3×3 inertia added as torques
//! ([`prehensile_control::ball_joint_coupling`]).

use prehensile_core::hand::{Inertial, Joint};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;
use rapier3d_f64::prelude::{
    ColliderBuilder, ColliderHandle, GenericJointBuilder, Group, ImpulseJointHandle,
    InteractionGroups, InteractionTestMode, JointAxesMask, JointAxis, MassProperties, Matrix,
    MotorModel, PhysicsWorld, Pose, RigidBodyBuilder, RigidBodyHandle, Rotation as Quat, Vector,
};

use crate::world::convert;
use crate::world::holding_wrench::{holding_wrench, FrameMotion};

/// Mass of the intermediate body of a two-axis joint, as a fraction of its bone's mass. The
/// dynamics model treats that link as massless; the solver needs a mass ratio near one along the
/// chain (at 5% the passive hand drifted 0.17 rad from neutral and joint limits stopped holding).
/// Its weight and inertia are compensated like the bones' (see [`crate::holding_wrench`]).
pub const INTERMEDIATE_MASS_FRACTION: f64 = 1.0;

/// One controlled degree of freedom: a revolute joint between two bodies, or one axis of a
/// spherical joint.
#[derive(Debug, Clone, Copy)]
struct DofJoint {
    joint: ImpulseJointHandle,
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    /// The joint axis in the child body's frame.
    axis_in_child: Vector,
    /// The motor's axis (`AngX` for a revolute joint).
    motor: JointAxis,
    /// For a spherical joint, the bone's rest rotation in its parent (the joint's first body is
    /// the child, so that its motors turn about the bone's own axes as the controller's do).
    ball_rest: Option<Quat>,
}

/// A hand in a rapier world.
#[derive(Debug, Clone)]
pub struct ArticulatedHand {
    hand: HandModel,
    /// The body of every bone (the root's is kinematic).
    bones: Vec<RigidBodyHandle>,
    /// The intermediate bodies of two-axis joints.
    intermediates: Vec<RigidBodyHandle>,
    /// Every moving body with its mass, centre of mass and inertia (body frame), for the
    /// compensation wrenches.
    masses: Vec<(RigidBodyHandle, Inertial)>,
    /// One per degree of freedom, in [`HandModel::dof_names`] order.
    dofs: Vec<DofJoint>,
    colliders: Vec<ColliderHandle>,
    /// The bone of every collider, parallel to `colliders`.
    collider_bones: Vec<usize>,
}

/// Collision filtering: hands never collide with themselves; `group` is this hand's bit
/// (objects and other hands collide with it).
pub fn hand_groups(group: Group) -> InteractionGroups {
    InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And)
}

impl ArticulatedHand {
    /// Adds `hand` to the world with its root bone's parent frame at `root` and joint angles `q`
    /// (one per degree of freedom), in collision group `group` with skin friction `friction`.
    pub fn insert(
        hand: &HandModel,
        world: &mut PhysicsWorld,
        root: &Transform,
        q: &[f64],
        group: Group,
        friction: f64,
    ) -> Self {
        let mut rotations = vec![Rotation::identity(); hand.bones().len()];
        for (k, bone) in hand.bones().iter().enumerate() {
            rotations[k] = bone
                .joint
                .rotation(&q[bone.first_dof..bone.first_dof + bone.joint.dofs()]);
        }
        let mut world_frames = vec![Transform::identity(); hand.bones().len()];
        prehensile_core::hand::kinematics::forward_kinematics(
            hand,
            root,
            &rotations,
            &mut world_frames,
        );
        let mut built = Self {
            hand: hand.clone(),
            bones: Vec::with_capacity(hand.bones().len()),
            intermediates: Vec::new(),
            masses: Vec::new(),
            dofs: Vec::with_capacity(hand.dof_count()),
            colliders: Vec::new(),
            collider_bones: Vec::new(),
        };
        for k in 0..hand.bones().len() {
            built.add_bone(world, k, &world_frames[k], (group, friction));
            if hand.bones()[k].parent.is_some() {
                built.add_joint(world, k, q, &world_frames);
            }
        }
        built
    }

    /// Bone `k`'s body at `frame` (the root's kinematic), with its mass and its capsules'
    /// colliders in collision group `group` with skin friction `friction`.
    fn add_bone(
        &mut self,
        world: &mut PhysicsWorld,
        k: usize,
        frame: &Transform,
        (group, friction): (Group, f64),
    ) {
        let bone = &self.hand.bones()[k];
        let builder = match bone.parent {
            None => RigidBodyBuilder::kinematic_position_based(),
            Some(_) => RigidBodyBuilder::dynamic(),
        };
        let mut builder = builder.pose(convert::pose(frame)).can_sleep(false);
        if let Some(inertial) = &bone.inertial {
            builder = builder.additional_mass_properties(mass_properties(
                inertial.mass,
                convert::point(&inertial.center_of_mass),
                &inertial.inertia,
            ));
        }
        let body = world.bodies.insert(builder);
        if let (Some(inertial), Some(_)) = (bone.inertial, bone.parent) {
            self.masses.push((body, inertial));
        }
        for capsule in self.hand.bone_capsules(k) {
            let collider = ColliderBuilder::capsule_from_endpoints(
                convert::point(&capsule.a),
                convert::point(&capsule.b),
                capsule.radius,
            )
            .density(0.0)
            .friction(friction)
            .collision_groups(hand_groups(group));
            self.colliders.push(world.colliders.insert_with_parent(
                collider,
                body,
                &mut world.bodies,
            ));
            self.collider_bones.push(k);
        }
        self.bones.push(body);
    }

    /// The joint between bone `k` and its parent, one [`DofJoint`] per degree of freedom.
    fn add_joint(&mut self, world: &mut PhysicsWorld, k: usize, q: &[f64], frames: &[Transform]) {
        let bone = self.hand.bones()[k].clone();
        let parent = bone.parent.expect("a bone with a parent");
        let (parent_body, body) = (self.bones[parent], self.bones[k]);
        let rest = convert::pose(&bone.rest);
        match &bone.joint {
            Joint::Fixed => {
                let joint = GenericJointBuilder::new(JointAxesMask::LOCKED_FIXED_AXES)
                    .local_frame1(rest)
                    .contacts_enabled(false);
                world.impulse_joints.insert(parent_body, body, joint, true);
            }
            Joint::Hinge(axis) => {
                let axis = convert::vector(&axis.axis);
                let dof = revolute(world, parent_body, rest, body, Pose::IDENTITY, axis);
                self.dofs.push(dof);
            }
            Joint::TwoAxis { flexion, abduction } => {
                // The intermediate body sits at the bone's joint turned by its abduction.
                let frame = frames[parent]
                    * bone.rest
                    * Rotation::from_axis_angle(&abduction.axis, q[bone.first_dof + 1]);
                let mass = bone.inertial.map_or(1e-4, |i| i.mass) * INTERMEDIATE_MASS_FRACTION;
                let middle = self.add_intermediate(world, &frame, mass);
                // Degree of freedom 0 is flexion, 1 abduction.
                let (inner, outer) = (
                    convert::vector(&flexion.axis),
                    convert::vector(&abduction.axis),
                );
                let flex = revolute(world, middle, Pose::IDENTITY, body, Pose::IDENTITY, inner);
                let abd = revolute(world, parent_body, rest, middle, Pose::IDENTITY, outer);
                self.dofs.push(flex);
                self.dofs.push(abd);
            }
            Joint::Ball { .. } => {
                let joint = world
                    .impulse_joints
                    .insert(body, parent_body, spherical(rest), true);
                for (motor, axis_in_child) in [
                    (JointAxis::AngX, Vector::X),
                    (JointAxis::AngY, Vector::Y),
                    (JointAxis::AngZ, Vector::Z),
                ] {
                    self.dofs.push(DofJoint {
                        joint,
                        parent: parent_body,
                        child: body,
                        axis_in_child,
                        motor,
                        ball_rest: Some(rest.rotation),
                    });
                }
            }
        }
    }

    /// A two-axis joint's intermediate body at `frame`, of `mass` (a small sphere's inertia
    /// about the joint centre).
    fn add_intermediate(
        &mut self,
        world: &mut PhysicsWorld,
        frame: &Transform,
        mass: f64,
    ) -> RigidBodyHandle {
        let inertia = 0.4 * mass * 0.005f64.powi(2);
        let middle = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .pose(convert::pose(frame))
                .can_sleep(false)
                .additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    mass,
                    Vector::splat(inertia),
                )),
        );
        self.intermediates.push(middle);
        self.masses.push((
            middle,
            Inertial {
                mass,
                center_of_mass: Point3::origin(),
                inertia: nalgebra::Matrix3::from_diagonal_element(inertia),
            },
        ));
        middle
    }

    /// The hand model.
    pub fn model(&self) -> &HandModel {
        &self.hand
    }

    /// The root (palm) body.
    pub fn root_body(&self) -> RigidBodyHandle {
        self.bones[0]
    }

    /// Every bone's body.
    pub fn bone_bodies(&self) -> &[RigidBodyHandle] {
        &self.bones
    }

    /// Every capsule collider of the hand.
    pub fn colliders(&self) -> &[ColliderHandle] {
        &self.colliders
    }

    /// The bone each of [`ArticulatedHand::colliders`] belongs to.
    pub fn collider_bones(&self) -> &[usize] {
        &self.collider_bones
    }

    /// Bone `k`'s body pose in the world.
    fn bone_frame(&self, world: &PhysicsWorld, k: usize) -> Transform {
        convert::transform(world.bodies[self.bones[k]].position())
    }

    /// The bone whose origin is farthest from where its joint holds it on its parent, and that
    /// distance in metres (`None` for a hand without joints). The joints keep this near zero;
    /// a solver that has lost the hand shows it here even when rapier's velocity caps keep
    /// every number finite.
    pub fn widest_joint_gap(&self, world: &PhysicsWorld) -> Option<(usize, f64)> {
        self.hand
            .bones()
            .iter()
            .enumerate()
            .filter_map(|(k, bone)| {
                let held_at = self.bone_frame(world, bone.parent?)
                    * Point3::from(bone.rest.translation.vector);
                let at = Point3::from(self.bone_frame(world, k).translation.vector);
                Some((k, (at - held_at).norm()))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Joint angles and rates of every degree of freedom, read from the bodies.
    pub fn state(&self, world: &PhysicsWorld, q: &mut [f64], qd: &mut [f64]) {
        for (k, bone) in self.hand.bones().iter().enumerate() {
            let Some(parent) = bone.parent else { continue };
            let n = bone.joint.dofs();
            if n == 0 {
                continue;
            }
            let rotation = |k| self.bone_frame(world, k).rotation;
            let relative = (rotation(parent) * bone.rest.rotation).inverse() * rotation(k);
            bone.joint
                .angles(&relative, &mut q[bone.first_dof..bone.first_dof + n]);
        }
        for (k, dof) in self.dofs.iter().enumerate() {
            let child = &world.bodies[dof.child];
            let parent = &world.bodies[dof.parent];
            let axis = *child.rotation() * dof.axis_in_child;
            qd[k] = (child.angvel() - parent.angvel()).dot(axis);
        }
    }

    /// Clears last step's forces, sets every joint's motor to its spring (stiffness, damping,
    /// target; the implicit τP + τA with the diagonal of `I`) for the hand at angles `q`, and
    /// adds the `coupling` torques (a ball joint's cross terms of `I`, explicit).
    pub fn drive(
        &self,
        world: &mut PhysicsWorld,
        springs: &[prehensile_control::JointSpring],
        q: &[f64],
        coupling: &[f64],
    ) {
        for body in self.bones.iter().chain(&self.intermediates) {
            if let Some(b) = world.bodies.get_mut(*body) {
                b.reset_forces(false);
                b.reset_torques(false);
            }
        }
        for (k, (dof, s)) in self.dofs.iter().zip(springs).enumerate() {
            let (target, target_velocity) = match dof.ball_rest {
                None => (s.target, s.target_velocity),
                Some(rest) => {
                    // Rapier measures a spherical joint's angle about an axis as twice the
                    // arcsine of that component of the relative quaternion (child⁻¹·parent here:
                    // the joint rotation's inverse), not as a rotation-vector component. Its target
                    // is offset by the difference at the current pose, so the spring's torque
                    // there is exactly the controller's; rates change sign with the body order.
                    let child = *world.bodies[dof.child].rotation();
                    let parent = *world.bodies[dof.parent].rotation();
                    let mut relative = child.inverse() * parent * rest;
                    if relative.w < 0.0 {
                        relative = -relative;
                    }
                    let component = relative.xyz()[dof.motor as usize - 3];
                    let measured = 2.0 * component.clamp(-1.0, 1.0).asin();
                    (measured - (s.target - q[k]), -s.target_velocity)
                }
            };
            if let Some(joint) = world.impulse_joints.get_mut(dof.joint, false) {
                joint
                    .data
                    .set_motor(dof.motor, target, target_velocity, s.stiffness, s.damping);
            }
            if coupling[k] != 0.0 {
                let axis = *world.bodies[dof.child].rotation() * dof.axis_in_child;
                world.bodies[dof.child].add_torque(axis * coupling[k], false);
                world.bodies[dof.parent].add_torque(-axis * coupling[k], false);
            }
        }
    }

    /// Adds to every moving body the wrench that carries it along with the palm moving as
    /// `palm` and holds it against `gravity` (τARM and τG; see [`crate::holding_wrench`]).
    pub fn hold(&self, world: &mut PhysicsWorld, palm: &FrameMotion, gravity: &Vec3) {
        for (handle, inertial) in &self.masses {
            let body = &mut world.bodies[*handle];
            let frame = convert::transform(body.position());
            let turn = frame.rotation.to_rotation_matrix().into_inner();
            let (force, torque) = holding_wrench(
                inertial.mass,
                &(frame * inertial.center_of_mass),
                &(turn * inertial.inertia * turn.transpose()),
                palm,
                gravity,
            );
            body.add_force(convert::vector(&force), false);
            body.add_torque(convert::vector(&torque), false);
        }
    }

    /// Moves the root toward `root` by the next step (kinematic: the arm is prescribed).
    pub fn move_root(&self, world: &mut PhysicsWorld, root: &Transform) {
        let palm = *root * self.hand.bones()[0].rest;
        world.bodies[self.bones[0]].set_next_kinematic_position(convert::pose(&palm));
    }
}

/// A revolute joint turning `axis` (given in the child's frame, which at zero angle is
/// `frame1` in the parent's) with a force-based motor.
fn revolute(
    world: &mut PhysicsWorld,
    parent: RigidBodyHandle,
    frame1: Pose,
    child: RigidBodyHandle,
    frame2: Pose,
    axis: Vector,
) -> DofJoint {
    let align = Pose::from_rotation(Quat::from_rotation_arc(Vector::X, axis.normalize()));
    let joint = GenericJointBuilder::new(JointAxesMask::LOCKED_REVOLUTE_AXES)
        .local_frame1(frame1 * align)
        .local_frame2(frame2 * align)
        .motor_model(JointAxis::AngX, MotorModel::ForceBased)
        .contacts_enabled(false);
    DofJoint {
        joint: world.impulse_joints.insert(parent, child, joint, true),
        parent,
        child,
        axis_in_child: frame2.rotation * axis,
        motor: JointAxis::AngX,
        ball_rest: None,
    }
}

/// A spherical joint from the child (first body, at its origin) to the parent (second body, at
/// the bone's rest frame `rest`), with force-based motors about the child's three axes.
fn spherical(rest: Pose) -> GenericJointBuilder {
    let mut joint = GenericJointBuilder::new(JointAxesMask::LOCKED_SPHERICAL_AXES)
        .local_frame2(rest)
        .contacts_enabled(false);
    for axis in [JointAxis::AngX, JointAxis::AngY, JointAxis::AngZ] {
        joint = joint.motor_model(axis, MotorModel::ForceBased);
    }
    joint
}

/// Mass properties with a full inertia tensor about the centre of mass.
fn mass_properties(mass: f64, com: Vector, inertia: &nalgebra::Matrix3<f64>) -> MassProperties {
    let m = Matrix::from_cols_array(&[
        inertia[(0, 0)],
        inertia[(1, 0)],
        inertia[(2, 0)],
        inertia[(0, 1)],
        inertia[(1, 1)],
        inertia[(2, 1)],
        inertia[(0, 2)],
        inertia[(1, 2)],
        inertia[(2, 2)],
    ]);
    MassProperties::with_inertia_matrix(com, mass, m)
}

/// Why a hand cannot be simulated.
pub fn check_hand(hand: &HandModel) -> Result<(), crate::error::SimError> {
    for bone in hand.bones() {
        if bone.parent.is_some() && bone.joint.dofs() > 0 && bone.inertial.is_none() {
            return Err(crate::error::SimError::Massless {
                bone: bone.name.clone(),
            });
        }
    }
    Ok(())
}

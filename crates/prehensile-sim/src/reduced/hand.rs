//! One hand of the reduced-coordinate engine ([`crate::reduced::world`]): its state in joint
//! angles and rates under a kinematic palm, its dynamics (the bias by Newton–Euler with the
//! palm's real motion, the controller's τG + τARM, the mass matrix), the controller's springs
//! integrated implicitly block by block, and its side of the contact rows.

use nalgebra::{Cholesky, DMatrix, DMatrixViewMut, Dyn};
use prehensile_control::JointSpring;
use prehensile_control::{bias_torques, crba, rnea, BaseMotion, DynamicsData, DynamicsModel};
use prehensile_core::hand::kinematics::forward_kinematics;
use prehensile_core::hand::Joint;
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;

use crate::error::SimError;
use crate::world::contacts::Contacts;
use crate::world::holding_wrench::FrameMotion;

/// Contacts a capsule may have with the object: its point nearest the object, and each end
/// that touches too (a bone lying along a face or a cylinder's side, where one point would let
/// the object pivot about it and its place wander along the bone from step to step; MuJoCo's
/// capsule–plane and rapier's capsule–mesh contacts likewise keep two or more points).
pub(super) const CONTACT_SLOTS: usize = 3;

/// A hand: its model, state and drive, and the buffers of its step.
pub(crate) struct ReducedHand {
    pub(super) hand: HandModel,
    pub(super) dynamics: DynamicsModel,
    pub(super) data: DynamicsData,
    pub(super) q: Vec<f64>,
    pub(super) qd: Vec<f64>,
    /// The root placement now.
    pub(super) root: Transform,
    /// What drives it over the next step (set by the engine's `drive`).
    pub(super) springs: Vec<JointSpring>,
    pub(super) coupling: Vec<f64>,
    pub(super) palm_motion: FrameMotion,
    pub(super) compensate: (bool, bool),
    pub(super) next_root: Transform,
    /// The blocks of M: dofs that share a moving ancestor.
    blocks: Vec<Block>,
    /// Per bone, every degree of freedom that moves it (its own and its ancestors'), all in
    /// one block.
    pub(super) movers: Vec<Vec<usize>>,
    /// Per bone, the block of its movers (none for the palm's bones).
    block_of_bone: Vec<Option<usize>>,
    /// Per degree of freedom, its place in its block.
    place_in_block: Vec<usize>,
    /// The palm's origin, velocity and spin over this step.
    palm_velocity: (Point3, Vec3, Vec3),
    pub(super) rotations: Vec<Rotation>,
    pub(super) frames: Vec<Transform>,
    /// Per degree of freedom, its joint's origin and axis in the world this step.
    pub(super) axes: Vec<(Point3, Vec3)>,
    /// Per capsule, the contact fraction of the step before (the narrow phase's warm start)
    /// and the impulses (normal, two tangents) of each of its contacts the step before (the
    /// solver's; see [`super::world::ContactSlot`]).
    pub(super) fractions: Vec<Option<f64>>,
    pub(super) impulses: Vec<[[f64; 3]; CONTACT_SLOTS]>,
    /// The generalized forces of this step and the velocity before contact.
    pub(super) bias: Vec<f64>,
    pub(super) force: Vec<f64>,
    pub(super) free: Vec<f64>,
    /// The contacts of the last step.
    pub(super) report: Contacts,
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
    /// Those rows' Jacobians on the block's dofs, signed as the row's relative velocity counts
    /// this hand (rows × dofs, row-major).
    jacobian: Vec<f64>,
    /// (M + dt D + dt² K)⁻¹ Jᵀ for those rows, dofs × rows, column-major.
    response: Vec<f64>,
    /// One column of the block's size.
    scratch: Vec<f64>,
}

impl ReducedHand {
    /// `hand` at root placement `root` and angles `start`, at rest.
    pub(super) fn new(hand: &HandModel, root: &Transform, start: &[f64]) -> Result<Self, SimError> {
        if hand.bones()[0].joint.dofs() > 0 {
            return Err(SimError::JointedRoot {
                hand: hand.name().to_string(),
                bone: hand.bones()[0].name.clone(),
            });
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
                    jacobian: Vec::new(),
                    response: Vec::new(),
                    scratch: Vec::new(),
                });
                blocks.len() - 1
            });
            blocks[b]
                .dofs
                .extend(bone.first_dof..bone.first_dof + bone.joint.dofs());
        }
        let mut place_in_block = vec![0; n];
        for block in &mut blocks {
            let size = block.dofs.len();
            block.spare = DMatrix::zeros(size, size);
            block.scratch = vec![0.0; size];
            for (i, &k) in block.dofs.iter().enumerate() {
                place_in_block[k] = i;
            }
        }
        let block_of_bone = top
            .iter()
            .map(|t| t.and_then(|t| block_of_top[t]))
            .collect();
        let dynamics = DynamicsModel::new(hand);
        let capsules = hand.capsules().len();
        Ok(Self {
            hand: hand.clone(),
            data: dynamics.data(),
            dynamics,
            q: start.to_vec(),
            qd: vec![0.0; n],
            root: *root,
            springs: vec![JointSpring::SLACK; n],
            coupling: vec![0.0; n],
            palm_motion: FrameMotion::at_rest(Point3::from(
                (root * bones[0].rest).translation.vector,
            )),
            compensate: (false, false),
            next_root: *root,
            blocks,
            movers,
            block_of_bone,
            place_in_block,
            palm_velocity: (Point3::origin(), Vec3::zeros(), Vec3::zeros()),
            rotations: vec![Rotation::identity(); bones.len()],
            frames: vec![Transform::identity(); bones.len()],
            axes: vec![(Point3::origin(), Vec3::zeros()); n],
            fractions: vec![None; capsules],
            impulses: vec![[[0.0; 3]; CONTACT_SLOTS]; capsules],
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
    pub(super) fn palm_at(&self, root: &Transform) -> Transform {
        root * self.hand.bones()[0].rest
    }

    /// Places the bones at the current angles and root, every joint axis in the world, and
    /// the palm's velocity over the step of `dt` to the next root.
    pub(super) fn place(&mut self, dt: f64) {
        self.palm_velocity = self.palm_velocity(dt);
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
    pub(super) fn free_velocity(&mut self, dt: f64, gravity: &Vec3) -> Result<(), SimError> {
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
        let failed = |e| SimError::Dynamics(Box::new(e));
        self.free.iter_mut().for_each(|v| *v = 0.0);
        self.force.copy_from_slice(&self.coupling);
        // Newton–Euler is affine in the base's accelerations at given rates: when τG + τARM
        // hold the hand against all of the palm's motion and the palm does not turn, the bias
        // less the compensation is the velocity products alone, one pass at a still base.
        let cancelled = gravity_held && arm_held && real.angular_velocity == Vec3::zeros();
        let base = if cancelled {
            BaseMotion::at_rest(Vec3::zeros())
        } else {
            if gravity_held || arm_held {
                let compensation =
                    bias_torques(&self.dynamics, &mut self.data, &self.q, &held).map_err(failed)?;
                for (f, c) in self.force.iter_mut().zip(compensation) {
                    *f += c;
                }
            }
            real
        };
        let zeros = &self.free;
        let bias = rnea(
            &self.dynamics,
            &mut self.data,
            &self.q,
            &self.qd,
            zeros,
            &base,
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
            let factor = Cholesky::new(effective)
                .ok_or_else(|| SimError::MassMatrix(self.hand.name().to_string()))?;
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

    /// Forgets the last step's contact rows.
    pub(super) fn clear_rows(&mut self) {
        for block in &mut self.blocks {
            block.rows.clear();
            block.jacobian.clear();
        }
    }

    /// Adds this hand's side of contact row `row` at `point` of `bone` along `direction`, its
    /// velocity counted with `sign` (−1 for the hand the direction leaves, +1 for the one it
    /// enters); returns that signed velocity before contact (the palm's and the free rates').
    pub(super) fn add_row(
        &mut self,
        row: usize,
        bone: usize,
        point: &Point3,
        direction: &Vec3,
        sign: f64,
    ) -> f64 {
        let (origin, velocity, spin) = self.palm_velocity;
        let mut total = sign * (velocity + spin.cross(&(point - origin))).dot(direction);
        let Some(b) = self.block_of_bone[bone] else {
            return total;
        };
        let block = &mut self.blocks[b];
        block.rows.push(row);
        let start = block.jacobian.len();
        block.jacobian.resize(start + block.dofs.len(), 0.0);
        for &dof in &self.movers[bone] {
            let (origin, axis) = self.axes[dof];
            let entry = sign * axis.cross(&(point - origin)).dot(direction);
            block.jacobian[start + self.place_in_block[dof]] = entry;
            total += entry * self.free[dof];
        }
        total
    }

    /// Adds this hand's part of the Delassus matrix J M̃⁻¹ Jᵀ of `rows` rows (row-major).
    pub(super) fn add_delassus(&mut self, rows: usize, delassus: &mut [f64]) {
        for block in &mut self.blocks {
            let (size, count) = (block.dofs.len(), block.rows.len());
            if count == 0 {
                continue;
            }
            block.response.clear();
            block.response.extend_from_slice(&block.jacobian);
            // The row-major rows × dofs Jacobian is the column-major dofs × rows Jᵀ.
            if let Some(factor) = &block.factor {
                factor.solve_mut(&mut DMatrixViewMut::from_slice(
                    &mut block.response,
                    size,
                    count,
                ));
            }
            for (a, &ra) in block.rows.iter().enumerate() {
                let row = &block.jacobian[a * size..(a + 1) * size];
                for (b, &rb) in block.rows.iter().enumerate() {
                    let response = &block.response[b * size..(b + 1) * size];
                    let coupling: f64 = row.iter().zip(response).map(|(j, x)| j * x).sum();
                    delassus[ra * rows + rb] += coupling;
                }
            }
        }
    }

    /// The rates after the contact impulses `lambda`: the free rates plus M̃⁻¹ Jᵀ λ.
    pub(super) fn apply_impulses(&mut self, lambda: &[f64]) {
        self.qd.copy_from_slice(&self.free);
        for block in &self.blocks {
            let size = block.dofs.len();
            for (c, &r) in block.rows.iter().enumerate() {
                let response = &block.response[c * size..(c + 1) * size];
                for (i, &k) in block.dofs.iter().enumerate() {
                    self.qd[k] += response[i] * lambda[r];
                }
            }
        }
    }

    /// Integrates the angles over `dt` at the new rates and moves the root on.
    pub(super) fn integrate(&mut self, dt: f64) {
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use prehensile_control::bias_torques;

    /// Hands with every kind of joint: hinges, two-axis joints (human), ball joints.
    pub(crate) fn hands() -> Vec<(&'static str, HandModel)> {
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
            placed.place(1.0);
            let h = 1e-6;
            let mut moved = ReducedHand::new(&hand, &root, &q).unwrap();
            moved.qd.copy_from_slice(&rates);
            moved.next_root = root;
            moved.integrate(h);
            moved.place(1.0);
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

    /// With the palm accelerating but not turning and τG + τARM on, the free rates come from
    /// one Newton–Euler pass; they are those of the bias and the compensation computed apart.
    #[test]
    fn a_fully_compensated_bias_is_the_velocity_products_alone() {
        for (name, hand) in hands() {
            let n = hand.dof_count();
            let q: Vec<f64> = (0..n).map(|k| 0.2 * ((k % 4) as f64 - 1.5)).collect();
            let rates: Vec<f64> = (0..n).map(|k| ((k * 5 % 7) as f64 - 3.0) / 2.0).collect();
            let root = Transform::from_parts(
                Vec3::new(0.0, 0.1, 0.0).into(),
                Rotation::from_euler_angles(0.4, 0.2, -0.3),
            );
            let gravity = Vec3::new(0.0, 0.0, -9.81);
            let motion = FrameMotion {
                linear_acceleration: Vec3::new(3.0, -2.0, 1.0),
                ..FrameMotion::at_rest(Point3::origin())
            };
            let free = |compensate: (bool, bool)| {
                let mut h = ReducedHand::new(&hand, &root, &q).unwrap();
                h.qd.copy_from_slice(&rates);
                h.palm_motion = motion;
                h.compensate = compensate;
                h.free_velocity(1e-3, &gravity).unwrap();
                (h.free.clone(), h.force.clone(), h.bias.clone())
            };
            let (shortcut, _, _) = free((true, true));
            // The same through both passes: the bias under the real motion and gravity less
            // the compensation, rebuilt here from the uncompensated run's bias.
            let (_, _, real_bias) = free((false, false));
            let palm = root * hand.bones()[0].rest;
            let to_palm = palm.rotation.inverse();
            let base = BaseMotion {
                linear_acceleration_minus_gravity: to_palm * (motion.linear_acceleration - gravity),
                ..BaseMotion::at_rest(Vec3::zeros())
            };
            let model = DynamicsModel::new(&hand);
            let mut data = model.data();
            let held = bias_torques(&model, &mut data, &q, &base).unwrap().to_vec();
            let mass = crba(&model, &mut data, &q).unwrap().clone();
            let dt = 1e-3;
            // Springs are zero: M q̇⁺ = M q̇ + dt (held − bias).
            let rhs = &mass * nalgebra::DVector::from_column_slice(&rates)
                + nalgebra::DVector::from_fn(n, |k, _| dt * (held[k] - real_bias[k]));
            let expected = mass.cholesky().unwrap().solve(&rhs);
            let error = (0..n)
                .map(|k| (shortcut[k] - expected[k]).abs())
                .fold(0.0, f64::max);
            assert!(error < 1e-9, "{name}: off by {error}");
        }
    }
}

//! The rapier engine: every bone a rigid body joined to its parent by impulse joints whose
//! motors carry the controller's springs ([`crate::ArticulatedHand`]), the object a dynamic body
//! with a convex collision shape ([`crate::ObjectBody`]).

use prehensile_core::math::{Transform, Vec3};
use prehensile_core::{HandModel, ObjectModel};
use rapier3d_f64::prelude::{Group, PhysicsWorld, RigidBody};

use crate::error::{Divergence, SimError};
use crate::rapier::articulated_hand::ArticulatedHand;
use crate::rapier::object_body::ObjectBody;
use crate::world::contacts::Contacts;
use crate::world::convert;
use crate::world::engine::{bone_ran_away, runaway, HandDrive, PhysicsEngine};
use crate::world::holding_wrench::FrameMotion;
use crate::world::settings::Settings;

/// Hands and an object in a rapier world.
pub(crate) struct RapierWorld {
    world: PhysicsWorld,
    hands: Vec<ArticulatedHand>,
    object: Option<ObjectBody>,
    friction: f64,
    density: f64,
    /// [`crate::RapierSettings::joint_gap_limit`].
    joint_gap_limit: f64,
}

impl RapierWorld {
    /// An empty world with `settings`' step, gravity and solver.
    pub fn new(settings: &Settings) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = convert::vector(&settings.gravity);
        world.integration_parameters.dt = settings.dt;
        // Hands are centimetre-sized: tolerances scale with the length unit.
        world.integration_parameters.length_unit = 0.01;
        world.integration_parameters.num_solver_iterations = settings.rapier.solver_iterations;
        world.integration_parameters.num_internal_pgs_iterations = settings.rapier.inner_iterations;
        // Joint chains converge far better when joint impulses carry over between steps.
        world.integration_parameters.warmstart_joints = true;
        // No CCD: rapier's automatic CCD sweeps fast bodies against fixed colliders only, and
        // this world has none (the palm is kinematic, the object dynamic), so its per-body
        // checks were 3–4% of a step for nothing.
        world.integration_parameters.max_ccd_substeps = 0;
        Self {
            world,
            hands: Vec::new(),
            object: None,
            friction: settings.friction,
            density: settings.object_density,
            joint_gap_limit: settings.rapier.joint_gap_limit,
        }
    }
}

fn runaway_body(b: &RigidBody) -> bool {
    let p = b.position();
    let finite = p.translation.is_finite() && p.rotation.is_finite();
    runaway(
        finite,
        &convert::vec3(b.linvel()),
        &convert::vec3(b.angvel()),
    )
}

impl PhysicsEngine for RapierWorld {
    fn add_hand(
        &mut self,
        hand: &HandModel,
        root: &Transform,
        start: &[f64],
    ) -> Result<(), SimError> {
        let group = Group::from_bits_truncate(Group::GROUP_2.bits() << self.hands.len());
        self.hands.push(ArticulatedHand::insert(
            hand,
            &mut self.world,
            root,
            start,
            group,
            self.friction,
        ));
        Ok(())
    }

    fn add_object(
        &mut self,
        object: &ObjectModel,
        pose: &Transform,
        fixed: bool,
    ) -> Result<f64, SimError> {
        let body = ObjectBody::insert(
            &mut self.world,
            object,
            pose,
            self.density,
            self.friction,
            fixed,
        )?;
        Ok(self.object.insert(body).mass)
    }

    fn let_go_object(&mut self) {
        if let Some(o) = &self.object {
            o.let_go(&mut self.world);
        }
    }

    fn object_pose(&self) -> Option<Transform> {
        self.object.as_ref().map(|o| o.pose(&self.world))
    }

    fn palm(&self, i: usize) -> Transform {
        convert::transform(self.world.bodies[self.hands[i].root_body()].position())
    }

    fn joint_state(&self, i: usize, q: &mut [f64], qd: &mut [f64]) {
        self.hands[i].state(&self.world, q, qd);
    }

    fn drive(&mut self, i: usize, drive: &HandDrive) -> Result<(), SimError> {
        let body = &self.hands[i];
        body.drive(&mut self.world, drive.springs, drive.q, drive.coupling);
        if drive.compensate_gravity || drive.compensate_arm {
            let palm = if drive.compensate_arm {
                drive.palm
            } else {
                FrameMotion::at_rest(drive.palm.origin)
            };
            let gravity = if drive.compensate_gravity {
                convert::vec3(self.world.gravity)
            } else {
                Vec3::zeros()
            };
            body.hold(&mut self.world, &palm, &gravity);
        }
        body.move_root(&mut self.world, &drive.next_root);
        Ok(())
    }

    fn step(&mut self) -> Result<(), SimError> {
        self.world.step();
        Ok(())
    }

    fn contacts(&self, i: usize) -> Contacts {
        let body = &self.hands[i];
        let mut c = Contacts {
            bone_forces: vec![0.0; body.bone_bodies().len()],
            ..Contacts::default()
        };
        let dt = self.world.integration_parameters.dt;
        for (&collider, &bone) in body.colliders().iter().zip(body.collider_bones()) {
            let mut touching = false;
            for pair in self.world.narrow_phase.contact_pairs_with(collider) {
                for manifold in pair.manifolds() {
                    for point in &manifold.points {
                        if point.dist <= 0.0 {
                            c.penetration = c.penetration.max(-point.dist);
                        }
                        if point.data.impulse > 0.0 {
                            touching = true;
                            c.force += point.data.impulse / dt;
                            c.bone_forces[bone] += point.data.impulse / dt;
                        }
                    }
                }
            }
            c.touching += usize::from(touching);
        }
        c
    }

    fn penetration(&self, i: usize) -> f64 {
        let body = &self.hands[i];
        body.colliders()
            .iter()
            .flat_map(|&collider| self.world.narrow_phase.contact_pairs_with(collider))
            .flat_map(|pair| pair.manifolds())
            .flat_map(|manifold| &manifold.points)
            .fold(0.0, |deepest: f64, point| deepest.max(-point.dist))
    }

    fn diverged(&self) -> Option<Divergence> {
        for (i, h) in self.hands.iter().enumerate() {
            let hand = h.model();
            if let Some((k, gap)) = h.widest_joint_gap(&self.world) {
                if gap > self.joint_gap_limit {
                    return Some(Divergence::JointGap {
                        hand: i,
                        bone: hand.bones()[k].name.clone(),
                        gap,
                    });
                }
            }
            for (k, body) in h.bone_bodies().iter().enumerate() {
                if runaway_body(&self.world.bodies[*body]) {
                    return Some(bone_ran_away(hand, i, k));
                }
            }
        }
        match &self.object {
            Some(o) if runaway_body(&self.world.bodies[o.body]) => Some(Divergence::Object),
            _ => None,
        }
    }

    fn bone_frames(&self, i: usize, out: &mut Vec<Transform>) {
        out.clear();
        out.extend(
            self.hands[i]
                .bone_bodies()
                .iter()
                .map(|b| convert::transform(self.world.bodies[*b].position())),
        );
    }
}

//! A simulation: hands, each driven by its own grasp controller along a prescribed arm
//! trajectory, and at most one object, in a world with gravity and friction stepped by one of
//! the [`Engine`]s. Every step reads each hand's joint state, advances its state machine, sets
//! its joint springs (τP + τA) and compensation (τG + τARM), steps the world, and checks that
//! nothing diverged.

use prehensile_control::{
    ball_joint_coupling, joint_springs, outboard_inertia_into, ControllerState, DynamicsData,
    DynamicsError, DynamicsModel, GraspController, GraspState, JointSpring, Setpoint,
};
use prehensile_core::animation::Keyframe;
use prehensile_core::math::{Point3, Rotation, Transform};
use prehensile_core::{HandModel, ObjectModel};

use crate::error::{Divergence, SimError};
use crate::rapier::articulated_hand::check_hand;
use crate::rapier::world::RapierWorld;
use crate::reduced::world::ReducedWorld;
use crate::world::arm_trajectory::ArmTrajectory;
use crate::world::contacts::Contacts;
use crate::world::engine::{HandDrive, PhysicsEngine};
use crate::world::settings::{Engine, Settings};

/// What a hand's controller measures its distance to (the paper's "distance from hand to
/// object", which drives the state machine).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DistanceTo {
    /// Always this far (no object: the state machine stays where the distance puts it).
    Constant(f64),
    /// The distance of the root's origin from this point in the object's frame (the world's
    /// without an object): the root's place in the grasp. The hand reaches the object
    /// (distance 0, D0) when the arm has brought it to its grasp; the place moves with the
    /// object, so a held object stays at distance ≈ 0 and a dropped one moves away.
    GraspPlace(Point3),
    /// The distance between this hand's root origin and another hand's, minus `contact` (the
    /// root distance at which the hands meet).
    OtherHand {
        /// Index of the other hand.
        other: usize,
        /// Metres.
        contact: f64,
    },
}

/// A hand to simulate.
#[derive(Debug, Clone)]
pub struct HandSetup {
    /// The hand model (with masses on every moving bone).
    pub hand: HandModel,
    /// Its controller.
    pub controller: GraspController,
    /// Where the arm takes it.
    pub arm: ArmTrajectory,
    /// Joint angles at the start.
    pub start: Vec<f64>,
    /// What the controller's distance is measured to.
    pub distance: DistanceTo,
    /// When the release command is given, seconds.
    pub release_at: Option<f64>,
    /// Gravity compensation τG.
    pub compensate_gravity: bool,
    /// Arm-motion compensation τARM.
    pub compensate_arm: bool,
    /// Manual setpoint changes `(time, setpoint or None for the state machine)` (Fig. 7).
    pub manual: Vec<(f64, Option<Setpoint>)>,
}

/// A change of a hand's controller state.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StateChange {
    /// Seconds.
    pub time: f64,
    /// Which hand.
    pub hand: usize,
    /// The new state.
    pub state: String,
    /// The distance that caused it, metres.
    pub distance: f64,
}

struct SimHand {
    setup: HandSetup,
    q: Vec<f64>,
    qd: Vec<f64>,
    palm_local: Transform,
    frames: Vec<Keyframe>,
    /// The hand's dynamics, built once, and their buffers.
    dynamics: DynamicsModel,
    dynamics_data: DynamicsData,
    /// What its controller changes as it runs.
    control: ControllerState,
    /// This step's joint springs and ball-joint cross torques.
    springs: Vec<JointSpring>,
    coupling: Vec<f64>,
}

/// The most hands a world takes.
const MAX_HANDS: usize = 30;

/// A running simulation.
pub struct Simulation {
    settings: Settings,
    engine: Box<dyn PhysicsEngine>,
    hands: Vec<SimHand>,
    /// The object's mass, kg, once it is added.
    object_mass: Option<f64>,
    /// The bone frames of a recorded hand (kept to reuse).
    frames: Vec<Transform>,
    object_frames: Vec<Transform>,
    time: f64,
    steps: u64,
    next_record: f64,
    timeline: Vec<StateChange>,
    max_penetration: f64,
}

impl Simulation {
    /// An empty world.
    pub fn new(settings: Settings) -> Result<Self, SimError> {
        settings.check()?;
        let engine: Box<dyn PhysicsEngine> = match settings.engine {
            Engine::Rapier => Box::new(RapierWorld::new(&settings)),
            Engine::Reduced => Box::new(ReducedWorld::new(&settings)),
        };
        Ok(Self {
            settings,
            engine,
            hands: Vec::new(),
            object_mass: None,
            frames: Vec::new(),
            object_frames: Vec::new(),
            time: 0.0,
            steps: 0,
            next_record: 0.0,
            timeline: Vec::new(),
            max_penetration: 0.0,
        })
    }

    /// Adds a hand; returns its index.
    pub fn add_hand(&mut self, setup: HandSetup) -> Result<usize, SimError> {
        let hand = &setup.hand;
        check_hand(hand)?;
        let n = hand.dof_count();
        let s = &setup.controller.setpoints;
        let lengths_ok = setup.start.len() == n
            && s.neutral.len() == n
            && s.limits.len() == n
            && s.positions
                .values()
                .chain(s.velocities.values())
                .all(|v| v.len() == n);
        if !lengths_ok {
            return Err(SimError::ControllerLength {
                hand: hand.name().to_string(),
                dofs: n,
            });
        }
        let mut numbers = s
            .positions
            .values()
            .chain(s.velocities.values())
            .chain(std::iter::once(&s.neutral))
            .chain(std::iter::once(&setup.start))
            .flatten()
            .chain(s.limits.iter().flatten());
        if let Some(k) = numbers.position(|v| !v.is_finite()) {
            return Err(SimError::ControllerNotFinite {
                hand: hand.name().to_string(),
                index: k,
            });
        }
        if self.hands.len() >= MAX_HANDS {
            return Err(SimError::TooManyHands(MAX_HANDS));
        }
        self.engine
            .add_hand(hand, &setup.arm.at(0.0), &setup.start)?;
        let palm_local = hand.bones()[0].rest;
        let dynamics = DynamicsModel::new(hand);
        self.hands.push(SimHand {
            control: ControllerState::default(),
            dynamics_data: dynamics.data(),
            dynamics,
            springs: vec![JointSpring::SLACK; n],
            coupling: vec![0.0; n],
            q: setup.start.clone(),
            qd: vec![0.0; n],
            setup,
            palm_local,
            frames: Vec::new(),
        });
        Ok(self.hands.len() - 1)
    }

    /// Adds the object at `pose`; `fixed` holds it until [`Simulation::let_go_object`].
    /// Returns its mass, kg.
    pub fn add_object(
        &mut self,
        object: &ObjectModel,
        pose: &Transform,
        fixed: bool,
    ) -> Result<f64, SimError> {
        let mass = self.engine.add_object(object, pose, fixed)?;
        self.object_mass = Some(mass);
        Ok(mass)
    }

    /// Lets a fixed object go.
    pub fn let_go_object(&mut self) {
        self.engine.let_go_object();
    }

    /// Seconds simulated.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Joint angles of hand `i`.
    pub fn joint_angles(&self, i: usize) -> &[f64] {
        &self.hands[i].q
    }

    /// The controller state of hand `i`.
    pub fn state(&self, i: usize) -> GraspState {
        self.hands[i].control.state
    }

    /// The controller of hand `i` (to change α while running).
    pub fn controller_mut(&mut self, i: usize) -> &mut GraspController {
        &mut self.hands[i].setup.controller
    }

    /// What hand `i`'s controller changes as it runs (its state; a manual setpoint, which the
    /// setup's `manual` changes also set).
    pub fn controller_state_mut(&mut self, i: usize) -> &mut ControllerState {
        &mut self.hands[i].control
    }

    /// The object's pose, if there is one.
    pub fn object_pose(&self) -> Option<Transform> {
        self.engine.object_pose()
    }

    /// The object's mass, kg, if there is an object.
    pub fn object_mass(&self) -> Option<f64> {
        self.object_mass
    }

    /// Hand `i`'s root placement now.
    pub fn root(&self, i: usize) -> Transform {
        self.engine.palm(i) * self.hands[i].palm_local.inverse()
    }

    /// The world frame of hand `i`'s root bone (its palm) now.
    pub fn palm_frame(&self, i: usize) -> Transform {
        self.engine.palm(i)
    }

    /// What hand `i`'s controller asked of the engine for the last step: a linear spring per
    /// degree of freedom (τP + τA) and the ball joints' cross torques.
    pub fn joint_springs(&self, i: usize) -> (&[JointSpring], &[f64]) {
        (&self.hands[i].springs, &self.hands[i].coupling)
    }

    /// The state machine's changes so far.
    pub fn timeline(&self) -> &[StateChange] {
        &self.timeline
    }

    /// Deepest penetration between any hand and the object or another hand so far, metres.
    pub fn max_penetration(&self) -> f64 {
        self.max_penetration
    }

    /// The recorded keyframes of hand `i` and of the object (at `record_fps`).
    pub fn recording(&self, i: usize) -> (&[Keyframe], &[Transform]) {
        (&self.hands[i].frames, &self.object_frames)
    }

    /// The hand model of hand `i`.
    pub fn hand_model(&self, i: usize) -> &HandModel {
        &self.hands[i].setup.hand
    }

    /// Contacts of hand `i` with everything outside it, this step.
    pub fn contacts(&self, i: usize) -> Contacts {
        self.engine.contacts(i)
    }

    fn distance(&self, i: usize) -> f64 {
        let origin = |k: usize| self.root(k).translation.vector;
        match self.hands[i].setup.distance {
            DistanceTo::Constant(d) => d,
            DistanceTo::GraspPlace(p) => {
                let place = self.object_pose().map_or(p, |o| o * p);
                let d = (origin(i) - place.coords).norm();
                // The arm arrives exactly; rounding must not keep the state machine from D0.
                if d < 1e-6 {
                    0.0
                } else {
                    d
                }
            }
            DistanceTo::OtherHand { other, contact } => {
                ((origin(i) - origin(other)).norm() - contact).max(0.0)
            }
        }
    }

    /// Advances one step.
    pub fn step(&mut self) -> Result<(), SimError> {
        self.drive_hands()?;
        self.engine.step()?;
        self.time += self.settings.dt;
        self.steps += 1;
        self.check_step()
    }

    /// Before the world steps: records at the recording rate, reads every hand's joint state,
    /// advances its state machine and sets its joint springs and holding wrenches.
    fn drive_hands(&mut self) -> Result<(), SimError> {
        let dt = self.settings.dt;
        let next = self.time + dt;
        if self.time >= self.next_record - 1e-12 {
            self.record();
            self.next_record += 1.0 / self.settings.record_fps;
        }
        for i in 0..self.hands.len() {
            let distance = self.distance(i);
            let h = &mut self.hands[i];
            self.engine.joint_state(i, &mut h.q, &mut h.qd);
            for &(at, choice) in &h.setup.manual {
                if at <= self.time && at > self.time - dt {
                    h.control.manual_setpoint = choice;
                }
            }
            let release = h.setup.release_at.is_some_and(|t| self.time >= t);
            let before = h.control.state;
            let blend = h
                .setup
                .controller
                .advance(&mut h.control, distance, release);
            if h.control.state != before {
                self.timeline.push(StateChange {
                    time: self.time,
                    hand: i,
                    state: format!("{:?}", h.control.state),
                    distance,
                });
            }
            let c = &h.setup.controller;
            let time = self.time;
            let inertia = outboard_inertia_into(&h.dynamics, &mut h.dynamics_data, &h.q)
                .map_err(|e| diverged(time, i, e))?;
            joint_springs(
                inertia,
                &h.q,
                &c.setpoints,
                &blend,
                &c.gains,
                c.active,
                &mut h.springs,
            );
            ball_joint_coupling(inertia, &h.springs, &h.q, &h.qd, &mut h.coupling);
            let h = &self.hands[i];
            self.engine.drive(
                i,
                &HandDrive {
                    q: &h.q,
                    springs: &h.springs,
                    coupling: &h.coupling,
                    palm: h.setup.arm.frame_motion(self.time, &h.palm_local),
                    compensate_gravity: h.setup.compensate_gravity,
                    compensate_arm: h.setup.compensate_arm,
                    next_root: h.setup.arm.at(next),
                },
            )?;
        }
        Ok(())
    }

    /// After the world stepped: the deepest penetration so far, and whether anything diverged.
    fn check_step(&mut self) -> Result<(), SimError> {
        for i in 0..self.hands.len() {
            self.max_penetration = self.max_penetration.max(self.engine.penetration(i));
        }
        match self.engine.diverged() {
            Some(what) => Err(SimError::Diverged {
                time: self.time,
                what,
            }),
            None => Ok(()),
        }
    }

    fn record(&mut self) {
        for (i, h) in self.hands.iter_mut().enumerate() {
            self.engine.bone_frames(i, &mut self.frames);
            let frames = &self.frames;
            let bones = h.setup.hand.bones();
            let rotations = bones
                .iter()
                .enumerate()
                .map(|(k, bone)| match bone.parent {
                    None => Rotation::identity(),
                    Some(p) => ((frames[p] * bone.rest).inverse() * frames[k]).rotation,
                })
                .collect();
            h.frames.push(Keyframe {
                time: self.time,
                root: frames[0] * h.palm_local.inverse(),
                rotations,
            });
        }
        if let Some(pose) = self.object_pose() {
            self.object_frames.push(pose);
        }
    }
}

fn diverged(time: f64, hand: usize, error: DynamicsError) -> SimError {
    SimError::Diverged {
        time,
        what: Divergence::Dynamics {
            hand,
            error: Box::new(error),
        },
    }
}

#[cfg(test)]
mod tests {
    //! Our part of a step allocates nothing once running, beyond rapier's change tracking
    //! (rapier's own `PhysicsWorld::step` allocates about ten times a step inside its pipeline;
    //! that is not ours to change).

    use prehensile_core::{shapes, ObjectModel};
    use prehensile_testkit::allocation_count::{
        allocations_on_this_thread as allocations, CountingAllocator,
    };

    use crate::scenarios::held_still;
    use crate::{Engine, Settings, Simulation};

    #[global_allocator]
    static COUNT: CountingAllocator = CountingAllocator;

    /// The Shadow hand holding the sphere still on `engine` at 1 ms, not recording (keyframes
    /// are output, not step work).
    fn shadow_holding_the_sphere(engine: Engine) -> Simulation {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/hands/shadow_hand/reach.xml"
        );
        let hand = prehensile_formats::load_hand(std::path::Path::new(path)).unwrap();
        let sphere = shapes::builtin_object("sphere").unwrap();
        let sphere = ObjectModel::new("sphere", sphere, None).unwrap();
        let settings = Settings {
            record_fps: 1e-3,
            engine,
            ..Settings::for_step(0.001)
        };
        held_still(&hand, &sphere, settings).unwrap()
    }

    #[test]
    fn our_part_of_a_step_allocates_nothing() {
        let mut sim = shadow_holding_the_sphere(Engine::Rapier);
        sim.step().unwrap();
        let mut ours = 0;
        for _ in 0..100 {
            let before = allocations();
            sim.drive_hands().unwrap();
            let driven = allocations();
            sim.engine.step().unwrap();
            sim.time += sim.settings.dt;
            let stepped = allocations();
            sim.check_step().unwrap();
            ours += driven - before + allocations() - stepped;
        }
        assert!(
            sim.contacts(0).touching > 0,
            "the hand let go of the sphere"
        );
        // What is left is rapier's change tracking: setting 22 joint motors and clearing the
        // bodies' forces pushes their handles onto lists rapier empties every step (3–4
        // allocations a step, measured). Before the dynamics had a model and data, the step
        // built new vectors of its own every time (links, composite inertias, the outboard
        // inertia, springs, coupling torques, bone frames, contact forces).
        assert!(
            ours <= 4 * 100,
            "100 steps allocated {ours} times outside rapier's step"
        );
    }

    #[test]
    fn a_whole_step_of_the_reduced_engine_allocates_nothing() {
        let mut sim = shadow_holding_the_sphere(Engine::Reduced);
        // The contacts' buffers grow to their most rows within the first steps.
        for _ in 0..100 {
            sim.step().unwrap();
        }
        let before = allocations();
        for _ in 0..100 {
            sim.step().unwrap();
        }
        let allocated = allocations() - before;
        assert!(
            sim.contacts(0).touching > 0,
            "the hand let go of the sphere"
        );
        assert_eq!(allocated, 0, "100 steps allocated {allocated} times");
    }
}

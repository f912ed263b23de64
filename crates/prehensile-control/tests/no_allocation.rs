//! The dynamics and the controller allocate nothing once their model and data are built: a
//! counting global allocator around inverse dynamics, the mass matrix and the controller's
//! torques. (The simulation step's own check is a unit test in `prehensile-sim`.)

use prehensile_control::{
    crba, rnea, BaseMotion, ControllerState, DynamicsModel, Gains, GraspController, PerSetpoint,
};
use prehensile_core::math::Vec3;
use prehensile_testkit::allocation_count::{allocations_on_this_thread, CountingAllocator};

#[global_allocator]
static COUNT: CountingAllocator = CountingAllocator;

fn allocations_in(f: impl FnOnce()) -> usize {
    let before = allocations_on_this_thread();
    f();
    allocations_on_this_thread() - before
}

#[test]
fn the_dynamics_and_the_controller_allocate_nothing() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let model = DynamicsModel::new(&hand);
    let mut data = model.data();
    let n = hand.dof_count();
    let (q, qd, qdd) = (vec![0.2; n], vec![0.5; n], vec![1.0; n]);
    let base = BaseMotion::at_rest(Vec3::new(0.0, 0.0, -9.81));
    let setpoints = prehensile_control::Setpoints {
        positions: PerSetpoint::from_fn(|s| vec![0.1 * s.index() as f64; n]),
        velocities: PerSetpoint::from_fn(|_| vec![0.0; n]),
        neutral: vec![0.0; n],
        limits: vec![[-1.0, 1.0]; n],
    };
    let controller = GraspController::new(Gains::grasp(), setpoints);
    let mut state = ControllerState::default();
    let mut tau = vec![0.0; n];
    // Warm up, then count.
    let mut run = || {
        rnea(&model, &mut data, &q, &qd, &qdd, &base).unwrap();
        crba(&model, &mut data, &q).unwrap();
        controller
            .torques(
                &mut state, &model, &mut data, &q, &qd, &base, 0.02, false, true, &mut tau,
            )
            .unwrap();
    };
    run();
    let counted = allocations_in(|| {
        for _ in 0..10 {
            run()
        }
    });
    assert_eq!(counted, 0, "the dynamics allocated {counted} times");
    assert!(tau.iter().any(|t| *t != 0.0));
}

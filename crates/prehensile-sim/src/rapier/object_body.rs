//! An object as a dynamic rigid body.
//!
//! Collision shape: the convex hull when the object is convex (its hull's volume within 2% of
//! the mesh's), else a convex decomposition (parry's V-HACD). Not the exact triangle mesh: a
//! triangle mesh is a shell, so a capsule pushed through a wall in one step stays inside with
//! nothing pushing it out, while convex parts are solid and always push penetrating fingers back
//! out. The decomposition's error is bounded by its voxel size (the object's extent / 64);
//! mass properties come from the exact mesh, not the parts.

use prehensile_core::math::Transform;
use prehensile_core::ObjectModel;
use rapier3d_f64::parry::transformation::vhacd::VHACDParameters;
use rapier3d_f64::prelude::{
    ColliderBuilder, ColliderHandle, Group, InteractionGroups, InteractionTestMode, PhysicsWorld,
    RigidBodyBuilder, RigidBodyHandle, RigidBodyType, SharedShape, Vector,
};

use crate::error::SimError;
use crate::world::convert;
use crate::world::object_mass::solid_mass_properties;

/// Collision group of objects (hands use the bits above it).
pub const OBJECT_GROUP: Group = Group::GROUP_1;

/// How the object's collision shape was made.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum ObjectShape {
    /// The object is convex: its hull.
    ConvexHull,
    /// A convex decomposition into this many parts.
    ConvexDecomposition(usize),
}

/// An object in a rapier world.
#[derive(Debug, Clone)]
pub struct ObjectBody {
    /// The body.
    pub body: RigidBodyHandle,
    /// Its collider.
    pub collider: ColliderHandle,
    /// How its collision shape was made.
    pub shape: ObjectShape,
    /// Mass, kg.
    pub mass: f64,
}

/// The collision shape of an object (hull or decomposition) and how it was made.
pub fn object_shape(object: &ObjectModel) -> Result<(SharedShape, ObjectShape), SimError> {
    let mesh = object.mesh();
    let points: Vec<Vector> = mesh.vertices.iter().map(convert::point).collect();
    let hull = SharedShape::convex_hull(&points)
        .ok_or_else(|| SimError::FlatObject(object.name().to_string()))?;
    let hull_volume = hull.mass_properties(1.0).mass();
    if hull_volume <= 1.02 * object.volume() {
        return Ok((hull, ObjectShape::ConvexHull));
    }
    let params = VHACDParameters {
        resolution: 64,
        concavity: 0.005,
        max_convex_hulls: 32,
        ..VHACDParameters::default()
    };
    let shape = SharedShape::convex_decomposition_with_params(&points, &mesh.triangles, &params);
    let parts = shape.as_compound().map_or(1, |c| c.shapes().len());
    Ok((shape, ObjectShape::ConvexDecomposition(parts)))
}

impl ObjectBody {
    /// Adds `object` at `pose` with the given density (kg/m³) and friction; `fixed` holds it in
    /// place (a kinematic body) until [`ObjectBody::let_go`].
    pub fn insert(
        world: &mut PhysicsWorld,
        object: &ObjectModel,
        pose: &Transform,
        density: f64,
        friction: f64,
        fixed: bool,
    ) -> Result<Self, SimError> {
        let (shape, kind) = object_shape(object)?;
        let props = solid_mass_properties(object, density)?;
        let kind_of_body = if fixed {
            RigidBodyType::KinematicPositionBased
        } else {
            RigidBodyType::Dynamic
        };
        let body = world.bodies.insert(
            RigidBodyBuilder::new(kind_of_body)
                .pose(convert::pose(pose))
                .additional_mass_properties(props)
                .can_sleep(false),
        );
        let collider = world.colliders.insert_with_parent(
            ColliderBuilder::new(shape)
                .density(0.0)
                .friction(friction)
                .collision_groups(InteractionGroups::new(
                    OBJECT_GROUP,
                    Group::ALL,
                    InteractionTestMode::And,
                )),
            body,
            &mut world.bodies,
        );
        Ok(Self {
            body,
            collider,
            shape: kind,
            mass: props.mass(),
        })
    }

    /// Lets a fixed object go: from now on it is dynamic, under gravity and contacts.
    pub fn let_go(&self, world: &mut PhysicsWorld) {
        if let Some(b) = world.bodies.get_mut(self.body) {
            b.set_body_type(RigidBodyType::Dynamic, true);
        }
    }

    /// The object's pose.
    pub fn pose(&self, world: &PhysicsWorld) -> Transform {
        convert::transform(world.bodies[self.body].position())
    }
}

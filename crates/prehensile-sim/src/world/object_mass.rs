//! An object's mass properties as a solid, from its exact mesh (not its collision shape), for
//! either engine.

use prehensile_core::ObjectModel;
use rapier3d_f64::prelude::{MassProperties, SharedShape};

use crate::error::SimError;
use crate::world::convert;

/// The exact mass properties of `object` as a solid of `density` kg/m³ (the closed mesh, not
/// its collision shape), in the object's frame.
pub(crate) fn solid_mass_properties(
    object: &ObjectModel,
    density: f64,
) -> Result<MassProperties, SimError> {
    if !(density.is_finite() && density > 0.0) {
        return Err(SimError::OutOfRange {
            setting: "object_density",
            value: density,
            low: 1e-3,
            high: 1e5,
        });
    }
    let mesh = object.mesh();
    let solid = SharedShape::trimesh(
        mesh.vertices.iter().map(convert::point).collect(),
        mesh.triangles.clone(),
    )
    .map_err(|_| SimError::FlatObject(object.name().to_string()))?;
    Ok(solid.mass_properties(density))
}

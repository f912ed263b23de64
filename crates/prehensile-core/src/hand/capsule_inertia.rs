//! Mass properties of solid capsules, for hands whose files give no masses (TOML hands): each
//! bone weighs what its capsules would at the density of soft tissue.

use nalgebra::Matrix3;

use super::model::Inertial;
use crate::math::{Point3, Rotation, Vec3};

/// Density of soft tissue, kg/m³ (hands are mostly muscle, fat and bone: about 1.1 g/cm³).
pub const TISSUE_DENSITY: f64 = 1100.0;

/// Mass, centre of mass and inertia (about the centre of mass) of solid capsules `(a, b, r)` of
/// uniform `density`, combined; `None` for no capsules.
pub fn capsules_inertial(capsules: &[(Point3, Point3, f64)], density: f64) -> Option<Inertial> {
    let parts: Vec<(f64, Point3, Matrix3<f64>)> = capsules
        .iter()
        .map(|(a, b, r)| {
            let axis = b - a;
            let length = axis.norm();
            let cylinder = density * std::f64::consts::PI * r * r * length;
            let hemisphere = density * 2.0 / 3.0 * std::f64::consts::PI * r * r * r;
            let along = cylinder * r * r / 2.0 + 2.0 * hemisphere * 2.0 * r * r / 5.0;
            let across = cylinder * (length * length / 12.0 + r * r / 4.0)
                + 2.0
                    * hemisphere
                    * (2.0 * r * r / 5.0 + length * length / 4.0 + 3.0 * length * r / 8.0);
            // Local frame: z along the axis.
            let local = Matrix3::from_diagonal(&Vec3::new(across, across, along));
            let turn = Rotation::rotation_between(&Vec3::z(), &axis).unwrap_or_else(|| {
                // Zero length (a sphere) or antiparallel: any frame does for the symmetric case.
                if axis.norm() > 0.0 {
                    Rotation::from_axis_angle(&Vec3::x_axis(), std::f64::consts::PI)
                } else {
                    Rotation::identity()
                }
            });
            let r3 = turn.to_rotation_matrix().into_inner();
            (
                cylinder + 2.0 * hemisphere,
                nalgebra::center(a, b),
                r3 * local * r3.transpose(),
            )
        })
        .collect();
    let mass: f64 = parts.iter().map(|p| p.0).sum();
    if parts.is_empty() || mass <= 0.0 {
        return None;
    }
    let com = Point3::from(
        parts
            .iter()
            .fold(Vec3::zeros(), |acc, p| acc + p.1.coords * p.0)
            / mass,
    );
    // Parallel axis theorem to the combined centre of mass.
    let inertia = parts.iter().fold(Matrix3::zeros(), |acc, (m, c, i)| {
        let d = c - com;
        acc + i + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * *m
    });
    Some(Inertial {
        mass,
        center_of_mass: com,
        inertia,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zero_length_capsule_is_a_solid_sphere_and_mass_adds_up() {
        let r = 0.01;
        let sphere = capsules_inertial(&[(Point3::origin(), Point3::origin(), r)], 1000.0).unwrap();
        let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        assert!((sphere.mass - m).abs() < 1e-15);
        assert!((sphere.inertia[(0, 0)] - 0.4 * m * r * r).abs() < 1e-15);
        // A long thin capsule: close to a rod, m L² / 12 across.
        let rod = capsules_inertial(
            &[(
                Point3::new(0.0, 0.0, -0.5),
                Point3::new(0.0, 0.0, 0.5),
                1e-4,
            )],
            1000.0,
        )
        .unwrap();
        assert!((rod.inertia[(0, 0)] / (rod.mass / 12.0) - 1.0).abs() < 1e-3);
        // Two capsules: masses add, centre of mass between them.
        let two = capsules_inertial(
            &[
                (
                    Point3::new(-1.0, 0.0, 0.0),
                    Point3::new(-1.0, 0.0, 0.1),
                    0.01,
                ),
                (Point3::new(1.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.1), 0.01),
            ],
            1000.0,
        )
        .unwrap();
        assert!(two.center_of_mass.x.abs() < 1e-12);
    }
}

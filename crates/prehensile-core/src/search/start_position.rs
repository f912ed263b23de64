//! The starting hand position (§5.6.1, §6.5.2): the nearest hook, the hook's z axis along
//! d = hook − shoulder, and the palm toward the hook from above.

use crate::math::{Point3, Rotation, Vec3};

/// The hook nearest to the shoulder (§6.5.2 step 1); `None` if there are no hooks.
pub fn nearest_hook(hooks: &[Point3], shoulder: &Point3) -> Option<Point3> {
    hooks
        .iter()
        .min_by(|a, b| (*a - shoulder).norm().total_cmp(&(*b - shoulder).norm()))
        .copied()
}

/// Hook rotation of the starting position: z (fingers) along `hook − shoulder`, y (out of the
/// palm) as close to `−up` as possible, so the hand comes from above with the palm toward the
/// hook. `None` when the shoulder is on the hook.
pub fn start_rotation(hook: &Point3, shoulder: &Point3, up: &Vec3) -> Option<Rotation> {
    let d = hook - shoulder;
    if d.norm() < 1e-6 || !d.iter().all(|c| c.is_finite()) {
        return None;
    }
    let z = d.normalize();
    let mut y = -up - z * (-up).dot(&z);
    if y.norm() < 1e-6 {
        // Reaching straight down or up: any palm direction across z will do; pick one stably.
        let helper = if z.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        };
        y = helper - z * helper.dot(&z);
    }
    let y = y.normalize();
    let x = y.cross(&z);
    let m = nalgebra::Matrix3::from_columns(&[x, y, z]);
    Some(Rotation::from_rotation_matrix(
        &nalgebra::Rotation3::from_matrix_unchecked(m),
    ))
}

/// The default shoulder for a hook: 35 cm behind, 20 cm to the side of the hand and 35 cm above
/// it, "behind" and "aside" taken from the horizontal axes across `up`. A left hand (its thumb on
/// the +x side of the hand frame, see [`crate::HandModel::is_left`]) has its shoulder on the other
/// side.
pub fn default_shoulder(hand: &crate::HandModel, hook: &Point3, up: &Vec3) -> Point3 {
    let (behind, side) = if up.z.abs() > 0.5 {
        (Vec3::x(), Vec3::y())
    } else if up.y.abs() > 0.5 {
        (Vec3::z(), Vec3::x())
    } else {
        (Vec3::y(), Vec3::z())
    };
    let side = if hand.is_left() { -side } else { side };
    hook - behind * 0.35 - side * 0.2 + up * 0.35
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingers_point_from_shoulder_to_hook_and_palm_faces_down() {
        let hook = Point3::new(0.5, 0.0, 0.0);
        let shoulder = Point3::new(0.0, 0.0, 0.4);
        let r = start_rotation(&hook, &shoulder, &Vec3::z()).unwrap();
        let z = r * Vec3::z();
        assert!((z - (hook - shoulder).normalize()).norm() < 1e-12);
        let y = r * Vec3::y();
        assert!(y.z < 0.0, "palm normal should point down, got {y:?}");
        assert!(start_rotation(&hook, &hook, &Vec3::z()).is_none());
        let straight_down = start_rotation(&hook, &Point3::new(0.5, 0.0, 1.0), &Vec3::z()).unwrap();
        assert!(((straight_down * Vec3::z()) + Vec3::z()).norm() < 1e-12);
    }

    #[test]
    fn nearest_hook_is_chosen() {
        let hooks = [Point3::new(1.0, 0.0, 0.0), Point3::new(0.2, 0.0, 0.0)];
        assert_eq!(nearest_hook(&hooks, &Point3::origin()), Some(hooks[1]));
        assert_eq!(nearest_hook(&[], &Point3::origin()), None);
    }
}

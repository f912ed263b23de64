//! Contact impulses by projected Gauss–Seidel (Erleben, *Velocity-based shock propagation for
//! multibody dynamics animation*, 2007; the solver of ODE, Bullet and rapier): contact by contact,
//! the normal row is relaxed against the Delassus matrix and kept non-negative, then the two
//! tangent rows together (their 2×2 block, as rapier solves them), their impulse as a vector kept
//! within Coulomb's friction cone: a disk of radius μ λₙ, as MuJoCo's elliptic cones and rapier
//! keep it. (Each tangent clamped to ±μ λₙ on its own, a pyramid, holds √2 times as hard along
//! the diagonal of two tangents that are only an arbitrary frame: a squeezed 5 g sphere stuck to
//! fingers that then rolled it 17–24 mm out of place; with the disk it rests 9–11 mm on and holds,
//! as in MuJoCo and rapier; docs/QUALITY.md.) Written by hand: the contact rows of
//! one step are a dense system of a few dozen rows, and no crate solves this complementarity
//! problem on a dense matrix without building its own scene.

/// A contact problem of `3 k` rows (contact `c`'s normal row is `3 c`, its tangents `3 c + 1` and
/// `3 c + 2`): relative velocity `u = free + D λ`, wanted `uₙ ≥ target`, `λₙ ≥ 0`, `λₙ (uₙ − target)
/// = 0`, the tangents' impulse `(λ₁, λ₂)` no longer than `friction · λₙ`.
pub(crate) struct ContactProblem<'a> {
    /// The Delassus matrix, `3 k × 3 k`, column-major.
    pub delassus: &'a [f64],
    /// Relative velocity of each row before any impulse.
    pub free: &'a [f64],
    /// The least relative normal velocity of each normal row (0 for tangent rows).
    pub target: &'a [f64],
    /// Friction coefficient.
    pub friction: f64,
    /// A sweep that changes no impulse by more than this share of the largest ends the solve.
    pub converged: f64,
    /// Each normal row's compliance as a share of its Delassus diagonal (MuJoCo's constraint
    /// regularization, `(1 − d) / d` of its impedance d): the velocity error a row tolerates per
    /// unit of impulse. It bounds the impulses of rows that cannot all be met (a finger dragged
    /// by the palm into a held object) where an exact solve would grow them step after step.
    pub softness: f64,
}

/// Relaxes `lambda` (warm-started: pass last step's impulses, or zeros) for at most `sweeps`
/// sweeps, contact by contact (its normal row, then its two tangents together), stopping early
/// once a sweep changes no impulse by more than [`ContactProblem::converged`] of the largest; returns the sweeps
/// made.
pub(crate) fn projected_gauss_seidel(
    problem: &ContactProblem,
    sweeps: usize,
    lambda: &mut [f64],
) -> usize {
    let rows = problem.free.len();
    debug_assert_eq!(problem.delassus.len(), rows * rows);
    // Warm starts come from last step's contacts: fit them to this step's cone first.
    for contact in lambda.chunks_exact_mut(3) {
        contact[0] = contact[0].max(0.0);
        within_cone(contact, problem.friction);
    }
    // Row r's relative velocity with the impulses as they stand (D is symmetric: row r is
    // column r).
    let velocity = |r: usize, lambda: &[f64]| {
        problem.free[r]
            + problem.delassus[r * rows..(r + 1) * rows]
                .iter()
                .zip(lambda)
                .map(|(d, l)| d * l)
                .sum::<f64>()
    };
    let entry = |r: usize, c: usize| problem.delassus[r * rows + c];
    for sweep in 1..=sweeps {
        let (mut change, mut largest) = (0.0f64, 0.0f64);
        for normal in (0..rows).step_by(3) {
            // The normal row, softened; a row no impulse can move keeps its impulse.
            let diagonal = entry(normal, normal);
            if diagonal > 0.0 {
                let compliance = problem.softness * diagonal;
                let error =
                    velocity(normal, lambda) + compliance * lambda[normal] - problem.target[normal];
                let value = (lambda[normal] - error / (diagonal + compliance)).max(0.0);
                change = change.max((value - lambda[normal]).abs());
                largest = largest.max(value);
                lambda[normal] = value;
            }
            // The two tangents together, stiff (a compliant tangent would let a held object
            // creep): the impulse that stops both at once, K⁻¹ times their velocities, K their
            // 2×2 block of D (rapier's central-friction solve: one tangent at a time, an
            // anisotropic K turns the impulse between them from sweep to sweep), then brought
            // into the cone. A singular K (one tangent nothing can move along) is solved row by
            // row.
            let (t1, t2) = (normal + 1, normal + 2);
            let before = [lambda[t1], lambda[t2]];
            let (k11, k12, k22) = (entry(t1, t1), entry(t1, t2), entry(t2, t2));
            let determinant = k11 * k22 - k12 * k12;
            if determinant > 1e-12 * (k11 * k22).max(f64::MIN_POSITIVE) {
                let e1 = velocity(t1, lambda) - problem.target[t1];
                let e2 = velocity(t2, lambda) - problem.target[t2];
                lambda[t1] -= (k22 * e1 - k12 * e2) / determinant;
                lambda[t2] -= (k11 * e2 - k12 * e1) / determinant;
            } else {
                for t in [t1, t2] {
                    let diagonal = entry(t, t);
                    if diagonal > 0.0 {
                        lambda[t] -= (velocity(t, lambda) - problem.target[t]) / diagonal;
                    }
                }
            }
            within_cone(&mut lambda[normal..normal + 3], problem.friction);
            for (t, before) in [t1, t2].into_iter().zip(before) {
                change = change.max((lambda[t] - before).abs());
                largest = largest.max(lambda[t].abs());
            }
        }
        if change <= problem.converged * largest {
            return sweep;
        }
    }
    sweeps
}

/// Scales a contact's tangent impulses `contact[1..3]` back onto the disk of radius
/// `friction · contact[0]` when they lie beyond it, keeping their direction.
fn within_cone(contact: &mut [f64], friction: f64) {
    let bound = friction * contact[0];
    let length = contact[1].hypot(contact[2]);
    if length > bound {
        let scale = if length > 0.0 { bound / length } else { 0.0 };
        contact[1] *= scale;
        contact[2] *= scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit Delassus matrix of one contact.
    const UNIT: [f64; 9] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];

    /// Relaxes `lambda` against `delassus` and `free` (targets 0) for at most `sweeps` sweeps;
    /// returns the sweeps made.
    fn relax(
        delassus: &[f64],
        free: &[f64],
        friction: f64,
        softness: f64,
        sweeps: usize,
        lambda: &mut [f64],
    ) -> usize {
        let target = vec![0.0; free.len()];
        let problem = ContactProblem {
            delassus,
            free,
            target: &target,
            friction,
            converged: 1e-6,
            softness,
        };
        projected_gauss_seidel(&problem, sweeps, lambda)
    }

    /// A point on a table: one contact, unit Delassus. Pressed down at 1 m/s it gets exactly the
    /// impulse that stops it; pulled away it gets none; pushed sideways harder than friction
    /// allows, it slides with the tangent impulse at the cone's edge.
    #[test]
    fn one_contact_stops_separates_and_slides() {
        let solve = |free: [f64; 3]| {
            let mut lambda = [0.0; 3];
            relax(&UNIT, &free, 0.5, 0.0, 5, &mut lambda);
            lambda
        };
        assert_eq!(solve([-1.0, 0.2, 0.0]), [1.0, -0.2, 0.0]);
        assert_eq!(solve([1.0, 0.2, 0.0]), [0.0, 0.0, 0.0]);
        assert_eq!(solve([-1.0, 2.0, 0.0]), [1.0, -0.5, 0.0]);
    }

    /// Friction is the same in every direction along the surface: pushed sideways too hard, a
    /// point slides with a friction impulse of μ λₙ whichever way the push points in the
    /// tangents' frame, opposite the push. (Each tangent clamped on its own, the diagonal push
    /// met √2 μ λₙ.) And a tangent along which nothing can move does not keep the other past
    /// the cone.
    #[test]
    fn friction_is_isotropic() {
        for degrees in [0.0f64, 30.0, 45.0, 60.0, 90.0, 135.0] {
            let (s, c) = degrees.to_radians().sin_cos();
            let mut lambda = [0.0; 3];
            relax(&UNIT, &[-1.0, 2.0 * c, 2.0 * s], 0.5, 0.0, 20, &mut lambda);
            assert!((lambda[0] - 1.0).abs() < 1e-12, "{degrees}°: {lambda:?}");
            assert!(
                (lambda[1].hypot(lambda[2]) - 0.5).abs() < 1e-12,
                "{degrees}°: {lambda:?}"
            );
            assert!(
                (lambda[1] * s - lambda[2] * c).abs() < 1e-12,
                "{degrees}°: opposite the push, {lambda:?}"
            );
        }
        // The second tangent cannot move (zero diagonal) and keeps what the warm start left it.
        let stuck = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
        let mut lambda = [1.0, 0.0, 2.0];
        relax(&stuck, &[-1.0, 2.0, 0.0], 0.5, 0.0, 20, &mut lambda);
        assert!(
            lambda[1].hypot(lambda[2]) <= 0.5 * lambda[0] + 1e-12,
            "{lambda:?}"
        );
    }

    /// A contact that sticks stops along both tangents in one sweep, even where pushing along
    /// one tangent moves it along the other (an anisotropic tangent block).
    #[test]
    fn a_sticking_contact_stops_in_both_tangents_at_once() {
        let delassus = [1.0, 0.0, 0.0, 0.0, 2.0, 0.5, 0.0, 0.5, 1.0];
        let free = [-1.0, 0.1, 0.05];
        let mut lambda = [0.0; 3];
        relax(&delassus, &free, 1.0, 0.0, 1, &mut lambda);
        for t in [1, 2] {
            let velocity = free[t] + (0..3).map(|k| delassus[t * 3 + k] * lambda[k]).sum::<f64>();
            assert!(
                velocity.abs() < 1e-12,
                "tangent {t}: {velocity} ({lambda:?})"
            );
        }
    }

    /// Two contacts sharing a body converge to the impulses a direct solve gives.
    #[test]
    fn coupled_contacts_converge_to_the_direct_solution() {
        // Normal rows 0 and 3 coupled by 0.5; tangents decoupled and unloaded.
        let mut delassus = [0.0; 36];
        for r in 0..6 {
            delassus[r * 6 + r] = 1.0;
        }
        delassus[3] = 0.5;
        delassus[3 * 6] = 0.5;
        let free = [-2.0, 0.0, 0.0, -2.0, 0.0, 0.0];
        let mut lambda = [0.0; 6];
        let sweeps = relax(&delassus, &free, 1.0, 0.0, 60, &mut lambda);
        // Both contacts stop: [1 ½; ½ 1] λ = [2 2], λ = [4/3 4/3]. The sweeps stop once they
        // change the impulses by a millionth: well before 60, and that near.
        assert!(sweeps < 20, "{sweeps} sweeps");
        assert!((lambda[0] - 4.0 / 3.0).abs() < 1e-5, "{lambda:?}");
        assert!((lambda[3] - 4.0 / 3.0).abs() < 1e-5, "{lambda:?}");
    }

    /// Two contacts that cannot both be met (one row asks the other's direction to close while
    /// it opens): exact, the sweeps push the impulses up without end; with softness they settle
    /// where each row's error pays for its impulse.
    #[test]
    fn softness_bounds_the_impulses_of_conflicting_contacts() {
        // Rows 0 and 3 along the same direction with opposite signs: D = [1 −1; −1 1].
        let mut delassus = [0.0; 36];
        for r in 0..6 {
            delassus[r * 6 + r] = 1.0;
        }
        delassus[3] = -1.0;
        delassus[3 * 6] = -1.0;
        let free = [-1.0, 0.0, 0.0, -1.0, 0.0, 0.0];
        let solve = |softness: f64, sweeps: usize| {
            let mut lambda = [0.0; 6];
            relax(&delassus, &free, 1.0, softness, sweeps, &mut lambda);
            lambda[0]
        };
        assert!(
            solve(0.0, 200) > 2.0 * solve(0.0, 100),
            "exact impulses keep growing"
        );
        let (settled, longer) = (solve(0.1, 100), solve(0.1, 200));
        assert!(
            (settled - longer).abs() < 1e-6 && settled < 11.0,
            "{settled} {longer}"
        );
    }
}

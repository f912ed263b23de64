//! Contact impulses by projected Gauss–Seidel (Erleben, *Velocity-based shock propagation for
//! multibody dynamics animation*, 2007; the solver of ODE, Bullet and rapier): each contact's
//! three rows (normal, two tangents) are relaxed in turn against the Delassus matrix, the normal
//! impulse kept non-negative and each tangent's within the friction pyramid μ λₙ. Written by
//! hand: the contact rows of one step are a dense system of a few dozen rows, and no crate
//! solves this complementarity problem on a dense matrix without building its own scene.

/// A sweep that changes no impulse by more than this share of the largest ends the solve.
pub(crate) const CONVERGED: f64 = 1e-6;

/// A contact problem of `3 k` rows (contact `c`'s normal row is `3 c`, its tangents `3 c + 1` and
/// `3 c + 2`): relative velocity `u = free + D λ`, wanted `uₙ ≥ target`, `λₙ ≥ 0`, `λₙ (uₙ − target)
/// = 0`, tangents within `friction · λₙ`.
pub(crate) struct ContactProblem<'a> {
    /// The Delassus matrix, `3 k × 3 k`, column-major.
    pub delassus: &'a [f64],
    /// Relative velocity of each row before any impulse.
    pub free: &'a [f64],
    /// The least relative normal velocity of each normal row (0 for tangent rows).
    pub target: &'a [f64],
    /// Friction coefficient.
    pub friction: f64,
    /// Each normal row's compliance as a share of its Delassus diagonal (MuJoCo's constraint
    /// regularization, `(1 − d) / d` of its impedance d): the velocity error a row tolerates per
    /// unit of impulse. It bounds the impulses of rows that cannot all be met (a finger dragged
    /// by the palm into a held object) where an exact solve would grow them step after step.
    pub softness: f64,
}

/// Relaxes `lambda` (warm-started: pass last step's impulses, or zeros) for at most `sweeps`
/// sweeps, stopping early once a sweep changes no impulse by more than [`CONVERGED`] of the
/// largest; returns the sweeps made.
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
        let bound = problem.friction * contact[0];
        for tangent in &mut contact[1..] {
            *tangent = tangent.clamp(-bound, bound);
        }
    }
    for sweep in 1..=sweeps {
        let (mut change, mut largest) = (0.0f64, 0.0f64);
        for r in 0..rows {
            let column = &problem.delassus[r * rows..(r + 1) * rows];
            let diagonal = column[r];
            if diagonal <= 0.0 {
                continue;
            }
            let normal = r - r % 3;
            // Friction rows stay stiff: a compliant tangent would let a held object creep.
            let compliance = if r == normal {
                problem.softness * diagonal
            } else {
                0.0
            };
            // D is symmetric: row r is column r.
            let velocity = problem.free[r]
                + compliance * lambda[r]
                + column
                    .iter()
                    .zip(lambda.iter())
                    .map(|(d, l)| d * l)
                    .sum::<f64>();
            let value = lambda[r] - (velocity - problem.target[r]) / (diagonal + compliance);
            let value = if r == normal {
                value.max(0.0)
            } else {
                let bound = problem.friction * lambda[normal];
                value.clamp(-bound, bound)
            };
            change = change.max((value - lambda[r]).abs());
            largest = largest.max(value.abs());
            lambda[r] = value;
        }
        if change <= CONVERGED * largest {
            return sweep;
        }
    }
    sweeps
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point on a table: one contact, unit Delassus. Pressed down at 1 m/s it gets exactly the
    /// impulse that stops it; pulled away it gets none; pushed sideways harder than friction
    /// allows, it slides with the tangent impulse at the cone's edge.
    #[test]
    fn one_contact_stops_separates_and_slides() {
        let delassus = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let solve = |free: [f64; 3]| {
            let mut lambda = [0.0; 3];
            let problem = ContactProblem {
                delassus: &delassus,
                free: &free,
                target: &[0.0; 3],
                friction: 0.5,
                softness: 0.0,
            };
            projected_gauss_seidel(&problem, 5, &mut lambda);
            lambda
        };
        assert_eq!(solve([-1.0, 0.2, 0.0]), [1.0, -0.2, 0.0]);
        assert_eq!(solve([1.0, 0.2, 0.0]), [0.0, 0.0, 0.0]);
        assert_eq!(solve([-1.0, 2.0, 0.0]), [1.0, -0.5, 0.0]);
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
        let problem = ContactProblem {
            delassus: &delassus,
            free: &free,
            target: &[0.0; 6],
            friction: 1.0,
            softness: 0.0,
        };
        let sweeps = projected_gauss_seidel(&problem, 60, &mut lambda);
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
            let problem = ContactProblem {
                delassus: &delassus,
                free: &free,
                target: &[0.0; 6],
                friction: 1.0,
                softness,
            };
            projected_gauss_seidel(&problem, sweeps, &mut lambda);
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

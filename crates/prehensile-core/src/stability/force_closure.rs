//! Force closure by linear programming, fast enough for every pose the search evaluates (the
//! hull behind ε takes milliseconds in six dimensions; this takes tens of microseconds).
//!
//! The origin lies strictly inside the convex hull of the wrenches `w_i` exactly when the
//! wrenches span all six dimensions and some convex combination `Σ λ_i w_i = 0` gives every
//! wrench a positive weight. The margin is the largest smallest weight, scaled by the number of
//! wrenches: `n · max { t : Σ λ_i w_i = 0, Σ λ_i = 1, λ_i ≥ t }`, in (0, 1] with force closure
//! (1 when the origin is the wrenches' centroid) and 0 without. It grows as the contacts' pushes
//! balance each other more evenly, so the search uses it to steer toward wrapping grasps.
//!
//! Solved with `microlp` (pure Rust, builds for wasm32) with `μ_i = λ_i − t` so that the problem
//! has seven equality rows.

use microlp::{ComparisonOp, OptimizationDirection, Problem};
use nalgebra::{Matrix6, Vector6};

/// Margins below this count as no force closure.
pub const MARGIN_TOLERANCE: f64 = 1e-6;

/// The force-closure margin of `wrenches`: in (0, 1] in force closure, 0 otherwise.
pub fn force_closure_margin(wrenches: &[[f64; 6]]) -> f64 {
    let n = wrenches.len();
    if n < 7 || wrenches.iter().flatten().any(|c| !c.is_finite()) {
        return 0.0;
    }
    // Full rank: the smallest eigenvalue of Σ w wᵀ against its largest.
    let mut gram = Matrix6::zeros();
    for w in wrenches {
        let v = Vector6::from_column_slice(w);
        gram += v * v.transpose();
    }
    let eigen = gram.symmetric_eigenvalues();
    if eigen.min() <= 1e-12 * eigen.max().max(f64::MIN_POSITIVE) {
        return 0.0;
    }
    let mut problem = Problem::new(OptimizationDirection::Maximize);
    let mu: Vec<_> = (0..n)
        .map(|_| problem.add_var(0.0, (0.0, f64::INFINITY)))
        .collect();
    let t = problem.add_var(1.0, (f64::NEG_INFINITY, f64::INFINITY));
    for k in 0..6 {
        let sum: f64 = wrenches.iter().map(|w| w[k]).sum();
        let mut row: Vec<_> = mu.iter().zip(wrenches).map(|(&v, w)| (v, w[k])).collect();
        row.push((t, sum));
        problem.add_constraint(&row, ComparisonOp::Eq, 0.0);
    }
    let mut row: Vec<_> = mu.iter().map(|&v| (v, 1.0)).collect();
    row.push((t, n as f64));
    problem.add_constraint(&row, ComparisonOp::Eq, 1.0);
    match problem.solve().map(|o| o.into_solution()) {
        Ok(Ok(solved)) => {
            let margin = solved.objective() * n as f64;
            if margin > MARGIN_TOLERANCE {
                margin.min(1.0)
            } else {
                0.0
            }
        }
        _ => 0.0,
    }
}

//! Force closure by linear programming, fast enough for every pose the search evaluates (the
//! hull behind ε takes milliseconds in six dimensions).
//!
//! The origin lies strictly inside the convex hull of the wrenches `w_i` exactly when the
//! wrenches span all six dimensions and some convex combination `Σ λ_i w_i = 0` gives every
//! wrench a positive weight. The margin is the largest smallest weight, scaled by the number of
//! wrenches: `n · max { t : Σ λ_i w_i = 0, Σ λ_i = 1, λ_i ≥ t }`, in (0, 1] with force closure
//! (1 when the origin is the wrenches' centroid) and 0 without.
//!
//! With `μ_i = λ_i − t ≥ 0` the problem has seven equality rows and `n + 1` columns (t ≥ 0
//! suffices: a negative optimum means no force closure). It is solved by a dense two-phase
//! simplex with Bland's rule, written here because the problem is tiny and fixed in shape: a
//! general sparse solver (`microlp`) took 200–500 µs per pose, this takes tens, and its buffers
//! are reused. Checked against the hull on every oracle case (`tests/integration/stability_oracle.rs`).

use nalgebra::{Matrix6, Vector6};

/// Margins below this count as no force closure.
pub const MARGIN_TOLERANCE: f64 = 1e-6;

/// Rows of the problem: six wrench components and the weights' sum.
const ROWS: usize = 7;
/// Pivot tolerance.
const EPS: f64 = 1e-11;
/// Most simplex pivots before giving up (Bland's rule cannot cycle; this bounds rounding).
const MAX_PIVOTS: usize = 10_000;

/// The buffers of [`ForceClosure::margin`].
#[derive(Debug, Clone, Default)]
pub struct ForceClosure {
    /// Row-major tableau: `ROWS + 1` rows (the last is the objective) of `columns + 1` entries.
    tableau: Vec<f64>,
    basis: Vec<usize>,
}

impl ForceClosure {
    /// Empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// The force-closure margin of `wrenches`: in (0, 1] in force closure, 0 otherwise.
    pub fn margin(&mut self, wrenches: &[[f64; 6]]) -> f64 {
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
        // λ_i = μ_i + t: the column of t is (Σ w_i, n).
        let mut column = [0.0; ROWS];
        for w in wrenches {
            for (c, x) in column.iter_mut().zip(w) {
                *c += x;
            }
        }
        column[6] = n as f64;
        let margin = self.maximize(wrenches, &column).unwrap_or(0.0) * n as f64;
        if margin > MARGIN_TOLERANCE {
            margin.min(1.0)
        } else {
            0.0
        }
    }

    /// How far the wrenches' hull reaches from the origin along `direction`: the largest `s`
    /// with `s · direction` a convex combination of `wrenches`. For a grasp in force closure,
    /// pushing `direction` with a total contact force of one, the grasp's load ratio along it
    /// (what the hull's facet on that ray gives, for a linear program's cost). `None` when the
    /// origin is outside the hull.
    pub fn reach(&mut self, wrenches: &[[f64; 6]], direction: &[f64; 6]) -> Option<f64> {
        let mut column = [0.0; ROWS];
        for (c, d) in column.iter_mut().zip(direction) {
            *c = -d;
        }
        self.maximize(wrenches, &column)
    }

    /// `max t` subject to `Σ x_i (w_i, 1) + t · column = (0, …, 0, 1)`, `x ≥ 0`, `t ≥ 0`: the
    /// problem both [`ForceClosure::margin`] and [`ForceClosure::reach`] are. `None` when it is
    /// infeasible, unbounded, or rounding defeats the simplex.
    fn maximize(&mut self, wrenches: &[[f64; 6]], column: &[f64; ROWS]) -> Option<f64> {
        let n = wrenches.len();
        // Columns: x_0..x_{n-1}, t, then one artificial per row; last entry of a row: its
        // right-hand side.
        let columns = n + 1 + ROWS;
        let width = columns + 1;
        self.tableau.clear();
        self.tableau.resize((ROWS + 1) * width, 0.0);
        self.basis.clear();
        let t = n;
        for r in 0..ROWS {
            let row = &mut self.tableau[r * width..(r + 1) * width];
            if r < 6 {
                for (i, w) in wrenches.iter().enumerate() {
                    row[i] = w[r];
                }
            } else {
                row[..n].fill(1.0);
                row[columns] = 1.0;
            }
            row[t] = column[r];
            // Right-hand sides are 0 or 1: no row needs flipping to keep them non-negative.
            row[n + 1 + r] = 1.0;
            self.basis.push(n + 1 + r);
        }
        // Phase 1: maximize −Σ artificials, i.e. the objective row is −Σ rows over the
        // non-artificial columns.
        let (body, objective) = self.tableau.split_at_mut(ROWS * width);
        objective.fill(0.0);
        for r in 0..ROWS {
            for c in 0..columns {
                if c < n + 1 {
                    objective[c] -= body[r * width + c];
                }
            }
            objective[columns] -= body[r * width + columns];
        }
        if !self.solve(width, n + 1 + ROWS) {
            return None;
        }
        if -self.tableau[ROWS * width + columns] > 1e-9 {
            return None; // infeasible: the origin is outside the wrenches' hull
        }
        // Artificials still basic (at zero) leave the basis, or their row is redundant.
        for r in 0..ROWS {
            if self.basis[r] > n {
                if let Some(c) = (0..=n).find(|&c| self.tableau[r * width + c].abs() > EPS) {
                    self.pivot(width, r, c);
                }
            }
        }
        // Phase 2: maximize t, artificials barred from entering. Objective row: −(c) expressed in
        // the current basis, c = e_t.
        {
            let (body, objective) = self.tableau.split_at_mut(ROWS * width);
            objective.fill(0.0);
            objective[t] = -1.0;
            for (r, &b) in self.basis.iter().enumerate() {
                let coefficient = objective[b];
                if coefficient != 0.0 {
                    for c in 0..width {
                        objective[c] -= coefficient * body[r * width + c];
                    }
                }
            }
        }
        if !self.solve(width, n + 1) {
            return None;
        }
        Some(
            self.basis
                .iter()
                .position(|&b| b == t)
                .map_or(0.0, |r| self.tableau[r * width + columns]),
        )
    }

    /// Simplex pivots on the tableau (maximization; the objective row holds reduced costs, a
    /// negative one may enter) over entering columns `< enter_below`. False if unbounded or out
    /// of pivots.
    fn solve(&mut self, width: usize, enter_below: usize) -> bool {
        let rhs = width - 1;
        for _ in 0..MAX_PIVOTS {
            // Bland: the lowest-index column with a negative reduced cost enters.
            let objective = &self.tableau[ROWS * width..];
            let Some(enter) = (0..enter_below).find(|&c| objective[c] < -EPS) else {
                return true;
            };
            // Ratio test; ties broken by the lowest basis index (Bland).
            let mut leave: Option<(usize, f64)> = None;
            for r in 0..ROWS {
                let a = self.tableau[r * width + enter];
                if a > EPS {
                    let ratio = self.tableau[r * width + rhs] / a;
                    let better = match leave {
                        None => true,
                        Some((l, best)) => {
                            ratio < best - EPS
                                || (ratio <= best + EPS && self.basis[r] < self.basis[l])
                        }
                    };
                    if better {
                        leave = Some((r, ratio));
                    }
                }
            }
            let Some((row, _)) = leave else {
                return false;
            };
            self.pivot(width, row, enter);
        }
        false
    }

    fn pivot(&mut self, width: usize, row: usize, column: usize) {
        let p = self.tableau[row * width + column];
        for c in 0..width {
            self.tableau[row * width + c] /= p;
        }
        for r in 0..=ROWS {
            if r == row {
                continue;
            }
            let factor = self.tableau[r * width + column];
            if factor != 0.0 {
                for c in 0..width {
                    self.tableau[r * width + c] -= factor * self.tableau[row * width + c];
                }
            }
        }
        self.basis[row] = column;
    }
}

/// The force-closure margin of `wrenches` with fresh buffers (see [`ForceClosure::margin`]).
pub fn force_closure_margin(wrenches: &[[f64; 6]]) -> f64 {
    ForceClosure::new().margin(wrenches)
}

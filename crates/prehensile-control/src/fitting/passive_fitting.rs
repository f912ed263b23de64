//! The passive controller's parameters from a motion library (Pollard & Zordan §4): the neutral
//! pose is the mean pose, the joint limits the extremes observed for each degree of freedom.

use crate::error::DynamicsError;

/// Neutral pose and limits `[min, max]` per degree of freedom from frames of joint angles (all
/// of one length, at least one frame, every value finite).
pub fn fit_passive(frames: &[Vec<f64>]) -> Result<(Vec<f64>, Vec<[f64; 2]>), DynamicsError> {
    let Some(first) = frames.first() else {
        return Err(DynamicsError::Length {
            what: "motion (frames)",
            got: 0,
            expected: 1,
        });
    };
    let n = first.len();
    let mut sum = vec![0.0; n];
    let mut limits = vec![[f64::INFINITY, f64::NEG_INFINITY]; n];
    for frame in frames {
        if frame.len() != n {
            return Err(DynamicsError::Length {
                what: "a motion frame",
                got: frame.len(),
                expected: n,
            });
        }
        for (k, &v) in frame.iter().enumerate() {
            if !v.is_finite() {
                return Err(DynamicsError::NonFinite("motion"));
            }
            sum[k] += v;
            limits[k] = [limits[k][0].min(v), limits[k][1].max(v)];
        }
    }
    let neutral = sum.iter().map(|s| s / frames.len() as f64).collect();
    Ok((neutral, limits))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_extremes() {
        let frames = vec![vec![0.0, 1.0], vec![0.4, -1.0], vec![0.2, 0.0]];
        let (neutral, limits) = fit_passive(&frames).unwrap();
        assert!((neutral[0] - 0.2).abs() < 1e-15 && neutral[1].abs() < 1e-15);
        assert_eq!(limits, vec![[0.0, 0.4], [-1.0, 1.0]]);
        assert!(fit_passive(&[]).is_err());
        assert!(fit_passive(&[vec![0.0, 1.0], vec![0.0]]).is_err());
        assert!(fit_passive(&[vec![f64::NAN]]).is_err());
    }
}

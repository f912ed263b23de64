//! A grasp request as every front end states it — names and plain numbers, each with its
//! default — checked and resolved here once: the CLI, the Python package, the batch and the
//! browser build translate their arguments into [`GraspOptions`] and never check or default
//! them on their own.

use std::time::Duration;

use crate::hand::HandModel;
use crate::math::Point3;
use crate::object::ObjectModel;
use crate::parameter::{finite_point, in_range, ParameterError, UpAxis};
use crate::stability::ContactModel;

use super::defaults;
use super::find_grasp::GraspRequest;
use super::planner::{SearchError, SearchParams};
use super::quality::{QualityWeights, ValidityRule};
use super::start_position::default_shoulder;

/// One grasp request in the terms a user gives it. [`Default`] is every front end's default;
/// [`GraspOptions::request`] checks every field and resolves what depends on the hand and the
/// object (the shoulder, the threads).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GraspOptions {
    /// A movement of the hand, or `auto` ([`defaults::MOVEMENT`]).
    pub movement: String,
    /// Hook, object frame, metres (default: the object's own hook, its centre of mass).
    pub hook: Option<[f64; 3]>,
    /// Shoulder, object frame, metres (default: [`default_shoulder`]).
    pub shoulder: Option<[f64; 3]>,
    /// The world's up axis.
    pub up: UpAxis,
    /// Seed of the random search angles.
    pub seed: u64,
    /// Threads evaluating each step's candidates (default: one per core). The result is the
    /// same on any number.
    pub threads: Option<usize>,
    /// Quality weights G, F, T, W[, S] (default: Eq. 5.1 or 5.2 by movement).
    pub weights: Option<Vec<f64>>,
    /// Coulomb friction the search assumes.
    pub friction: f64,
    /// Which grasps are valid.
    pub validity: ValidityRule,
    /// Steps to go on looking past a power grasp whose contacts all push from one side.
    pub one_sided_patience: u32,
    /// Wall-time budget of the whole request, milliseconds (default: run to the stop rules).
    pub budget_ms: Option<f64>,
}

impl Default for GraspOptions {
    fn default() -> Self {
        Self {
            movement: defaults::MOVEMENT.to_string(),
            hook: None,
            shoulder: None,
            up: defaults::UP,
            seed: defaults::SEED,
            threads: None,
            weights: None,
            friction: defaults::FRICTION,
            validity: defaults::VALIDITY,
            one_sided_patience: defaults::ONE_SIDED_PATIENCE,
            budget_ms: None,
        }
    }
}

impl GraspOptions {
    /// The hook, checked, if one is given: the object to search is
    /// [`ObjectModel::with_hooks`] of it.
    pub fn hook_point(&self) -> Result<Option<Point3>, ParameterError> {
        self.hook
            .map(|h| finite_point("hook", h).map(Point3::from))
            .transpose()
    }

    /// The search parameters, every number checked.
    pub fn params(&self) -> Result<SearchParams, ParameterError> {
        let weights = self
            .weights
            .as_deref()
            .map(QualityWeights::from_slice)
            .transpose()?;
        let friction = in_range(
            "friction",
            self.friction,
            1e-6,
            defaults::MAX_FRICTION,
            "rubber on wood is about 0.5-1",
        )?;
        let threads = match self.threads {
            Some(n) => {
                in_range("threads", n as f64, 1.0, defaults::MAX_THREADS as f64, "")? as usize
            }
            None => std::thread::available_parallelism().map_or(1, usize::from),
        };
        let params = SearchParams {
            seed: self.seed,
            up: self.up.vector(),
            weights,
            validity: self.validity,
            one_sided_patience: self.one_sided_patience,
            contact_model: ContactModel {
                friction,
                ..ContactModel::default()
            },
            threads: threads.min(defaults::MAX_THREADS),
            ..SearchParams::default()
        };
        in_range(
            "one_sided_patience",
            f64::from(self.one_sided_patience),
            0.0,
            f64::from(params.max_steps),
            "steps, at most the search's step limit",
        )?;
        Ok(params)
    }

    /// The budget, checked.
    pub fn budget(&self) -> Result<Option<Duration>, ParameterError> {
        self.budget_ms
            .map(|ms| {
                in_range(
                    "budget_ms",
                    ms,
                    1e-3,
                    defaults::MAX_BUDGET_MS,
                    "milliseconds, at most a day",
                )
                .map(|ms| Duration::from_secs_f64(ms / 1e3))
            })
            .transpose()
    }

    /// The request for `hand` on `object` (already hung from [`GraspOptions::hook_point`]):
    /// every field checked, the shoulder defaulted from the object's hook, the movement looked
    /// up on the hand.
    pub fn request(
        &self,
        hand: &HandModel,
        object: &ObjectModel,
    ) -> Result<GraspRequest, SearchError> {
        let params = self.params()?;
        let budget = self.budget()?;
        let hook = object.hooks().first().ok_or(SearchError::NoHooks)?;
        let shoulder = match self.shoulder {
            Some(s) => Point3::from(finite_point("shoulder", s)?),
            None => default_shoulder(hand, hook, &params.up),
        };
        super::find_grasp::movements_to_try(hand, &self.movement)?;
        Ok(GraspRequest {
            movement: self.movement.clone(),
            shoulder,
            params,
            budget,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_number_is_checked() {
        let bad = [
            GraspOptions {
                friction: -1.0,
                ..Default::default()
            },
            GraspOptions {
                friction: f64::NAN,
                ..Default::default()
            },
            GraspOptions {
                threads: Some(0),
                ..Default::default()
            },
            GraspOptions {
                weights: Some(vec![0.0; 4]),
                ..Default::default()
            },
            GraspOptions {
                weights: Some(vec![1.0, 1.0, -1.0, 1.0]),
                ..Default::default()
            },
            GraspOptions {
                weights: Some(vec![1.0; 3]),
                ..Default::default()
            },
            GraspOptions {
                one_sided_patience: 1_000_000,
                ..Default::default()
            },
        ];
        for options in bad {
            assert!(options.params().is_err(), "{options:?}");
        }
        for ms in [0.0, -1.0, f64::NAN, 1e300] {
            let options = GraspOptions {
                budget_ms: Some(ms),
                ..Default::default()
            };
            assert!(options.budget().is_err(), "{ms}");
        }
        let hook = GraspOptions {
            hook: Some([0.0, f64::NAN, 0.0]),
            ..Default::default()
        };
        assert!(hook.hook_point().is_err());
        assert!(GraspOptions::default().params().is_ok());
    }

    #[test]
    fn all_zero_weights_say_why() {
        let options = GraspOptions {
            weights: Some(vec![0.0; 5]),
            ..Default::default()
        };
        let e = options.params().unwrap_err().to_string();
        assert!(e.contains("all are zero"), "{e}");
    }
}

//! A planner that owns its hand and object (shared through `Arc`), for front ends that keep a
//! search alive between calls — the Python package's `Planner`, the browser's session — where
//! [`GraspPlanner`]'s borrows cannot be expressed.

use std::sync::Arc;

use crate::hand::HandModel;
use crate::math::Point3;
use crate::object::ObjectModel;
use crate::workspace::Workspace;

use super::{GraspPlanner, GraspResult, SearchError, SearchParams};

struct Owner {
    hand: Arc<HandModel>,
    object: Arc<ObjectModel>,
}

self_cell::self_cell!(
    struct Cell {
        owner: Owner,
        #[not_covariant]
        dependent: GraspPlanner,
    }
);

/// A [`GraspPlanner`] together with the hand and object it searches.
pub struct SharedPlanner {
    cell: Cell,
}

impl SharedPlanner {
    /// A planner of `movement` (a movement of the hand; not `auto`).
    pub fn new(
        hand: Arc<HandModel>,
        object: Arc<ObjectModel>,
        movement: &str,
        shoulder: Point3,
        params: SearchParams,
    ) -> Result<Self, SearchError> {
        if hand.movement(movement).is_none() {
            return Err(SearchError::UnknownMovement {
                hand: hand.name().to_string(),
                movement: movement.to_string(),
                known: hand
                    .movements()
                    .iter()
                    .map(|m| m.name().to_string())
                    .collect(),
                auto_allowed: false,
            });
        }
        let cell = Cell::try_new(Owner { hand, object }, |o| {
            let m = o.hand.movement(movement).expect("checked above");
            GraspPlanner::new(&o.hand, &o.object, m, shoulder, params)
        })?;
        Ok(Self { cell })
    }

    /// The hand.
    pub fn hand(&self) -> &Arc<HandModel> {
        &self.cell.borrow_owner().hand
    }

    /// The object.
    pub fn object(&self) -> &Arc<ObjectModel> {
        &self.cell.borrow_owner().object
    }

    /// Reads the planner.
    pub fn with<R>(&self, f: impl FnOnce(&GraspPlanner) -> R) -> R {
        self.cell.with_dependent(|_, p| f(p))
    }

    /// Drives the planner.
    pub fn with_mut<R>(&mut self, f: impl FnOnce(&mut GraspPlanner) -> R) -> R {
        self.cell.with_dependent_mut(|_, p| f(p))
    }

    /// The best valid grasp so far, or the current pose marked not valid.
    pub fn result(&self) -> GraspResult {
        self.cell
            .with_dependent(|o, p| GraspResult::from_planner(p, &mut Workspace::new(&o.hand)))
    }
}

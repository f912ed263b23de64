//! Fitting the controller to an example motion (Pollard & Zordan §4–5.1), and its file.

pub mod active_fitting;
pub mod controller_fitting;
pub mod example_motion;
pub mod passive_fitting;

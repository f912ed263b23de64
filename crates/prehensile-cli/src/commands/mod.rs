//! One module per subcommand.

pub mod batch;
pub mod check;
pub mod demo;
pub mod fit;
pub mod grasp;
pub mod hands;
pub mod simulate;
pub mod view;

//! The Pollard & Zordan grasp controller: its six setpoints and its torque laws.

pub mod setpoint;
pub mod torque_laws;

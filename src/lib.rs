//! slither: a simulator and gait designer for snake locomotion.
pub mod energy;
pub mod integrator;
pub mod model;
pub mod problem;
pub mod rod;
pub mod state;
pub mod fd;
pub mod topology;

//! slither: a simulator and gait designer for snake locomotion.
pub mod contact;
pub mod energy;
pub mod fd;
pub mod gait;
pub mod observe;
pub mod integrator;
pub mod model;
pub mod output;
pub mod plot;
pub mod problem;
pub mod rod;
pub mod sim;
pub mod state;
pub mod topology;

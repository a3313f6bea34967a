//! Line-pull control: steering a payload-mode parachute by shortening suspension lines.
//!
//! Scheduled pulls (`[[control]]`) need nothing at run time: they are rest-length schedules
//! of the line rods (`build::control`, engine `rod::stretch`), read from the evaluation time.
//! Guidance (`[guidance]`) decides pulls while flying: [`guidance::Controller`] writes the
//! lines' commands between steps, choosing the pull direction by inverting
//! the canopy's measured response to pulls ([`response::Response`]). Sensor-started pulls
//! ([`trigger::Triggers`]) read a height sensor ([`sensor::HeightSensor`]) after every step
//! and start their pull when it reads their threshold. docs/control.md has the laws and the
//! studies.
pub mod guidance;
pub mod response;
pub mod sensor;
pub mod trigger;

pub use guidance::Controller;
pub use trigger::{TriggerRecord, Triggers};

//! The time stepper and the Newton solver: backward Euler's exact numerical damping, local
//! error control, quadratic convergence with exact drag Jacobians, the symmetric
//! approximation and its Krylov correction, predictors, and bit-identical continuation from
//! a checkpointed history.
mod aero_newton;
mod backward_euler;
mod common;
mod error_control;
mod error_filter;
mod factor_precision;
mod ladder;
mod newton_accuracy;
mod newton_descent;
mod newton_update;
mod predictor;
mod rod_history;

//! The engine's models against analytic and published references: the standard atmosphere,
//! drag laws and falling bodies (also through stratified air and permeable fabric), DER cantilevers (small and large deflection, end moment, vibration), rod networks
//! and frames, shell meshes. Each module documents its reference and its tolerance.
mod aero_added_mass;
mod aero_incidence;
mod aero_inflation;
mod aero_laws;
mod aero_linear;
mod aero_permeable;
mod aero_stratified;
mod aero_terminal;
mod aero_wind;
mod atmosphere;
mod contact;
#[path = "../common/mesh.rs"]
mod mesh;
mod rod_cantilever;
mod rod_frames;
mod rod_network;
mod rod_vibration;
mod shell_fabric;
mod shell_membrane;
mod shell_mesh;

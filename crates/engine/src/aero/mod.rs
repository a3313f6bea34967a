//! Aerodynamic drag elements.

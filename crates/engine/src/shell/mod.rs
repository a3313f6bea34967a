//! Discrete shells (hinge model). Elements are added by the shell modules.

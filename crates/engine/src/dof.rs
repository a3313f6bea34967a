//! Degree-of-freedom layout: node positions first, then rod-edge twist angles.

/// Layout of the generalised coordinate vector `q`.
///
/// `q[3 i + k]` is coordinate `k` (x, y, z) of node `i` in metres; `q[3 n_nodes + e]` is the
/// twist angle θ of rod edge `e` in radians (the material frame's rotation about the edge
/// tangent, measured from the edge's reference frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DofLayout {
    /// Number of nodes (3 DOFs each).
    pub n_nodes: usize,
    /// Number of rod edges carrying a twist DOF.
    pub n_twists: usize,
}

impl DofLayout {
    /// A layout with `n_nodes` nodes and `n_twists` twist angles.
    pub fn new(n_nodes: usize, n_twists: usize) -> Self {
        Self { n_nodes, n_twists }
    }
    /// Total number of DOFs.
    pub fn len(&self) -> usize {
        3 * self.n_nodes + self.n_twists
    }
    /// True when there are no DOFs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Index of coordinate `k` (0 = x, 1 = y, 2 = z) of node `i`.
    #[inline]
    pub fn node(&self, i: usize, k: usize) -> usize {
        3 * i + k
    }
    /// Index of the twist angle of twist edge `e`.
    #[inline]
    pub fn twist(&self, e: usize) -> usize {
        3 * self.n_nodes + e
    }
}

//! A model: DOF layout, lumped masses, fixed DOFs and forces; and the state it evolves.
use crate::dof::DofLayout;
use crate::error::EngineError;
use crate::force::Force;

/// Dynamic state: configuration, velocity and time.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Generalised coordinates (see [`DofLayout`]).
    pub q: Vec<f64>,
    /// Generalised velocities.
    pub v: Vec<f64>,
    /// Time (s).
    pub t: f64,
}

impl State {
    /// State at rest at configuration `q`, time 0.
    pub fn at_rest(q: Vec<f64>) -> Self {
        let n = q.len();
        Self {
            q,
            v: vec![0.0; n],
            t: 0.0,
        }
    }
}

/// Handle of a force added to a [`Model`] ([`Model::add_force`]): its position in
/// [`Model::forces`], which never changes (forces are only ever appended).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ForceId(usize);

impl ForceId {
    /// Position of the force in [`Model::forces`].
    pub fn index(self) -> usize {
        self.0
    }
}

/// Everything the stepper needs: masses, constraints and forces.
pub struct Model {
    /// DOF layout.
    pub layout: DofLayout,
    /// Lumped mass per DOF: kg for positions, kg·m² for twist angles.
    pub mass: Vec<f64>,
    /// `fixed[d]` is true when DOF `d` is prescribed (kept at its value, zero velocity).
    pub fixed: Vec<bool>,
    /// All force families, in the order they were added (a [`ForceId`] indexes this list;
    /// append with [`Model::add_force`], do not remove).
    pub forces: Vec<Box<dyn Force>>,
}

impl Model {
    /// An empty model (no mass, nothing fixed, no forces).
    pub fn new(layout: DofLayout) -> Self {
        let n = layout.len();
        Self {
            layout,
            mass: vec![0.0; n],
            fixed: vec![false; n],
            forces: Vec::new(),
        }
    }
    /// Number of DOFs.
    pub fn n_dofs(&self) -> usize {
        self.layout.len()
    }
    /// Add a force family; the returned id gets it back ([`Model::force`]).
    pub fn add_force(&mut self, f: impl Force + 'static) -> ForceId {
        self.forces.push(Box::new(f));
        ForceId(self.forces.len() - 1)
    }
    /// The force added as `id`.
    pub fn force(&self, id: ForceId) -> &dyn Force {
        self.forces[id.0].as_ref()
    }
    /// The force added as `id`, mutably (e.g. to change its load scale).
    pub fn force_mut(&mut self, id: ForceId) -> &mut dyn Force {
        self.forces[id.0].as_mut()
    }
    /// Add a point mass `m` (kg) to node `i`.
    pub fn add_node_mass(&mut self, i: usize, m: f64) {
        for k in 0..3 {
            self.mass[3 * i + k] += m;
        }
    }
    /// Clamp all three coordinates of node `i`.
    pub fn fix_node(&mut self, i: usize) {
        for k in 0..3 {
            self.fixed[3 * i + k] = true;
        }
    }
    /// Mass of node `i` (kg).
    pub fn node_mass(&self, i: usize) -> f64 {
        self.mass[3 * i]
    }
    /// Total translational mass (kg).
    pub fn total_mass(&self) -> f64 {
        (0..self.layout.n_nodes).map(|i| self.node_mass(i)).sum()
    }
    /// Check that every force's stencils are in range, the low-rank parts are within
    /// [`crate::linsolve::MAX_RANK`] terms, and every free DOF has mass.
    pub fn validate(&self, need_mass: bool) -> Result<(), EngineError> {
        let n = self.n_dofs();
        let rank: usize = self.forces.iter().map(|f| f.low_rank_rank()).sum();
        if rank > crate::linsolve::MAX_RANK {
            return Err(EngineError::LowRank {
                rank,
                max: crate::linsolve::MAX_RANK,
            });
        }
        for f in &self.forces {
            let dofs = f.stencils().iter().chain(f.low_rank_dofs());
            if let Some(&d) = dofs.into_iter().find(|&&d| d >= n) {
                return Err(EngineError::DofOutOfRange {
                    force: f.name().to_string(),
                    dof: d,
                    n,
                });
            }
        }
        if need_mass {
            for d in 0..n {
                let m = self.mass[d];
                if !(self.fixed[d] || m > 0.0 && m.is_finite()) {
                    return Err(EngineError::NonPositiveMass { dof: d, mass: m });
                }
            }
        }
        Ok(())
    }
    /// Let every force take its step-dependent stencils from the state a step of `dt` starts
    /// from ([`Force::begin_step`]); true when any stencils changed.
    pub fn begin_step(&mut self, q: &[f64], v: &[f64], dt: f64) -> bool {
        let mut changed = false;
        for f in &mut self.forces {
            changed |= f.begin_step(q, v, dt);
        }
        changed
    }
    /// Whether any force bounds the moves of the step solver's iterates ([`Force::max_step`]).
    pub fn bounds_steps(&self) -> bool {
        self.forces.iter().any(|f| f.bounds_steps())
    }
    /// The largest fraction of the move `dq` from `q` every force admits ([`Force::max_step`]).
    pub fn max_step(&self, q: &[f64], dq: &[f64], gap: f64) -> f64 {
        (self.forces.iter().filter(|f| f.bounds_steps()))
            .map(|f| f.max_step(q, dq, gap))
            .fold(1.0, f64::min)
    }
    /// Total potential energy of the conservative forces (J).
    pub fn energy(&self, q: &[f64]) -> f64 {
        self.forces.iter().filter_map(|f| f.energy(q)).sum()
    }
}

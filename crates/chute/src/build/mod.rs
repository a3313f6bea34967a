//! Builders: turn a validated [`Scenario`] into an engine model plus the bookkeeping the
//! observers need (which nodes are canopy, where the payload is, which forces are drag).

/// An engine model ready to run, with what observers and outputs need to know about it.
pub struct Built {
    /// The engine model (masses, fixed DOFs, forces).
    pub model: engine::Model,
    /// Initial state (at rest, flat canopy).
    pub state: engine::State,
    /// Canopy node indices (metrics are mass-weighted over these).
    pub canopy_nodes: Vec<usize>,
    /// The payload node, when the load hangs on lines.
    pub payload_node: Option<usize>,
    /// Canopy triangles (shell models; empty for rods).
    pub triangles: Vec<[usize; 3]>,
    /// Line segments drawn and written to VTK (rod canopy edges, suspension lines).
    pub segments: Vec<[usize; 2]>,
    /// Indices into `model.forces` of the drag families.
    pub drag_forces: Vec<usize>,
    /// Index into `model.forces` of the triangle drag family (per-triangle output).
    pub triangle_drag: Option<usize>,
    /// Total weight of everything that falls (N).
    pub total_weight_n: f64,
    /// Weight of the canopy alone (N).
    pub canopy_weight_n: f64,
    /// Σ C_D A of the flat canopy facing the flow (m²): flat terminal velocity reference.
    pub flat_drag_area_m2: f64,
    /// Reference length for the Reynolds number (m): the canopy's largest dimension.
    pub reference_length_m: f64,
    /// Derived quantities for `chute check` (name, value with units).
    pub derived: Vec<(String, String)>,
}

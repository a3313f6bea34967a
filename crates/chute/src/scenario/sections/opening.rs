//! `[contact]` and `[opening]`: self-contact of the canopy and its lines, and a canopy that
//! starts packed at line stretch (docs/opening.md).

use std::path::PathBuf;

use super::super::keys::{choice, key, section, when, Cond};

/// The condition of the start-mesh key.
const FROM_FILE: Cond = when("opening.pack", "mesh");

/// Default `contact.distance_m` over `canopy.edge_length_m`: half the spacing of the packed
/// canopy's gathered cloth at the default packed radius (a ring's nodes, about one edge apart
/// flat, are gathered to a tenth of that), so the packed canopy starts with no pair active.
pub const DISTANCE_PER_EDGE: f64 = 0.05;
/// Default `opening.packed_radius_m` over `canopy.radius_m`.
pub const PACKED_RADIUS_PER_RADIUS: f64 = 0.1;

choice! {
    /// How the packed canopy is folded.
    pub enum Packing {
        /// Every gore pulled down along the axis: the canopy a narrow cone from the apex to
        /// a skirt of `packed_radius_m`.
        Pulled = "pulled",
        /// The gores gathered into lobes around the axis: the cone's cross-section a star
        /// with one lobe per load site.
        Bundle = "bundle",
        /// Every canopy node where `opening.mesh_file` puts it (the flat mesh folded).
        Mesh = "mesh",
    }
}

section! {
    /// `[contact]`: the canopy's cloth and its lines never pass through each other (an
    /// incremental-potential barrier; absent: no contact, as in the report).
    pub struct Contact {
        /// activation distance √d̂: parts of the canopy or lines closer than this repel
        #[serde(skip_serializing_if = "Option::is_none")]
        distance_m: Option<f64> = None => key()
            .unit("m")
            .positive("a distance")
            .default_doc("`canopy.edge_length_m` / 20")
            .note("< `canopy.edge_length_m` / 2 (nodes of one triangle are not a contact)"),
        /// the barrier's stiffness κ, as the approach speed at which a canopy node is
        /// stopped at a tenth of `distance_m`
        stop_speed_mps: f64 = 10.0 => key().unit("m/s").positive("a speed"),
    }
}

section! {
    /// `[opening]`: the canopy starts packed, at line stretch, moving at
    /// `canopy.initial_velocity_mps` (absent: flat, as in the report).
    pub struct Opening {
        /// how the canopy is packed
        pack: Packing = Packing::Pulled => key().required(
            "say how the canopy is packed: `pack = \"pulled\"`, \"bundle\" or \"mesh\""
        ),
        /// `pack = "mesh"`: the start's canopy (`.obj` or DisMech `.txt`): the canopy mesh's
        /// nodes in its order, folded, with its triangles; relative paths resolve against
        /// the scenario file's directory (stored absolute)
        #[serde(skip_serializing_if = "Option::is_none")]
        mesh_file: Option<PathBuf> = None => key()
            .only_with(FROM_FILE, "")
            .required_with(FROM_FILE, "reads the folded canopy from a mesh file (.obj or .txt)")
            .note("the canopy's nodes and triangles, folded"),
        /// radius of the packed canopy's skirt around its axis
        #[serde(skip_serializing_if = "Option::is_none")]
        packed_radius_m: Option<f64> = None => key()
            .unit("m")
            .positive("a radius")
            .default_doc("`canopy.radius_m` / 10")
            .note("< `canopy.radius_m` / 2"),
        /// the packed canopy's axis tilted from the vertical (turned about the y axis through
        /// the apex, lines and payload with it; 0: apex straight up, payload below)
        attitude_deg: f64 = 0.0 => key()
            .unit("deg")
            .between(-90.0, 90.0, "a tilt from the vertical")
            .note("≠ 0 needs `fluid.inflation_speed = \"canopy\"`"),
    }
}

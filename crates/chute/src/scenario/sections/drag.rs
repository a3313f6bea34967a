//! The choices of the shell's drag law in `[fluid]` (docs/aero.md).

use super::super::keys::choice;

choice! {
    /// Shell drag model.
    pub enum ShellDrag {
        /// Report §II.D: normal (C_D) and tangential (C_t) quadratic drag per triangle.
        Report = "report",
        /// DisMech-style pressure drag on the normal velocity only, coefficient C_D.
        Pressure = "pressure",
        /// Inflation pressure C_D ½ρw² (w: descent speed through the air) on every triangle's
        /// inside normal whatever its angle to the flow (the trapped air of an inflated
        /// canopy), plus the report's tangential drag C_t.
        Inflation = "inflation",
        /// The inflation pressure plus a windward excess that gives the canopy the normal-force
        /// curve `incidence_cn` against `incidence_alpha_deg`: it swings and glides.
        Incidence = "incidence",
    }
}

choice! {
    /// The descent speed that sets the inflation pressure.
    pub enum InflationSpeed {
        /// Each triangle's own speed through the air (its centroid's).
        Panel = "panel",
        /// The canopy's: the rest-area-weighted mean of the triangles' velocities through
        /// the air, read at the start of each step and held over it.
        Canopy = "canopy",
    }
}

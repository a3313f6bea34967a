//! The canopy's normal-force table of `fluid.shell_drag = "incidence"`: read and checked
//! once, for the builder and the validator alike.

use super::error::Origin;
use super::sections::ShellDrag;
use super::source::Provenance;
use super::validate::Checker;
use super::Scenario;
use engine::aero::incidence::CurveError;
use engine::aero::IncidenceCurve;

/// The `C_N(α)` table of a scenario flown under the incidence law, or `None` under any
/// other law (or when the table is missing or invalid, which validation reports).
pub fn incidence_curve(s: &Scenario) -> Option<IncidenceCurve> {
    table(s)?.ok()
}

/// The table as the engine reads it, when the law wants one and both keys are set.
fn table(s: &Scenario) -> Option<Result<IncidenceCurve, CurveError>> {
    let f = &s.fluid;
    if f.shell_drag != ShellDrag::Incidence {
        return None;
    }
    let (a, c) = (f.incidence_alpha_deg.as_ref()?, f.incidence_cn.as_ref()?);
    Some(IncidenceCurve::try_from_degrees(a, c))
}

/// Report a table the engine refuses, naming the key the fault is in.
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    let Some(Err(e)) = table(s) else {
        return;
    };
    let f = &s.fluid;
    let key = match e {
        CurveError::Shape | CurveError::NotOdd { .. } => "fluid.incidence_cn",
        CurveError::NotFinite(i)
            if f.incidence_alpha_deg
                .as_ref()
                .is_some_and(|a| a[i].is_finite()) =>
        {
            "fluid.incidence_cn"
        }
        _ => "fluid.incidence_alpha_deg",
    };
    let value = match key {
        "fluid.incidence_cn" => format!("{:?}", f.incidence_cn.as_deref().unwrap_or_default()),
        _ => format!("{:?}", f.incidence_alpha_deg.as_deref().unwrap_or_default()),
    };
    c.fail(key, value, e.to_string());
}

/// The loader's warning about a tangential drag the incidence law does not add: its table is
/// the whole canopy's normal force, skin friction included.
pub(super) fn notes(s: &Scenario, prov: &Provenance, out: &mut Vec<String>) {
    if s.fluid.shell_drag == ShellDrag::Incidence
        && prov.origin("fluid.tangential_drag_coefficient") != Origin::Default
    {
        out.push(
            "fluid.tangential_drag_coefficient ignored: under fluid.shell_drag = \"incidence\" \
             the C_N(α) table is the whole canopy's normal force, skin friction included"
                .to_string(),
        );
    }
}

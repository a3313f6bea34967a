//! A study's objective (`minimise` in the study file): the complete case whose summary field,
//! or its magnitude, is smallest — e.g. `minimise = "|landing_velocity_mps|"` for the pull that
//! lands softest. The table's Markdown (and the console) name that case.
use super::table::{Row, Table};
use super::InputsState;
use super::{LANDING_COLUMNS, METRIC_COLUMNS};

/// What a study minimises.
#[derive(Debug, Clone, PartialEq)]
pub struct Objective {
    /// A numeric table column (a `summary.json` field).
    pub field: String,
    /// Minimise its magnitude `|x|` rather than `x`.
    pub magnitude: bool,
}

impl Objective {
    /// `field` or `|field|`, where `field` is a numeric table column; the error says which
    /// fields are allowed.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let (field, magnitude) = match t.strip_prefix('|').and_then(|r| r.strip_suffix('|')) {
            Some(inner) => (inner.trim(), true),
            None => (t, false),
        };
        let numeric = || {
            METRIC_COLUMNS
                .iter()
                .chain(LANDING_COLUMNS)
                .filter(|c| **c != "reached_terminal")
        };
        if !numeric().any(|c| *c == field) {
            let allowed: Vec<&str> = numeric().copied().collect();
            return Err(format!(
                "`minimise = \"{text}\"`: not a numeric column of the study table; give one of \
                 {allowed:?}, or its magnitude as `|name|`"
            ));
        }
        Ok(Self {
            field: field.to_string(),
            magnitude,
        })
    }

    /// As written: `field` or `|field|`.
    pub fn text(&self) -> String {
        if self.magnitude {
            format!("|{}|", self.field)
        } else {
            self.field.clone()
        }
    }

    /// The quantity minimised for `row`: a complete row, not run from inputs other than its
    /// study's now (stale), with a finite value.
    pub fn value(&self, row: &Row) -> Option<f64> {
        let x: f64 = row.metrics.get(&self.field)?.parse().ok()?;
        let x = if self.magnitude { x.abs() } else { x };
        let stale = matches!(row.inputs, InputsState::Changed(_));
        (row.complete && !stale && x.is_finite()).then_some(x)
    }
}

impl Table {
    /// The complete row that minimises the table's objective, and its value (the first of
    /// equal ones, in row order).
    pub fn best(&self) -> Option<(&Row, f64)> {
        let o = self.objective.as_ref()?;
        self.rows
            .iter()
            .filter_map(|r| o.value(r).map(|x| (r, x)))
            .fold(None, |best: Option<(&Row, f64)>, (r, x)| match best {
                Some((_, b)) if b <= x => best,
                _ => Some((r, x)),
            })
    }

    /// The Markdown line that names the best case, when the table has an objective.
    pub fn best_line(&self) -> Option<String> {
        let o = self.objective.as_ref()?;
        let what = format!("smallest `{}` of the complete, current cases", o.text());
        Some(match self.best() {
            None => format!(
                "**Best** ({what}): none: no complete case has `{}`",
                o.field
            ),
            Some((r, x)) => {
                let set: Vec<String> = r
                    .overrides
                    .iter()
                    .map(|(k, v)| format!("{k} = {v}"))
                    .collect();
                let set = if set.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", set.join(", "))
                };
                let sig4 = crate::scenario::derived::sig4;
                // What a landing study reads beside it: touchdown, flight time, line peak.
                let landing: Vec<String> = LANDING_COLUMNS
                    .iter()
                    .filter_map(|k| {
                        let v: f64 = r.metrics.get(*k)?.parse().ok()?;
                        Some(format!("{k} = {}", sig4(v)))
                    })
                    .collect();
                let landing = if landing.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", landing.join(", "))
                };
                format!("**Best** ({what}): `{}`{set}: {}{landing}", r.case, sig4(x))
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::CaseState;

    fn row(case: &str, v: &str, complete: bool) -> Row {
        Row {
            index: 0,
            case: case.into(),
            overrides: [("control[0].below_m".to_string(), case.to_string())].into(),
            metrics: [
                ("landing_velocity_mps".to_string(), v.to_string()),
                ("peak_line_tension_n".to_string(), "1129.4".to_string()),
            ]
            .into(),
            complete,
            state: if complete {
                CaseState::Complete
            } else {
                CaseState::Incomplete("stopped".into())
            },
            inputs: InputsState::Current,
        }
    }

    #[test]
    fn the_best_case_is_the_smallest_complete_value_or_magnitude() {
        let rows = vec![
            row("4", "-5.1", true),
            row("1", "-1.9", true),
            row("0.5", "-0.7", false), // smaller, but not complete
            row("2", "", true),        // no value
            row("3", "-1.9", true),    // equal: the first one stays
            row("0.7", "-0.1", true),  // smallest, but stale
        ];
        let mut rows = rows;
        rows[5].inputs = InputsState::Changed("its scenario changed".into());
        let mut t = Table {
            rows,
            objective: Some(Objective::parse("|landing_velocity_mps|").unwrap()),
            ..Table::default()
        };
        let (r, x) = t.best().unwrap();
        assert_eq!((r.case.as_str(), x), ("1", 1.9));
        let line = t.best_line().unwrap();
        assert!(
            line.ends_with(
                "`1` (control[0].below_m = 1): 1.900 (landing_velocity_mps = -1.900, \
                 peak_line_tension_n = 1129)"
            ),
            "{line}"
        );
        assert!(t.to_markdown().ends_with(&format!("\n{line}\n")));
        // The signed value: the most negative.
        t.objective = Some(Objective::parse("landing_velocity_mps").unwrap());
        assert_eq!(t.best().unwrap().0.case, "4");
        t.rows.retain(|r| !r.complete);
        assert!(t.best_line().unwrap().contains("none: no complete case"));
        t.objective = None;
        assert_eq!(t.best_line(), None);
    }

    #[test]
    fn only_numeric_columns_can_be_minimised() {
        let o = Objective::parse(" |flight_time_s| ").unwrap();
        assert_eq!(
            (o.field.as_str(), o.magnitude, o.text()),
            ("flight_time_s", true, "|flight_time_s|".to_string())
        );
        for bad in ["reached_terminal", "wall_time_s", "|nothing|", ""] {
            let e = Objective::parse(bad).unwrap_err();
            assert!(
                e.contains("not a numeric column") && e.contains("peak_line_tension_n"),
                "{e}"
            );
        }
    }
}

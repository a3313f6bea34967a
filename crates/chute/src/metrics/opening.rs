//! The opening of a packed canopy (`[opening]`): the opening shock and how long and how far
//! the canopy takes to fill, in the terms of the recovery handbooks (Knacke, *Parachute
//! Recovery Systems Design Manual*, NWC TP 6575, ch. 5). Definitions in docs/opening.md.

use super::descent::window_mean;

/// The canopy is filled once its projected diameter first reaches this fraction of its
/// steady value (the handbook's "first full inflation", with a margin so that a canopy that
/// approaches its steady diameter from below has a defined fill time).
pub const FILLED: f64 = 0.95;

/// What the opening metrics need besides the series.
#[derive(Debug, Clone, Copy)]
pub struct OpeningParams {
    /// Nominal diameter D₀ = 2R of the flat canopy (m).
    pub nominal_diameter_m: f64,
    /// Dynamic pressure at line stretch, ½ ρ v₀² at the start (Pa).
    pub line_stretch_pressure_pa: f64,
}

/// The opening fields of `summary.json`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Opening {
    /// Largest force of the lines on the payload (N).
    pub peak_force_n: Option<f64>,
    /// `F_peak / (C_D S · q)` with the steady drag area and `q` at line stretch: Knacke's
    /// `C_x X₁`.
    pub load_factor: Option<f64>,
    /// From line stretch (t = 0) to the first time the projected diameter reaches
    /// [`FILLED`] of its steady value (s).
    pub fill_time_s: Option<f64>,
    /// The canopy's fall over the fill time, in nominal diameters.
    pub fill_distance_diameters: Option<f64>,
}

/// The opening metrics from the series `t` (s), canopy height `z` (m) and projected diameter
/// `d` (m), the exact peak line force (N), the steady drag area (m², none when the descent
/// did not settle) and the final window's start (s).
pub fn compute(
    (t, z, d): (&[f64], &[f64], &[f64]),
    peak_force_n: Option<f64>,
    drag_area_m2: Option<f64>,
    window_start_s: f64,
    p: &OpeningParams,
) -> Opening {
    let mut o = Opening {
        peak_force_n,
        ..Default::default()
    };
    let q = p.line_stretch_pressure_pa;
    if let (Some(f), Some(cds)) = (peak_force_n, drag_area_m2) {
        o.load_factor = (q > 0.0 && cds > 0.0).then(|| f / (cds * q));
    }
    if t.len() < 2 || drag_area_m2.is_none() {
        return o;
    }
    let steady = window_mean(t, d, window_start_s);
    let level = FILLED * steady;
    let Some(i) = d.iter().position(|&x| x >= level).filter(|&i| i > 0) else {
        return o;
    };
    let a = (level - d[i - 1]) / (d[i] - d[i - 1]);
    let t_fill = t[i - 1] + a * (t[i] - t[i - 1]);
    let z_fill = z[i - 1] + a * (z[i] - z[i - 1]);
    o.fill_time_s = Some(t_fill - t[0]);
    o.fill_distance_diameters = Some((z[0] - z_fill).abs() / p.nominal_diameter_m);
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A canopy whose diameter grows linearly from 0.5 m to 3 m over 0.2 s while falling at
    /// 20 m/s, then holds: it is filled at 95 % of 3 m, t = 0.2 (2.85 − 0.5)/2.5 = 0.188 s,
    /// 3.76 m down (1.253 diameters of 3 m); a 1200 N peak against C_D S q = 5 m² × 200 Pa
    /// is a factor 1.2.
    #[test]
    fn fill_time_distance_and_factor_of_a_linear_opening() {
        let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 1e-3).collect();
        let z: Vec<f64> = t.iter().map(|t| -20.0 * t).collect();
        let d: Vec<f64> = t.iter().map(|&t| 0.5 + 2.5 * (t / 0.2).min(1.0)).collect();
        let p = OpeningParams {
            nominal_diameter_m: 3.0,
            line_stretch_pressure_pa: 200.0,
        };
        let o = compute((&t, &z, &d), Some(1200.0), Some(5.0), 0.8, &p);
        let want = 0.2 * (2.85 - 0.5) / 2.5;
        assert!((o.fill_time_s.unwrap() - want).abs() < 1e-12, "{o:?}");
        assert!((o.fill_distance_diameters.unwrap() - 20.0 * want / 3.0).abs() < 1e-12);
        assert!((o.load_factor.unwrap() - 1.2).abs() < 1e-12);
        // No steady descent: no fill time, no factor.
        let o = compute((&t, &z, &d), Some(1200.0), None, 0.8, &p);
        assert_eq!((o.fill_time_s, o.load_factor), (None, None));
    }
}

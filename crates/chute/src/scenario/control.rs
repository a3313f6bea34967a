//! The cross-key rules of line pulls (`[[control]]`), their sensors (`[[sensor]]`) and
//! guidance (`[guidance]`): line indices against the number of suspension lines, the 10 %
//! floor on a pulled line's length, pulls on one line that overlap in time, and the sensor a
//! pull names (the declared rules already make the times and ramps non-negative and the
//! sections payload-only).

use super::validate::Checker;
use super::{CanopyShape, LoadMode, ModelKind, Scenario, SiteSet, Sites};

/// A pull may leave a line no shorter than this fraction of its length.
pub const MIN_LINE_FRACTION: f64 = 0.1;

/// The number of suspension lines (one per load site) as the scenario declares them; the
/// builder checks again after resolving sites to nodes (two points may share a node).
pub fn declared_line_count(s: &Scenario) -> usize {
    match &s.load.sites {
        Sites::Points(p) => p.len(),
        Sites::Named(set) => match (set, s.model.kind, s.canopy.shape) {
            (SiteSet::Ends, ..) => 2,
            (SiteSet::Center, ..) => 1,
            (SiteSet::Rim, ..) => s.load.rim_site_count,
            (SiteSet::Corners, ModelKind::Shell, CanopyShape::Hexagon) => 6,
            (SiteSet::Corners, ..) => 4,
            (SiteSet::CornersAndMidspan, ..) => 6,
        },
    }
}

/// Check the pulls and the guidance of `s` (only in payload mode: elsewhere the declared
/// "only with" rule has refused them).
pub(super) fn check(c: &mut Checker, s: &Scenario) {
    if s.load.mode != LoadMode::Payload {
        return;
    }
    sensors(c, s);
    let n = declared_line_count(s);
    let floor = (1.0 - MIN_LINE_FRACTION) * s.lines.length_m;
    for (i, p) in s.control.iter().enumerate() {
        let key = |k: &str| format!("control[{i}].{k}");
        lines(c, &key("lines"), &p.lines, n);
        trigger(c, s, i);
        if p.shorten_m > floor {
            c.fail(
                &key("shorten_m"),
                p.shorten_m,
                format!(
                    "would leave a line shorter than {:.0} % of its {} m (`lines.length_m`): at \
                     most {floor}",
                    100.0 * MIN_LINE_FRACTION,
                    s.lines.length_m
                ),
            );
        }
        for (j, q) in s.control[..i].iter().enumerate() {
            let shared = p.lines.iter().find(|l| q.lines.contains(l));
            if let Some(line) = shared.filter(|_| overlap(q, p)) {
                c.fail(
                    &key("start_s"),
                    p.start_s,
                    format!(
                        "this pull on line {line} overlaps control[{j}] (from {} s to {}): \
                         pulls on one line must follow each other (start after the other's \
                         release ends; a sensor's pull may start at any time after its \
                         `start_s`)",
                        q.start_s,
                        end_text(q)
                    ),
                );
            }
        }
    }
    if let Some(g) = &s.guidance {
        if s.atmosphere.ground_altitude_m.is_none() {
            c.fail(
                "guidance.target_m",
                format!("{:?}", g.target_m),
                "guidance steers to a point on the ground: set `atmosphere.ground_altitude_m` \
                 (with `atmosphere.model = \"isa1976\"`)",
            );
        }
        if g.target_m.len() != 2 {
            c.fail(
                "guidance.target_m",
                format!("{:?}", g.target_m),
                "must be two numbers [x, y] (m)",
            );
        }
        let scheduled = s.control.iter().map(|p| p.shorten_m).fold(0.0, f64::max);
        if g.max_pull_m + scheduled > floor {
            c.fail(
                "guidance.max_pull_m",
                g.max_pull_m,
                format!(
                    "with the largest `[[control]]` pull ({scheduled} m) it would leave a line \
                     shorter than {:.0} % of its {} m: at most {} in all",
                    100.0 * MIN_LINE_FRACTION,
                    s.lines.length_m,
                    floor
                ),
            );
        }
        if crate::control::response::Response::of(g.pull_side, s.canopy.shape, s.fluid.shell_drag)
            .is_none()
        {
            c.fail(
                "guidance.pull_side",
                g.pull_side.name(),
                format!(
                    "no response to line pulls is measured for a `{}` canopy under \
                     fluid.shell_drag = `{}`: set `towards` or `away` (measure it with a \
                     `[[control]]` pull, docs/control.md)",
                    s.canopy.shape.name(),
                    s.fluid.shell_drag.name()
                ),
            );
        }
        if g.ramp_s > g.update_s {
            c.fail(
                "guidance.ramp_s",
                g.ramp_s,
                format!(
                    "must be ≤ `guidance.update_s` = {} s (one ramp per decision)",
                    g.update_s
                ),
            );
        }
    }
}

fn lines(c: &mut Checker, key: &str, lines: &[usize], n: usize) {
    if lines.is_empty() {
        c.fail(key, "[]", "name at least one line");
    }
    if let Some(&l) = lines.iter().find(|&&l| l >= n) {
        c.fail(
            key,
            format!("{lines:?}"),
            format!(
                "line {l} does not exist: the load sites give {n} lines, 0 … {}",
                n - 1
            ),
        );
    }
    if let Some((k, &l)) = lines
        .iter()
        .enumerate()
        .find(|(k, l)| lines[..*k].contains(l))
    {
        c.fail(
            key,
            format!("{lines:?}"),
            format!("line {l} is named twice (entry {k})"),
        );
    }
}

/// End of a pull's release (s), infinite when it is held to the end or started by a sensor
/// (which may start it at any time).
fn end(p: &super::Control) -> f64 {
    match (p.hold_s, &p.sensor) {
        (Some(h), None) => p.start_s + 2.0 * p.ramp_s + h,
        _ => f64::INFINITY,
    }
}

fn end_text(p: &super::Control) -> String {
    match (p.hold_s, &p.sensor) {
        (_, Some(name)) => format!("whenever sensor `{name}` fires it"),
        (Some(_), None) => format!("{} s", end(p)),
        (None, None) => "the end, never released".into(),
    }
}

/// The sensors' names are unique and plain, their samples over the run are bounded like its
/// steps (a typo of a rate would run for ever), and a height needs the ground.
fn sensors(c: &mut Checker, s: &Scenario) {
    for (j, sn) in s.sensor.iter().enumerate() {
        if !name_ok(&sn.name) {
            c.fail(
                &format!("sensor[{j}].name"),
                format!("{:?}", sn.name),
                "name the sensor, with no leading or trailing space",
            );
        }
        let samples = sn.rate_hz * s.time.duration_s;
        if samples > super::validate::MAX_STEPS {
            c.fail(
                &format!("sensor[{j}].rate_hz"),
                sn.rate_hz,
                format!(
                    "{} samples over time.duration_s = {} s; at most {}",
                    super::derived::sig4(samples),
                    s.time.duration_s,
                    super::derived::sig4(super::validate::MAX_STEPS)
                ),
            );
        }
        if let Some(k) = s.sensor[..j].iter().position(|o| o.name == sn.name) {
            c.fail(
                &format!("sensor[{j}].name"),
                &sn.name,
                format!("sensor[{k}] has this name already: names must be unique"),
            );
        }
        if s.atmosphere.ground_altitude_m.is_none() {
            c.fail(
                &format!("sensor[{j}].reads"),
                sn.reads.name(),
                "a height is measured above the ground: set `atmosphere.ground_altitude_m`",
            );
        }
    }
}

/// A pull's sensor exists and has a threshold; a clock pull has none.
fn trigger(c: &mut Checker, s: &Scenario, i: usize) {
    let p = &s.control[i];
    let key = |k: &str| format!("control[{i}].{k}");
    match (&p.sensor, p.below_m) {
        (Some(name), below) => {
            // A sensor with a bad name has its own error: the reference is not the culprit.
            let named = s.sensor.iter().all(|sn| name_ok(&sn.name));
            if named && !s.sensor.iter().any(|sn| &sn.name == name) {
                let known: Vec<&str> = s.sensor.iter().map(|sn| sn.name.as_str()).collect();
                let have = if known.is_empty() {
                    "no `[[sensor]]` is declared".to_string()
                } else {
                    format!("the sensors are {known:?}")
                };
                c.fail(
                    &key("sensor"),
                    name,
                    format!("no sensor has this name: {have}"),
                );
            }
            if below.is_none() {
                c.fail(
                    &key("sensor"),
                    name,
                    "say at which reading the pull starts, e.g. `below_m = 10.0`",
                );
            }
        }
        (None, Some(b)) => c.fail(
            &key("below_m"),
            b,
            "is only used with `sensor` (the reading that starts the pull): name one, or \
             remove `below_m` to start the pull by the clock at `start_s`",
        ),
        (None, None) => {}
    }
}

/// A sensor's name: not empty, no leading or trailing space.
fn name_ok(name: &str) -> bool {
    !name.is_empty() && name.trim() == name
}

/// Sensors that no pull reads (they do nothing), and sensor pulls whose threshold the
/// release height already meets (they fire at the first sample) or a noise-free height never
/// reaches (below the ground).
pub fn sensor_warnings(s: &Scenario) -> Vec<String> {
    let unused = s
        .sensor
        .iter()
        .enumerate()
        .filter(|(_, sn)| !s.control.iter().any(|p| p.sensor.as_ref() == Some(&sn.name)))
        .map(|(j, sn)| {
            format!(
                "sensor[{j}] `{}` is read by no `[[control]]` pull (`sensor = \"{}\"`): it does nothing",
                sn.name, sn.name
            )
        });
    let release = s
        .atmosphere
        .ground_altitude_m
        .map(|g| s.atmosphere.altitude_m - g);
    let thresholds = s.control.iter().enumerate().filter_map(|(i, p)| {
        let (below, name) = (p.below_m?, p.sensor.as_ref()?);
        let noisy = s
            .sensor
            .iter()
            .any(|sn| &sn.name == name && sn.noise_m > 0.0);
        match release {
            Some(h) if below >= h => Some(format!(
                "control[{i}].below_m = {below} m is at or above the release height ({h} m above \
                 the ground, the canopy's plane): the pull fires at the first sample after \
                 its start_s"
            )),
            _ if below < 0.0 && !noisy => Some(format!(
                "control[{i}].below_m = {below} m is below the ground, which ends the run: a \
                 noise-free sensor never fires it"
            )),
            _ => None,
        }
    });
    unused.chain(thresholds).collect()
}

/// Whether two pulls act on a line at the same time (one may start where the other ends).
fn overlap(a: &super::Control, b: &super::Control) -> bool {
    a.start_s < end(b) && b.start_s < end(a)
}

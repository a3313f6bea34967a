//! Line pulls: the rest-length schedule of each suspension line from `[[control]]` and
//! `[guidance]` (engine: `rod::stretch`), and what the outputs and the controller need to
//! know about the lines afterwards.
use std::ops::Range;

use super::BuildError;
use crate::resolve::ModelSpec;
use crate::scenario::control::MIN_LINE_FRACTION;
use engine::rod::{Pull, RestSchedule, RodHandles, StretchHistory, TriggeredPull};
use engine::{ForceId, Model};

/// The schedule of line `line` (0-based, in site order) of `s`: its clock pulls, and its
/// sensor pulls as triggered pulls (not fired) whose `source` is the `[[control]]` index.
pub fn schedule(s: &ModelSpec, line: usize) -> RestSchedule {
    let on_line = || {
        s.control
            .iter()
            .enumerate()
            .filter(|(_, c)| c.lines.contains(&line))
    };
    let pull = |c: &crate::scenario::Control| Pull {
        start: c.start_s,
        ramp: c.ramp_s,
        shorten: c.shorten_m,
        hold: c.hold_s,
    };
    RestSchedule {
        pulls: on_line()
            .filter(|(_, c)| c.sensor.is_none())
            .map(|(_, c)| pull(c))
            .collect(),
        command_ramp: s.guidance.as_ref().map_or(0.0, |g| g.ramp_s),
        triggered: on_line()
            .filter(|(_, c)| c.sensor.is_some())
            .map(|(i, c)| TriggeredPull {
                pull: pull(c),
                source: i,
                fired: None,
            })
            .collect(),
    }
}

/// Refuse pulls the scenario check could not see: a line index beyond the lines the sites
/// resolved to (two points on one node make one line), and a pull leaving a line (whose
/// length is that from its site to the payload) below 10 % of it.
pub fn check(s: &ModelSpec, line_lengths: &[f64]) -> Result<(), BuildError> {
    let n = line_lengths.len();
    for (i, c) in s.control.iter().enumerate() {
        if let Some(&l) = c.lines.iter().find(|&&l| l >= n) {
            return Err(BuildError::key(
                format!("control[{i}].lines"),
                format!(
                    "line {l} does not exist: the load sites resolved to {n} lines, 0 … {}",
                    n - 1
                ),
            ));
        }
        let pull = c.shorten_m + s.guidance.as_ref().map_or(0.0, |g| g.max_pull_m);
        for &l in &c.lines {
            let len = line_lengths[l];
            if pull > (1.0 - MIN_LINE_FRACTION) * len {
                return Err(BuildError::key(
                    format!("control[{i}].shorten_m"),
                    format!(
                        "line {l} is {len:.4} m long (site to payload): a pull of {pull} m \
                         (with any guidance) would leave less than {:.0} % of it",
                        100.0 * MIN_LINE_FRACTION
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// One suspension line of the built model.
#[derive(Debug, Clone)]
pub struct Line {
    /// Its network edges, site end first.
    pub edges: Range<usize>,
    /// Node pair of each of those edges.
    pub nodes: Vec<[usize; 2]>,
    /// Axial stiffness E A (N).
    pub stiffness_n: f64,
    /// Initial rest length L₀ (m).
    pub rest_len_m: f64,
    /// Rest length of each edge at zero shortening (m).
    pub edge_rest_m: Vec<f64>,
    /// Its schedule and the schedule's index in the stretching family, when pulled.
    pub schedule: Option<(RestSchedule, usize)>,
    /// The canopy node it hangs from.
    pub site: usize,
}

/// The suspension lines and the force that holds their schedules.
#[derive(Debug, Clone)]
pub struct Lines {
    /// The lines, in site order.
    pub lines: Vec<Line>,
    /// The rod stretching family (its history holds the guidance commands).
    pub stretch: ForceId,
}

impl Lines {
    /// Collect the lines `line_rods` (site order) after the rods are installed.
    pub fn new(
        handles: &RodHandles,
        line_rods: &[usize],
        sites: &[usize],
        stiffness_n: f64,
    ) -> Option<Self> {
        let stretch = handles.stretch?;
        let lines = line_rods
            .iter()
            .zip(sites)
            .map(|(&r, &site)| {
                let edges = handles.rod_edges[r].clone();
                let edge_rest_m = handles.rest_len[edges.clone()].to_vec();
                Line {
                    nodes: handles.edges[edges.clone()].to_vec(),
                    rest_len_m: edge_rest_m.iter().sum(),
                    edge_rest_m,
                    edges,
                    stiffness_n,
                    schedule: None,
                    site,
                }
            })
            .collect();
        Some(Self { lines, stretch })
    }

    /// The schedules, in the order of their index in the stretching family.
    fn schedules(&self) -> Vec<&RestSchedule> {
        let mut by_index: Vec<(usize, &RestSchedule)> = self
            .lines
            .iter()
            .filter_map(|l| l.schedule.as_ref().map(|(s, k)| (*k, s)))
            .collect();
        by_index.sort_by_key(|&(k, _)| k);
        by_index.into_iter().map(|(_, s)| s).collect()
    }

    /// The controller's commands and the triggers' firings (the family's history).
    pub fn history(&self, model: &Model) -> StretchHistory {
        let n = self.schedules().len();
        StretchHistory::decode(&model.force(self.stretch).history(), n)
    }

    /// Set the history of the stretching family (commands and firings).
    pub fn set_history(&self, model: &mut Model, h: &StretchHistory) {
        model
            .force_mut(self.stretch)
            .restore_history(&h.encode())
            .expect("one command per schedule, one firing per triggered pull");
    }

    /// The `[[control]]` index of each triggered pull, in the order of the history's firings.
    pub fn firing_sources(&self) -> Vec<usize> {
        let schedules = self.schedules();
        schedules
            .iter()
            .flat_map(|s| &s.triggered)
            .map(|p| p.source)
            .collect()
    }

    /// Rest length (m), length (m) and tension at the site end (N) of every line at `q`, `t`,
    /// under the history `h`.
    pub fn sample(&self, q: &[f64], t: f64, h: &StretchHistory) -> Vec<[f64; 3]> {
        let mut fired: Vec<RestSchedule> = self.schedules().into_iter().cloned().collect();
        h.apply_firings(&mut fired);
        self.lines
            .iter()
            .map(|l| {
                let s = l
                    .schedule
                    .as_ref()
                    .map_or(0.0, |(_, k)| fired[*k].shortening(t, &h.commands[*k]));
                let len = |[a, b]: [usize; 2]| {
                    (0..3)
                        .map(|c| (q[3 * b + c] - q[3 * a + c]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                };
                let length: f64 = l.nodes.iter().map(|&e| len(e)).sum();
                let top_rest = l.edge_rest_m[0] * (1.0 - s / l.rest_len_m);
                let tension = l.stiffness_n * (len(l.nodes[0]) / top_rest - 1.0);
                [l.rest_len_m - s, length, tension]
            })
            .collect()
    }
}

/// `chute check`'s lines on the pulls, the sensors and the guidance of `s`.
pub fn describe(s: &crate::scenario::Scenario) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = s
        .control
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let verb = if c.shorten_m >= 0.0 {
                "shorten"
            } else {
                "lengthen"
            };
            let ramp = if c.ramp_s > 0.0 {
                format!("over {} s", c.ramp_s)
            } else {
                "at once".into()
            };
            let release = match c.hold_s {
                Some(h) => format!(
                    ", held {h} s, released by {} s",
                    c.start_s + 2.0 * c.ramp_s + h
                ),
                None => ", never released".into(),
            };
            let when = match (&c.sensor, c.below_m) {
                (Some(name), Some(b)) => format!(
                    "when sensor `{name}` reads ≤ {b} m (from {} s, after its latency)",
                    c.start_s
                ),
                _ => format!("from {} s", c.start_s),
            };
            (
                format!("pull control[{i}]"),
                format!(
                    "lines {:?}: {verb} by {} m {when} {ramp}{release}",
                    c.lines,
                    c.shorten_m.abs(),
                ),
            )
        })
        .collect();
    out.extend(s.sensor.iter().map(|sn| {
        (
            format!("sensor `{}`", sn.name),
            format!(
                "{} above the ground, {} Hz, latency {} s, noise σ = {} m (seed {})",
                sn.reads.name(),
                sn.rate_hz,
                sn.latency_s,
                sn.noise_m,
                sn.seed
            ),
        )
    }));
    if let Some(g) = &s.guidance {
        out.push((
            "guidance".into(),
            format!(
                "to [{}, {}] m: pull ≤ {} m = {} × predicted miss, every {} s over {} s, \
                 pull side by `{}`",
                g.target_m[0],
                g.target_m[1],
                g.max_pull_m,
                g.gain,
                g.update_s,
                g.ramp_s,
                g.pull_side.name()
            ),
        ));
    }
    out
}

//! A study case continued by `chute resume`: what its `done.json` then says.

use std::path::Path;

use super::table::{read_json, write_atomic};
use super::DONE_FILE;
use crate::app::{AppError, RunOutcome};

/// After `chute resume` of a study case's directory `dir`: its `done.json` (when it has one)
/// says how the resumed run ended, and its wall time grows by `wall_s`; a resume that
/// extended the run to `extended_to` seconds records inputs no study has, so the case is
/// never taken as current again. A resume refused as bad input changed nothing and leaves
/// the marker as it was.
pub fn mark_resumed(
    dir: &Path,
    result: &Result<RunOutcome, AppError>,
    wall_s: f64,
    extended_to: Option<f64>,
) -> Result<(), AppError> {
    let done = dir.join(DONE_FILE);
    let Some(mut marker) = read_json(&done) else {
        return Ok(());
    };
    let (word, message) = match result {
        Ok(o) if o.complete => ("complete", None),
        Ok(o) => ("incomplete", o.message.clone()),
        Err(e @ AppError::RunFailed(_)) => ("incomplete", Some(e.to_string())),
        Err(e @ AppError::Io { .. }) => ("failed", Some(e.to_string())),
        Err(_) => return Ok(()),
    };
    marker["status"] = word.into();
    marker["message"] = message.into();
    if let Some(d) = extended_to {
        // Not the study's case any more: never current, so a study re-runs it.
        marker["inputs"] = format!("extended by chute resume to time.duration_s = {d}").into();
    }
    // The resumed run wrote its own summary.
    marker["summary_digest"] = super::summary_digest(dir).into();
    let wall = marker["wall_time_s"].as_f64().unwrap_or(0.0) + wall_s;
    marker["wall_time_s"] = wall.into();
    write_atomic(&done, format!("{marker:#}\n").as_bytes())
}

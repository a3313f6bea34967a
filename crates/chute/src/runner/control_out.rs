//! The run loop's line-pull outputs: `lines.csv` and `track.csv` at every frame and at the
//! end, `track.png` at the end (`output::control_files`). Only runs whose lines are pulled
//! (`[[control]]` or `[guidance]`) write them.
use std::path::Path;

use super::{io_err, RunError};
use crate::build::Built;
use crate::output::control_files::{track_plot, ControlFiles, TRACK_PNG};

/// The streamed files and the time of their last rows.
pub(super) struct Recorder {
    files: ControlFiles,
    last_t: Option<f64>,
}

impl Recorder {
    /// The recorder of `built`, or `None` when no line is pulled; `t_resume` cuts the files
    /// back to a checkpoint's time.
    pub fn open(
        built: &Built,
        out_dir: &Path,
        t_resume: Option<f64>,
    ) -> Result<Option<Self>, RunError> {
        let pulled = built
            .lines
            .as_ref()
            .is_some_and(|l| l.lines.iter().any(|x| x.schedule.is_some()));
        if !pulled {
            return Ok(None);
        }
        let files = ControlFiles::open(out_dir, t_resume).map_err(io_err(out_dir))?;
        Ok(Some(Self {
            files,
            last_t: t_resume,
        }))
    }

    /// The rows of the current state (once per time).
    pub fn push(&mut self, b: &Built, out_dir: &Path) -> Result<(), RunError> {
        let (Some(lines), Some(p)) = (&b.lines, b.payload_node) else {
            return Ok(());
        };
        let s = &b.state;
        if self.last_t == Some(s.t) {
            return Ok(());
        }
        self.last_t = Some(s.t);
        let rows = lines.sample(&s.q, s.t, &lines.history(&b.model));
        let payload = [s.q[3 * p], s.q[3 * p + 1], s.q[3 * p + 2]];
        self.files
            .push(s.t, &rows, payload)
            .map_err(io_err(out_dir))
    }

    /// `track.png` (best effort, like the other plots).
    pub fn plot(&self, out_dir: &Path, target: Option<[f64; 2]>, landing: Option<[f64; 2]>) {
        if let Ok(track) = self.files.track() {
            let _ = track_plot(&out_dir.join(TRACK_PNG), &track, target, landing);
        }
    }
}

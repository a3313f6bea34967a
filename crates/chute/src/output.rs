//! Files written by a run: the streamed time series, the summary, ParaView frames, plots and
//! the browser viewer; and the console summary printed for people.
//!
//! Every file written in one go goes through [`atomic::write_atomic`] so a crash never leaves a
//! half-written file; the time series is streamed and is a valid CSV prefix after every flush.
//! The file layout and every column/field are documented in `docs/outputs.md`.

pub mod atomic;
pub mod console;
pub mod control_files;
pub mod footprint_html;
pub mod footprint_plot;
pub mod lock;
pub mod mode_viewer;
pub mod plots;
pub mod record;
pub mod run_dir;
pub mod run_files;
pub mod scene3d;
pub mod summary;
pub mod timeseries;
pub mod trash;
pub mod viewer;
pub mod vtk;

pub use atomic::write_atomic;
pub use summary::{RunInfo, SolverCounters, Stepping, Summary};
pub use timeseries::{canopy_means, CanopyMeans, DecimatedSeries, Sample, TimeSeriesWriter};
pub use vtk::VtkSeries;

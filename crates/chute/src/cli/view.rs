//! `chute view`: write a run directory's `viewer.html` ([`crate::api::view`]) and say what it
//! holds, and when the run there did not finish.

use super::ViewArgs;
use crate::api::AppError;

pub(super) fn cmd_view(a: &ViewArgs) -> Result<(), AppError> {
    let v = crate::api::view(&a.run_dir)?;
    let r = &v.report;
    crate::out_line!(
        "wrote {} ({} bytes: {} of {} frames, {} triangles)",
        r.path.display(),
        r.bytes,
        r.frames_embedded,
        r.frames_total,
        r.triangles
    );
    if let Some(why) = v.unfinished {
        crate::err_line!(
            "note: `{}` holds an unfinished run: {why}",
            a.run_dir.display()
        );
    }
    Ok(())
}

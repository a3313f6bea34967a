"""chute.Result: summary, timeseries and frames as Python objects and numpy arrays of the
right shapes and dtypes; the temporary output directory lives as long as the Result."""

import gc

import numpy as np

import chute
from conftest import ROD, ROD_SET, SHELL, SHELL_SET


def test_timeseries_and_frames_shapes_and_dtypes():
    r = chute.run(SHELL, set=SHELL_SET)
    s = r.summary
    assert s["complete"] is True and s["scenario_name"] == "report-shell-4-sites"
    header = (r.out_dir / "timeseries.csv").read_text().splitlines()[0].split(",")
    ts = r.timeseries
    assert list(ts) == header
    for name, col in ts.items():
        assert col.ndim == 1 and len(col) == s["steps"] + 1, name
        want = np.int64 if name == "newton_iterations" else np.float64
        assert col.dtype == want, name
    assert ts["t_s"][0] == 0.0 and ts["t_s"][-1] == s["simulated_time_s"]
    f = r.frames
    n_frames = round(SHELL_SET["time.duration_s"] / SHELL_SET["output.frame_interval_s"]) + 1
    assert f.times.shape == (n_frames,) and f.times.dtype == np.float64
    assert np.allclose(f.times, np.arange(n_frames) * SHELL_SET["output.frame_interval_s"])
    n = f.positions.shape[1]
    assert f.positions.shape == (n_frames, n, 3) and f.velocities.shape == (n_frames, n, 3)
    assert f.positions.dtype == np.float64
    assert f.triangles.shape[1] == 3 and f.triangles.dtype == np.int64
    assert np.all(f.positions[0, :, 2] == 0.0)  # flat at t = 0
    sim = chute.Simulation(SHELL, set=SHELL_SET)
    assert np.array_equal(f.triangles, sim.triangles)
    assert "complete" in repr(r) and "report-shell-4-sites" in repr(r)


def test_the_temporary_directory_lives_as_long_as_the_result():
    r = chute.run(ROD, set={**ROD_SET, "time.duration_s": 0.02})
    d = r.out_dir
    assert (d / "summary.json").exists() and (d / "viewer.html").exists()
    del r
    gc.collect()
    assert not d.exists()
    r = chute.run(ROD, set={**ROD_SET, "time.duration_s": 0.02}, viewer=False)
    assert not (r.out_dir / "viewer.html").exists()
    r.cleanup()
    assert not r.out_dir.exists()


def test_progress_bar_is_drawn_on_stderr(capsys):
    chute.run(ROD, set={**ROD_SET, "time.duration_s": 0.02}, progress=True)
    err = capsys.readouterr().err
    # Redrawn every 0.1 s and once at the end, on one line.
    assert err.startswith("\r[") and err.endswith("\n")
    assert "100%  t = 0.020 / 0.02 s" in err.rsplit("\r", 1)[-1]


def test_progress_bar_text():
    import io

    from chute._progress import ProgressBar

    out = io.StringIO()
    bar = ProgressBar(out)
    bar(2.5, 10.0)
    bar.close()
    text = out.getvalue()
    assert text.startswith("\r[" + "#" * 8 + "-" * 22 + "]  25%  t = 2.500 / 10 s")
    assert text.endswith("\n")

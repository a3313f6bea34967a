"""Ctrl-C: SIGINT to a process inside a long chute.run stops the run at its next step with
valid partial outputs (KeyboardInterrupt carries them); inside Simulation.step it leaves the
state after the last whole step."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

from conftest import ROD

# Long enough never to finish before the signal: 60 s of simulated time.
CHILD_RUN = textwrap.dedent(
    """
    import json, sys, chute
    try:
        chute.run(sys.argv[1], set={"canopy.nodes": 21, "time.duration_s": 60}, out=sys.argv[2])
    except KeyboardInterrupt as e:
        print(json.dumps({"summary": e.result.summary, "rows": len(e.result.timeseries["t_s"])}))
        sys.exit(42)
    """
)

CHILD_SIM = textwrap.dedent(
    """
    import json, sys, chute
    sim = chute.Simulation(sys.argv[1], set={"canopy.nodes": 21, "time.duration_s": 60})
    print("ready", flush=True)
    try:
        sim.step(10**9)
    except KeyboardInterrupt:
        steps, t = sim.steps, sim.time
        took = sim.step(3)
        print(json.dumps({"steps": steps, "t": t, "took": took, "after": sim.steps}))
        sys.exit(42)
    """
)


def interrupt(child, *args, started):
    p = subprocess.Popen(
        [sys.executable, "-c", child, *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 120
    while not started(p):
        assert p.poll() is None, p.communicate()
        assert time.monotonic() < deadline, "the child did not start"
        time.sleep(0.05)
    time.sleep(0.5)  # well inside the stepping
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    return p.returncode, out, err, time.monotonic() - sent


def test_sigint_stops_a_run_with_partial_outputs(tmp_path):
    out = tmp_path / "run"
    code, stdout, stderr, after = interrupt(
        CHILD_RUN, ROD, out, started=lambda p: (out / "timeseries.csv").exists()
    )
    assert code == 42, stderr
    got = json.loads(stdout)
    s = got["summary"]
    assert s["complete"] is False
    assert s["stop_reason"].startswith("interrupted at t = ")
    assert 0 < s["simulated_time_s"] < 60
    assert got["rows"] == s["steps"] + 1
    assert (out / "checkpoint.bin").exists() and (out / "canopy.pvd").exists()
    on_disk = json.loads((out / "summary.json").read_text())
    assert on_disk == s
    assert after < 30, f"the run took {after:.1f} s to stop"


def test_sigint_stops_simulation_step_between_steps():
    ready = []

    def started(p):
        if not ready:
            ready.append(p.stdout.readline())
        return ready[0].startswith("ready")

    code, stdout, stderr, _ = interrupt(CHILD_SIM, ROD, started=started)
    assert code == 42, stderr
    got = json.loads(stdout)
    assert got["steps"] > 0 and abs(got["t"] - got["steps"] * 1e-3) < 1e-9
    assert got["took"] == 3 and got["after"] == got["steps"] + 3

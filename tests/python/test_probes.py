"""Probes from Python (sim.probes) and probes.csv surviving a killed run."""
import csv
import json
import os
import signal
import subprocess
import time

import consph
from conftest import CLI, tank_scene


def probe_scene():
    scene = tank_scene()
    scene["probes"] = [
        {"name": "floor", "kind": "pressure", "position": [0.3, 0.0, 0.2]},
        {"name": "depth", "kind": "level", "position": [0.3, 0.0, 0.2]},
        {"name": "tank", "kind": "force", "boundary": "tank"},
    ]
    return scene


def test_sim_probes_gives_the_latest_values_by_csv_column():
    sim = consph.Simulation.from_dict(probe_scene())
    sim.step(20)
    p = sim.probes
    assert set(p) == {"floor", "depth", "tank.fx", "tank.fy", "tank.fz", "tank.tx", "tank.ty", "tank.tz"}
    assert all(isinstance(v, float) for v in p.values())
    # The block (y = 0.1-0.5 m) falls towards the floor: the surface lies just above its top
    # particles (by about half a lattice spacing, 0.023 m), and the water pushes the tank down.
    top = sim.fluid("water").positions[:, 1].max()
    assert top < p["depth"] < top + 2 * 0.025
    assert p["tank.fy"] < 0
    assert sim.summary()["probes"] == p


def test_a_scene_without_probes_has_none():
    assert consph.Simulation.from_dict(tank_scene()).probes == {}


def test_a_killed_run_keeps_its_probe_rows(tmp_path):
    scene = probe_scene()
    scene["simulation"]["stopAt"] = 1000.0
    scene["output"] = {"enabled": True, "directory": str(tmp_path / "out"), "fps": 1}
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    proc = subprocess.Popen([CLI, str(path), "--threads", "1", "--quiet"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    csv_path = tmp_path / "out" / "probes.csv"
    deadline = time.time() + 60
    try:
        while time.time() < deadline:
            if csv_path.exists() and csv_path.read_text().count("\n") > 20:
                break
            time.sleep(0.05)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    rows = list(csv.reader(open(csv_path)))
    assert rows[0] == ["time", "floor", "depth", "tank.fx", "tank.fy", "tank.fz", "tank.tx", "tank.ty", "tank.tz"]
    assert len(rows) > 20
    # Every line written before the kill is whole: a row is written and flushed in one go.
    text = csv_path.read_text()
    assert text.endswith("\n")
    for row in rows[1:]:
        assert len(row) == 9
        [float(v) for v in row]

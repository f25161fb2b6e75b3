"""Errors become Python exceptions with the CLI's messages; warnings reach Python."""
import json
import os
import subprocess
import warnings

import numpy as np
import pytest

import consph
from conftest import CLI, REPO, free_particles_scene, tank_scene


def test_bad_scenes_raise_scene_error(tmp_path):
    with pytest.raises(consph.SceneError, match="cannot open scene file"):
        consph.Simulation.from_file(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"fluids": [\n  {"name": }\n]}')
    with pytest.raises(consph.SceneError, match=r"bad\.json:2:\d+: malformed JSON"):
        consph.Simulation.from_file(bad)
    scene = tank_scene()
    scene["simulation"]["particleRadius"] = "big"
    with pytest.raises(ValueError, match="simulation.particleRadius"):  # SceneError is a ValueError
        consph.Simulation.from_dict(scene)
    with pytest.raises(consph.SceneError, match="fluids: expected a non-empty array"):
        consph.Simulation.from_dict({"fluids": []})
    with pytest.raises(consph.SceneError, match="index 5 is past the end"):
        consph.Simulation.from_dict(tank_scene(), overrides={"fluids.5.density0": 1})
    with pytest.raises(consph.SceneError, match="not a finite number"):
        consph.Simulation.from_dict(tank_scene(), overrides={"simulation.gravity": [0, float("nan"), 0]})


def test_messages_equal_the_cli(tmp_path):
    scene = tank_scene(pressureSolver={"type": "NoSuchSolver"})
    path = tmp_path / "unknown.json"
    path.write_text(json.dumps(scene))
    cli = subprocess.run([CLI, str(path), "--no-output", "--quiet"],
                         capture_output=True, text=True)
    assert cli.returncode == 2
    with pytest.raises(consph.SceneError) as error:
        consph.Simulation.from_file(path)
    assert cli.stderr.strip() == "consph: error: " + str(error.value)
    assert "unknown pressure solver 'NoSuchSolver'; valid are: " in str(error.value)


def test_blow_ups_raise_simulation_error(free, tank):
    free.fluid().add_force(lambda ctx, fluid: fluid.accelerations.__setitem__((3, 1), np.nan))
    with pytest.raises(consph.SimulationError, match="non-finite position, velocity or pressure"):
        free.step(5)
    tank.fluid().velocities[7] = (1e4, 0, 0)
    with pytest.raises(RuntimeError, match=r"left the domain .* leaked through a boundary or the simulation blew up"):
        tank.step()


def test_warnings_reach_python():
    scene = tank_scene()
    scene["simulation"]["particleRadiuss"] = 0.1
    with pytest.warns(consph.ConsphWarning, match="particleRadiuss"):
        consph.Simulation.from_dict(scene)
    messages = []
    consph.Simulation.from_dict(scene, log=lambda level, text: messages.append((level, text)))
    assert any(level == "warning" and "particleRadiuss" in text for level, text in messages)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(consph.ConsphWarning):  # warnings-as-errors works as in any Python library
            consph.Simulation.from_dict(scene)
    consph.Simulation.from_dict(free_particles_scene())  # no warnings for a clean scene


def test_unconvertible_scene_values_raise_scene_error_with_the_path():
    # Issue 16: these segfaulted (recursion) or raised RuntimeError "Unable to cast".
    scene = tank_scene()
    loop = []
    loop.append(loop)
    scene["description"] = loop
    with pytest.raises(consph.SceneError, match=r"^scene\.description\[0\]: the list contains itself$"):
        consph.Simulation.from_dict(scene)
    deep = {}
    for _ in range(50000):
        deep = {"a": deep}
    scene["description"] = deep
    with pytest.raises(consph.SceneError, match=r"^scene\.description(\.a)+: nested deeper than 200 levels$"):
        consph.Simulation.from_dict(scene)
    scene = tank_scene(sortInterval=2 ** 64)
    with pytest.raises(consph.SceneError, match=r"^scene\.simulation\.sortInterval: the integer 18446744073709551616 is out"):
        consph.Simulation.from_dict(scene)
    scene = tank_scene(sortInterval=-2 ** 63 - 1)
    with pytest.raises(consph.SceneError, match=r"^scene\.simulation\.sortInterval: the integer"):
        consph.Simulation.from_dict(scene)
    scene = tank_scene()
    scene["fluids"][0]["name"] = "water\ud800"
    with pytest.raises(consph.SceneError, match=r"^scene\.fluids\[0\]\.name: the string is not valid Unicode"):
        consph.Simulation.from_dict(scene)
    scene = tank_scene()
    scene["\udcff"] = 1
    with pytest.raises(consph.SceneError, match=r"not valid Unicode"):
        consph.Simulation.from_dict(scene)
    with pytest.raises(consph.SceneError, match=r"^simulation\.stopAt: the integer"):
        consph.Simulation.from_dict(tank_scene(), overrides={"simulation.stopAt": 10 ** 30})


def test_thread_counts_are_clamped_and_end_times_finite(tank):
    try:
        with pytest.warns(consph.ConsphWarning, match="set_num_threads: 100000 threads clamped to"):
            consph.set_num_threads(100000)
        assert consph.get_num_threads() <= 1024
    finally:
        consph.set_num_threads(int(os.environ["OMP_NUM_THREADS"]))
    for bad in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match="until must be a finite time"):
            tank.run(until=bad)
    for bad in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match="output_fps: must be finite"):
            tank.output_fps = bad


def test_failed_writes_raise_output_error(tank, tmp_path):
    # Issue 16: a full disk raised SceneError (the bad-input class) and left a .tmp.
    with pytest.raises(consph.OutputError, match="cannot write '/dev/full'"):
        tank.export_frame("/dev/full")
    assert issubclass(consph.OutputError, OSError)
    with pytest.raises(consph.SceneError, match=r"fluids\[0\]\.name: '\.\./x' must not contain"):
        consph.Simulation.from_dict(tank_scene(), overrides={"fluids.0.name": "../x"})


def test_output_folder_of_another_run_is_refused(tmp_path):
    first = consph.Simulation.from_dict(tank_scene(), output=tmp_path / "out")
    first.step(2)
    first.output_directory = tmp_path / "out"  # its own folder: no check again
    with pytest.raises(consph.SceneError, match="holds another run's files .*pass --overwrite"):
        consph.Simulation.from_dict(tank_scene(), output=tmp_path / "out")
    consph.Simulation.from_dict(tank_scene(), output=tmp_path / "out", overrides={"output.overwrite": True})
    assert json.loads((tmp_path / "out" / "scene.resolved.json").read_text())["name"] == "TinyTank"


def test_a_splishsplash_scene_loads_as_the_cli_runs_it(tmp_path):
    # from_file and from_dict recognise SPlisHSPlasH's layout and run the consph scene it maps to
    # (the CLI's `consph run`); overrides then address that consph scene's keys.
    path = os.path.join(REPO, "data", "splishsplash", "scenes", "DamBreakModel.json")
    messages = []
    sim = consph.Simulation.from_file(path, overrides={"simulation.stopAt": 0.02}, output=False,
                                      log=lambda level, text: messages.append((level, text)))
    assert any("SPlisHSPlasH scene" in text for _, text in messages)
    assert any("mapResolution" in text for level, text in messages if level == "warning")
    converted = tmp_path / "converted.json"
    cli = subprocess.run([CLI, "convert", path, str(converted)], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    reference = consph.Simulation.from_file(converted, overrides={"simulation.stopAt": 0.02}, output=False,
                                            log=lambda level, text: None)
    assert sim.scene["simulation"]["stopAt"] == 0.02
    assert sim.fluids[0].size == reference.fluids[0].size
    np.testing.assert_array_equal(sim.fluids[0].positions, reference.fluids[0].positions)
    with open(path) as f:
        as_dict = consph.Simulation.from_dict(json.load(f), base_dir=os.path.dirname(path), output=False,
                                              log=lambda level, text: None)
    assert as_dict.fluids[0].size == sim.fluids[0].size

"""Scene mutation (issue 16): a few hundred mutants of the bundled scenes, each run through the
CLI for a tiny simulated time without output. Whatever the mutant, the only allowed outcomes are
exit 0 (valid), 2 (bad input) or 3 (a blow-up) with the error on one line: never a signal, a
hang, an internal error (exit 4) or a multi-line error. Deterministic (fixed seed)."""
import collections
import concurrent.futures
import copy
import glob
import json
import os
import random
import subprocess

from conftest import CLI, REPO

SCENES = sorted(glob.glob(os.path.join(REPO, "data", "scenes", "*.json")))
# CONSPH_MUTANTS raises the count for a long run (issue 16's report: 2000); the suite runs 300.
MUTANTS = int(os.environ.get("CONSPH_MUTANTS", "300"))
TIMEOUT = 30  # s per run: the slowest bundled scene loads in 0.5 s

VALUES = [None, True, False, "", "x", "../x", 0, -1, 1, 0.5, -0.5, 1e-308, 1e308, -1e308, 2 ** 63, -2 ** 63 - 1,
          [], {}, [1, 2], [0, 0, 0], [1e308, 1e308, 1e308], [-1e308, 0, 0], {"type": "x"}, "\u00ff\u0000"]


def paths(node, prefix=()):
    """Every (path, value) in the JSON tree, the root excluded."""
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        yield prefix + (key,), child
        yield from paths(child, prefix + (key,))


def parent_of(scene, path):
    node = scene
    for key in path[:-1]:
        node = node[key]
    return node


def mutate_tree(scene, rng):
    """One structural mutation; returns its class name."""
    path, value = rng.choice(list(paths(scene)))
    parent, key = parent_of(scene, path), path[-1]
    kind = rng.choice(["replace", "replace", "scale", "delete", "unknown-key", "duplicate"])
    if kind == "scale" and isinstance(value, (int, float)) and not isinstance(value, bool):
        parent[key] = value * rng.choice([-1, 0, 1e-6, 1e-3, 1e3, 1e6, 1e12])
    elif kind == "delete":
        del parent[key]
    elif kind == "unknown-key" and isinstance(value, dict):
        value["unknownKey"] = 1
    elif kind == "duplicate" and isinstance(value, list) and value:
        value.append(copy.deepcopy(rng.choice(value)))
    else:
        kind = "replace"
        parent[key] = copy.deepcopy(rng.choice(VALUES))
    return kind


def mutate_text(text, rng):
    kind = rng.choice(["truncate", "insert", "deep", "overflow"])
    at = rng.randrange(len(text))
    if kind == "truncate":
        return kind, text[:at]
    if kind == "insert":
        return kind, text[:at] + rng.choice(["{", "]", ",", "\"", "\\", "\x00", "\xff", "1e999", "-"]) + text[at:]
    if kind == "deep":
        return kind, text.replace("{", "{\"description\": " + "[" * 300 + "]" * 300 + ",", 1)
    return kind, text.replace(": 1", ": 1e999", 1) if ": 1" in text else text + "1e999"


def run_mutant(case):
    index, kind, text, scene_path, tmp = case
    path = os.path.join(tmp, "mutant_%03d.json" % index)
    with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    try:
        p = subprocess.run([CLI, path, "--quiet", "--no-output", "--stop-at", "0.002", "--threads", "1",
                            "--max-particles", "200000"], capture_output=True, text=True, errors="replace",
                           timeout=TIMEOUT, cwd=tmp)
        return index, kind, scene_path, p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        return index, kind, scene_path, "timeout", ""


def test_mutants_end_with_an_allowed_outcome(tmp_path):
    rng = random.Random(16)
    # The meshes the scenes name (../meshes/...) must resolve from the mutants' folder.
    scenes_dir = tmp_path / "scenes"
    scenes_dir.mkdir()
    os.symlink(os.path.join(REPO, "data", "meshes"), tmp_path / "meshes")
    cases = []
    for i in range(MUTANTS):
        scene_path = rng.choice(SCENES)
        with open(scene_path) as f:
            text = f.read()
        if rng.random() < 0.25:
            kind, mutant = mutate_text(text, rng)
        else:
            scene = json.loads(text)
            kind = mutate_tree(scene, rng)
            mutant = json.dumps(scene)
        cases.append((i, kind, mutant, scene_path, str(scenes_dir)))
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(run_mutant, cases))
    outcomes = collections.Counter()
    bad = []
    for index, kind, scene_path, code, stderr in results:
        outcomes[(kind, code)] += 1
        lines = [line for line in stderr.splitlines() if line.strip()]
        errors = [line for line in lines if not line.startswith(("warning: ", "consph: warning: "))]
        if code not in (0, 2, 3):
            bad.append((index, kind, os.path.basename(scene_path), code, stderr[-400:]))
        elif code != 0 and (len(errors) != 1 or not errors[0].startswith("consph: error: ")):
            bad.append((index, kind, os.path.basename(scene_path), code, "not one error line: " + stderr[-400:]))
    summary = ", ".join("%s -> %s: %d" % (k, c, n) for (k, c), n in sorted(outcomes.items(), key=str))
    print("%d mutants: %s" % (len(results), summary))  # the classes and counts, shown with pytest -s
    assert not bad, "%d bad outcomes (of %s):\n%s" % (len(bad), summary, "\n".join(map(str, bad[:20])))

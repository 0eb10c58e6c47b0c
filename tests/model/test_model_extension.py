"""A new model option is one module plus one settings field: demonstrated on a copy of the
package, in which an ankle spring is added that way and nothing else is edited, then the
solver's node function, the evaluated cycle, the model-cache key and the atlas key all follow."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
from helpers import random_decision

SRC = Path(__file__).resolve().parents[2] / "src" / "walk3d"

ELEMENT_MODULE = '''"""An ankle spring in parallel with the muscles: it carries ``k θ`` of each
ankle's dorsiflexion moment; the criterion sees the rest (``ModelSettings.ankle_spring``)."""

import dataclasses

from walk3d import mathops as mo
from walk3d.model.element import Element


def _apply(body, model, st, values):
    moments, i = [], 0
    for j, joint in enumerate(body.joints):
        m = list(st.moments[j])
        if joint.name.startswith("ankle"):
            m[joint.dof_slots[0]] = m[joint.dof_slots[0]] - model.ankle_spring * 2.0 * mo.asin(
                values[i])
        moments.append(tuple(m))
        i += joint.n_dof
    return dataclasses.replace(st, moments=moments)


ELEMENT = Element("ankle_spring", _apply)
'''

FIELD = '''    ankle_spring: Annotated[
        float | None, Role(nodes=True, off=None, element="walk3d.model.ankle_spring:ELEMENT")
    ] = None
    """Ankle spring stiffness, N·m/rad (:mod:`walk3d.model.ankle_spring`); None: none."""
'''

CHECK = """
import json
import numpy as np
from walk3d.body.model import build_body
from walk3d.model.settings import node_fields
from walk3d.problem import nlp
from walk3d.problem.settings import PredictionSettings
from walk3d.results.evaluate import evaluate_cycle
from walk3d.solve import atlas, solver

off = PredictionSettings(criterion="natural", period=1.1, double_support=0.13)
on = off.replace(ankle_spring=80.0)
body = build_body()
rng = np.random.default_rng(2)
y = rng.uniform(-0.15, 0.15, nlp.N_Y)
args = (y, np.array([0.05, 1.0, 0.01, 0.02, 0.01, 0.03]), 0.07,
        np.array([0.6, -0.7, 2 * np.pi / 1.1, 0.3, 0.1, 0.0]), rng.uniform(0.0, 0.5, nlp.N_T))
g = {k: np.array(nlp.node_function(body, s.model)(*args)[0]).ravel() for k, s in
     (("off", off), ("on", on))}
slack = nlp.G_ROWS["slack_pos"]
x = np.array(json.load(open(__import__("sys").argv[1])))
c = {k: evaluate_cycle(body, s, x).criteria for k, s in (("off", off), ("on", on))}
print(json.dumps({
    "node_key_on": "ankle_spring" in node_fields(on.model),
    "node_key_off": "ankle_spring" in node_fields(off.model),
    "atlas_on": atlas.settings_key(on)["model"].get("ankle_spring"),
    "atlas_off": "ankle_spring" in atlas.settings_key(off)["model"],
    "cache_keys_differ": solver.model_key(body, on.model) != solver.model_key(body, off.model),
    "slack_change": float(np.max(np.abs(g["on"][slack] - g["off"][slack]))),
    "rows_change": float(np.max(np.abs(g["on"][:slack.start] - g["off"][:slack.start]))),
    "c_tor": [c["off"]["C_tor"]["total"], c["on"]["C_tor"]["total"]],
}))
"""


def _copy_with_option(tmp: Path, field: str) -> Path:
    root = tmp / "src"
    shutil.copytree(SRC, root / "walk3d", ignore=shutil.ignore_patterns("__pycache__"))
    (root / "walk3d" / "model" / "ankle_spring.py").write_text(ELEMENT_MODULE)
    settings = root / "walk3d" / "model" / "settings.py"
    text = settings.read_text()
    anchor = "    changes: Annotated["
    assert anchor in text
    settings.write_text(text.replace(anchor, field + anchor, 1))
    return root


def _changed_files(root: Path) -> set[str]:
    out = set()
    for path in (root / "walk3d").rglob("*.py"):
        rel = path.relative_to(root / "walk3d")
        original = SRC / rel
        if not original.exists() or original.read_bytes() != path.read_bytes():
            out.add(str(rel))
    return out


def _run(root: Path, tmp: Path) -> dict:
    x = tmp / "x.json"

    x.write_text(json.dumps(random_decision(np.random.default_rng(0)).tolist()))
    env = {**os.environ, "PYTHONPATH": str(root), "WALK3D_CACHE": "0"}
    proc = subprocess.run([sys.executable, "-c", CHECK, str(x)], env=env, capture_output=True,
                          text=True, timeout=300, check=False)  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_model_option_is_one_module_and_one_settings_field(tmp_path):
    root = _copy_with_option(tmp_path, FIELD)
    assert _changed_files(root) == {"model/ankle_spring.py", "model/settings.py"}
    got = _run(root, tmp_path)
    assert got["node_key_on"] and not got["node_key_off"]  # the model-cache key
    assert got["atlas_on"] == 80.0 and not got["atlas_off"]  # the atlas key
    assert got["cache_keys_differ"]
    assert got["slack_change"] > 1e-3  # the solver's criterion rows see the spring ...
    assert got["rows_change"] == 0.0  # ... and nothing else
    assert abs(got["c_tor"][1] - got["c_tor"][0]) > 1e-3  # so does the evaluated cycle


def test_without_its_element_the_field_changes_only_the_keys(tmp_path):
    """Negative control: the same field with no element named in its role."""
    no_element = FIELD.replace(', element="walk3d.model.ankle_spring:ELEMENT"', "")
    root = _copy_with_option(tmp_path, no_element)
    got = _run(root, tmp_path)
    assert got["node_key_on"] and got["cache_keys_differ"]
    assert got["slack_change"] == 0.0 and got["c_tor"][0] == got["c_tor"][1]

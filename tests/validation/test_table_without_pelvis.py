"""A cycle table of leg angles without the pelvis's (OpenSim names): Table 2 is computed and a
note says why walk3d's inverse dynamics of the measured angles is left out, as for a trial's IK
without pelvis angles; it was exit 2 ('the projection needs the measured pelvis
orientation'), seen by the fuzz set's undamaged seed."""

from __future__ import annotations

import numpy as np
import pytest

from walk3d.validation.run import validate


def _table(path, pelvis: bool):
    p = np.linspace(0.0, 100.0, 51)
    c = np.cos(2 * np.pi * p / 100)
    cols = {"hip_flexion": 10 + 20 * c, "knee_angle": -(32 - 28 * c), "ankle_angle": 5 * c}
    if pelvis:
        cols |= {"pelvis_tilt": 2 * c, "pelvis_list": 0 * c + 1, "pelvis_rotation": 4 * c}
    head = ["percent_cycle"] + [f"{k}_deg_{s}" for k in cols for s in ("mean", "sd")]
    rows = [",".join(head)]
    rows += [",".join([f"{p[i]:g}"] + [f"{v[i]:.4f},3" for v in cols.values()])
             for i in range(p.size)]  # fmt: skip
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("pelvis", [False, True])
def test_a_table_without_pelvis_angles_is_validated_without_the_fit(
    synthetic_prediction, tmp_path, pelvis
):
    table = _table(tmp_path / "legs.csv", pelvis)
    v = validate({"p": synthetic_prediction}, [table], tmp_path / "out", figures=False)
    knee = next(r for r in v.table2 if (r["group"], r["quantity"]) == ("angle", "knee_flexion"))
    assert knee["status"] == "ok" and np.isfinite(knee["rmse"])
    if pelvis:  # control: with the pelvis's angles, the measured angles are fitted
        assert v.fit is not None
    else:
        assert v.fit is None and any("legs.csv: no pelvis angles" in n for n in v.notes)

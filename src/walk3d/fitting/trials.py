"""The measured trials a criterion is fitted to: a TOML file, one ``[[trial]]`` table each.

::

    [[trial]]
    name = "falisse"
    ik = "falisse2019/gait_1_ik.mot"      # V, T and Td from the trial (with grf) ...
    grf = "falisse2019/gait_1_grf.mot"
    mass = 62
    height = 1.70
    sex = "female"
    reference = ["falisse2019/cycle_right_leg_mean_sd.csv"]

    [[trial]]
    name = "winter"
    speed = 1.325                          # ... or given in the table
    period = 1.1396
    double_support = 0.114
    reference = ["winter/Winter_normal.csv"]

Relative paths are read from the TOML file's folder. ``reference`` takes what ``walk3d
validate --reference`` takes; ``reference_speed`` is its ``--speed`` (a treadmill's belt).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from walk3d.io.checks import input_problem, read_toml
from walk3d.io.errors import DataFileError

__all__ = ["FitTrial", "read_trials"]


class FitTrial(BaseModel):
    """One measured trial: who walked, how (or where to read it), and what to score against."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field(pattern=r"^[A-Za-z0-9_.-]{1,40}$")
    """Short name, used in file names."""
    mass: float = Field(68.8, gt=20, lt=250, strict=True)
    """kg; the paper's subject by default."""
    height: float = Field(1.77, ge=1.0, le=2.4, strict=True)
    """m; the paper's subject by default."""
    sex: Literal["male", "female"] = "male"
    ik: Path | None = None
    """IK storage that gives V (with ``grf``, also T and Td)."""
    grf: Path | None = None
    speed: float | None = Field(None, gt=0, le=4, strict=True)
    """m/s; overrides the trial's (a treadmill's belt speed)."""
    period: float | None = Field(None, gt=0, le=3, strict=True)
    """s."""
    double_support: float | None = Field(None, gt=0, le=1, strict=True)
    """s, one phase."""
    reference: list[Path] = Field(min_length=1)
    reference_speed: float | None = Field(None, gt=0, le=4, strict=True)

    @model_validator(mode="after")
    def _descriptors(self) -> FitTrial:
        from_trial = self.ik is not None or self.grf is not None
        if from_trial and (self.ik is None or self.grf is None):
            raise ValueError("ik and grf come together")
        if not from_trial and None in (self.speed, self.period, self.double_support):
            raise ValueError("give ik and grf, or speed, period and double_support")
        return self

    def files(self) -> list[Path]:
        """Every file the trial reads."""
        return [p for p in (self.ik, self.grf) if p is not None] + list(self.reference)


def _resolved(raw: dict, folder: Path) -> dict:
    out = dict(raw)
    for key in ("ik", "grf"):
        if isinstance(out.get(key), str):
            out[key] = (folder / out[key]).resolve()
    if isinstance(out.get("reference"), str):
        out["reference"] = [out["reference"]]
    if isinstance(out.get("reference"), list):
        out["reference"] = [(folder / p).resolve() if isinstance(p, str) else p
                            for p in out["reference"]]  # fmt: skip
    return out


def read_trials(path: str | PathLike[str]) -> list[FitTrial]:
    """The trials of ``path``; DataFileError (one line) when the file is missing, not TOML, a
    trial is malformed, two share a name, or a file it names does not exist."""
    p = Path(path)
    data = read_toml(p)
    raw = data.get("trial")
    if not isinstance(raw, list) or not raw or not all(isinstance(t, dict) for t in raw):
        raise DataFileError(p, "no [[trial]] tables")
    trials = []
    for i, table in enumerate(raw, start=1):
        try:
            trials.append(FitTrial(**_resolved(table, p.resolve().parent)))
        except ValidationError as exc:
            err = exc.errors()[0]
            where = ".".join(str(x) for x in err["loc"]) or "trial"
            raise DataFileError(p, f"trial {i}: {where}: {err['msg']}") from None
    names = [t.name for t in trials]
    if len(set(names)) != len(names):
        raise DataFileError(p, f"two trials share a name: {sorted(names)}")
    for t in trials:
        for f in t.files():
            if not f.exists():
                raise DataFileError(p, f"trial {t.name}: no such file {f}")
            why = input_problem(f)  # a FIFO would block its reader
            if why:
                raise DataFileError(p, f"trial {t.name}: {f} {why}")
    return trials

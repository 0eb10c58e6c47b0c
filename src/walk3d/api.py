"""The Python API: ``walk3d.predict(speed=...)`` returns a :class:`Prediction` that can be
tabulated (``to_dataframe``), plotted and saved; ``walk3d.load_result(DIR)`` reads one back.

Defaults are those of ``walk3d predict``: the paper's subject (68.8 kg, 1.77 m, male) at its
speed, T and Td predicted with the gait, the ``natural`` criterion, started from the atlas.
Bad input raises :class:`ValueError` with one line that names the input.
"""

from __future__ import annotations

import math
import numbers
import sys
import warnings
from collections.abc import Callable
from dataclasses import fields
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from walk3d.results.prediction import PredictedCycle
from walk3d.results.prediction import load_result as _load_result

if TYPE_CHECKING:
    import pandas
    from matplotlib.figure import Figure

    from walk3d.problem.settings import PredictionSettings

__all__ = [
    "Prediction",
    "criterion_value",
    "gait_fields",
    "load_result",
    "predict",
    "settings",
    "track",
]

_AXES = "xyz"


class Prediction(PredictedCycle):
    """A predicted gait cycle (:class:`walk3d.results.PredictedCycle`: read-only SI arrays, time
    first) that also tabulates, plots and saves itself."""

    @classmethod
    def of(cls, pred: PredictedCycle) -> Prediction:
        """The same cycle as this class (arrays shared, read-only)."""
        return pred if isinstance(pred, cls) else cls(**{f.name: getattr(pred, f.name)
                                                         for f in fields(pred)})  # fmt: skip

    @property
    def converged(self) -> bool:
        """Whether the solve converged: ``summary["converged"]`` is ``True`` itself (``"no"``
        is not); False for an unlabelled one."""
        from walk3d.results.labels import is_converged

        return is_converged(self.summary)

    @property
    def descriptors(self) -> dict[str, Any]:
        """Speed (m/s), period, double support (s), stride length (m), cadence (steps/min),
        stance fraction, and which were ``predicted`` (``summary["descriptors"]``)."""
        return dict(self.summary.get("descriptors", {}))

    def to_dataframe(self) -> pandas.DataFrame:
        """One row per time sample, indexed by ``time_s`` (the prediction's clock, which starts
        at right toe-off as in the paper and ``motion.mot``): ``percent_cycle`` (0 % at right
        heel strike, as ``walk3d validate``, ``report.html`` and ``markers.c3d``; it wraps to 0
        there), joint angles in degrees (``<dof>_deg``), joint moments
        (``<joint>_moment_<axis>_Nm``, active axes), each foot's ground reaction
        (``grf_<side>_<x|y|z>_N``), centre of pressure (``cop_<side>_<axis>_m``, NaN in swing),
        free moment and the pelvis origin (m)."""
        import numpy as np
        import pandas as pd

        from walk3d.validation.compare import cycle_timing

        t = self.time
        period, t_hs = cycle_timing(self)
        percent = 100.0 * np.mod(t - t[0] - t_hs, period) / period
        cols: dict[str, np.ndarray] = {"percent_cycle": percent}
        for k, name in enumerate(self.dof_names):
            cols[f"{name}_deg"] = np.degrees(self.joint_angle[:, k])
        for j, joint in enumerate(self.joint_names):
            for a in np.flatnonzero(self.joint_axis_active[j]):
                cols[f"{joint}_moment_{_AXES[a]}_Nm"] = self.joint_moment[:, j, a]
        for f, side in enumerate(("r", "l")):
            for a, axis in enumerate(_AXES):
                cols[f"grf_{side}_{axis}_N"] = self.grf_force[:, f, a]
            for a, axis in enumerate(_AXES):
                cols[f"cop_{side}_{axis}_m"] = self.grf_cop[:, f, a]
            cols[f"free_moment_{side}_Nm"] = self.grf_free_moment[:, f]
        for a, axis in enumerate(_AXES):
            cols[f"pelvis_{axis}_m"] = self.pelvis_position[:, a]
        return pd.DataFrame(cols, index=pd.Index(t, name="time_s"))

    def plot(self, path: str | PathLike[str] | None = None) -> Figure:
        """The summary figure (joint angles in degrees, ground reactions in N/kg), also written
        as a PNG to ``path`` when given."""
        from walk3d.plots.summary import save_png, summary_plot

        fig = summary_plot(self)
        if path is not None:
            save_png(fig, path)
        return fig

    def save(self, out_dir: str | PathLike[str], *, figure: bool = True, animate: bool = False,
             report: bool = True) -> Path:  # fmt: skip
        """Write the result folder ``walk3d predict --out`` writes (atomically; an earlier result
        there is replaced), with ``summary.png`` when ``figure``, ``animation.mp4`` when
        ``animate`` and ``report.html`` when ``report``. Returns the folder.

        Raises:
            ValueError: ``out_dir`` is an existing file or a folder of other files (as
                ``walk3d predict --out``), an array walk3d could not read back (NaN or infinite
                values, NaN centres of pressure aside), or ``animate`` and the summary's period
                is not the span of ``time``; nothing is written.
            OSError: the folder could not be written (one line; nothing is left behind).
        """
        from walk3d.pipeline import write_result
        from walk3d.report.writer import write_report_or_warn

        folder = write_result(self, out_dir, figure=figure, animate=animate)
        if report:
            write_report_or_warn(folder)
        return folder


def load_result(out_dir: str | PathLike[str]) -> Prediction:
    """Read a result folder (``walk3d predict --out``, :meth:`Prediction.save`)."""
    return Prediction.of(_load_result(out_dir))


def criterion_value(value: str) -> str:
    """A criterion preset name, weights like ``'tor=1,accel=0.5'``, or a TOML file of weights,
    as the canonical weights string. Raises ValueError naming what is wrong."""
    from walk3d.io.criterion import read_criterion
    from walk3d.io.errors import DataFileError
    from walk3d.model import terms

    if not isinstance(value, str):
        raise ValueError(f"criterion must be a preset name, weights or a TOML file, got "
                         f"{value!r:.40}")  # fmt: skip
    if value.lower().endswith(".toml"):
        try:
            value = read_criterion(value)
        except DataFileError as exc:
            raise ValueError(f"criterion {exc}") from None
    try:
        return terms.canonical(value)
    except ValueError as exc:
        raise ValueError(f"criterion: {exc}") from None


def gait_fields(speed: float, period: float | None, double_support: float | None,
                height: float) -> dict[str, Any]:  # fmt: skip
    """``speed``, ``period``, ``double_support`` and ``free`` settings fields: a None descriptor
    is predicted from a first guess (:func:`walk3d.problem.descriptors.auto_descriptors`).
    Raises ValueError when a given Td fits no period."""
    from walk3d.problem.descriptors import auto_descriptors

    if not (0 < speed <= 4.0 and 1.0 <= height <= 2.4):  # refused with its range by settings()
        return {"speed": speed, "period": period or 1.0, "double_support": double_support or 0.1}
    t, td, free = auto_descriptors(speed, height, period, double_support)
    return {"speed": speed, "period": t, "double_support": td, "free": free}


def settings(
    speed: float = 1.3806,
    period: float | None = None,
    double_support: float | None = None,
    **options: Any,
) -> PredictionSettings:
    """Validated settings with ``walk3d predict``'s defaults: ``criterion`` (a preset, weights
    or TOML file), ``mass``, ``height``, ``sex``, ``start``, ``nodes``, ``threads`` (default:
    every core) and any other :class:`~walk3d.problem.settings.PredictionSettings` field.
    Raises ValueError with one line, also for an ``hsl_library`` IPOPT must not load."""
    from walk3d.io.criterion import with_file_options
    from walk3d.io.errors import DataFileError
    from walk3d.model.settings import equal_steps_unused
    from walk3d.model.terms import DEFAULT_PRESET
    from walk3d.problem.settings import PredictionSettings, available_cores, first_error

    numbers_ = {"speed": speed, "period": period, "double_support": double_support}
    numbers_.update((k, options[k]) for k in ("mass", "height") if k in options)
    for name, value in numbers_.items():
        if not (value is None and name in ("period", "double_support")) and not _real(value):
            raise ValueError(f"{name} must be a finite number, got {value!r:.40}")
    options = {"height": 1.77, "threads": min(available_cores(), 64), **options}
    given = str(options.get("criterion", DEFAULT_PRESET))
    options["criterion"] = criterion_value(given)
    try:  # a fitted criterion file's [model] options (walk3d.io.criterion)
        options = with_file_options(given, options)
    except DataFileError as exc:
        raise ValueError(f"criterion {exc}") from None
    fields_ = gait_fields(speed, period, double_support, options["height"])
    try:
        made = PredictionSettings(**fields_, **options)
    except ValueError as exc:
        raise ValueError(first_error(exc)) from None
    if equal_steps_unused(made.model):
        raise ValueError(
            "equal_steps needs full_cycle=True or a one-sided change (a name "
            "ending in _r or _l): the half cycle's steps are equal already"
        )
    if made.solver.hsl_library:
        from walk3d.solve.options import hsl_library_error  # a FIFO, a library cut short

        unusable = hsl_library_error(made)
        if unusable:
            raise ValueError(unusable)
    return made


def predict(speed: float = 1.3806, *, period: float | None = None,
            double_support: float | None = None, mass: float = 68.8, height: float = 1.77,
            sex: str = "male", seed: int = 0, out: str | PathLike[str] | None = None,
            animate: bool = False, progress: bool | Callable[[str], None] = False,
            **options: Any) -> Prediction:  # fmt: skip
    """Predict one gait cycle at ``speed`` (m/s) for a body of ``mass`` (kg), ``height`` (m) and
    ``sex``. ``period`` and ``double_support`` (s) are predicted with the gait unless given.

    ``options``: ``criterion`` (default ``natural``; ``tor`` with period=1.08 and
    double_support=0.16 is the paper's case), ``start`` (``atlas`` or ``standing``) and any
    other settings field (:func:`settings`). ``out``: also write the result folder there (with
    ``report.html``, and ``animation.mp4`` when ``animate``). ``progress``: True prints the
    solver's stages to stderr; a callable receives them.

    A solve that does not converge still returns, with ``converged`` False and a
    :class:`RuntimeWarning`, as does a converged gait that does not look like walking. Raises
    ValueError for bad input, an ``out`` that is an existing
    file or a folder of other files included, before any solve.
    """
    from walk3d.pipeline import check_result_folder
    from walk3d.pipeline import predict as run
    from walk3d.report.writer import write_report_or_warn

    if isinstance(seed, numbers.Integral) and not isinstance(seed, bool):
        seed = int(seed)  # a NumPy integer too
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    if out is not None:
        check_result_folder(out)
    s = settings(speed, period, double_support, mass=mass, height=height, sex=sex, **options)
    on_stage = progress if callable(progress) else _print_stage if progress else None
    pred = Prediction.of(run(s, seed, out_dir=out, animate=animate, on_stage=on_stage))
    if out is not None:
        write_report_or_warn(out)
    if not pred.converged:
        warnings.warn(f"walk3d: the solve did not converge ({pred.summary.get('status')}); "
                      "this is not a valid prediction", RuntimeWarning, stacklevel=2)  # fmt: skip
    elif not (pred.summary.get("gait_checks") or {}).get("looks_like_walking", True):
        warnings.warn("walk3d: the converged gait does not look like walking (summary "
                      "gait_checks)", RuntimeWarning, stacklevel=2)  # fmt: skip
    return pred


def track(*, ik: str | PathLike[str] | None = None, grf: str | PathLike[str] | None = None,
          table: str | PathLike[str] | None = None, mass: float = 68.8, height: float = 1.77,
          sex: str = "male", out: str | PathLike[str] | None = None, seed: int = 0,
          **options: Any) -> Any:  # fmt: skip
    """Track a measured gait (``ik`` with ``grf``, or a cycle ``table``) inside walk3d's model:
    every constraint of :func:`predict`, the criterion replaced by the deviation from the data
    with a small weight left on it (docs/tracking.md). ``options``: ``speed``, ``period``,
    ``double_support`` (default: the trial's), ``criterion``, ``weight`` (of the tracking, against
    the criterion's 1) and other settings fields. Returns a :class:`walk3d.tracking.Tracked`
    (``prediction``, ``rows``: RMSE per DoF and force component, ``binding``). Raises ValueError
    (or :class:`walk3d.io.errors.DataFileError`) for bad input, before any solve."""
    from walk3d.tracking import track as run
    from walk3d.tracking import track_settings, write_tracking
    from walk3d.validation.target import tracking_target

    given = {k: options.pop(k, None) for k in ("speed", "period", "double_support")}
    for name, value in {"mass": mass, "height": height, **given}.items():
        if value is not None and not _real(value):
            raise ValueError(f"{name} must be a finite number, got {value!r:.40}")
    target = tracking_target(table=table, ik=ik, grf=grf, mass=mass, **given)
    if out is None:
        return run(target, mass=mass, height=height, sex=sex, seed=seed, **given, **options)
    from walk3d.pipeline import check_result_folder

    check_result_folder(out)
    settings = track_settings(target, mass=mass, height=height, sex=sex, **given, **options)
    return write_tracking(target, settings, out, seed)


def _real(value: Any) -> bool:
    """A finite real number that is not a bool (an int too large for a float is not)."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _print_stage(message: str) -> None:
    print(f"walk3d: {message}", file=sys.stderr, flush=True)

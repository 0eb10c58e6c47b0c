"""Shared pieces of the ``walk3d`` command line: the Typer app, consoles, option types,
the one-line error exit and settings validation."""

from __future__ import annotations

import os
import sys
from typing import Annotated, Any

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import typer  # noqa: E402
from rich.console import Console  # noqa: E402

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Predict three-dimensional whole-body human walking.",
    pretty_exceptions_enable=False,
)
console = Console()
err_console = Console(stderr=True)

GAIT = "Gait and subject"
MODEL = "Model"
SOLVER = "Solver"
"""Help panels: the three groups of walk3d.problem.settings.PredictionSettings."""

Mass = Annotated[float, typer.Option("--mass", help="Body mass, kg.", rich_help_panel=GAIT)]
Height = Annotated[float, typer.Option("--height", help="Stature, m.", rich_help_panel=GAIT)]
Sex = Annotated[
    str, typer.Option("--sex", help="de Leva table: male or female.", rich_help_panel=GAIT)
]
Speed = Annotated[
    float, typer.Option("--speed", help="Walking speed V, m/s.", rich_help_panel=GAIT)
]
Period = Annotated[
    str,
    typer.Option(
        "--period",
        help="Gait-cycle period T, s, or auto: predicted with the gait, per distance walked "
        "(docs/descriptors.md).",
        rich_help_panel=GAIT,
    ),
]
DoubleSupport = Annotated[
    str,
    typer.Option(
        "--double-support",
        help="Duration Td of one double support, s, or auto: predicted with the gait.",
        rich_help_panel=GAIT,
    ),
]
Paper = Annotated[
    bool,
    typer.Option(
        "--paper",
        help="The paper's case: its subject (68.8 kg, 1.77 m, male), V 1.3806 m/s, T 1.08 s, "
        "Td 0.16 s and C_tor; options given as well override it.",
        rich_help_panel=GAIT,
    ),
]
PAPER_CASE = {"speed": 1.3806, "period": "1.08", "double_support": "0.16", "mass": 68.8,
              "height": 1.77, "sex": "male", "criterion": "tor"}  # fmt: skip
"""What ``--paper`` sets."""
Criterion = Annotated[
    str,
    typer.Option(
        "--criterion",
        help="natural (the preset: effort plus smoothness, impact, arm pose and pelvis terms), "
        "tor or en (the paper's), weights like 'tor=1,accel=0.5,head=0.1', or a TOML file of "
        "weights (docs/criteria.md).",
        rich_help_panel=MODEL,
    ),
]
SplitTerms = Annotated[
    int,
    typer.Option("--split-terms", rich_help_panel=MODEL, help="Free terms (0-4) of the trailing "
                 "foot's load in double support, chosen by the solver; 0: the paper's split "
                 "(docs/criteria.md)."),
]  # fmt: skip
Handover = Annotated[
    bool,
    typer.Option(
        "--handover/--free-landing",
        help="Pass the chain's root from the trailing to the leading foot over double support "
        "(the default), so velocities are continuous at heel strike and OpenSim's inverse "
        "dynamics needs no residual force (walk3d verify); --free-landing: the paper's switch "
        "at heel strike. T and Td are predicted with the free landing (docs/opensim.md).",
        rich_help_panel=MODEL,
    ),
]
SolverName = Annotated[
    str,
    typer.Option(
        "--solver",
        help="ipopt (default) or sqp: CasADi's sqpmethod, the paper's method; far slower, and "
        "not yet seen to converge on the default problem (docs/solver.md).",
        rich_help_panel=SOLVER,
    ),
]
Nodes = Annotated[
    int, typer.Option("--nodes", help="Time nodes per half cycle.", rich_help_panel=SOLVER)
]
LinearSolver = Annotated[
    str,
    typer.Option(
        "--linear-solver",
        help="IPOPT's linear solver: mumps (default, built in) or an HSL solver (ma27, ma57, "
        "ma77, ma86, ma97) from an HSL library you have (--hsl-library).",
        rich_help_panel=SOLVER,
    ),
]
Perturbation = Annotated[
    float,
    typer.Option(
        "--perturbation",
        help="Amplitude of the uniform random numbers added to the start (Fourier "
        "coefficients of sin(angle/2); an atlas start adds 4 % of it, and none for seed "
        "0; 0.25 gives an atlas start ±0.01). From standing, "
        "the default keeps the default prediction on the best walking optimum; 0.1 sends more "
        "of a campaign's starts to walking optima (docs/solver.md).",
        rich_help_panel=SOLVER,
    ),
]
Start = Annotated[
    str,
    typer.Option(
        "--start",
        help="atlas: start from walk3d's own solved neighbour and solve the full problem alone "
        "(seconds; standing when the atlas has no entry or it fails), or standing: the paper's "
        "upright start plus noise, through the posture and balance stages.",
        rich_help_panel=SOLVER,
    ),
]
DescriptorsFrom = Annotated[
    str,
    typer.Option(
        "--descriptors-from",
        help="atlas: predicted T and Td blended from the atlas's free-landing optima, then one "
        "solve (seconds); solve: the free landing solved first, then the handover at its T and "
        "Td (docs/descriptors.md).",
        rich_help_panel=SOLVER,
    ),
]
MaxIter = Annotated[
    int,
    typer.Option(
        "--max-iter", help="Advanced: solver iteration limit per stage.", rich_help_panel=SOLVER
    ),
]
Restarts = Annotated[
    int,
    typer.Option(
        "--restarts",
        help="Times a start that did not converge is tried again from a new standing start "
        "(the seed's next random stream; 0: a single try, as in the paper).",
        rich_help_panel=SOLVER,
    ),
]
HslLibrary = Annotated[
    str | None,
    typer.Option(
        "--hsl-library",
        help="Path of libhsl.so or libcoinhsl.so (HSL solvers).",
        rich_help_panel=SOLVER,
    ),
]


def input_file(
    ctx: typer.Context, param: typer.CallbackParam, value: str | list[str] | None
) -> str | list[str] | None:
    """Callback of an option or argument naming files to read: one that is a folder, FIFO,
    socket or device (:func:`walk3d.io.checks.input_problem`; a FIFO blocked its reader for
    ever) is refused in one line naming the option, exit code 2, before the command starts. A
    missing file is left to the command's reader, which names it."""
    from walk3d.io.checks import input_problem

    if ctx.resilient_parsing:  # completion: nothing is read
        return value
    name = param.opts[0] if param.param_type_name == "option" else str(param.name)
    for path in [value] if isinstance(value, str) else value or []:
        why = input_problem(path)
        if why:
            fail(f"{name} {path}: {why}")
    return value


FromTrial = Annotated[
    str | None,
    typer.Option(
        "--from-trial",
        help="IK .mot of a measured trial: V, T and Td from it (needs --grf).",
        rich_help_panel=GAIT,
        callback=input_file,
    ),
]
TrialGrf = Annotated[
    str | None,
    typer.Option(
        "--grf",
        help="GRF .mot of the --from-trial trial.",
        rich_help_panel=GAIT,
        callback=input_file,
    ),
]
PlateThreshold = Annotated[
    float, typer.Option("--threshold", help="Force-plate contact threshold, N.")
]
BeltSpeed = Annotated[
    float | None, typer.Option("--speed", help="Belt speed for treadmill trials, m/s.")
]
CalibrationFile = Annotated[
    str | None,
    typer.Option(
        "--calibration",
        help="Calibration JSON (walk3d calibrate): roll-over, ratios.",
        rich_help_panel=MODEL,
        callback=input_file,
    ),
]
CompileLater = Annotated[
    bool,
    typer.Option(
        "--compile-later/--no-compile-later",
        help="After a solve in CasADi's VM, compile this model's derivatives in the background "
        "(about 3 min, low priority) so that later predictions solve about twice as fast; "
        "also off with WALK3D_COMPILE_LATER=0.",
        rich_help_panel=SOLVER,
    ),
]


EXIT_WRITE = 3
"""Exit code of a command whose output could not be written (disk full, permissions)."""
EXIT_NOT_WALKING = 4
"""Exit code of a prediction that converged on a gait that does not look like walking (its
result is written and labelled): a script must not take it for a walk."""


def exit_code(summary: dict) -> int:
    """``walk3d predict``'s exit code for a written result: 1 when the solve did not converge,
    :data:`EXIT_NOT_WALKING` when it converged on a gait that does not look like walking, 0."""
    if not summary.get("converged"):
        return 1
    if not (summary.get("gait_checks") or {}).get("looks_like_walking", True):
        return EXIT_NOT_WALKING
    return 0


def fail(message: str, code: int = 2) -> None:
    """Print one error line and exit (2 = bad input)."""
    sys.stderr.write(f"walk3d: error: {message}\n")
    raise typer.Exit(code)


def positive_options(**values: float | None) -> None:
    """One line and exit 2 for the first option given that is not a finite number above zero
    (``--speed nan``, ``--mass -1``); a keyword names its option (``mass``: ``--mass``)."""
    from walk3d.io.checks import positive_numbers  # the library's check, named as an option

    for name, value in values.items():
        try:
            positive_numbers(**{name: value})
        except ValueError as exc:
            fail(f"--{name.replace('_', '-')}{str(exc)[len(name) :]}")


def check_output_folder(path: str, option: str = "--out", replaces: str | None = None,
                        own: tuple[str, ...] = (), **checks: Any) -> None:  # fmt: skip
    """Refuse, before any work, an output folder that is a file, cannot be written, lies in a
    result folder (but ``home``) or holds other files than a ``replaces`` result (and ``own``):
    one line and exit 2 (:func:`walk3d.outputs.check_output_folder`, the API's check too)."""
    from walk3d.outputs import check_output_folder as check

    try:
        check(path, option, replaces, own or None, **checks)
    except ValueError as exc:
        fail(str(exc))


def check_output_file(
    path: str, option: str = "--out", suffix: str | None = None, **checks: Any
) -> None:
    """Refuse, before any work, an output file that is a folder, lacks ``suffix``, cannot be
    created, lies in a result folder (but ``home``), is an input or is not walk3d's (``inputs``,
    ``existing``): one line and exit 2 (:func:`walk3d.outputs.check_output_file`)."""
    from walk3d.outputs import check_output_file as check

    try:
        check(path, option, suffix, **checks)
    except ValueError as exc:
        fail(str(exc))


def criterion_option(value: str) -> str:
    """``--criterion``: :func:`walk3d.api.criterion_value`, or one line and exit 2."""
    from walk3d.api import criterion_value

    try:
        return criterion_value(value)
    except ValueError as exc:
        fail(f"--{exc}")
    raise AssertionError  # fail() exits


def given_on_command_line(ctx: typer.Context, name: str) -> bool:
    """Whether option ``name`` (its parameter name) was typed, not defaulted."""
    return getattr(ctx.get_parameter_source(name), "name", "") == "COMMANDLINE"


def paper_case(ctx: typer.Context, paper: bool, values: dict) -> dict:
    """``values`` with :data:`PAPER_CASE` in place of every one not typed, when ``paper``."""
    if not paper:
        return values
    return {k: v if k not in PAPER_CASE or given_on_command_line(ctx, k) else PAPER_CASE[k]
            for k, v in values.items()}  # fmt: skip


def _descriptor(value: str | float, option: str) -> float | None:
    if str(value).strip().lower() == "auto":
        return None
    from walk3d.decimals import decimal  # 1_0 is not 10

    number = value if isinstance(value, float) else decimal(str(value))
    if not (number > 0 and number < float("inf")):
        fail(f"{option} must be a positive number of seconds or auto, got {value!r}")
    return number


def gait_fields(
    speed: float, period: str | float, double_support: str | float, height: float
) -> dict:
    """``speed``, ``period``, ``double_support`` and ``free`` settings fields
    (:func:`walk3d.api.gait_fields`; ``auto`` descriptors are predicted); one error line and
    exit 2 for a value that is neither a number nor auto."""
    from walk3d.api import gait_fields as fields

    try:
        return fields(speed, _descriptor(period, "--period"),
                      _descriptor(double_support, "--double-support"), height)  # fmt: skip
    except ValueError as exc:
        fail(str(exc))
    raise AssertionError  # fail() exits


def settings_from_options(criterion: str, solver: str, seed: int, **fields):
    """Validated PredictionSettings from command-line values, or one error line and exit 2."""
    from walk3d.io.criterion import with_file_options  # a fitted file's [model] options
    from walk3d.model.settings import equal_steps_unused
    from walk3d.problem.settings import PredictionSettings, first_error

    given, criterion = criterion, criterion_option(criterion)  # the file's checks first
    try:
        fields = with_file_options(given, fields)
    except ValueError as exc:  # DataFileError too
        fail(" ".join(str(exc).split()))
    if solver not in ("ipopt", "sqp"):
        fail(f"--solver must be 'ipopt' or 'sqp', got {solver!r}")
    if seed < 0:
        fail(f"--seed must be a non-negative integer, got {seed}")
    try:
        settings = PredictionSettings(criterion=criterion, **fields)
    except ValueError as exc:
        fail(first_error(exc))
    if solver == "sqp" and settings.model.split_terms:
        fail("--split-terms needs --solver ipopt (the SLSQP baseline solves the paper's split)")
    if equal_steps_unused(settings.model):  # as walk3d.api.settings refuses it
        fail("--equal-steps needs --full-cycle or a one-sided change (a name ending in _r or "
             "_l, --leg-length-difference): the half cycle's steps are equal already")  # fmt: skip
    if settings.solver.linear_solver != "mumps" and solver == "ipopt":
        from walk3d.solve.options import linear_solver_error

        problem = linear_solver_error(settings, "--hsl-library")
        if problem:
            fail(problem)
    return settings


def scheduler_option(scheduler: str | None) -> None:
    """``--scheduler``: a Dask scheduler that answers (:func:`walk3d.campaign.runner.
    check_scheduler`), or one line and exit 2; nothing to check when None."""
    if not scheduler:
        return
    from walk3d.campaign.runner import check_scheduler

    try:
        check_scheduler(scheduler)
    except ValueError as exc:
        fail(str(exc))

"""The solve as a plan: stages as data, and the one loop that runs them.

A :class:`Stage` names the NLP it solves (:data:`walk3d.problem.nlp.STAGES`), where it starts,
its iteration limit and progress checks, and which stage follows when it converges or not.
:func:`default_plan` makes the plan of a :class:`~walk3d.problem.settings.SolverSettings`;
:func:`run_plan` runs a plan through a callback that solves one stage, with the restart policy.
Both are pure (no IPOPT), so the policy is tested on scripted stage outcomes. The stages:

0. *posture*: every kinematic constraint, minimizing joint rates, accelerations and
   coordinates (no inverse dynamics);
1. *balance*: the same, with the total ground reaction kept physical under the feet;
2. *full*: the criterion under all constraints.

docs/solver.md has the measurements behind the plan.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

from walk3d.model import terms
from walk3d.problem.settings import SolverSettings

__all__ = ["END", "SUCCESS", "Plan", "Stage", "default_plan", "run_plan"]

END = "end"
"""The successor that ends an attempt."""
SUCCESS = frozenset({"Solve_Succeeded", "Solved_To_Acceptable_Level"})
"""Return statuses counted as converged (IPOPT's, and sqpmethod's ``Solve_Succeeded``)."""

Start = Literal["standing", "previous", "criterion"]
"""Where a stage starts: the attempt's standing start, the previous stage's end, or that end
with the full stage's extra variables made consistent
(:func:`walk3d.solve.ipopt.full_stage_start`)."""


@dataclass(frozen=True, kw_only=True)
class Stage:
    """One stage of a plan."""

    key: str
    """Its name in the plan (unique)."""
    name: str
    """Its name in the stage records of ``summary.json``."""
    problem: Literal["posture", "balance", "full", "free"]
    """The NLP it solves (``free``: the full NLP with the predicted descriptors free,
    :func:`walk3d.solve.ipopt.solve_stages`)."""
    start: Start
    max_iter: int
    """IPOPT's iteration limit."""
    checks: tuple[tuple[int, float], ...] = ()
    """``(iteration, violation)``: stop the stage at that iteration if its largest constraint
    violation is still above the value."""
    on_success: str = END
    on_failure: str = END
    restart_on_failure: bool = False
    """A failure ends the attempt while a restart is left (on the last attempt, ``on_failure``
    follows)."""
    title: str
    """Progress message when the stage starts."""
    label: str
    """Prefix of its per-iteration progress messages."""
    failure_note: str = ""
    """Progress message when it fails and ``on_failure`` follows."""
    restart_note: str = ""
    """Progress message when it fails and the attempt ends for a restart."""

    def stops(self, iteration: int, violation: float) -> bool:
        """Whether a progress check stops the stage at this iteration."""
        return any(it == iteration and violation > v for it, v in self.checks)


@dataclass(frozen=True)
class Plan:
    """Stages, the first one first; every successor is a stage of the plan or :data:`END`."""

    stages: tuple[Stage, ...]

    def __post_init__(self) -> None:
        keys = [s.key for s in self.stages]
        if len(set(keys)) != len(keys):
            raise ValueError(f"stage keys must be unique, got {keys}")
        for s in self.stages:
            for nxt in (s.on_success, s.on_failure):
                if nxt != END and nxt not in keys:
                    raise ValueError(f"stage {s.key!r} is followed by unknown stage {nxt!r}")

    @property
    def first(self) -> Stage:
        return self.stages[0]

    def __getitem__(self, key: str) -> Stage:
        for s in self.stages:
            if s.key == key:
                return s
        raise KeyError(f"unknown stage {key!r}; known: {[s.key for s in self.stages]}")

    def next(self, stage: Stage, converged: bool, restart_left: bool) -> str:
        """The key of the stage after ``stage``, or :data:`END`."""
        if converged:
            return stage.on_success
        if stage.restart_on_failure and restart_left:
            return END
        return stage.on_failure


def default_plan(solver: SolverSettings, criterion: str = "tor") -> Plan:
    """The stages of ``solver.posture_stage``.

    ``fallback``: balance from standing, then full. If either fails, posture and balance from
    standing again, then full once more. ``first``: posture, balance, full. ``off``: balance,
    full. A balance stage after the posture stage (or the only one) that fails ends the
    attempt while a restart is left: the full stage after it seldom converged.
    """
    limit = solver.max_iter
    crit = terms.label(criterion)
    full = dict(problem="full", start="criterion", max_iter=min(limit, solver.full_max_iter),
                title=f"stage 2/2: minimizing {crit}", label=f"stage 2/2 ({crit})")  # fmt: skip
    balance_title = "stage 1/2: balance (walking posture, total reaction under the feet)"
    balance = dict(key="balance", name="balance", problem="balance", on_success="full",
                   on_failure="full", max_iter=min(limit, solver.posture_balance_max_iter),
                   restart_on_failure=True, label="stage 1/2 (balance)",
                   restart_note="the balance stage did not converge: restarting instead of "
                   "the full stage")  # fmt: skip
    posture = Stage(key="posture", name="posture", problem="posture", start="standing",
                    max_iter=limit, on_success="balance", on_failure="balance",
                    title="stage 0: walking posture (geometry only)",
                    label="stage 0 (posture)")  # fmt: skip
    after_posture = Stage(start="previous", title="stage 1/2: balance, from the walking posture",
                          **balance)  # fmt: skip
    last_full = Stage(key="full", name="full", **full)
    if solver.posture_stage == "first":
        return Plan((posture, after_posture, last_full))
    if solver.posture_stage == "off":
        return Plan((Stage(start="standing", title=balance_title, **balance), last_full))
    retry = "the full stage did not converge: retrying from standing through the posture stage"
    direct = Stage(key="balance_direct", name="balance_direct", problem="balance",
                   start="standing", max_iter=solver.balance_max_iter,
                   checks=tuple(solver.progress_checks().items()), on_success="full_direct",
                   on_failure="posture", title=balance_title,
                   label="stage 1/2 (balance)")  # fmt: skip
    first_full = Stage(key="full_direct", name="full", on_failure="posture", failure_note=retry,
                       **full)  # fmt: skip
    return Plan((direct, first_full, posture, after_posture, last_full))


StageRunner = Callable[[Stage, int], dict]
"""``run(stage, attempt) -> record``: solve one stage; the record has at least ``status``."""


@dataclass(frozen=True)
class PlanResult:
    """What :func:`run_plan` returns."""

    records: list[dict]
    """Every stage run, in order, each with its ``attempt``."""
    attempts: int
    converged: bool
    """Whether the last stage run converged."""


def run_plan(
    plan: Plan, restarts: int, run: StageRunner, note: Callable[[str], None] = lambda _m: None
) -> PlanResult:
    """Run ``plan`` from up to ``restarts + 1`` standing starts, until an attempt's last stage
    converges. ``note`` receives the policy's messages (a restart, a retry)."""
    records: list[dict] = []
    converged = False
    attempt = 0
    for attempt in range(restarts + 1):
        if attempt:
            note(f"not converged: restarting from a new standing start "
                 f"({attempt + 1} of {restarts + 1})")  # fmt: skip
        stage: Stage | None = plan.first
        while stage is not None:
            record = run(stage, attempt)
            record["attempt"] = attempt
            records.append(record)
            converged = record["status"] in SUCCESS
            key = plan.next(stage, converged, restart_left=attempt < restarts)
            if not converged:
                message = stage.failure_note if key == stage.on_failure else stage.restart_note
                if message:
                    note(message)
            stage = None if key == END else plan[key]
        if converged:
            break
    return PlanResult(records, attempt + 1, converged)

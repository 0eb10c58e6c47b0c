"""Building the prediction NLP's solvers: one :class:`Solver` per settings and method.

A :class:`Solver` holds the NLP's bounds and lifting maps; its stage solvers (CasADi ``nlpsol``
with IPOPT, or ``sqpmethod``) are built on first use, in the calling thread (CasADi's symbolics
are not thread-safe). Solvers are kept in memory per settings (:func:`build_solver`), the
model's SX functions on disk too (:mod:`walk3d.solve.model_cache`). docs/solver.md has figures.
"""

from __future__ import annotations

import inspect
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cache

import casadi as ca
import numpy as np

from walk3d.body.model import BodyModel
from walk3d.model.settings import node_fields
from walk3d.problem import derivatives, free_nlp, nlp, similarity
from walk3d.problem.bounds import Bounds, bounded_rows, bounds
from walk3d.problem.layout import NlpLayout
from walk3d.problem.schedule import Schedule, lifting_maps, nlp_layout, schedule
from walk3d.problem.settings import ModelSettings, PredictionSettings, body_for
from walk3d.solve import blas, compiled, model_cache, progress
from walk3d.solve.options import ipopt_options, sqp_options
from walk3d.solve.plan import Plan, Stage, default_plan
from walk3d.solve.progress import IterationReporter

WARM_START = {"ipopt.warm_start_init_point": "yes", "ipopt.mu_init": 1e-6,
              "ipopt.warm_start_bound_push": 1e-9, "ipopt.warm_start_mult_bound_push": 1e-9,
              "ipopt.warm_start_slack_bound_push": 1e-9}  # fmt: skip
"""IPOPT's options for a start from a primal-dual point near the optimum (an atlas blend): its
multipliers are used and barely moved off the bounds, and the barrier starts small. From the
blend at 1.3806 m/s, 8 iterations instead of 25 to the same optimum (docs/starts.md)."""
COMPILED_NODES = {"balance": nlp.node_name(False, True, False),
                  "full": nlp.node_name(True, True, False),
                  "full_hs": nlp.node_name(True, True, True)}  # fmt: skip
"""Node functions whose derivatives can be compiled to C (:func:`compile_solver`), by NLP kind:
the mapped nodes of the balance and full NLPs, and the full NLP's node 0 (``<kind>_hs``, with
the heel-strike rows; otherwise about 2 s of every process's set-up). The posture NLP's
derivatives are small; the balance NLP's node 0 stays in CasADi's VM too."""
CHUNKS = 8
"""Column blocks per compiled Jacobian or Hessian (:func:`derivatives.derivative_chunks`)."""


@dataclass(frozen=True, eq=False, kw_only=True)
class Solver:
    """The NLP of one settings: bounds and lifting maps at once, stage solvers on first use.

    Building a stage's exact derivatives is most of a build, so a stage solver is built when
    first asked for (:meth:`stage`); stages of one NLP and iteration limit share a solver, and a
    solve builds only the stages it runs.
    """

    settings: PredictionSettings
    body: BodyModel
    method: str
    functions: Mapping[str, ca.Function]
    """The model's SX functions (:func:`walk3d.problem.nlp.model_functions`), each made on first
    use (:class:`walk3d.solve.model_cache.LazyFunctions`)."""
    bounds: Bounds
    bounds_balance: Bounds
    bounds_posture: Bounds
    lift: np.ndarray
    schedule: Schedule
    layout: NlpLayout
    """The blocks of ``z`` and ``g`` (:mod:`walk3d.problem.layout`)."""
    plan: Plan
    """The stages a solve runs (:func:`walk3d.solve.plan.default_plan`)."""
    build_time_s: float
    """Time to set up the solver without its stages (model functions, bounds)."""
    bounds_free: Bounds | None = None
    """The full NLP's bounds with the predicted descriptors free (``settings.gait.free``; the
    other NLPs pin them at the first guess), for the last stage; None without."""
    compiled: dict[str, derivatives.NodeDerivs] = field(default_factory=dict, repr=False)
    """Compiled ``(jac, grad, hess)`` of the mapped node function, by NLP kind (those found in
    the cache at build time; :func:`compile_solver` makes them)."""
    stage_build_s: dict[str, float] = field(default_factory=dict, repr=False)
    """Seconds spent building each NLP (``nlp:<kind>``) and stage solver (``<kind>:<limit>``)."""
    stage_rows: dict[str, np.ndarray] = field(init=False, repr=False)
    """By NLP kind, the constraint rows its stage solvers see (:func:`bounded_rows`)."""
    reporters: dict[str, IterationReporter] = field(init=False, repr=False)
    """IPOPT's per-iteration callbacks by NLP kind, shared by its stages (:mod:`.progress`)."""
    _built: dict[str, object] = field(default_factory=dict, repr=False)
    _locks: dict[str, threading.Lock] = field(default_factory=dict, repr=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def __post_init__(self) -> None:
        rows = {kind: bounded_rows(self.nlp_bounds(kind)) for kind in nlp.STAGES}
        reporters = {kind: IterationReporter(f"walk3d_progress_{kind}",
                                             self.nlp_bounds(kind).lbz.size, r.size)
                     for kind, r in rows.items()}  # fmt: skip
        if self.bounds_free is not None:  # the full NLP and its solvers, other bounds
            rows["free"], reporters["free"] = rows["full"], reporters["full"]
        object.__setattr__(self, "stage_rows", rows)
        object.__setattr__(self, "reporters", reporters)

    @property
    def from_cache(self) -> bool:
        """Whether every model function made so far was read from the on-disk cache."""
        f = self.functions
        return isinstance(f, model_cache.LazyFunctions) and bool(f.hits) and not f.misses

    def _lock_for(self, key: str) -> threading.Lock:
        with self._lock:
            return self._locks.setdefault(key, threading.Lock())

    def nlp_bounds(self, kind: str) -> Bounds:
        """The bounds of NLP ``kind`` (posture, balance, full, or free: the full NLP with the
        predicted descriptors free) on all its rows."""
        return {"posture": self.bounds_posture, "balance": self.bounds_balance,
                "full": self.bounds, "free": self.bounds_free}[kind]  # fmt: skip

    def stage_bounds(self, kind: str) -> Bounds:
        """The bounds that the stage solvers of NLP ``kind`` take: those of the NLP, on the rows
        they keep (:attr:`stage_rows`); ``g`` in a stage's solution has these rows."""
        b, rows = self.nlp_bounds(kind), self.stage_rows[kind]
        return Bounds(b.lbz, b.ubz, b.lbg[rows], b.ubg[rows])

    def nlp_problem(self, kind: str) -> dict:
        """The NLP dict of ``kind`` on all its rows (posture, balance, full; ``step``: the full
        one with its anchor shift, :func:`walk3d.problem.nlp.build_nlp`) with its derivative
        functions, built once."""
        kind = "full" if kind == "free" else kind
        key = f"nlp:{kind}"
        with self._lock_for(key):
            if key not in self._built:
                t0 = time.perf_counter()
                shift, kd = (True, "full") if kind == "step" else (False, kind)
                build = free_nlp.build_free_nlp if self.settings.gait.free else nlp.build_nlp
                prob, _, _ = progress.awaited(lambda: build(
                    self.body, self.settings, *nlp.STAGES[kd], functions=self.functions,
                    node_derivs=self.compiled.get(kd), node0_derivs=self.compiled.get(f"{kd}_hs"),
                    **({"shift": True} if shift else {})))  # fmt: skip
                self._built[key] = prob
                self.stage_build_s[key] = time.perf_counter() - t0
            return self._built[key]  # type: ignore[return-value]

    def stage_problem(self, kind: str, rows: np.ndarray | None = None) -> dict:
        """The NLP dict of ``kind`` with its derivatives, on ``rows`` (default: those its stage
        solvers see)."""
        rows = self.stage_rows[kind] if rows is None else rows
        return derivatives.select_rows(self.nlp_problem(kind), rows)

    def _stage(self, stage: Stage | str) -> Stage:
        return self.plan[stage] if isinstance(stage, str) else stage

    def stage(self, stage: Stage | str, warm: bool = False) -> ca.Function:
        """The solver of ``stage`` (a :class:`Stage` or its key in :attr:`plan`), built on first
        use and shared by the stages of the same NLP and iteration limit; ``warm``: with IPOPT's
        warm start (:data:`WARM_START`), for a start with multipliers."""
        st = self._stage(stage)
        kind = "full" if st.problem == "free" else st.problem  # the same solver, other bounds
        key = f"{kind}:{st.max_iter}" + (":warm" if warm else "")
        with self._lock_for(key):
            if key not in self._built:
                prob = self.stage_problem(kind)
                t0 = time.perf_counter()
                if self.method == "ipopt":
                    opts = ipopt_options(self.settings) | {"ipopt.max_iter": st.max_iter}
                    opts |= WARM_START if warm else {}
                    plugin = "ipopt"
                else:
                    opts, plugin = sqp_options(self.settings), "sqpmethod"
                opts["iteration_callback"] = self.reporters[kind]
                fn = progress.awaited(
                    lambda: ca.nlpsol(
                        f"walk3d_{st.key}", plugin, *_with_derivatives(prob, opts, plugin)
                    )
                )
                self._built[key] = fn
                self.stage_build_s[key] = time.perf_counter() - t0
            return self._built[key]  # type: ignore[return-value]

    @property
    def constraints(self) -> ca.Function:
        """``g(z)`` of the full stage (to start it consistently), built once (from a full-cycle
        step's NLP at zero shift if only that is built: the same rows)."""
        with self._lock_for("constraints"):
            if "constraints" not in self._built:
                step = "nlp:full" not in self._built and "nlp:step" in self._built
                prob = self.nlp_problem("step" if step else "full")
                self._built["constraints"] = derivatives.constraint_function(prob)
            return self._built["constraints"]  # type: ignore[return-value]


def model_key(body: BodyModel, model: ModelSettings) -> str:
    """The model cache key: the body and the settings that shape the node functions
    (:func:`walk3d.model.settings.node_fields`), all that
    :func:`walk3d.problem.nlp.model_functions` receives. The gait descriptors reach the node
    functions as node parameters, so one entry serves every V, T and Td of a body."""
    return model_cache.model_key(node_fields(model), body)


def _model_functions(
    body: BodyModel, model: ModelSettings, use_cache: bool
) -> model_cache.LazyFunctions:
    """The model's SX functions (:func:`walk3d.problem.nlp.model_functions`), each made on first
    use, from the disk cache when ``use_cache`` and it has the function."""
    key = model_key(body, model) if use_cache else None
    return model_cache.LazyFunctions(
        nlp.MODEL_FUNCTIONS, lambda name: nlp.model_functions(body, model, (name,))[name], key
    )


def _compiled_key(fns: dict[str, ca.Function], settings: PredictionSettings, kind: str) -> str:
    """Key of ``kind``'s compiled blocks: what they are made of (the node function itself,
    serialized, the criterion, the blocks, the code that makes them, CasADi) and the compiler
    flags. Not the model key: that changes with any edit of walk3d's source, and a compile
    takes minutes. The code is the source of the two functions that build the blocks, not
    their whole module, so that other edits there keep the libraries."""
    code = [inspect.getsource(f) for f in (derivatives.derivative_chunks,
                                           derivatives.node_symbols)]  # fmt: skip
    made_of = (fns[COMPILED_NODES[kind]].serialize(), _crit(settings), CHUNKS, ca.__version__,
               *code)  # fmt: skip
    return compiled.library_key(repr(made_of), compiled.flags())


def _chunk_names(kind: str) -> list[str]:
    return [f"walk3d_{kind}_{d}_{i}" for d in ("jac", "hess") for i in range(CHUNKS)]


def _crit(settings: PredictionSettings) -> int:
    return nlp.criterion_row(settings.model)


def _chunk_functions(settings: PredictionSettings, fns: dict[str, ca.Function],
                     kind: str) -> dict[str, ca.Function]:  # fmt: skip
    """The SX functions to compile for ``kind``, by name (:func:`_chunk_names`)."""
    blocks = derivatives.derivative_chunks(fns[COMPILED_NODES[kind]], _crit(settings), CHUNKS,
                                           prefix=f"walk3d_{kind}")  # fmt: skip
    return {f.name(): f for f in blocks["jac"] + blocks["hess"]}


def _load_compiled(
    settings: PredictionSettings, fns: Mapping[str, ca.Function]
) -> dict[str, derivatives.NodeDerivs]:
    """The compiled node derivatives found in the cache, as ``(jac, grad, hess)`` by kind. With
    no library in the cache, no key is made (a key serializes, and so makes, a node function)."""
    out: dict[str, derivatives.NodeDerivs] = {}
    if not compiled.any_libraries():
        return out
    for kind in COMPILED_NODES:
        libs = compiled.load_functions(_compiled_key(fns, settings, kind), _chunk_names(kind))
        if libs is None:
            continue
        names = _chunk_names(kind)
        jac = derivatives.assemble([libs[n] for n in names[:CHUNKS]], f"walk3d_{kind}_jac")
        hess = [libs[n] for n in names[CHUNKS:]]  # mapped block by block (map_blocks)
        grad = derivatives.node_gradient(fns[COMPILED_NODES[kind]], _crit(settings))
        out[kind] = (jac, grad, hess)
    return out


@cache
def _build(settings: PredictionSettings, method: str = "ipopt", use_cache: bool = True) -> Solver:
    t0 = time.perf_counter()
    if settings.gait.free:
        free_nlp.check_supported(settings)
    body = body_for(settings)
    fns = _model_functions(body, settings.model, use_cache)
    sch = schedule(settings)
    lift = lifting_maps(settings, sch)
    # only IPOPT takes the structured derivatives (_with_derivatives): sqp needs no libraries
    comp = _load_compiled(settings, fns) if use_cache and method == "ipopt" else {}
    return Solver(
        settings=settings, body=body, method=method, functions=fns,
        bounds=bounds(body, settings, sch),
        bounds_balance=bounds(body, settings, sch, dynamics=False),
        bounds_posture=bounds(body, settings, sch, dynamics=False, balance=False),
        bounds_free=bounds(body, settings, sch, free=True) if settings.gait.free else None,
        lift=lift, schedule=sch, layout=nlp_layout(body, settings, sch),
        plan=default_plan(settings.solver, settings.model.criterion),
        build_time_s=time.perf_counter() - t0, compiled=comp,
    )  # fmt: skip


def _with_derivatives(prob: dict, opts: dict, plugin: str = "ipopt") -> tuple[dict, dict]:
    """The NLP dict and solver options, with the structured derivatives (if built) as options.

    Only IPOPT's interface takes them (``grad_f``, ``jac_g``, ``hess_lag``); ``sqpmethod``
    refuses those options, so it gets CasADi's own (equal, slower) derivatives of the NLP.
    """
    prob = dict(prob)
    derivs = prob.pop("derivatives", {})
    return prob, opts | derivs if plugin == "ipopt" else opts


def build_solver(
    settings: PredictionSettings, method: str = "ipopt", cache: bool | None = None
) -> Solver:
    """The solver for these settings (built on first use, then reused in this process).

    ``cache``: whether to read and write the model's SX functions in the on-disk cache
    (:mod:`walk3d.solve.model_cache`); None (default) follows ``$WALK3D_CACHE`` (on unless ``0``).
    First puts an optimized BLAS under IPOPT when it can (:func:`walk3d.solve.blas.activate`).
    """
    blas.activate()
    return _build(settings, method, model_cache.cache_enabled(cache))


def forget_solvers() -> None:
    """Drop the solvers kept in memory (:func:`build_solver`): a sweep's every speed builds its
    own, and each holds hundreds of MB."""
    _build.cache_clear()


def _compile_kinds(settings: PredictionSettings) -> list[str]:
    """The NLP kinds compiled for ``settings``: the full NLP's node 0 and other nodes, and the
    balance NLP's only for standing starts (a start from the atlas runs the full NLP alone)."""
    return [k for k in ("full_hs", "full", "balance")
            if k != "balance" or settings.solver.start == "standing"]  # fmt: skip


def compiled_status(settings: PredictionSettings) -> dict:
    """``{"compiled": [kinds], "missing": libraries :func:`compile_solver` still has to
    compile}`` for the solves of these settings (those of the reference subject,
    :mod:`walk3d.problem.similarity`, so the same for every mass and stature)."""
    settings = similarity.reference_problem(settings)[0]
    fns = _model_functions(body_for(settings), settings.model, True)
    kinds = [k for k in COMPILED_NODES if compiled.load_functions(
        _compiled_key(fns, settings, k), _chunk_names(k)) is not None]  # fmt: skip
    todo = [k for k in _compile_kinds(settings) if k not in kinds]
    return {"compiled": kinds, "missing": 2 * CHUNKS * len(todo)}


def compile_solver(
    settings: PredictionSettings,
    on_done: Callable[[str, int, int], None] | None = None,
    jobs: int | None = None,
) -> dict:
    """Compile the node derivatives of the full NLP (and of the balance NLP, for standing starts)
    to C and store them in the cache (:mod:`walk3d.solve.compiled`), unless already there; later
    :func:`build_solver` calls load them. Minutes of compiling, once, for a solve
    about twice as fast (docs/solver.md). ``on_done(name, done, total)`` after each library.
    Returns ``{"compiled": number compiled now, "wall_time_s": ...}``; raises
    :class:`walk3d.solve.compiled.CompileError` when there is no compiler or it fails.
    What is compiled is the reference subject's problem (:mod:`walk3d.problem.similarity`),
    which :func:`walk3d.solve.ipopt.solve` solves for every mass and stature of this sex."""
    t0 = time.perf_counter()
    settings = similarity.reference_problem(settings)[0]
    body = body_for(settings)
    done: list[str] = []

    def report(name: str, i: int, n: int) -> None:
        done.append(name)
        if on_done:
            on_done(name, i, n)

    # the free landing is solved first only with descriptors_from = solve (solve.landing)
    models = [settings.model]
    sv = settings.solver
    if settings.model.handover and settings.gait.free and sv.descriptors_from == "solve":
        models.insert(0, settings.model.model_copy(update={"handover": False}))
    kinds = _compile_kinds(settings)
    for model in models:
        fns = _model_functions(body, model, True)
        solved = settings.model_copy(update={"model": model})
        for kind in kinds:
            key = _compiled_key(fns, solved, kind)
            if compiled.load_functions(key, _chunk_names(kind)) is None:
                compiled.compile_functions(key, _chunk_functions(solved, fns, kind), jobs, report)
    _build.cache_clear()  # the next build_solver loads what was compiled
    return {"compiled": len(done), "wall_time_s": time.perf_counter() - t0}

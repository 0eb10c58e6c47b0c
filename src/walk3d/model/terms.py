"""The criterion: its terms by name, and the weighted criteria that combine them.

A criterion spec is ``tor``, ``en`` (the paper's C_tor and C_en), a preset name, or weights
``name=w,...`` over one of those two bases and any registered term (:class:`Term`). The
built-in terms are :data:`walk3d.model.builtin_terms.BUILTIN`; :func:`register` adds one from
outside the package, which then works everywhere a built-in does (the solver's objective, the
evaluated cycle, the summary and the campaign ranking). docs/extending.md shows how.
"""

from __future__ import annotations

import hashlib
import inspect
import math
from typing import Any

from walk3d.body.model import BodyModel
from walk3d.decimals import decimal
from walk3d.kinematics.forward import Pose
from walk3d.model.builtin_terms import BUILTIN
from walk3d.model.term import Node, Parts, Term

__all__ = ["BASES", "DEFAULT_PRESET", "PRESETS", "Node", "Term", "base", "canonical", "extras",
           "fingerprint", "get", "integrands", "label", "minimized", "names", "node_names",
           "parse", "preset_name", "register", "reported", "unregister", "user_terms",
           "weighted"]  # fmt: skip

BASES = ("tor", "en")
"""The paper's criteria; a weighted criterion holds exactly one of them (its absolute values
are the exact slack variables of the NLP)."""
PRESETS: dict[str, dict[str, float]] = {
    "natural": {"tor": 1.0, "accel": 0.5, "jerk": 1.0, "head": 0.5, "impact": 5.0, "shear": 1.0,
                "pose": 0.5, "pelvis": 1.0, "spin": 2.0, "arms": 1.0},
}  # fmt: skip
"""Named weighted criteria (docs/criteria.md: how the weights were chosen)."""
DEFAULT_PRESET = "natural"

_TERMS: dict[str, Term] = {t.name: t for t in BUILTIN}
_BUILTIN_NAMES = frozenset(_TERMS)


def register(term: Term, *, replace: bool = False) -> Term:
    """Add ``term`` to the criterion's terms, so that a spec can weight it by its name.
    Raises ValueError for a base's or a built-in's name, or a taken one unless ``replace``."""
    if not isinstance(term, Term):
        raise TypeError(f"a criterion term must be a walk3d.model.terms.Term, got {term!r}")
    if not term.name.isidentifier() or term.name in BASES or term.name in _BUILTIN_NAMES:
        raise ValueError(f"criterion term name {term.name!r} is taken or not an identifier")
    if term.name in _TERMS and not replace:
        raise ValueError(f"criterion term {term.name!r} is registered already")
    if term.formula is None:
        raise ValueError(f"criterion term {term.name!r} needs a formula")
    _TERMS[term.name] = term
    return term


def unregister(name: str) -> None:
    """Remove a term :func:`register` added (built-ins stay)."""
    if name in _BUILTIN_NAMES:
        raise ValueError(f"criterion term {name!r} is built in")
    _TERMS.pop(name, None)


def names() -> tuple[str, ...]:
    """Every term a criterion can weight beyond its base: built-ins first, in report order."""
    return tuple(_TERMS)


def node_names() -> tuple[str, ...]:
    """:func:`names` with a formula at the nodes (all but ``jerk``)."""
    return tuple(n for n, t in _TERMS.items() if t.formula is not None)


def user_terms() -> tuple[Term, ...]:
    """The terms :func:`register` added (a campaign's workers register them too)."""
    return tuple(t for n, t in _TERMS.items() if n not in _BUILTIN_NAMES)


WHAT_IF_KEYS = ("C_weighted", "C_overload", "C_step_asymmetry")
"""Keys of a summary's ``objective`` that are not terms: the total and the what-if parts."""


def reported(objective: dict) -> tuple[str, ...]:
    """The term keys of a summary's ``objective`` in report order: ``C_tor``, ``C_en``, the
    registered terms, then any other term it records (a term registered where it was made)."""
    known = ("C_tor", "C_en", *(f"C_{k}" for k in names()))
    other = [k for k in objective if k.startswith("C_") and k not in known + WHAT_IF_KEYS]
    return tuple(k for k in known if k in objective) + tuple(other)


def get(name: str) -> Term:
    """The registered term ``name``. Raises KeyError."""
    return _TERMS[name]


def fingerprint(spec: str) -> str:
    """What a cache key needs beyond ``spec``'s canonical form: the formulas of its registered
    (not built-in) terms, so that an edited user term is not served from a cache. Empty for a
    spec of built-ins."""
    user = sorted(n for n in parse(spec) if n in _TERMS and n not in _BUILTIN_NAMES)
    h = hashlib.sha256()
    for name in user:
        t = _TERMS[name]
        try:
            code = inspect.getsource(t.formula)
        except (OSError, TypeError):
            code = f"{t.formula.__module__}.{t.formula.__qualname__}"
        h.update(f"{name}\0{t.scale!r}\0{code}\0".encode())
    return h.hexdigest()[:16] if user else ""


def canonical(spec: str) -> str:
    """The criterion ``spec`` in canonical form: ``tor``, ``en``, or ``name=w,...`` in
    :data:`BASES` + :func:`names` order with zero weights dropped. A preset name expands to
    its weights, so that the form says what is solved. Raises ValueError with one line."""
    weights = parse(spec)
    if set(weights) == {"tor"} and weights["tor"] == 1.0:
        return "tor"
    if set(weights) == {"en"} and weights["en"] == 1.0:
        return "en"
    return ",".join(f"{k}={weights[k]:g}" for k in BASES + names() if k in weights)


def parse(spec: str) -> dict[str, float]:
    """Weights by term name from ``tor``, ``en``, a preset name, or ``name=w,...`` (which may
    start with a preset name: ``natural,pelvis=0,trunk=1`` is the preset with those changes)."""
    s = str(spec).strip()
    if s in BASES:
        return {s: 1.0}
    if s in PRESETS:
        return dict(PRESETS[s])
    known = ", ".join(BASES + names())
    if "=" not in s:
        raise ValueError(f"criterion must be tor, en, a preset ({', '.join(PRESETS)}) or "
                         f"weights like 'tor=1,accel=0.5'; got {s!r}")  # fmt: skip
    weights: dict[str, float] = {}
    given: set[str] = set()
    parts = [p.strip() for p in s.split(",")]
    if "" in parts:
        raise ValueError(f"criterion {s!r} has an empty item")
    for part in parts:
        if part in PRESETS and not given and not weights:  # a preset, changed: natural,trunk=1
            weights.update((k, w) for k, w in PRESETS[part].items())
            continue
        name, _, value = part.partition("=")
        name = name.strip()
        if name not in BASES + names():
            raise ValueError(f"unknown criterion term {name!r} (known: {known})")
        w = decimal(value)  # float() would read 0_5 as 5
        if math.isnan(w):
            raise ValueError(f"criterion weight of {name} must be a finite number, got {value!r}")
        if not math.isfinite(w) or w < 0:
            raise ValueError(f"criterion weight of {name} must be finite and ≥ 0, got {value!r}")
        if name in given:
            raise ValueError(f"criterion term {name} is given twice")
        given.add(name)
        weights.pop(name, None)
        if w > 0:
            weights[name] = w
    bases = [b for b in BASES if b in weights]
    if len(bases) != 1:
        raise ValueError("a weighted criterion needs exactly one of tor and en with a weight > 0 "
                         f"(got {s!r})")  # fmt: skip
    return weights


def base(spec: str) -> str:
    """``tor`` or ``en``: the paper criterion inside ``spec`` (canonical or not)."""
    return next(b for b in BASES if b in parse(spec))


def extras(spec: str) -> dict[str, float]:
    """The weights of the terms of ``spec`` beyond its base, possibly empty."""
    return {k: w for k, w in parse(spec).items() if k not in BASES}


def label(spec: str) -> str:
    """Short name for tables and progress lines: ``C_tor``, ``C_en`` or ``C_weighted``."""
    return f"C_{spec}" if spec in BASES else "C_weighted"


def minimized(objective: dict, spec: str) -> float | None:
    """The criterion value the solver minimized, from a summary's ``objective``: ``C_weighted``'s
    total (the weighted terms and any what-if part: overload, step asymmetry), else the value of
    :func:`label` (older summaries), or None."""
    weighted_ = objective.get("C_weighted")
    if isinstance(weighted_, dict) and isinstance(weighted_.get("total"), (int, float)):
        return float(weighted_["total"])
    return (objective.get(label(spec)) or {}).get("total")


def preset_name(spec: str) -> str | None:
    """The preset whose weights ``spec`` has, or None (also for a spec that names a term not
    registered here, as a stored result's may)."""
    try:
        w = parse(spec)
    except ValueError:
        return None
    return next((n for n, p in PRESETS.items() if p == w), None)


def integrands(
    body: BodyModel,
    coords: list[tuple[Any, Any, Any]],
    pose: Pose,
    force: tuple[Any, Any, Any],
    moments: list[Any] | None = None,
    wanted: tuple[str, ...] | None = None,
) -> dict[str, Parts]:
    """Per node term (``wanted``, default all of :func:`node_names`), its integrand split into
    ``(x, y, z)`` parts whose sum is the integrand (dimensionless, per s).

    ``coords``: the 26 coordinate triples; ``pose`` their kinematics; ``force`` the total
    ground reaction, N; ``moments``: the 24 active DoF moments, N·m (terms that need them are
    left out without them)."""
    axes = [slot for j in body.joints for slot in j.dof_slots]
    node = Node(body, coords, pose, force, moments, axes)
    out = {}
    for name in node_names() if wanted is None else wanted:
        t = _TERMS[name]
        if moments is not None or not t.needs_moments:
            out[name] = t.integrand(node)
    return out


def weighted(weights: dict[str, float], parts: dict[str, Parts]) -> Any:
    """``Σ_j w_j term_j`` over the node terms in ``weights`` (``parts`` as from
    :func:`integrands`; ``jerk`` is not a node term), in :func:`names` order."""
    total = 0.0
    for name in names():
        if name in weights and name in parts:
            x, y, z = parts[name]
            total = total + weights[name] * (x + y + z)
    return total

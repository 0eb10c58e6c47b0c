"""Compare two results of ``benchmarks/run.py``: ``python benchmarks/compare.py [[OLD] NEW]``.

Without paths it compares the reference ``benchmarks/reference/run.json`` with the newest raw
run ``benchmarks/runs/run-*.json``; with one path, the reference with that file. First it
prints both results' environment headers side by side (commit, CPU, versions, BLAS, date,
solver revision; ``benchmarks/environment.py``), marking the fields that differ. Results
written before the header existed show what they recorded (the solver revision and BLAS at
most) and ``-`` for the rest.

This machine's speed varies by 10-30 % from hour to hour, so a change of the median can be the
hour's and not the code's. Starts that took exactly the same iterations in both runs followed
the same path, and their time ratio measures the machine; the other starts show what the code
changed. Prints per seed the iterations, times and criterion values of both runs, then the
medians, the same-path time ratio and the old median scaled by it.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:  # environment.py sits next to this script; also when loaded by path
    sys.path.insert(0, _HERE)
import environment  # noqa: E402

NAME = "run"


def _load(path: str | Path) -> dict:
    return json.loads(Path(path).read_text(encoding="utf-8"))


def _runs(path: str | Path) -> dict[int, dict]:
    return {int(r["seed"]): r for r in _load(path)["runs"]}


def header(result: dict) -> dict:
    """A result's environment header; for a result written before the header existed, the
    fields it recorded at its top level (``solve_revision``, ``blas``, ``cpu_count``)."""
    env = result.get(environment.KEY)
    if isinstance(env, dict):
        return env
    old = {"solve_revision": result.get("solve_revision"), "blas": result.get("blas"),
           "cores": result.get("cpu_count")}  # fmt: skip
    return {k: v for k, v in old.items() if v is not None}


def _shown(env: dict, field: str) -> str:
    if field == "commit" and env.get("commit"):
        return env["commit"] + (" (dirty)" if env.get("dirty") else "")
    value = env.get(field)
    return "-" if value is None else str(value)


def header_rows(old: dict, new: dict) -> list[tuple[str, str, str, bool]]:
    """``(field, old, new, differs)`` for the header fields either result records (``-``
    where one does not; that is not counted as a difference)."""
    rows = []
    for field in environment.FIELDS:
        if field == "dirty":  # shown with the commit
            continue
        a, b = _shown(old, field), _shown(new, field)
        if a == "-" and b == "-":
            continue
        rows.append((field, a, b, a != b and "-" not in (a, b)))  # unrecorded: not a difference
    return rows


def settings_differences(old: dict, new: dict) -> list[tuple[str, object, object]]:
    """``(setting, old, new)`` for every prediction setting the two results ran with that
    differs (grouped or flat, as any walk3d stored them); such results compare other problems."""
    from walk3d.problem.settings import flat_settings

    a, b = flat_settings(old.get("settings") or {}), flat_settings(new.get("settings") or {})
    return [(k, a.get(k), b.get(k)) for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]


def compare(old: dict[int, dict], new: dict[int, dict]) -> dict:
    """Medians of both runs over their converged starts, and the machine's speed ratio."""
    seeds = sorted(set(old) & set(new))
    same = [s for s in seeds if old[s]["iterations"] == new[s]["iterations"]]
    ratios = [new[s]["wall_time_s"] / old[s]["wall_time_s"] for s in same]

    def median(runs: dict[int, dict]) -> float:
        times = [runs[s]["wall_time_s"] for s in seeds if runs[s]["converged"]]
        return statistics.median(times) if times else float("nan")

    ratio = statistics.median(ratios) if ratios else float("nan")
    return {
        "seeds": seeds,
        "same_path": same,
        "changed": [s for s in seeds if s not in same],
        "median_old_s": median(old),
        "median_new_s": median(new),
        "machine_ratio": ratio,
        "median_old_scaled_s": median(old) * ratio,
    }


def resolve(
    paths: list[str], reference: Path | None = None, runs: Path | None = None
) -> list[Path]:
    """The two files to compare: ``paths`` if two; else the reference first, then the one path
    given or the newest raw run."""
    if len(paths) > 2:
        raise SystemExit("give at most two result files")
    if len(paths) == 2:
        return [Path(p) for p in paths]
    ref = environment.reference_path(NAME, reference)
    if len(paths) == 1:
        new = Path(paths[0])
    else:
        new = environment.newest_run(NAME, runs)
        if new is None:
            raise SystemExit(f"no raw run {NAME}-*.json in {runs or environment.RUNS}: "
                             "run python benchmarks/run.py first, or give two files")  # fmt: skip
    if not ref.is_file():
        raise SystemExit(f"no reference {ref}: give two files")
    return [ref, new]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="*", metavar="OLD.json NEW.json",
                    help="default: the reference and the newest raw run")  # fmt: skip
    args = ap.parse_args(argv)
    old_path, new_path = resolve(args.paths)
    old_data, new_data = _load(old_path), _load(new_path)
    print(f"old: {old_path}\nnew: {new_path}")
    for name, data in (("old", old_data), ("new", new_data)):
        if environment.KEY not in data:
            print(f"{name}: written before the environment header; only what it recorded shown")
        elif data[environment.KEY].get("note"):
            print(f"{name}: {data[environment.KEY]['note']}")
    rows = header_rows(header(old_data), header(new_data))
    width = max([len(r[1]) for r in rows] + [8])
    if rows:
        print(f"{'':15} {'old':{width}} new")
    for field, a, b, differs in rows:
        print(f"{field:15} {a:{width}} {b}{'   differs' if differs else ''}")
    for key, a, b in settings_differences(old_data, new_data):
        print(f"settings differ: {key}: old {a!r}, new {b!r}")
    print()
    old = {int(r["seed"]): r for r in old_data["runs"]}
    new = {int(r["seed"]): r for r in new_data["runs"]}
    c = compare(old, new)
    print(f"{'seed':>4} {'it old':>7} {'it new':>7} {'s old':>7} {'s new':>7} "
          f"{'C old':>7} {'C new':>7}")  # fmt: skip
    for s in c["seeds"]:
        a, b = old[s], new[s]
        mark = "" if s in c["same_path"] else "  changed"
        times = f"{a['wall_time_s']:7.1f} {b['wall_time_s']:7.1f}"
        crit = f"{a['criterion']:7.3f} {b['criterion']:7.3f}"
        print(f"{s:4d} {a['iterations']:7d} {b['iterations']:7d} {times} {crit}{mark}")
    print(f"median per converged solve: {c['median_old_s']:.1f} s -> {c['median_new_s']:.1f} s")
    print(f"{len(c['same_path'])} starts took the same iterations; their time ratio "
          f"(new / old, the machine's) is {c['machine_ratio']:.2f}, so the old median at the new "
          f"run's machine speed is {c['median_old_scaled_s']:.1f} s")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())

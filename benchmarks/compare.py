"""Compare two runs of ``benchmarks/run.py``: ``python benchmarks/compare.py OLD.json NEW.json``.

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


def _runs(path: str) -> dict[int, dict]:
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    return {int(r["seed"]): r for r in data["runs"]}


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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    args = ap.parse_args(argv)
    old, new = _runs(args.old), _runs(args.new)
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

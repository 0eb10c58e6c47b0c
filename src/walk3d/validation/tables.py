"""Rich tables of a validation run, for the command line."""

from __future__ import annotations

from rich.table import Table

from walk3d.validation.run import Validation

__all__ = ["table2", "table3"]


def _fmt(value, digits: int = 3) -> str:
    return "-" if value is None or value != value else f"{value:.{digits}f}"


def table2(v: Validation, title: str) -> Table:
    """Table 2 of the first prediction: RMSE (also as a fraction of the measured range), r, R²,
    the reference's mean SD and the status."""
    t = Table(title=title)
    for col in ("quantity", "unit", "RMSE", "/range", "r", "R²", "ref. SD", "status"):
        t.add_column(col)
    key = "" if "rmse" in v.table2_columns else f"_{v.comparisons[0].prediction_name}"
    for row in v.table2:
        t.add_row(row["label"], row["unit"], _fmt(row[f"rmse{key}"]),
                  _fmt(row[f"rmse_of_range{key}"], 2), _fmt(row[f"r{key}"], 2),
                  _fmt(row[f"r2{key}"], 2), _fmt(row["reference_sd"]), row["status"])  # fmt: skip
    return t


def table3(rows: list[dict]) -> Table:
    """Table 3: per source and criterion, the total and the z, x, y shares."""
    t = Table(title="Table 3: criteria and their x/y/z split")
    for col in ("source", "criterion", "total", "z", "x", "y"):
        t.add_column(col)
    for k in range(0, len(rows), 4):
        block = {r["component"]: r for r in rows[k : k + 4]}
        tot = block["total"]
        cells = [f"{block[c]['percent']:.0f}% ({block[c]['value']:.4g})" for c in "zxy"]
        t.add_row(tot["source"], tot["criterion"], f"{tot['value']:.4g}", *cells)
    return t

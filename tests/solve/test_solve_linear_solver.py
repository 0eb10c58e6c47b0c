"""IPOPT's linear solver: MUMPS by default with its tuned options, an HSL solver on request,
a missing HSL library found by a probe instead of a failed solve, and one IPOPT must not load
(cut short, a FIFO) refused before it is loaded."""

import os
import re
from pathlib import Path

import casadi as ca
import pytest

from walk3d import api
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import options

WHOLE = next(Path(ca.__file__).parent.glob("_casadi*.so"))
"""A whole ELF library (CasADi's own; no HSL solver in it)."""


def test_mumps_is_the_default_with_metis_ordering():
    opts = options.ipopt_options(PredictionSettings())
    assert opts["ipopt.linear_solver"] == "mumps"
    assert opts["ipopt.mumps_pivot_order"] == 5 and "ipopt.hsllib" not in opts
    assert options.linear_solver_error(PredictionSettings()) is None


def test_an_hsl_solver_gets_its_library_and_no_mumps_options():
    s = PredictionSettings(linear_solver="ma57", hsl_library=str(WHOLE))
    opts = options.ipopt_options(s)
    assert opts["ipopt.linear_solver"] == "ma57"
    assert opts["ipopt.hsllib"] == str(WHOLE)
    assert not any(k.startswith("ipopt.mumps") for k in opts)


@pytest.mark.parametrize("name", ["ma27", "ma57"])
def test_a_missing_hsl_library_is_reported_in_one_line(name):
    s = PredictionSettings(linear_solver=name, hsl_library="/nonexistent/libhsl.so")
    message = options.linear_solver_error(s)
    assert message is not None and name in message and "\n" not in message
    assert "/nonexistent/libhsl.so" in message


def _library(tmp_path: Path, kind: str) -> str:
    """An HSL library path of ``kind``: CasADi's whole library, a copy cut short, a FIFO, a
    folder, or a bare name (looked up on the library path)."""
    path = tmp_path / "libhsl.so"
    if kind == "cut":
        path.write_bytes(WHOLE.read_bytes()[: WHOLE.stat().st_size // 2])
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    return {"whole": str(WHOLE), "name": "libhsl.so"}.get(kind, str(path))


REFUSED = [("cut", "cut short"), ("fifo", "not a regular file (a FIFO)"), ("folder", "a folder")]


@pytest.mark.parametrize(("kind", "why"), [*REFUSED, ("whole", None), ("name", None)])
def test_an_hsl_library_ipopt_must_not_load_is_refused_before_it_is_loaded(tmp_path, kind, why):
    """A library cut short crashed the process in the dynamic loader (bus error, exit 135) and a
    FIFO blocked it for ever: refused in one line before IPOPT sees it, by the settings of the
    API and by the options of every solve. Negative control: a whole library, and a bare name
    that the loader looks up on the library path, pass (none is loaded here)."""
    lib = _library(tmp_path, kind)
    s = PredictionSettings(linear_solver="ma27", hsl_library=lib)
    message = options.hsl_library_error(s, "--hsl-library")
    if why is None:
        assert message is None
        assert options.ipopt_options(s)["ipopt.hsllib"] == lib
        assert api.settings(linear_solver="ma27", hsl_library=lib).solver.hsl_library == lib
        return
    assert message is not None and "\n" not in message, message
    assert message.startswith(f"--hsl-library {lib} ") and why in message, message
    assert "HSL solver ma27" in message
    with pytest.raises(ValueError, match=re.escape(why)):
        options.ipopt_options(s)
    with pytest.raises(ValueError, match=f"hsl_library {re.escape(lib)} .*{re.escape(why)}"):
        api.settings(linear_solver="ma27", hsl_library=lib)

"""IPOPT's linear solver: MUMPS by default with its tuned options, an HSL solver on request,
and a missing HSL library found by a probe instead of a failed solve."""

import pytest

from walk3d.problem.settings import PredictionSettings
from walk3d.solve import options


def test_mumps_is_the_default_with_metis_ordering():
    opts = options.ipopt_options(PredictionSettings())
    assert opts["ipopt.linear_solver"] == "mumps"
    assert opts["ipopt.mumps_pivot_order"] == 5 and "ipopt.hsllib" not in opts
    assert options.linear_solver_error(PredictionSettings()) is None


def test_an_hsl_solver_gets_its_library_and_no_mumps_options():
    s = PredictionSettings(linear_solver="ma57", hsl_library="/opt/hsl/libcoinhsl.so")
    opts = options.ipopt_options(s)
    assert opts["ipopt.linear_solver"] == "ma57"
    assert opts["ipopt.hsllib"] == "/opt/hsl/libcoinhsl.so"
    assert not any(k.startswith("ipopt.mumps") for k in opts)


@pytest.mark.parametrize("name", ["ma27", "ma57"])
def test_a_missing_hsl_library_is_reported_in_one_line(name):
    s = PredictionSettings(linear_solver=name, hsl_library="/nonexistent/libhsl.so")
    message = options.linear_solver_error(s)
    assert message is not None and name in message and "\n" not in message
    assert "/nonexistent/libhsl.so" in message

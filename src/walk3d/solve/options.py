"""The solvers' options: IPOPT's (with the linear solver's) and CasADi ``sqpmethod``'s, and the
checks that an HSL linear solver can be loaded."""

from __future__ import annotations

import casadi as ca

from walk3d.io.elf import library_problem
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import blas

__all__ = ["hsl_library_error", "ipopt_options", "linear_solver_error", "sqp_options"]


def hsl_library_error(settings: PredictionSettings, option: str = "hsl_library") -> str | None:
    """Why IPOPT must not load the HSL library of ``settings`` in this process (one line naming
    ``option``), or None. IPOPT maps it with the dynamic loader: a library cut short took the
    process down with a bus error, and a FIFO blocked it for ever
    (:func:`walk3d.io.elf.library_problem`)."""
    path = settings.solver.hsl_library
    if settings.solver.linear_solver == "mumps" or not path:
        return None
    why = library_problem(path)
    if why is None:
        return None
    return (f"{option} {path} cannot be loaded for the HSL solver "
            f"{settings.solver.linear_solver}: {why}; "
            "give a whole libhsl.so or libcoinhsl.so, or use mumps")  # fmt: skip


def ipopt_options(settings: PredictionSettings) -> dict:
    """IPOPT's options for ``settings`` (every stage; each stage sets its own ``max_iter``).
    Raises ValueError (one line) for an HSL library IPOPT must not load
    (:func:`hsl_library_error`)."""
    unusable = hsl_library_error(settings)
    if unusable:
        raise ValueError(unusable)
    opts = {
        "print_time": False,
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "ipopt.max_iter": settings.solver.max_iter,
        "ipopt.tol": settings.solver.tol,
        "ipopt.mu_strategy": "adaptive",
    }
    if settings.solver.linear_solver != "mumps":
        opts["ipopt.linear_solver"] = settings.solver.linear_solver
        if settings.solver.hsl_library:
            opts["ipopt.hsllib"] = settings.solver.hsl_library
        return opts
    return opts | {
        "ipopt.linear_solver": "mumps",
        # METIS ordering: on this KKT structure the fastest ordering measured, several times
        # faster than MUMPS's automatic choice (docs/solver.md)
        "ipopt.mumps_pivot_order": 5,
        # MUMPS's workspace as MUMPS estimates it, not IPOPT's default 1000 % more, whose
        # clearing at every factorization cost system time; same iterates (docs/solver.md).
        # If the estimate is ever short, IPOPT enlarges it and refactors
        "ipopt.mumps_mem_percent": 100,
    }


def sqp_options(settings: PredictionSettings) -> dict:
    """CasADi ``sqpmethod`` (the paper used MATLAB's SQP) with the qrqp QP solver."""
    return {
        "qpsol": "qrqp",
        "qpsol_options": {"print_iter": False, "print_header": False, "error_on_fail": False},
        "max_iter": settings.solver.max_iter,
        "tol_pr": settings.solver.tol,
        "tol_du": settings.solver.tol,
        "print_header": False,
        "print_iteration": False,
        "print_status": False,
        "print_time": False,
        "error_on_fail": False,
    }


def linear_solver_error(settings: PredictionSettings, option: str = "hsl_library") -> str | None:
    """None if IPOPT can use ``settings.solver.linear_solver``; otherwise why not, in one line.

    An HSL solver is loaded from a shared library at run time, and IPOPT reports a missing or
    unusable one only as ``Invalid_Option`` when a solve starts; a two-variable problem finds
    that out before a long solve or campaign does. A library IPOPT must not load is refused
    before the probe (:func:`hsl_library_error`, naming ``option``)."""
    if settings.solver.linear_solver == "mumps":
        return None
    unusable = hsl_library_error(settings, option)
    if unusable:
        return unusable
    blas.activate()  # before IPOPT is first loaded (walk3d.solve.blas)
    x = ca.SX.sym("x", 2)
    probe = ca.nlpsol("walk3d_probe", "ipopt", {"x": x, "f": ca.sumsqr(x - 1), "g": x[0] + x[1]},
                      ipopt_options(settings))  # fmt: skip
    probe(x0=[0.0, 0.0], lbg=0.0, ubg=1.0)
    if probe.stats()["success"]:
        return None
    where = settings.solver.hsl_library or "IPOPT's default library name on the library path"
    return (f"IPOPT could not use the HSL solver {settings.solver.linear_solver} from {where} "
            f"({probe.stats()['return_status']}); give the HSL library's path "
            "(libhsl.so or libcoinhsl.so) or use the default solver, mumps")  # fmt: skip

"""The solvers' options: IPOPT's (with the linear solver's) and CasADi ``sqpmethod``'s, each
stage's iteration limit, and the check that an HSL linear solver can be loaded."""

from __future__ import annotations

import casadi as ca

from walk3d.problem.settings import PredictionSettings
from walk3d.solve import blas

__all__ = ["ipopt_options", "linear_solver_error", "sqp_options", "stage_max_iter"]


def stage_max_iter(settings: PredictionSettings, name: str) -> int:
    """IPOPT's iteration limit for stage ``name``: ``max_iter``, or the stage's own limit (at
    most ``max_iter``, except ``balance_max_iter``, which a stage test relies on exceeding it)."""
    own = {"balance_direct": settings.balance_max_iter,
           "balance": min(settings.max_iter, settings.posture_balance_max_iter),
           "full": min(settings.max_iter, settings.full_max_iter)}  # fmt: skip
    return own.get(name, settings.max_iter)


def ipopt_options(settings: PredictionSettings) -> dict:
    """IPOPT's options for ``settings`` (every stage; :func:`stage_max_iter` sets each limit)."""
    opts = {
        "print_time": False,
        "ipopt.print_level": 0,
        "ipopt.sb": "yes",
        "ipopt.max_iter": settings.max_iter,
        "ipopt.tol": settings.tol,
        "ipopt.mu_strategy": "adaptive",
    }
    if settings.linear_solver != "mumps":
        opts["ipopt.linear_solver"] = settings.linear_solver
        if settings.hsl_library:
            opts["ipopt.hsllib"] = settings.hsl_library
        return opts
    return opts | {
        "ipopt.linear_solver": "mumps",
        # METIS ordering: on this KKT structure (20 nodes, balance stage, 20 iterations) the
        # linear algebra took 1.6 s with METIS, 5.0 s with QAMD, 8.3 s with AMD and 25-30 s
        # with AMF, PORD or MUMPS's automatic choice
        "ipopt.mumps_pivot_order": 5,
        # MUMPS's workspace: IPOPT's default reserves 1000 % more than MUMPS estimates, and
        # clearing that memory at every factorization took 1.7 s of system time in seed 0's
        # full stage (10.6 s -> 8.8 s of linear algebra with 100 %, same iterates); if the
        # estimate is ever short, IPOPT enlarges it and refactors
        "ipopt.mumps_mem_percent": 100,
    }


def sqp_options(settings: PredictionSettings) -> dict:
    """CasADi ``sqpmethod`` (the paper used MATLAB's SQP) with the qrqp QP solver."""
    return {
        "qpsol": "qrqp",
        "qpsol_options": {"print_iter": False, "print_header": False, "error_on_fail": False},
        "max_iter": settings.max_iter,
        "tol_pr": settings.tol,
        "tol_du": settings.tol,
        "print_header": False,
        "print_iteration": False,
        "print_status": False,
        "print_time": False,
        "error_on_fail": False,
    }


def linear_solver_error(settings: PredictionSettings) -> str | None:
    """None if IPOPT can use ``settings.linear_solver``; otherwise why not, in one line.

    An HSL solver is loaded from a shared library at run time, and IPOPT reports a missing or
    unusable one only as ``Invalid_Option`` when a solve starts; a two-variable problem finds
    that out before a long solve or campaign does."""
    if settings.linear_solver == "mumps":
        return None
    blas.activate()  # before IPOPT is first loaded (walk3d.solve.blas)
    x = ca.SX.sym("x", 2)
    probe = ca.nlpsol("walk3d_probe", "ipopt", {"x": x, "f": ca.sumsqr(x - 1), "g": x[0] + x[1]},
                      ipopt_options(settings))  # fmt: skip
    probe(x0=[0.0, 0.0], lbg=0.0, ubg=1.0)
    if probe.stats()["success"]:
        return None
    where = settings.hsl_library or "IPOPT's default library name on the library path"
    return (f"IPOPT could not use the HSL solver {settings.linear_solver} from {where} "
            f"({probe.stats()['return_status']}); give the HSL library's path "
            "(libhsl.so or libcoinhsl.so) or use the default solver, mumps")  # fmt: skip

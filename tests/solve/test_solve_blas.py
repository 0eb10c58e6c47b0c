"""The BLAS bridge under CasADi's IPOPT (walk3d.solve.blas): it replaces CasADi's bundled OpenBLAS
in the process, exports every function CasADi's libraries take from it, gives IPOPT the same
solution, and reports honestly when it cannot switch.

Each case runs in a fresh Python process: which BLAS IPOPT binds is fixed when IPOPT is
first loaded, once per process."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from walk3d.solve import blas, compiled

pytestmark = [
    pytest.mark.model,
    pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the bridge is Linux only"),
    pytest.mark.skipif(blas.bundled_library() is None, reason="this CasADi bundles no OpenBLAS"),
    pytest.mark.skipif(
        compiled.compiler() is None or shutil.which("nm") is None,
        reason="no C compiler or nm on PATH",
    ),  # fmt: skip
]

# A least-squares problem with a dense 40 x 40 block and 10 equality constraints: MUMPS
# factors a dense front, so its BLAS is exercised. Prints the solution, IPOPT's status and
# which BLAS libraries the process has mapped.
_SCRIPT = r"""
import json, sys
import numpy as np
from walk3d.solve import blas
if sys.argv[1] == "late":  # load IPOPT before walk3d tries to switch
    import casadi as ca
    y = ca.SX.sym("y")
    ca.nlpsol("first", "ipopt", {"x": y, "f": y**2}, {"print_time": 0, "ipopt.print_level": 0,
              "ipopt.sb": "yes"})
st = blas.activate()
import casadi as ca
rng = np.random.default_rng(3)
A, b = rng.normal(size=(60, 40)), rng.normal(size=60)
C, d = rng.normal(size=(10, 40)), rng.normal(size=10)
x = ca.SX.sym("x", 40)
g = ca.mtimes(ca.DM(C), x) + 0.1 * ca.sin(x[:10])
f = ca.sumsqr(ca.mtimes(ca.DM(A), x) - b) + ca.sum1(x**4) / 4
S = ca.nlpsol("s", "ipopt", {"x": x, "f": f, "g": g},
              {"print_time": 0, "ipopt.print_level": 0, "ipopt.sb": "yes"})
r = S(x0=0, lbg=d, ubg=d)
maps = [line.split()[-1] for line in open("/proc/self/maps") if line.strip().endswith(".so")
        or ".so." in line]
print(json.dumps({"active": st.active, "describe": st.describe(), "after": blas.status().active,
                  "x": np.array(r["x"]).ravel().tolist(), "status": S.stats()["return_status"],
                  "maps": sorted(set(maps))}))
"""


def _run(mode: str, cache: Path, **env: str) -> dict:
    full = os.environ | {"WALK3D_CACHE_DIR": str(cache), "OPENBLAS_NUM_THREADS": "1"} | env
    out = subprocess.run([sys.executable, "-c", _SCRIPT, mode], capture_output=True, text=True,
                         env=full, check=False, timeout=300)  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1]) | {"stderr": out.stderr}


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("blas-cache")


@pytest.fixture(scope="module")
def bridged(cache):
    pytest.importorskip("scipy_openblas32", reason="scipy-openblas32 is not installed")
    return _run("early", cache)


def test_bridge_replaces_casadis_openblas(bridged, cache):
    assert bridged["active"] and bridged["after"], bridged["describe"]
    assert bridged["describe"].startswith("scipy-openblas32 ")
    bundled = str(blas.bundled_library().resolve())
    assert bundled not in bridged["maps"]  # IPOPT and MUMPS bound the bridge instead
    assert any(Path(m).name.startswith("blas-") and Path(m).parent == cache
               for m in bridged["maps"])  # fmt: skip
    assert bridged["status"] == "Solve_Succeeded"


def test_bridge_exports_every_function_casadi_takes_from_its_openblas(bridged, cache):
    nm = shutil.which("nm")
    (lib,) = cache.glob("blas-*.so")
    exported = blas._functions(nm, lib, undefined=False)
    needed = blas._needed(nm, blas.bundled_library())
    assert {"dgemm_", "dtrsm_", "ddot_"} <= needed  # MUMPS and IPOPT's own calls
    assert needed <= exported, sorted(needed - exported)[:5]


def test_same_solution_with_either_blas(bridged, cache):
    own = _run("early", cache, WALK3D_BLAS="casadi")
    assert not own["active"] and "$WALK3D_BLAS=casadi" in own["describe"]
    assert str(blas.bundled_library().resolve()) in own["maps"]
    assert own["status"] == "Solve_Succeeded"
    diff = max(abs(a - b) for a, b in zip(bridged["x"], own["x"], strict=True))
    assert diff < 1e-7


def test_too_late_once_ipopt_is_loaded(cache):
    late = _run("late", cache)
    assert not late["active"] and "loaded before" in late["describe"]
    assert late["status"] == "Solve_Succeeded"


def test_missing_scipy_openblas_keeps_casadis(cache, tmp_path):
    # a module that fails to import stands in for the missing package
    (tmp_path / "scipy_openblas32.py").write_text("raise ImportError('absent')\n")
    path = os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])
    out = _run("early", cache, PYTHONPATH=path)
    assert not out["active"] and "not installed" in out["describe"]
    assert out["status"] == "Solve_Succeeded"


def test_a_damaged_bridge_is_built_again_not_loaded(bridged, cache):
    """A truncated bridge (``blas-*.so``) would crash the dynamic loader: it fails its digest,
    and the next process says so, builds it again and runs as before."""
    (bridge,) = cache.glob("blas-*.so")
    data = bridge.read_bytes()
    bridge.write_bytes(data[: len(data) // 3])
    assert compiled.verified(bridge) is not None
    again = _run("early", cache)
    assert again["active"] and again["status"] == bridged["status"], again["describe"]
    assert "ignoring the BLAS bridge" in again["stderr"]  # one warning line says so
    assert "ignoring the BLAS bridge" not in bridged["stderr"]  # the control: a good one
    assert compiled.verified(bridge) is None and bridge.read_bytes() == data

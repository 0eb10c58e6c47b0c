"""Running a multi-start campaign on a Dask distributed cluster.

Start ``k`` (``0 <= k < starts``) uses seed ``base_seed + k``, so any start can be re-run alone
with ``walk3d predict --seed``. Each start is one Dask task (:func:`walk3d.campaign.task.
run_start`) submitted with plain data; tasks run in long-lived worker processes, each of which
builds the compiled model once. Without a scheduler address a :class:`distributed.LocalCluster`
is started with one single-threaded worker process per core (at most one per pending start).

Call :func:`run_campaign` from code guarded by ``if __name__ == "__main__"``: worker processes
are spawned, and spawning re-imports the main module.

With a scheduler address the workers are whatever that cluster runs: they need walk3d installed,
must see the campaign folder at the same absolute path (they write the results), and should be
started with ``OPENBLAS_NUM_THREADS=1`` (set here only for local workers).
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from walk3d.campaign import ranking, resume, start_folders, store, task
from walk3d.model import terms
from walk3d.problem.settings import PredictionSettings, available_cores

if TYPE_CHECKING:
    from distributed import Client

__all__ = ["CampaignReport", "check_scheduler", "dask_client", "run_campaign"]

WORKER_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

DASK_LOG_LEVEL = logging.CRITICAL
"""Dask's messages below this level are not printed by a local cluster. A campaign records
every start's failure itself, and at Ctrl-C a worker whose scheduler has just closed would
otherwise print a heartbeat traceback (logged at ERROR) under the one-line message."""

TRACKER_QUIET = "ignore::UserWarning:multiprocessing.resource_tracker"
"""A ``PYTHONWARNINGS`` filter for the local cluster's processes, the resource tracker among
them. At Ctrl-C while the workers start, the tracker frees their semaphores itself and would
print a two-line warning about them under the one-line message."""


@dataclass
class CampaignReport:
    """What a campaign run did and what the folder now holds."""

    out_dir: Path
    criterion: str
    starts: int
    base_seed: int
    ran: int
    """Starts run by this call (finished, failed or errored)."""
    skipped: int
    """Requested starts already finished before this call (resume)."""
    rows: list[dict] = field(default_factory=list)
    """Ranking of every start in the folder, best first (see :mod:`walk3d.campaign.ranking`)."""
    best_seed: int | None = None
    wall_time_s: float = 0.0
    removed_temporaries: int = 0
    retried: int = 0
    """Starts that had failed on the environment (disk, memory, lost worker) and ran again."""

    @property
    def converged(self) -> int:
        """Number of converged starts in the folder."""
        return sum(1 for r in self.rows if r["converged"])

    @property
    def errors(self) -> int:
        """Number of starts that raised or whose worker died."""
        return sum(1 for r in self.rows if r["status"].startswith("error:"))

    @property
    def missing(self) -> int:
        """Requested starts with no record (their record could not be written): rerun to retry."""
        return self.starts - sum(
            1 for r in self.rows if self.base_seed <= r["seed"] < self.base_seed + self.starts
        )

    @property
    def any_converged(self) -> bool:
        return self.best_seed is not None


SCHEDULER_TIMEOUT_S = 8.0
"""How long a campaign waits for ``--scheduler`` to answer before refusing it."""


def check_scheduler(address: str, timeout_s: float = SCHEDULER_TIMEOUT_S) -> None:
    """Raise ValueError (one line) unless ``address`` is a Dask scheduler address that accepts
    a connection and greets it within ``timeout_s``; checked before a campaign folder is made.
    A listener that is not Dask's would leave ``Client`` waiting without end."""
    from distributed.comm import parse_address
    from distributed.comm.addressing import parse_host_port

    try:
        scheme, location = parse_address(address)
        host, port = parse_host_port(location) if scheme in ("tcp", "tls") else (None, None)
    except ValueError as exc:
        raise ValueError(f"--scheduler {address!r} is not a scheduler address "
                         f"(e.g. tcp://10.0.0.5:8786): {exc}") from None  # fmt: skip
    if host is None:
        return  # another transport: the client reports it
    import socket

    try:
        with socket.create_connection((host, int(port)), timeout=timeout_s) as conn:
            conn.settimeout(timeout_s)
            greeted = conn.recv(1) if scheme == "tcp" else b"tls"
    except TimeoutError:
        greeted = b""
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ValueError(f"no Dask scheduler answers at {address} ({reason.lower()})") from None
    if not greeted:  # a Dask scheduler sends its handshake first; a dashboard or other server waits
        raise ValueError(f"{address} accepts connections but is not a Dask scheduler (no "
                         f"handshake within {timeout_s:g} s; the scheduler's port is usually "
                         "8786, its dashboard's 8787)")  # fmt: skip


@contextlib.contextmanager
def dask_client(workers: int | None, scheduler: str | None, pending: int) -> Iterator[Client]:
    """A Dask client: to ``scheduler`` if given, else to a fresh local process cluster."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        with Client(scheduler) as client:
            _register_terms(client)
            yield client
        return
    for key, value in WORKER_ENV.items():
        os.environ[key] = value  # inherited by the spawned worker processes
    filters = os.environ.get("PYTHONWARNINGS", "")
    if TRACKER_QUIET not in filters.split(","):
        os.environ["PYTHONWARNINGS"] = ",".join(f for f in (filters, TRACKER_QUIET) if f)
    n = max(1, min(workers or available_cores(), pending))
    # a task that kills its worker is retried once, then recorded as an error
    try:
        with (
            dask.config.set({"distributed.scheduler.allowed-failures": 1}),
            LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=DASK_LOG_LEVEL,
                env=dict(WORKER_ENV),
            ) as cluster,
            Client(cluster) as client,
        ):
            client.register_plugin(task.IgnoreInterrupt())
            _register_terms(client)
            yield client
    except KeyboardInterrupt:  # the cluster's event loop may be left with a failed future
        logging.getLogger("asyncio").setLevel(logging.CRITICAL)
        raise


def _register_terms(client: Client) -> None:
    """Register this process's user criterion terms on every worker (none: nothing to do)."""
    user = terms.user_terms()
    if user:
        client.register_plugin(task.RegisterTerms(user))


def _progress(console: Console | None, enabled: bool) -> Progress:
    return Progress(
        TextColumn("[bold]walk3d campaign"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[note]}"),
        TimeElapsedColumn(),
        TextColumn("remaining"),
        TimeRemainingColumn(),
        console=console,
        disable=not enabled,
    )


def _note(records: dict[int, dict], criterion: str) -> str:
    values = [
        r["criterion_value"]
        for r in records.values()
        if r.get("converged") and isinstance(r.get("criterion_value"), (int, float))
    ]
    best = f"{min(values):.4g}" if values else "-"
    errors = sum(1 for r in records.values() if str(r.get("status", "")).startswith("error:"))
    text = f"converged {len(values)}  best C_{criterion} {best}"
    return text + (f"  errors {errors}" if errors else "")


MAX_WORKERS = 256
"""Local worker processes: each holds a model of about 1 GB, and a machine with more cores
than this scales out with a scheduler (``--scheduler``)."""
MAX_STARTS = 100_000
"""Starts in one campaign: each is a solve of seconds to minutes, so more is days of a
cluster's time, and its futures alone would fill the memory."""


def _validate(starts: int, base_seed: int, workers: int | None, solver: str) -> None:
    from walk3d.solve import SOLVERS

    if isinstance(starts, bool) or not isinstance(starts, int) or not 1 <= starts <= MAX_STARTS:
        raise ValueError(f"starts must be an integer in [1, {MAX_STARTS}], got {starts!r}")
    if isinstance(base_seed, bool) or not isinstance(base_seed, int) or base_seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {base_seed!r}")
    if workers is not None and (not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS):
        raise ValueError(f"workers must be an integer in [1, {MAX_WORKERS}], got {workers!r}")
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")


def run_campaign(
    settings: PredictionSettings,
    starts: int,
    base_seed: int,
    out_dir: str | Path,
    workers: int | None = None,
    scheduler: str | None = None,
    solver: str = "ipopt",
    progress: bool = True,
    console: Console | None = None,
) -> CampaignReport:
    """Run (or resume) the campaign of ``starts`` random starts in ``out_dir``.

    Finished starts already in ``out_dir`` are skipped once verified
    (:mod:`walk3d.campaign.resume`: a damaged one runs again, another problem's is refused, as
    is a start entry that is a file, a link or holds files walk3d did not write:
    :mod:`walk3d.campaign.start_folders`).
    Every start that finishes is written at once, atomically; failed solves, exceptions and
    dead workers are recorded, never fatal.
    Finally ``ranking.csv`` and ``best/`` are written for every start in the folder.

    Raises:
        ValueError: invalid ``starts``, ``base_seed``, ``workers`` or ``solver``, or a
            ``scheduler`` that is malformed or does not answer (:func:`check_scheduler`).
        walk3d.campaign.store.CampaignMismatch: ``out_dir`` holds a different campaign, or a
            start folder holds another problem's or another seed's prediction, or is not
            walk3d's own (:func:`~walk3d.campaign.start_folders.resumable_records`).
    """
    _validate(starts, base_seed, workers, solver)
    if scheduler:
        check_scheduler(scheduler)
    t0 = time.perf_counter()
    out = Path(out_dir)
    store.open_campaign(out, settings, base_seed, starts, solver)
    removed = store.clean_temporaries(out)
    records = start_folders.resumable_records(out)  # refuses what is not walk3d's own
    seeds = [base_seed + k for k in range(starts)]
    resume.verified_records(out, settings, records, seeds)  # before any solve
    retried = store.forget_environment_failures(out, records, seeds)
    pending = [s for s in seeds if s not in records]
    criterion = settings.model.criterion
    with _progress(console, progress) as bar:
        job = bar.add_task("starts", total=starts, completed=starts - len(pending),
                           note=_note(records, criterion))  # fmt: skip

        def advance() -> None:
            bar.update(job, advance=1, note=_note(records, criterion))

        if pending:
            try:
                with dask_client(workers, scheduler, len(pending)) as client:
                    _run_pending(client, settings, pending, solver, out, records, advance)
            except BaseException:
                if not scheduler:  # the local workers are gone: their temporaries are partial
                    store.clean_temporaries(out)
                raise
    # every task has ended: a temporary left now is a killed worker's, not a running one's
    removed += store.clean_temporaries(out)
    rows = ranking.order_records(list(records.values()))  # the verified records, not the files'
    ranking.write_ranking(out, rows)
    best = ranking.update_best(out, rows)
    return CampaignReport(
        out_dir=out, criterion=criterion, starts=starts, base_seed=base_seed,
        ran=len(pending), skipped=len(seeds) - len(pending), rows=rows, best_seed=best,
        wall_time_s=time.perf_counter() - t0, removed_temporaries=len(removed),
        retried=len(retried),
    )  # fmt: skip


def _run_pending(
    client: Client,
    settings: PredictionSettings,
    pending: list[int],
    solver: str,
    out: Path,
    records: dict[int, dict],
    advance: Callable[[], None],
) -> None:
    """Submit one task per pending seed and collect records as tasks finish."""
    from distributed import as_completed

    settings_dict = settings.model_dump()
    root = str(store.starts_dir(out).resolve())  # workers may run in another directory
    tag = uuid.uuid4().hex[:8]
    futures = {
        client.submit(task.run_start, settings_dict, seed, solver, root, pure=False,
                      key=f"walk3d-start-{seed:06d}-{tag}"): seed
        for seed in pending
    }  # fmt: skip
    for future in as_completed(futures):
        seed = futures[future]
        try:
            record = future.result()
        except Exception as exc:
            if future.status != "error":  # cancelled or lost: leave the start for a resume
                continue
            # the task raised outside its own guard, or its worker died (KilledWorker)
            try:
                record = task.write_error(root, seed, settings.model.criterion, exc)
            except OSError:  # not even a record fits (disk full): the start stays pending
                continue
        if record is None:  # its result did not fit (disk full): the start stays pending
            continue
        records[seed] = record
        advance()
        future.release()

"""Campaigns larger than one batch: the loops split into coarse chunks (thousands of loops
each: one batched run per chunk, never one loop per task), run one after the other in this
process or as tasks on Dask (`dask.distributed`, the optional extra `fuzzyc[dask]`).

A loop draws its plant params and noise from its own stream, keyed by its number in the
campaign (runtime.noise.KeyedNoise), so the numbers do not depend on the split: any chunk size,
any number of workers, or one batch in one process give the same loops.
"""
from __future__ import annotations

import contextlib
import logging
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Sequence

from fuzzyc.display import plural
from fuzzyc.language.limits import MAX_WORKERS

from .progress import Progress

DEFAULT_CHUNK = 10_000   # loops per task: a WEDM loop step costs ~0.3 us batched, so a task
                         # of 10^4 loops is seconds of work against milliseconds of overhead


SCHEDULER_SCHEMES = ("tcp", "tls")
LOCAL_HOST = "127.0.0.1"   # --workers: nothing of the local cluster listens beyond this machine
# seconds a cluster may take to show a worker: a campaign on a cluster without workers would
# otherwise wait forever for its first result
WORKER_WAIT = 120.0
# where a tls:// scheduler's client certificate comes from (Dask's own config)
TLS_ENV = ("DASK_DISTRIBUTED__COMM__TLS__CA_FILE, DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT "
           "and DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY")


@dataclass
class Cluster:
    """Where the chunks run. Neither workers nor scheduler: in this process, one after the
    other (a campaign bigger than memory still runs). workers: a Dask LocalCluster of that many
    single-threaded worker processes; scheduler: the address of a running Dask scheduler
    (tcp://host:8786), whose workers must have fuzzyc installed. chunk: loops per task.
    progress: a bar over the tasks on stderr (None: only on a terminal).

    Used as a context manager (`with Cluster(workers=2) as cluster:`), one Dask client (and
    local cluster) serves every campaign inside; otherwise each campaign starts its own."""
    workers: int | None = None
    scheduler: str | None = None
    chunk: int = DEFAULT_CHUNK
    progress: bool | None = None

    def __post_init__(self) -> None:
        chunks(0, self.chunk)      # checks the size
        if self.workers is not None and not 1 <= self.workers <= MAX_WORKERS:
            raise ValueError(f"workers must be from 1 to {MAX_WORKERS}, not {self.workers}")
        if self.workers is not None and self.scheduler:
            raise ValueError("give workers (a local cluster) or scheduler (a running one), "
                             "not both")
        scheme = self.scheduler.partition("://")[0] if "://" in (self.scheduler or "") else "tcp"
        if scheme not in SCHEDULER_SCHEMES:     # Dask's others fail inside it (ucx: TypeError)
            forms = " or ".join(f"{s}://HOST:PORT" for s in SCHEDULER_SCHEMES)
            raise ValueError(f"a scheduler address must be {forms}, not {self.scheduler}")
        self._open: contextlib.ExitStack | None = None
        self._client: Any = None
        self._held = False

    @property
    def local(self) -> bool:
        """True when the chunks run in this process."""
        return self.workers is None and not self.scheduler

    def client(self) -> Any:
        """The Dask client, started on first use."""
        if self._client is None:
            self._open = contextlib.ExitStack()
            self._client = self._open.enter_context(_client(self))
        return self._client

    def close(self) -> None:
        if self._open is not None:
            self._open.close()
        self._open = self._client = None

    def __enter__(self) -> "Cluster":
        self._held = True
        return self

    def __exit__(self, *exc) -> None:
        self._held = False
        self.close()


BLOCK = 8   # loops: a chunk is a multiple of this (see chunks)


def chunks(total: int, size: int) -> list[range]:
    """The loops 0..total-1 as consecutive ranges of `size` loops, a multiple of BLOCK.

    Why: a loop must compute the same bits in any batch. OpenBLAS's matrix-vector kernels
    (the engine's sums over output terms) take 8 rows at a time and the leftover rows another
    way, so a loop's last bits depend on its place modulo 8; chunks that start at multiples of
    8 keep every loop's place. For the same reason a last range of one loop joins the one
    before: numpy sums a (T, 1) column pairwise but the columns of a (T, N) batch row by row."""
    if size < BLOCK or size % BLOCK:
        raise ValueError(f"a chunk must be a multiple of {BLOCK} loops (the place of a loop in its "
                         f"batch modulo {BLOCK} changes its last bits), not {size}")
    starts = list(range(0, total, size))
    if len(starts) > 1 and total - starts[-1] == 1:
        starts.pop()
    return [range(start, end) for start, end in zip(starts, starts[1:] + [total])]


def map_chunks(task: Callable[[Any], Any], items: Sequence, cluster: Cluster,
               label: str = "chunks") -> list:
    """[task(item) for item in items], in order, run where `cluster` says. `task` and the
    items travel to the workers by (cloud)pickle: module-level functions and plain data."""
    bar = Progress(len(items), cluster.progress, label=f"{label} ({plural(len(items), 'task')})")
    if cluster.local:
        results = []
        for item in items:
            bar.update(len(results))
            results.append(task(item))
        bar.close()
        return results
    try:
        client = cluster.client()        # a FuzzycError first when Dask is missing
        from distributed import as_completed
        futures = client.map(task, items, pure=False)
        for done, _ in enumerate(as_completed(futures), start=1):
            if done < len(items):      # close() draws the last state
                bar.update(done)
        bar.close()
        return client.gather(futures)     # re-raises a task's exception here
    finally:
        if not cluster._held:
            cluster.close()


@contextlib.contextmanager
def _client(cluster: Cluster) -> Iterator[Any]:
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        from fuzzyc.errors import Diagnostic, FuzzycError
        raise FuzzycError([Diagnostic(None, "--workers and --scheduler run on Dask, which is "
                                            "not installed: pip install 'fuzzyc[dask]'")]) \
            from None
    if cluster.scheduler:
        from fuzzyc.errors import Diagnostic, FuzzycError
        if cluster.scheduler.startswith("tls://") and not _tls_configured():
            # Dask would fail with a TypeError about an ssl_context
            raise FuzzycError([Diagnostic(None, f"{cluster.scheduler} needs TLS certificates: "
                                                f"set {TLS_ENV} (docs/campaigns.md)")])
        try:
            client = Client(cluster.scheduler)
        except (ValueError, OSError) as exc:     # a malformed address, nobody listening
            raise FuzzycError([Diagnostic(None, f"cannot reach the Dask scheduler at "
                                                f"{cluster.scheduler}: {exc}")]) from None
        with client:
            _wait_for_workers(client, 1, cluster.scheduler)
            yield client
        return
    # processes, one thread each: the batched numpy loop holds the GIL between array calls.
    # Everything listens on 127.0.0.1 only, and the scheduler's HTTP server (which Dask always
    # starts) gets no dashboard and no routes: with dashboard_address=":0" the dashboard and
    # /json/identity.json answered on every interface. Workers read the routes from the
    # config they are spawned with, so the config must hold while the cluster starts.
    import dask
    with dask.config.set({"distributed.scheduler.http.routes": [],
                          "distributed.worker.http.routes": []}):
        local = LocalCluster(n_workers=cluster.workers, threads_per_worker=1, processes=True,
                             host=LOCAL_HOST, dashboard_address=f"{LOCAL_HOST}:0",
                             scheduler_kwargs={"dashboard": False},
                             silence_logs=logging.ERROR)
    with local, Client(local) as client:
        _wait_for_workers(client, cluster.workers, "the local cluster")
        yield client


def _wait_for_workers(client, count: int, where: str) -> None:
    from fuzzyc.errors import Diagnostic, FuzzycError
    try:
        client.wait_for_workers(count, timeout=WORKER_WAIT)
    except (TimeoutError, OSError):
        raise FuzzycError([Diagnostic(None, f"{where} has fewer than {count} Dask worker(s) "
                                            f"after {WORKER_WAIT:g} s")]) from None


def _tls_configured() -> bool:
    """True when the Dask config (its YAML files, DASK_* variables) gives the client a TLS
    context: what Client(address) uses for a tls:// address. FuzzycError when the files it
    names cannot be read (a traceback otherwise)."""
    from distributed.security import Security

    from fuzzyc.errors import Diagnostic, FuzzycError
    try:
        return Security().get_connection_args("client")["ssl_context"] is not None
    except OSError as exc:      # ssl.SSLError is one too: a key that does not fit its cert
        raise FuzzycError([Diagnostic(None, f"cannot use the TLS certificates of the Dask "
                                            f"config ({TLS_ENV}): {exc}")]) from None


@dataclass
class Campaign:
    """A Monte Carlo campaign's result: `metrics` label -> (batch,) values, one per loop, in
    loop order; `summary` label -> {mean, min, max, unit} over them (runtime.simulate
    summarize's); `trace` the full trace of the first loops only (for CSV and plots)."""
    batch: int
    metrics: dict
    summary: dict
    trace: Any


def simulate_campaign(scenario, batch: int, cluster: Cluster, keep: int = 20,
                      **options) -> Campaign:
    """`batch` loops of a scenario (runtime.simulate.simulate's options: baseline, backend,
    seed, randomize) run in chunks where `cluster` says; the same numbers as one
    simulate(scenario, batch, ...) whatever the split. The chunks record only the signals the
    metrics read (a 300-s run of 10,000 loops records 600 MB per signal); the first `keep`
    loops run once more as a batch of their own (a multiple of 8 loops, so every loop keeps
    its place) recording every signal, for the trace."""
    import functools

    import numpy as np

    from .simulate import summarize_values
    if options.get("pace", "sim") != "sim":
        raise ValueError("a campaign runs in simulated time (pace='sim')")
    shown = range(0, min(batch, -(-keep // BLOCK) * BLOCK))
    tasks = [(loops, _metric_signals(scenario)) for loops in chunks(batch, cluster.chunk)]
    parts = map_chunks(functools.partial(_simulate_chunk, scenario, options),
                       [(shown, None)] + tasks, cluster, label="loops")
    trace = parts[0]
    trace.signals = {name: v[:, :keep] for name, v in trace.signals.items()}
    metrics = {label: np.concatenate([values[label] for values in parts[1:]])
               for label in parts[1]}
    return Campaign(batch, metrics, summarize_values(scenario, metrics), trace)


def _metric_signals(scenario) -> list[str]:
    """The signals the scenario's metrics read: the judged signal, a target that is a signal,
    a `where` flag."""
    names = []
    for spec in scenario.metrics:
        names += [spec.get("signal"), spec.get("where")]
        names.append(spec["target"] if isinstance(spec.get("target"), str) else None)
    return list(dict.fromkeys(n for n in names if n))


def _simulate_chunk(scenario, options: dict, task: tuple[range, list[str] | None]):
    """One task: the loops of one chunk as a batch. With signals named: their per-loop
    metrics (runtime.simulate.loop_metrics); without: the trace of every signal."""
    from .simulate import loop_metrics, simulate
    loops, record = task
    trace = simulate(scenario, batch=len(loops), first=loops.start, progress=False,
                     record=record, **options)
    return trace if record is None else loop_metrics(scenario, trace)

"""Campaigns split into chunks, in this process or on Dask: the same numbers as one batch.

Every loop draws its plant params and noise from its own stream (keyed by its number in the
campaign), so neither the chunk size nor the number of workers may change a single bit of any
loop's metrics, of the summary or of the written files."""
import filecmp
import json

import numpy as np
import pytest

# Dask clusters start with this file alone in a plain pytest process (`make test`'s second
# step): collected with the whole suite (in an xdist worker, or all `-m cluster` tests in one
# process) the campaign on the fixture's cluster waited forever, its workers gone (4 runs of
# 4); this file alone passed every time (7 runs). The cause is not found yet.
pytestmark = pytest.mark.cluster

from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.plants.scenario import load
from fuzzyc.runtime.campaign import Cluster, chunks, map_chunks, simulate_campaign
from fuzzyc.runtime.simulate import loop_metrics, simulate, summarize
from fuzzyc.verifier import Options, verify_model
from conftest import ROOT

BATCH, SEED = 61, 5


def test_chunks_cover_the_loops_in_order():
    # 25 loops by 8: 0-7, 8-15, 16-23 and a last loop alone, which joins 16-23 (a (T, 1)
    # column is summed pairwise by numpy, a batch's columns row by row)
    assert chunks(25, 8) == [range(0, 8), range(8, 16), range(16, 25)]
    assert chunks(30, 16) == [range(0, 16), range(16, 30)]
    assert chunks(32, 16) == [range(0, 16), range(16, 32)]
    assert chunks(1, 8) == [range(0, 1)]
    # BLAS takes 8 rows at a time: a chunk of 6 would move loops 6, 7, ... to other places
    for size in (1, 6, 12, 10_001):
        with pytest.raises(ValueError, match="a chunk must be a multiple of 8 loops"):
            Cluster(chunk=size)
    with pytest.raises(ValueError, match="not both"):
        Cluster(workers=2, scheduler="tcp://localhost:8786")


@pytest.fixture(scope="module")
def wedm():
    """The WEDM finish cut, 1 s, 61 randomized loops as one batch: the reference."""
    scenario = load("wedm_finish", {"duration": "1"})
    trace = simulate(scenario, batch=BATCH, seed=SEED, randomize=True)
    return scenario, trace, loop_metrics(scenario, trace)


def assert_same_campaign(campaign, wedm):
    scenario, trace, metrics = wedm
    assert campaign.batch == BATCH
    for label, values in metrics.items():
        np.testing.assert_array_equal(campaign.metrics[label], values)     # bit for bit
    assert json.dumps(campaign.summary) == json.dumps(summarize(scenario, trace))
    for name, values in trace.signals.items():          # the first 20 loops, whole
        np.testing.assert_array_equal(campaign.trace[name], values[:, :20])


@pytest.mark.parametrize("chunk", [8, 24, 32, 64, 1000])
def test_chunks_in_this_process_give_the_numbers_of_one_batch(wedm, chunk):
    campaign = simulate_campaign(wedm[0], BATCH, Cluster(chunk=chunk, progress=False),
                                 seed=SEED, randomize=True)
    assert_same_campaign(campaign, wedm)


def test_the_loops_differ_and_another_seed_changes_them(wedm):
    # the equality above is not that of constant numbers: the randomized loops spread, and
    # seed 6 draws other loops
    scenario, _, metrics = wedm
    voltage = metrics["mean(gap_voltage)"]
    assert np.ptp(voltage) > 1.0
    other = simulate_campaign(scenario, BATCH, Cluster(chunk=32), seed=SEED + 1, randomize=True)
    assert not np.array_equal(other.metrics["mean(gap_voltage)"], voltage)


@pytest.fixture(scope="module")
def scheduler():
    """A local Dask cluster of 2 single-thread worker processes; its scheduler's address."""
    distributed = pytest.importorskip("distributed", reason="Dask is the optional extra "
                                                            "fuzzyc[dask]")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster:
        yield cluster.scheduler_address


@pytest.mark.parametrize("chunk", [8, 40])
def test_two_dask_workers_give_the_numbers_of_one_batch(wedm, scheduler, chunk):
    campaign = simulate_campaign(wedm[0], BATCH, Cluster(scheduler=scheduler, chunk=chunk),
                                 seed=SEED, randomize=True)
    assert_same_campaign(campaign, wedm)


def test_one_local_worker_gives_the_numbers_of_one_batch(wedm):
    pytest.importorskip("distributed", reason="Dask is the optional extra fuzzyc[dask]")
    campaign = simulate_campaign(wedm[0], BATCH, Cluster(workers=1, chunk=16),
                                 seed=SEED, randomize=True)
    assert_same_campaign(campaign, wedm)


def _simulate_cli(folder, *extra):
    assert main(["simulate", "--scenario", "wedm_finish", "--set", "duration=1", "--batch",
                 str(BATCH), "--randomize", "--seed", str(SEED), "-o", str(folder),
                 *extra]) == 0
    return folder


def test_simulate_command_writes_the_same_files_in_chunks(tmp_path, scheduler):
    plain = _simulate_cli(tmp_path / "plain")
    for extra in (["--chunk", "16"], ["--scheduler", scheduler, "--chunk", "24"]):
        split = _simulate_cli(tmp_path / "split", *extra)
        for name in ("summary.txt", "summary.json", "trace.csv"):
            assert filecmp.cmp(plain / name, split / name, shallow=False), (extra, name)
    assert json.loads((plain / "summary.json").read_text())["batch"] == BATCH


def test_the_c_back_end_in_chunks_writes_the_same_files(tmp_path):
    pytest.importorskip("fuzzyc.backends.c.load", reason="the C back end needs a C compiler")
    plain = _simulate_cli(tmp_path / "plain", "--backend", "c")
    split = _simulate_cli(tmp_path / "split", "--backend", "c", "--chunk", "8")
    for name in ("summary.json", "trace.csv"):
        assert filecmp.cmp(plain / name, split / name, shallow=False), name


def test_workers_without_dask_is_a_clear_error(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)   # import fails
    with pytest.raises(FuzzycError, match=r"pip install 'fuzzyc\[dask\]'"):
        simulate_campaign(load("wedm_finish", {"duration": "0.04"}), 4,
                          Cluster(workers=2, chunk=8))
    assert main(["simulate", "--scenario", "wedm_finish", "--set", "duration=0.04",
                 "--batch", "4", "--workers", "2", "-o", str(tmp_path)]) == 2
    assert "fuzzyc[dask]" in capsys.readouterr().err


def _edm_faults():
    """The shipped EDM sinking servo's closed-loop property with sensor faults: 20 drawn
    cases, some of which break it (tests/test_verify_disturbances.py)."""
    from fuzzyc.language.parser import load as load_model
    model = load_model(f"{ROOT}/rulebases/edm_sink_gap.fz")
    model.properties = [p for p in model.properties
                        if p.kind == "closed_loop" and p.args["faults"]]
    return model


def _verdicts(results):
    return [(r.status, [(e.method, e.status, e.detail, e.cases) for e in r.evidence],
             None if r.violation is None else json.dumps(
                 {k: v for k, v in r.violation.trace.items() if k not in ("t", "signals")},
                 default=str)) for r in results]


def test_closed_loop_search_in_chunks_gives_the_same_verdicts(scheduler):
    whole = verify_model(_edm_faults(), Options(max_examples=20, seed=0, shrink_rounds=1))
    assert whole[0].status.name == "VIOLATED"      # so the comparison covers a shrunk case
    # the EDM servo's centroid goes through BLAS: chunks of 6 would differ in the last bits
    for cluster in (Cluster(chunk=8), Cluster(scheduler=scheduler, chunk=16)):
        split = verify_model(_edm_faults(), Options(max_examples=20, seed=0, shrink_rounds=1,
                                                    cluster=cluster))
        assert _verdicts(split) == _verdicts(whole)
        signals = whole[0].violation.trace["signals"]
        assert signals.keys() == split[0].violation.trace["signals"].keys()
        for name, values in signals.items():
            np.testing.assert_array_equal(split[0].violation.trace["signals"][name], values)


def test_one_client_serves_every_campaign_inside_with(scheduler):
    with Cluster(scheduler=scheduler, chunk=8) as cluster:
        assert map_chunks(abs, [-1, -2], cluster) == [1, 2]
        first = cluster.client()
        assert map_chunks(abs, [-3], cluster) == [3]
        assert cluster.client() is first
    assert cluster._client is None

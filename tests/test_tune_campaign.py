"""A closed-loop tune whose cost runs its batch in chunks (`fuzzyc tune --scenario ...
--chunk/--workers/--scheduler`, fuzzyc.tune.loop.ClosedLoop with a runtime.campaign.Cluster).

A loop draws its plant and noise from its own stream and keeps its place modulo 8 in any chunk,
so a chunked cost must give the bits of one batch: per loop values, their means, the search's
path and the tuned file, byte for byte.  The toy of tests/test_tune_loop.py (a constant K into
the FOPDT plant), 20 loops with randomized plants (gain, time constant and dead time drawn per
loop, so the loops differ): chunks of 8 loops in this process here, on two Dask workers in the
`cluster` test (make test runs it alone)."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import fuzzyc
from fuzzyc.runtime.campaign import Cluster
from fuzzyc.tune.loop import ClosedLoop
from fuzzyc.tune.space import Space

from test_tune_loop import SETS, TOY, _loaded

BATCH = 20          # two chunks of 8 and one of 4


@pytest.fixture
def toy(tmp_path):
    path = tmp_path / "toy.fz"
    path.write_text(TOY)
    return path


def _loop(path, cluster):
    model, scenario = _loaded(path, properties=False)
    return ClosedLoop(scenario, Space(model), "iae(y, 0.6)", batch=BATCH, randomize=True,
                      limits=(("final(y)", 1.0),), cluster=cluster)


def test_chunked_values_are_the_one_batch_bits(toy):
    whole = _loop(toy, None)
    chunked = _loop(toy, Cluster(chunk=8))
    for theta in ([1.5], [0.9], [0.6]):
        expected = whole.values(np.array(theta))
        got = chunked.values(np.array(theta))
        assert [v.tobytes() for v in got] == [v.tobytes() for v in expected]
        assert got[0].shape == (BATCH,)
    # not vacuous: the randomized loops differ, and K moves the cost
    assert np.ptp(whole.values(np.array([1.5]))[0]) > 0
    assert whole(np.array([1.5])) != whole(np.array([0.9]))


def _tuned(path, cluster):
    return fuzzyc.tune(path, scenario="fopdt_step", minimize="iae(y, 0.6)", sets=SETS,
                       batch=BATCH, randomize=True, max_evaluations=12, max_examples=5,
                       cluster=cluster)


def test_chunked_tune_writes_the_same_file(toy):
    whole, chunked = _tuned(toy, None), _tuned(toy, Cluster(chunk=8))
    assert chunked.text == whole.text
    assert chunked.fit.values.tobytes() == whole.fit.values.tobytes()
    assert whole.fit.cost_after < whole.fit.cost_before


def test_a_cluster_goes_with_a_scenario_not_with_data(toy, tmp_path, capsys):
    from fuzzyc.cli import main
    data = tmp_path / "d.csv"
    data.write_text("y,u\n0,1\n")
    code = main(["tune", str(toy), "--data", str(data), "--chunk", "8",
                 "-o", str(tmp_path / "out.fz")])
    assert code == 2
    assert "--workers, --scheduler and --chunk go with --scenario" in capsys.readouterr().err
    with pytest.raises(ValueError, match="goes with a scenario: drop it for a fit to data"):
        fuzzyc.tune(toy, data, cluster=Cluster(chunk=8))


@pytest.mark.cluster
def test_tune_on_two_dask_workers_writes_the_same_file(toy, tmp_path):
    """The command line of docs/tuning.md, small: --workers 2 --chunk 8 against one process."""
    pytest.importorskip("distributed")
    sets = [a for k, v in SETS.items() for a in ("--set", f"{k}={v}")]
    texts = []
    for where in ([], ["--workers", "2", "--chunk", "8"]):
        out = tmp_path / f"tuned{len(texts)}.fz"
        run = subprocess.run([sys.executable, "-m", "fuzzyc", "tune", str(toy), "--scenario",
                              "fopdt_step", "--minimize", "iae(y, 0.6)", *sets, "--batch",
                              str(BATCH), "--randomize", "--max-evaluations", "12",
                              "--max-examples", "5", *where, "-o", str(out)],
                             capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stderr[-2000:]
        texts.append(out.read_text())
    assert texts[1] == texts[0] == _tuned(toy, None).text

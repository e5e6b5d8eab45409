"""Dask clusters of a campaign are not open to the network (docs/security.md).

`--workers N` starts a local cluster that listens on 127.0.0.1 only, scheduler, nannies and
workers alike, with no dashboard and no HTTP routes (it used to serve the dashboard and
/json/identity.json on every interface). `--scheduler tls://...` takes its certificates from
the Dask config (DASK_DISTRIBUTED__COMM__TLS__... variables) and gives the same numbers as a
campaign in this process."""
import json
import logging
import shutil
import subprocess
import urllib.error
import urllib.request

import numpy as np
import pytest

# Dask clusters start with this file alone in a plain pytest process (`make test`'s second
# step): collected with the whole suite (in an xdist worker, or all `-m cluster` tests in one
# process) the campaign on the fixture's cluster waited forever, its workers gone (4 runs of
# 4); this file alone passed every time (7 runs). The cause is not found yet.
pytestmark = pytest.mark.cluster

distributed = pytest.importorskip("distributed", reason="Dask is the optional extra "
                                                        "fuzzyc[dask]")
import dask  # noqa: E402
import psutil  # noqa: E402  (a dependency of distributed)

from fuzzyc.cli import main  # noqa: E402
from fuzzyc.errors import FuzzycError  # noqa: E402
from fuzzyc.plants.scenario import load  # noqa: E402
from fuzzyc.runtime.campaign import Cluster, map_chunks, simulate_campaign  # noqa: E402

BATCH, SEED = 40, 3


def _listening() -> set[tuple[int, str, int]]:
    """(pid, address, port) of every listening inet socket of this process and its children."""
    me = psutil.Process()
    found = set()
    for process in [me] + me.children(recursive=True):
        try:
            connections = process.net_connections(kind="inet")
        except psutil.Error:       # a child that ended meanwhile
            continue
        found |= {(process.pid, c.laddr.ip, c.laddr.port) for c in connections
                  if c.status == psutil.CONN_LISTEN}
    return found


def test_a_local_cluster_listens_on_127_0_0_1_only_and_serves_no_dashboard():
    before = _listening()
    with Cluster(workers=1, chunk=8) as cluster:
        client = cluster.client()
        local = client.cluster            # the LocalCluster the campaign code started
        assert map_chunks(abs, [-1, -2], cluster) == [1, 2]    # it works
        opened = _listening() - before
        workers = list(client.scheduler_info()["workers"])

        assert local.scheduler_address.startswith("tcp://127.0.0.1:")
        assert workers and all(w.startswith("tcp://127.0.0.1:") for w in workers)
        # what the system says, not what Dask reports: scheduler, nanny, worker and the HTTP
        # servers Dask always starts, all on the loopback address (":0" meant 0.0.0.0)
        assert opened, "no listening socket found"
        assert {address for _, address, _ in opened} == {"127.0.0.1"}, opened
        ports = {port for _, _, port in opened}
        assert int(local.scheduler_address.rsplit(":", 1)[1]) in ports
        # no dashboard: the scheduler's HTTP server has no routes at all
        http_port = local.scheduler.http_server.port
        for path in ("/status", "/json/identity.json", "/health", "/metrics"):
            with pytest.raises(urllib.error.HTTPError) as answer:
                urllib.request.urlopen(f"http://127.0.0.1:{http_port}{path}", timeout=5)
            assert answer.value.code == 404, path
    # the config that hid the routes held only while the cluster started
    assert dask.config.get("distributed.scheduler.http.routes")


def _self_signed(folder):
    """cert.pem and key.pem for 127.0.0.1, its own CA: with cryptography, else openssl."""
    cert, key = folder / "cert.pem", folder / "key.pem"
    try:
        import datetime
        import ipaddress

        from cryptography import x509
        from cryptography.hazmat.primitives import hashes, serialization
        from cryptography.hazmat.primitives.asymmetric import ec
        from cryptography.x509.oid import NameOID
    except ImportError:
        openssl = shutil.which("openssl")
        if openssl is None:
            pytest.skip("neither the cryptography package nor openssl to make a certificate")
        subprocess.run([openssl, "req", "-x509", "-newkey", "ec", "-pkeyopt",
                        "ec_paramgen_curve:prime256v1", "-nodes", "-keyout", str(key),
                        "-out", str(cert), "-days", "1", "-subj", "/CN=127.0.0.1",
                        "-addext", "subjectAltName=IP:127.0.0.1",
                        "-addext", "basicConstraints=critical,CA:TRUE"],
                       check=True, capture_output=True)
        return cert, key
    private = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "127.0.0.1")])
    now = datetime.datetime.now(datetime.timezone.utc)
    certificate = (x509.CertificateBuilder().subject_name(name).issuer_name(name)
                   .public_key(private.public_key()).serial_number(x509.random_serial_number())
                   .not_valid_before(now - datetime.timedelta(minutes=5))
                   .not_valid_after(now + datetime.timedelta(days=1))
                   .add_extension(x509.SubjectAlternativeName(
                       [x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]), critical=False)
                   .add_extension(x509.BasicConstraints(ca=True, path_length=None),
                                  critical=True)
                   .sign(private, hashes.SHA256()))
    cert.write_bytes(certificate.public_bytes(serialization.Encoding.PEM))
    key.write_bytes(private.private_bytes(serialization.Encoding.PEM,
                                          serialization.PrivateFormat.PKCS8,
                                          serialization.NoEncryption()))
    return cert, key


@pytest.fixture
def tls_cluster(tmp_path):
    """A TLS-only local Dask cluster on 127.0.0.1 (one worker); its address and certificate."""
    from distributed.security import Security
    cert, key = _self_signed(tmp_path)
    security = Security(tls_ca_file=str(cert), require_encryption=True,
                        **{f"tls_{role}_{part}": str(path)
                           for role in ("scheduler", "worker", "client")
                           for part, path in (("cert", cert), ("key", key))})
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  protocol="tls://", security=security, host="127.0.0.1",
                                  dashboard_address="127.0.0.1:0",
                                  silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address, cert, key


@pytest.fixture
def dask_env(monkeypatch):
    """Sets DASK_* variables as a user would and makes Dask read them again (it reads them at
    import); the config is read afresh without them afterwards."""
    def set_env(**variables):
        for name, value in variables.items():
            monkeypatch.setenv(name, str(value))
        dask.config.refresh()
    yield set_env
    monkeypatch.undo()
    dask.config.refresh()


def test_a_tls_scheduler_gives_the_numbers_of_this_process(tls_cluster, dask_env, tmp_path):
    address, cert, key = tls_cluster
    assert address.startswith("tls://127.0.0.1:")
    scenario = load("wedm_finish", {"duration": "1"})
    here = simulate_campaign(scenario, BATCH, Cluster(chunk=16, progress=False),
                             seed=SEED, randomize=True)

    # without certificates: a clear message, not Dask's TypeError about an ssl_context
    with pytest.raises(FuzzycError, match="needs TLS certificates: set "
                                          "DASK_DISTRIBUTED__COMM__TLS__CA_FILE"):
        map_chunks(abs, [-1], Cluster(scheduler=address))

    # a file the config names that cannot be read: a clear message too
    dask_env(DASK_DISTRIBUTED__COMM__TLS__CA_FILE=tmp_path / "missing.pem",
             DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT=cert,
             DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY=key)
    with pytest.raises(FuzzycError, match="cannot use the TLS certificates of the Dask config"):
        map_chunks(abs, [-1], Cluster(scheduler=address))

    dask_env(DASK_DISTRIBUTED__COMM__TLS__CA_FILE=cert)
    there = simulate_campaign(scenario, BATCH, Cluster(scheduler=address, chunk=16,
                                                       progress=False),
                              seed=SEED, randomize=True)
    assert there.metrics.keys() == here.metrics.keys()
    for label, values in here.metrics.items():
        np.testing.assert_array_equal(there.metrics[label], values)     # bit for bit
    assert json.dumps(there.summary) == json.dumps(here.summary)

    # the command line, as docs/campaigns.md shows it
    command = ["simulate", "--scenario", "wedm_finish", "--set", "duration=1", "--batch",
               str(BATCH), "--randomize", "--seed", str(SEED), "--chunk", "16"]
    assert main(command + ["-o", str(tmp_path / "here")]) == 0
    assert main(command + ["--scheduler", address, "-o", str(tmp_path / "there")]) == 0
    assert ((tmp_path / "there" / "summary.json").read_bytes()
            == (tmp_path / "here" / "summary.json").read_bytes())

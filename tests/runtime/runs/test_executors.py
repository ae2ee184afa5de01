"""Executors: a real Dask cluster gives the serial run's files byte for byte; mistakes are one line."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.runs._executors import LocalExecutor, SerialExecutor
from mazegen.runtime.runs._launcher import executor_for
from tests.conftest import EXAMPLES
from tests.runtime.rundirs import file_digests

SMALL = {"seed": 2, "runs": 3, "population": 60, "generations": 3}


def test_dask_local_cluster_writes_what_a_serial_run_writes(tmp_path):
    distributed = pytest.importorskip("distributed")
    serial = tmp_path / "serial"
    mazegen.run(EXAMPLES / "factory.maze", **SMALL, out_dir=serial, executor="serial")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        dask = tmp_path / "dask"
        result = mazegen.run(
            EXAMPLES / "factory.maze",
            **SMALL,
            out_dir=dask,
            executor="dask",
            scheduler=cluster.scheduler_address,
            checkpoint_every=1,
        )
    assert len(result.runs) == 3 and all(documents for documents in result.best)
    assert file_digests(dask) == file_digests(serial)
    assert not (dask / "checkpoints").exists()  # the workers' checkpoints, removed once finished


def test_a_driving_spec_writes_the_same_files_on_every_executor(tmp_path):
    """Drive terms run the simulator inside each worker: its episodes, and so the fitness and the
    files, must not depend on where a run ran."""
    distributed = pytest.importorskip("distributed")
    spec = EXAMPLES / "adversarial.maze"
    small = {"seed": 3, "runs": 2, "population": 40, "generations": 2}
    mazegen.run(spec, **small, out_dir=tmp_path / "serial", executor="serial")
    mazegen.run(spec, **small, out_dir=tmp_path / "local", executor="local", workers=2)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        mazegen.run(
            spec, **small, out_dir=tmp_path / "dask", executor="dask", scheduler=cluster.scheduler_address
        )
    serial = file_digests(tmp_path / "serial")
    assert any("best" in name for name in serial)  # runs wrote their driven scenarios
    assert file_digests(tmp_path / "local") == serial
    assert file_digests(tmp_path / "dask") == serial


def test_unreachable_or_malformed_scheduler_is_a_one_line_error():
    pytest.importorskip("distributed")
    from mazegen.runtime.runs._dask_executor import DaskExecutor

    with pytest.raises(MazeError, match=r"cannot reach the Dask scheduler at tcp://127\.0\.0\.1:9: "):
        DaskExecutor(scheduler="tcp://127.0.0.1:9", connect_timeout=0.5)
    with pytest.raises(MazeError, match=r"not a Dask scheduler address 'host' \(missing port number"):
        DaskExecutor(scheduler="host")


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--executor", "dask"], "--executor dask needs --scheduler"),
        (["--scheduler", "tcp://127.0.0.1:8786"], "--scheduler goes with --executor dask"),
    ],
)
def test_executor_options_that_do_not_go_together(tmp_path, options, message):
    args = ["run", str(EXAMPLES / "factory.maze"), "--runs", "2", "-q", "-o", str(tmp_path / "r"), *options]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 1 and message in result.stderr and "Traceback" not in result.output
    assert not (tmp_path / "r").exists()


def test_local_executor_uses_no_more_workers_than_runs():
    assert isinstance(executor_for("local", runs=1), SerialExecutor)  # one run: no process to start
    with executor_for("local", runs=5, workers=2) as executor:
        assert isinstance(executor, LocalExecutor) and executor.name == "local:2"
    with pytest.raises(MazeError, match="unknown executor 'gpu'"):
        executor_for("gpu", runs=2)

"""The Python API: load a spec, build it, run it, resume it, sweep its settings, get the best scenarios.

Example::

    import mazegen
    spec = mazegen.load("examples/factory.maze")
    result = mazegen.run(spec, seed=3, population=500)
    print(result.best[0][0]["phenotype"])

Errors are :class:`~mazegen.errors.MazeError`; those naming an option name it as
this API does (``force=True``), where the command line says ``--force``.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mazegen.dsl.loader import load_spec
from mazegen.errors import MazeError
from mazegen.generator.build import build as build_files
from mazegen.spec import DETOUR, MAX_CLASSES, Spec

if TYPE_CHECKING:
    from mazegen.runtime.documents import Classification, Drive, Floor
    from mazegen.runtime.runs import Executor, Experiment, ExperimentResult, Reporter


Scenarios = str | os.PathLike[str] | Mapping[str, Any]
"""A scenario file, a folder of them (a run, a suite) or a scenario document."""


def load(path: str | os.PathLike[str]) -> Spec:
    """Load and check a ``.maze`` spec.

    Raises:
        MazeError: located at the user's line for any mistake in the spec.
    """
    return load_spec(path)


def build(spec: Spec | str | os.PathLike[str], out_dir: str | os.PathLike[str]) -> list[Path]:
    """Generate grammar.bnf, fitness.py, experiment.py and spec.json into ``out_dir``.

    ``spec`` is a :class:`Spec` or the path of a ``.maze`` file.
    """
    return build_files(spec if isinstance(spec, Spec) else load_spec(spec), Path(out_dir))


def run(
    spec: Spec | str | os.PathLike[str],
    *,
    seed: int | None = None,
    runs: int | None = None,
    population: int | None = None,
    generations: int | None = None,
    out_dir: str | os.PathLike[str] | None = None,
    force: bool = False,
    reporter: Reporter | None = None,
    executor: str | Executor = "serial",
    workers: int | None = None,
    scheduler: str | None = None,
    checkpoint_every: int | None = None,
    catalog: bool | str | os.PathLike[str] = True,
    keep_populations: bool = True,
    compile_seconds: float = 0.0,
) -> ExperimentResult:
    """Run a spec (a :class:`Spec`, a ``.maze`` file or a build directory).

    Settings given here override the spec's evolution block. With ``out_dir`` the run
    directory is written as runs finish (checkpoints included, so ``resume`` can continue
    it) and recorded in the catalog; the result holds each run's final population and
    best scenario documents either way.

    Args:
        spec: What to run.
        seed: Seed of the experiment.
        runs: Number of runs.
        population: Population size.
        generations: Generations after the random one.
        out_dir: The run directory to write.
        force: Replace an existing ``out_dir``.
        reporter: Progress display.
        executor: ``serial`` (this process, the default here), ``local`` (worker processes),
            ``dask`` (with ``scheduler``), or an :class:`~mazegen.runtime.runs._executors.Executor`.
        workers: Local worker processes (default: the cores).
        scheduler: The Dask scheduler's address, ``tcp://HOST:PORT``.
        checkpoint_every: Checkpoint every this many generations (0: never; default: every 30 s).
        catalog: The catalog file, ``True`` for ``catalog.sqlite`` beside ``out_dir``, ``False`` for none.
        keep_populations: Return each run's final population; without, the result holds each
            run's statistics and best documents (the populations are in ``out_dir``).
        compile_seconds: Seconds the caller spent compiling the kernels for this run ahead
            (:func:`mazegen.runtime.runs._warmup.compile_kernels`), counted in run 1's time.
    """
    from mazegen.runtime.runs import Experiment, Job, run_jobs

    def _run(build_dir: Path) -> ExperimentResult:
        experiment = Experiment.from_build_dir(build_dir).with_settings(
            seed=seed, runs=runs, population=population, generations=generations
        )
        run_dir = None if out_dir is None else Path(out_dir)
        job = Job(experiment, run_dir, force=force, compile_seconds=compile_seconds)
        return run_jobs(
            [job],
            executor=executor,
            workers=workers,
            scheduler=scheduler,
            catalog=catalog,
            checkpoint_every=checkpoint_every,
            reporter=reporter,
            keep_populations=keep_populations or out_dir is None,
        )[0]

    if not isinstance(spec, Spec) and Path(spec).is_dir():
        return _run(Path(spec))
    resolved = spec if isinstance(spec, Spec) else load_spec(spec)
    with tempfile.TemporaryDirectory(prefix="mazegen-build-") as temp:
        build_files(resolved, Path(temp))
        return _run(Path(temp))


def resume(
    run_dir: str | os.PathLike[str],
    *,
    reporter: Reporter | None = None,
    executor: str | Executor = "serial",
    workers: int | None = None,
    scheduler: str | None = None,
    checkpoint_every: int | None = None,
    catalog: bool | str | os.PathLike[str] = True,
    keep_populations: bool = True,
) -> ExperimentResult:
    """Continue an interrupted run directory from its runs' checkpoints (arguments as in :func:`run`).

    The finished directory is the same, byte for byte (``timing.csv`` aside), as if the
    experiment had never stopped.

    Raises:
        MazeError: for a folder that is not a run directory, a finished one, or a run whose
            checkpoints are all damaged.
    """
    from mazegen.runtime.runs import Job, run_jobs

    with tempfile.TemporaryDirectory(prefix="mazegen-resume-") as temp:
        job = Job(_resumable(Path(run_dir), Path(temp) / "build"), Path(run_dir), resume=True)
        return run_jobs(
            [job],
            executor=executor,
            workers=workers,
            scheduler=scheduler,
            catalog=catalog,
            checkpoint_every=checkpoint_every,
            reporter=reporter,
            keep_populations=keep_populations,
        )[0]


def sweep(
    specs: Sequence[Spec | str | os.PathLike[str]],
    settings: Mapping[str, Sequence[int | float]],
    *,
    out_dir: str | os.PathLike[str],
    runs: int | None = None,
    force: bool = False,
    reporter: Reporter | None = None,
    executor: str | Executor = "serial",
    workers: int | None = None,
    scheduler: str | None = None,
    checkpoint_every: int | None = None,
    catalog: bool | str | os.PathLike[str] = True,
) -> list[tuple[Path, ExperimentResult | None]]:
    """Run every combination of ``settings`` for every spec, each into ``out_dir/<cell>``.

    A cell directory already finished for the same experiment is skipped (its result is
    ``None``); one interrupted is resumed. All cells are recorded in one catalog
    (``out_dir/catalog.sqlite`` by default). Other arguments are as in :func:`run`.

    Args:
        specs: The specs (a fitness variant is a spec, or a swept ``fitness.TERM`` weight).
        settings: Values per setting, e.g. ``{"population": [500, 1000], "seed": range(1, 4)}``.
        out_dir: The sweep's folder.
        runs: Runs per cell (overrides the specs).
        force: Replace existing cell directories.

    Raises:
        MazeError: for an unknown setting, a value out of bounds, or a cell directory that
            holds another experiment (without ``force``).
    """
    from mazegen.runtime.campaigns import MAX_CELLS, Axis, plan_cells
    from mazegen.runtime.runs import Experiment, Job, run_jobs

    for name, values in settings.items():
        if len(values) > MAX_CELLS:  # counted before a range of a billion seeds is spelled out
            raise MazeError(f"{name}: {len(values)} values; a sweep has at most {MAX_CELLS} cells")
    axes = [Axis.parse(f"{name}={','.join(map(str, values))}") for name, values in settings.items()]
    resolved = [spec if isinstance(spec, Spec) else load_spec(spec) for spec in specs]
    if runs is not None:
        resolved = [spec.with_evolution(runs=runs) for spec in resolved]
    cells = plan_cells(resolved, axes, Path(out_dir), force=force)
    with tempfile.TemporaryDirectory(prefix="mazegen-sweep-") as temp:
        jobs = []
        for cell in cells:
            build = Path(temp) / cell.run_dir.name
            if cell.state == "resume":
                jobs.append(
                    Job(_resumable(cell.run_dir, build), cell.run_dir, resume=True, sweep=cell.settings)
                )
            elif cell.state == "new":
                build_files(cell.spec, build)
                experiment = Experiment.from_build_dir(build)
                jobs.append(Job(experiment, cell.run_dir, force=force, sweep=cell.settings))
        results = iter(
            run_jobs(
                jobs,
                executor=executor,
                workers=workers,
                scheduler=scheduler,
                catalog=catalog,
                checkpoint_every=checkpoint_every,
                reporter=reporter,
                keep_populations=False,
            )
        )
        return [(cell.run_dir, None if cell.state == "finished" else next(results)) for cell in cells]


def drive(
    scenarios: str
    | os.PathLike[str]
    | Mapping[str, Any]
    | Sequence[str | os.PathLike[str] | Mapping[str, Any]],
    controllers: str | Sequence[str],
    *,
    spec: Spec | str | os.PathLike[str] | None = None,
) -> list[Drive]:
    """Drive each controller through each scenario and return one :class:`Drive` per episode, in
    the order of the scenarios (a folder's in its order) and, within one, of the controllers.

    ``scenarios`` are scenario files, run or suite directories, folders of scenario files, or
    scenario documents (dicts, as :func:`json.load` reads them; they need ``spec``), any mix. Each
    scenario drives on its own start and goal, with the robot of its spec (``spec``, or the one
    found in its run or suite directory). A controller is a bundled name, ``package.module:name``
    or a name an installed package registers. Floors not driven for want of a path say
    ``no path``.

    Raises:
        MazeError: for a scenario that cannot be read or driven, naming it.
    """
    from mazegen.runtime.documents import drive_floors

    names = [controllers] if isinstance(controllers, str) else list(controllers)
    if not names:
        raise MazeError("drive needs at least one controller")
    floors = _floors(scenarios, spec)
    position = {id(floor): index for index, floor in enumerate(floors)}
    ordered, drives = drive_floors(floors, names)
    by_input = sorted(zip(ordered, drives), key=lambda pair: position[id(pair[0])])
    return [result for _, row in by_input for result in row]


def classes(
    scenarios: Scenarios | Sequence[Scenarios],
    controllers: str | Sequence[str] = (),
    *,
    spec: Spec | str | os.PathLike[str] | None = None,
    max_classes: int = MAX_CLASSES,
    detour: float = DETOUR,
) -> Classification:
    """The homotopy classes of each scenario's floor, and the scenarios grouped into the tests they
    make (docs/classes.md).

    ``scenarios`` and ``spec`` are taken as :func:`drive` takes them. Each floor keeps its
    ``max_classes`` shortest classes, none longer than ``detour`` times its shortest path. With
    ``controllers``, each drives every floor, and two floors are one test only when each
    controller's outcome and the class of its trajectory match too.

    Raises:
        MazeError: for a scenario that cannot be read, naming it.
    """
    from mazegen.runtime.documents import classify

    names = [controllers] if isinstance(controllers, str) else list(controllers)
    return classify(_floors(scenarios, spec), names, max_classes=max_classes, detour=detour)


def _floors(
    scenarios: Scenarios | Sequence[Scenarios], spec: Spec | str | os.PathLike[str] | None
) -> list[Floor]:
    """The floors of :func:`drive`'s ``scenarios``: files, folders and documents, any mix."""
    from mazegen.runtime.documents import checked_document, floor_of, load_floor, scenario_files

    given = spec if isinstance(spec, Spec) or spec is None else load_spec(spec)
    items = [scenarios] if isinstance(scenarios, str | os.PathLike | Mapping) else list(scenarios)
    floors: list[Floor] = []
    for number, item in enumerate(items, 1):
        if isinstance(item, Mapping):
            name = f"scenario {number}"
            if given is None:
                raise MazeError("a scenario document needs its spec: give spec=", filename=name)
            floors.append(floor_of(checked_document(dict(item), name), Path(name), given))
        else:
            paths = [path for path, _ in scenario_files(Path(item), any_folder=True)]
            floors += [load_floor(path, given) for path in paths]
    return floors


def _resumable(run_dir: Path, build: Path) -> Experiment:
    """The experiment of an interrupted run directory, loaded from a copy of its build in ``build``.

    Raises:
        MazeError: for a folder that is not a run directory, a finished or damaged one.
    """
    from mazegen.runtime.runs import resumable_experiment

    return resumable_experiment(run_dir, copy_to=build)

"""A bundled controller fitted to BARN's measured Gazebo runs on the training half, then driven as BARN
timed them: how near a fitted model comes to move_base in Gazebo, held out and not.

Usage:
    python benchmarks/barn_fit.py           # movebase, 8 parameters, 5 folds, 160 drives a fit (~20 min)
    python benchmarks/barn_fit.py --controller dwa --params horizon,obstacle_weight --budget 64

The floors are ``barn_validation.py``'s: the 150 training worlds of ``../shared/anchors/barn/`` imported
with ``mazegen import`` (for a robot of ``--robot-radius``, the Jackal's half-length by default), each with
the start and goal of BARN's 2020 timing runs. Each world's spec drives the Jackal as those runs timed
it (arrival within √0.1 m, no stuck timeout, time for 50 s of clock, backing up for ``movebase``, its
0.508 x 0.430 m body the box the simulator collides unless ``--disc``), and ``measured.csv`` holds its
five measured DWA runs with BARN's path length. ``mazegen fit``'s search (the cross-entropy method,
``--seed``) fits ``--params`` on every world after ``--folds``-fold cross-validation. Then every world
is driven under the 2020 protocol (``barn_validation.py``) three ways: with the defaults, with the
parameters fitted on all worlds, and with the parameters fitted on the other folds (held out): the
Spearman ρ of BARN's measure against the measured DWA mean, the success rates and the failure
agreement. The other 150 worlds are never read. Prints the tables and the fitted robot block.
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
from pathlib import Path

import numpy as np
from barn_validation import (
    FAILURE_S,
    GOALS,
    SUMMARY,
    add_body_arguments,
    fitted_controllers,
    gazebo_ceiling,
    load_worlds,
    measured,
    summary_row,
    timed_robot,
    write_measured,
)
from common import markdown_table

from mazegen.runtime.documents import FitProblem, SearchSpace, fit_controller, read_measured, robot_block

MOVEBASE_PARAMS = "obstacle_weight,path_weight,goal_weight,inflation,decay,horizon,padding,min_vel"
"""``movebase``'s parameters fitted by default: the trajectory scoring's weights, the costmap's
inflation and the footprint's padding, the rollout's horizon and its slowest speed."""
FIT_COLUMNS = [
    ("parameters", "parameters", "s"),
    ("rho", "Spearman ρ (fit's measure)", ".2f"),
    ("agreement", "agreement %", ".1f"),
    ("simulated", "simulated success %", ".1f"),
    ("measured", "measured success %", ".1f"),
]


def timed_specs(worlds: list, contact: str, reverse: bool, box: bool) -> None:
    """Give each world's spec the Jackal as the 2020 runs timed it, so the fit drives that robot."""
    for world in worlds:
        spec = dataclasses.replace(
            world.floors.spec, robot=timed_robot(world.floors, contact, reverse=reverse, box=box)
        )
        (Path(world.floors.files[0]).parent / "spec.json").write_text(spec.to_json(), encoding="utf-8")


def protocol_clocks(
    worlds: list, controller: str, robot_files: list[tuple[Path, np.ndarray]], box: bool
) -> np.ndarray:
    """Each world's 2020 clock, driven with the settings of the robot block that covers its row."""
    clocks = np.empty(len(worlds))
    for file, rows in robot_files:
        chosen = [worlds[k] for k in rows.tolist()]
        clocks[rows] = measured(chosen, controller, "end", fitted_controllers(file, worlds[0]), box=box)
    return clocks


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--controller", default="movebase")
    parser.add_argument(
        "--params", default=MOVEBASE_PARAMS, help="comma-separated (default: movebase's eight)"
    )
    parser.add_argument("--folds", type=int, default=5)
    parser.add_argument("--budget", type=int, default=160, help="drives of every world a fit may make")
    parser.add_argument("--seed", type=int, default=1)
    add_body_arguments(parser, 0.254)
    args = parser.parse_args()
    names = [name for name in args.params.split(",") if name]
    with tempfile.TemporaryDirectory(prefix="mazegen-barn-fit-") as temp:
        folder = Path(temp)
        worlds = load_worlds(folder, args.robot_radius)
        timed_specs(worlds, "end", reverse=args.controller == "movebase", box=not args.disc)
        write_measured(worlds, folder / "measured.csv")
        problem = FitProblem(read_measured(folder / "measured.csv"), args.controller, FAILURE_S)
        space = SearchSpace.of(args.controller, names)
        found = fit_controller(problem, space, folds=args.folds, budget=args.budget, seed=args.seed)
        blocks = []
        for name, values in [
            ("all", found.fitted),
            *((f"fold-{k}", v) for k, v in enumerate(found.fold_fits)),
        ]:
            file = folder / f"robot-{name}.maze"
            file.write_text(
                robot_block(args.controller, space, values, problem.spec, "measured.csv"), "utf-8"
            )
            blocks.append(file)
        every = np.arange(len(worlds))
        clocks = {
            "defaults": measured(worlds, args.controller, "end", box=not args.disc),
            "fitted on all worlds": protocol_clocks(
                worlds, args.controller, [(blocks[0], every)], box=not args.disc
            ),
        }
        if found.folds:  # (none with --folds 1)
            clocks["fitted on the other folds (held out)"] = protocol_clocks(
                worlds, args.controller, list(zip(blocks[1:], found.folds)), box=not args.disc
            )
        fitted_block = blocks[0].read_text(encoding="utf-8")
    print(
        f"{len(worlds)} training worlds, `{args.controller}` fitted on {', '.join(space.names)} "
        f"({args.folds} folds, {args.budget} drives a fit, seed {args.seed}); one Gazebo DWA run against "
        f"the mean of the other four: ρ {gazebo_ceiling(worlds):.2f}\n"
    )
    fit_rows = [("defaults", found.default), ("fitted, all worlds", found.result)]
    fit_rows += [(f"fitted on the others, held-out fold {k + 1}", a) for k, a in enumerate(found.held_out)]
    table = [
        {"parameters": name, "rho": a.rho, "agreement": 100 * a.agreement,
         "simulated": 100 * a.simulated_success, "measured": 100 * a.measured_success}
        for name, a in fit_rows
    ]  # fmt: skip
    print(markdown_table(table, FIT_COLUMNS))
    print("\nDriven as BARN's 2020 runs were timed (barn_validation.py's protocol):\n")
    rows = [summary_row(f"`{args.controller}`, {name}", seconds, worlds) for name, seconds in clocks.items()]
    print(markdown_table(rows, SUMMARY))
    print(
        f"\nGoals: ρ ≥ {GOALS['rho']}, success within {GOALS['success_points']:g} points of BARN's, "
        f"failure agreement ≥ {100 * GOALS['failure_agreement']:.0f} %\n"
    )
    fitted = [
        {"parameter": name, "default": default, "fitted": value}
        for name, default, value in zip(space.names, space.default, found.fitted)
    ]
    columns = [
        ("parameter", "parameter", "s"),
        ("default", "default (SI)", ".4g"),
        ("fitted", "fitted (SI)", ".4g"),
    ]
    print(markdown_table(fitted, columns))
    print("\n" + fitted_block)


if __name__ == "__main__":
    main()

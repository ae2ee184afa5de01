"""Known-bad specs and the one-line located message each must give (a table, as in Lark)."""

from __future__ import annotations

import pytest

from mazegen.dsl.loader import check_file, load_spec
from mazegen.errors import MazeError

ARENA = "arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }\n"
ELEMENT = "element box { shape square size 20..40 }\n"
SCENARIO = "scenario s on floor { elements box }\n"


def placement(*, sizes: str, positions: str) -> str:
    return f"scenario s on floor {{ elements box placement grammar sizes {sizes} positions {positions} }}\n"


def spec(*, arena: str = ARENA, element: str = ELEMENT, scenario: str = SCENARIO, tail: str = "") -> str:
    return element + arena + scenario + tail


def _hall_pgm() -> str:
    """A 20 x 16 map of 0.1 m cells: walls around (0), free inside (254)."""
    rows = [" ".join("0" if r in (0, 15) or c in (0, 19) else "254" for c in range(20)) for r in range(16)]
    return "P2\n20 16\n255\n" + "\n".join(rows) + "\n"


HALL_YAML = (
    "image: hall.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
)

PLUGIN_FILES = {
    "dock.py": "def dock_clearance(floors, x=0.0, y=0.0):\n    return floors.x[:, 0]\n",
    "broken.py": "def dock_clearance(floors)\n    return 0\n",
    "failing.py": "1 / 0\n\ndef dock_clearance(floors):\n    return 0\n",
    "hall.pgm": _hall_pgm(),
    "hall.yaml": HALL_YAML,
    "noresolution.yaml": HALL_YAML.replace("resolution: 0.1\n", ""),
    "short.yaml": HALL_YAML.replace("hall.pgm", "short.pgm"),
    "short.pgm": "P2\n20 16\n255\n0 0 0\n",
}
"""Metric plug-in and map files beside every spec of the table."""


TWO_ZONES = "{ zone a rect (0, 0) (10, 10) keep clear zone a rect (20, 20) (30, 30) keep clear "


def hall(properties: str = 'map "hall.yaml" cm', *, start: str = "(50, 50)") -> str:
    """An arena on the map hall.yaml (200 x 160 cm)."""
    return f"arena floor {{ {properties} start {start} goal (150, 110) robot radius 20 }}\n"


def tasks(body: str, *, unit: str = "cm") -> str:
    """An arena of tasks: ``body`` its stations and tasks."""
    return f"arena floor {{ size 1000 x 800 {unit} robot radius 20\n{body} }}\n"


ROW = "row line of box { count 2..4  spacing 10..20 }\n"
PX_ARENA = "arena floor { size 1000 x 800 px start (50, 50) goal (950, 750) robot radius 20 }\n"


def rows(
    *,
    row: str = ROW,
    scenario: str = "scenario s on floor { elements line }\n",
    arena: str = ARENA,
    element: str = ELEMENT,
) -> str:
    """A spec of rows: the element box, the arena, the scenario, then the row(s) (line 4 on)."""
    return element + arena + scenario + row


# (name, text, expected line:col, expected message fragment)
BAD_SPECS = [
    ("syntax: unknown keyword", "elemnt box { }\n", "1:1", "expected 'units', 'import', 'element'"),
    (
        "syntax: range needs a number",
        spec(element="element box { shape square size 20.. }\n"),
        "1:38",
        "expected a number, found '}'",
    ),
    (
        "syntax: a number with an exponent",
        spec(tail="fitness { count weight 1e3 }\n"),
        "4:24",
        "expected a number, found '1e3' (write numbers without an exponent",
    ),
    (
        "syntax: a decimal where a whole number goes",
        spec(tail="evolution { population 2.5 }\n"),
        "4:24",
        "expected a whole number, found '2.5' (write a whole number such as 4000)",
    ),
    ("syntax: size needs x", spec(arena="arena floor { size 1000 by 800 }\n"), "2:25", "expected 'x'"),
    ("syntax: unclosed block", ELEMENT + "arena floor { size 10 x 10 cm\n", "3:1", "found end of file"),
    (
        "unknown element",
        spec(scenario="scenario s on floor { elements box, crate }\n"),
        "3:37",
        "unknown element 'crate'",
    ),
    (
        "unknown element suggestion",
        spec(scenario="scenario s on floor { elements bxo }\n"),
        "3:32",
        "did you mean 'box'?",
    ),
    (
        "unknown arena",
        spec(scenario="scenario s on flor { elements box }\n"),
        "3:1",
        "unknown arena 'flor' (did you mean 'floor'?)",
    ),
    ("unknown library", "import manufactoring\n" + spec(), "1:1", "unknown library 'manufactoring'"),
    (
        "missing import file",
        'import "nowhere.maze"\n' + spec(),
        "1:1",
        "imported file 'nowhere.maze' not found",
    ),
    (
        "inverted range",
        spec(element="element box { shape square size 40..20 }\n"),
        "1:33",
        "empty size range 40..20 (low is above high)",
    ),
    ("zero size", spec(element="element box { shape square size 0..20 }\n"), "1:33", "size must be positive"),
    (
        "rect needs depth",
        spec(element="element box { shape rect size 20..40 }\n"),
        "1:26",
        "give 'size WIDTH x DEPTH'",
    ),
    (
        "depth on a square",
        spec(element="element box { shape square size 20 x 30 }\n"),
        "1:38",
        "only a rect takes a depth",
    ),
    ("no shape", spec(element="element box { size 20..40 }\n"), "1:1", "element 'box' has no shape"),
    (
        "duplicate property",
        spec(element="element box { shape square size 2 size 3 }\n"),
        "1:35",
        "duplicate 'size' in element 'box'",
    ),
    (
        "bad colour",
        spec(element='element box { shape square size 2 colour "red; x" }\n'),
        "1:35",
        "bad colour",
    ),
    (
        "two-sided polygon",
        spec(element="element box { shape points (0,0) (1,1) size 2 }\n"),
        "1:21",
        "bad points shape",
    ),
    ("duplicate element", spec(element=ELEMENT + ELEMENT), "2:1", "'box' is already declared at"),
    (
        "start outside",
        spec(arena="arena floor { size 100 x 100 start (150, 50) goal (50, 50) }\n"),
        "2:36",
        "start (150, 50) is outside the arena 100 x 100",
    ),
    (
        "goal inside the wall margin",
        spec(arena="arena floor { size 100 x 100 start (50, 50) goal (95, 50) robot radius 10 }\n"),
        "2:50",
        "goal (95, 50) is closer to the arena wall than the robot radius 10",
    ),
    (
        "arena without start",
        spec(arena="arena floor { size 100 x 100 goal (50, 50) }\n"),
        "2:1",
        "arena 'floor' has no start",
    ),
    (
        "population 0",
        spec(tail="evolution { population 0 }\n"),
        "4:13",
        "population must be from 1 to 1000000, got 0",
    ),
    ("genome 0", spec(tail="evolution { genome 0 }\n"), "4:13", "genome must be from 1 to 10000, got 0"),
    (
        "selection 1.5",
        spec(tail="evolution { selection 1.5 }\n"),
        "4:13",
        "selection must be within (0, 1], got 1.5",
    ),
    ("selection 0", spec(tail="evolution { selection 0 }\n"), "4:13", "selection must be within (0, 1]"),
    ("mutation rate", spec(tail="evolution { mutation 2 }\n"), "4:13", "mutation rate must be within [0, 1]"),
    (
        "codons start at 0",
        spec(tail="evolution { codons 1..255 }\n"),
        "4:20",
        "codons must be written 0..MAX",
    ),
    (
        "elitism too large",
        spec(tail="evolution { population 5 elitism 5 }\n"),
        "4:26",
        "elitism 5 must be below the population 5",
    ),
    (
        "population within the default elitism",
        spec(tail="evolution { population 1 }\n"),
        "4:13",
        "population 1 must be above the elitism 1 (the default",
    ),
    ("duplicate setting", spec(tail="evolution { seed 1 seed 2 }\n"), "4:20", "duplicate 'seed'"),
    ("duplicate term", spec(tail="fitness { count count }\n"), "4:17", "duplicate fitness term 'count'"),
    (
        "grid cell too coarse",
        spec(arena=ARENA.replace("robot radius 20", "robot radius 20 grid 300")),
        "2:81",
        "grid cell must be positive and at most a quarter of the arena's shorter side, got 300",
    ),
    (
        "grid cell too fine",
        spec(arena=ARENA.replace("robot radius 20", "robot radius 20 grid 0.5")),
        "2:81",
        "grid cell 0.5 makes more than 1024 cells on a side",
    ),
    (
        "solvable needs a mode",
        spec(tail="fitness { solvable }\n"),
        "4:20",
        "expected 'required' or 'penalty'",
    ),
    (
        "metric range backwards",
        spec(tail="fitness { tortuosity 2.0..1.4 weight 2 }\n"),
        "4:22",
        "a target range needs low < high, got 2..1.4",
    ),
    (
        "coverage is a fraction",
        spec(tail="fitness { coverage 0.2..1.5 }\n"),
        "4:20",
        "coverage is a fraction of the floor (0..1), got 0.2..1.5",
    ),
    (
        "classes beyond the most told",
        spec(tail="fitness { classes 9 weight 2 }\n"),
        "4:11",
        "classes N counts 1 to 8 classes (the most a floor is told), got 9",
    ),
    (
        "unknown difficulty level",
        spec(tail="fitness { difficulty target extreme }\n"),
        "4:29",
        "expected 'easy', 'medium' or 'hard'",
    ),
    (
        "duplicate metric term",
        spec(tail="fitness { tortuosity 1.2..1.5 tortuosity 1.5..2.0 }\n"),
        "4:31",
        "duplicate fitness term 'tortuosity'",
    ),
    (
        "size limit allow",
        spec(tail="fitness { size limit 500 allow }\n"),
        "4:11",
        "needs 'reject' or 'penalty W'",
    ),
    (
        "custom rule undefined",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= box <t> } }\n"),
        "3:52",
        "rule <t> is used but never defined",
    ),
    (
        "custom rule twice",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= box <s> ::= box } }\n"),
        "3:52",
        "rule <s> is defined twice",
    ),
    (
        "custom unknown element",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= crate } }\n"),
        "3:48",
        "unknown element 'crate'",
    ),
    ("no elements", spec(scenario="scenario s on floor { grammar flat }\n"), "3:1", "names no elements"),
    (
        "max elements 0",
        spec(scenario="scenario s on floor { elements box max elements 0 }\n"),
        "3:36",
        "max elements must be within 1..1000, got 0",
    ),
    (
        "max elements beyond the slots' bound",
        spec(scenario="scenario s on floor { elements box max elements 100000 }\n"),
        "3:36",
        "max elements must be within 1..1000, got 100000",
    ),
    ("two scenarios", spec(tail=SCENARIO), "4:1", "only one scenario block per file"),
    (
        "positions beyond arena",
        spec(
            scenario="scenario s on floor { elements box placement grammar sizes 1..8 positions 100..900 }\n"
        ),
        "3:75",
        "positions up to 900 go beyond the arena",
    ),
    # Hostile input (issue 19): every number bounded, nothing non-finite, no control character.
    (
        "import path with a NUL byte",
        'import "a\0b"\n' + spec(),
        "1:1",
        "import path 'a\\x00b' holds a control",
    ),
    (
        "import path with a line break",
        'import "a\nb"\n' + spec(),
        "1:1",
        "import path 'a\\nb' holds a control",
    ),
    (
        "import path too long",
        'import "' + "a" * 300 + '"\n' + spec(),
        "1:1",
        "imported file '" + "a" * 40 + "...' cannot be read: File name too long",
    ),
    (
        "a whole number of 5000 digits",
        spec(tail="evolution { seed " + "9" * 5000 + " }\n"),
        "4:18",
        "number too long: at most 20 digits before the point, got 5000",
    ),
    (
        "a 400-digit position",
        spec(scenario=placement(sizes="1..8", positions="0..1" + "0" * 399)),
        "3:78",
        "number too long: at most 20 digits before the point, got 400",
    ),
    (
        "a 400-digit weight",
        spec(tail="fitness { count weight 1" + "0" * 400 + " }\n"),
        "4:24",
        "number too long",
    ),
    (
        "a 400-digit arena size",
        spec(arena="arena floor { size 1" + "0" * 400 + " x 800 start (50, 50) goal (950, 750) }\n"),
        "2:20",
        "number too long",
    ),
    (
        "a 400-digit element size",
        spec(element="element box { shape square size 20..1" + "0" * 400 + " }\n"),
        "1:37",
        "number too long",
    ),
    (
        "sizes of a hundred million values",
        spec(scenario=placement(sizes="1..100000000", positions="0..100")),
        "3:60",
        "sizes 1..100000000 give 100000000 values; at most 10000",
    ),
    (
        "sizes scaled beyond the largest length",
        spec(scenario=placement(sizes="1..8 scale 200000", positions="0..100")),
        "3:36",
        "sizes up to 8 x scale 200000 must be at most 1000000, got 1600000",
    ),
    (
        "scale beyond the largest length",
        spec(scenario=placement(sizes="1..8 scale 10000000", positions="0..100")),
        "3:36",
        "scale must be at most 1000000, got 10000000",
    ),
    (
        "a polygon of a hundred million sides",
        spec(element="element box { shape polygon 100000000 size 20..40 }\n"),
        "1:21",
        "a regular polygon has 3 to 64 sides, got 100000000",
    ),
    (
        "a polygon of two million sides",
        spec(element="element box { shape polygon 2000000 size 20..40 }\n"),
        "1:21",
        "a regular polygon has 3 to 64 sides, got 2000000",
    ),
    (
        "an outline of 65 points",
        spec(element="element box { shape points " + "(0,0) (1,0) " * 32 + "(1,1) size 20..40 }\n"),
        "1:21",
        "an outline has at most 64 points, got 65",
    ),
    (
        "a figure of 65 bars",
        spec(element="element box { shape bars " + "(0,0)-(1,0) " * 65 + "thickness 1 size 20..40 }\n"),
        "1:21",
        "a bar figure has at most 64 bars, got 65",
    ),
    (
        "a point far away",
        spec(element="element box { shape points (0,0) (1,0) (1,10000000) size 20..40 }\n"),
        "1:40",
        "a point's coordinates must be within -1000000..1000000, got (1, 10000000)",
    ),
    (
        "a thick bar",
        spec(element="element box { shape bars (0,0)-(1,0) thickness 10000000 size 20..40 }\n"),
        "1:21",
        "bar thickness must be at most 1000000, got 10000000",
    ),
    (
        "an element larger than the largest length",
        spec(element="element box { shape square size 20..10000000 }\n"),
        "1:33",
        "size must be at most 1000000, got 10000000",
    ),
    (
        "a tall element",
        spec(element="element box { shape square size 20 height 10000000 }\n"),
        "1:36",
        "height must be at most 1000000, got 10000000",
    ),
    (
        "a rotation beyond a turn",
        spec(element="element box { shape square size 20 rotation 0, 1000 }\n"),
        "1:36",
        "rotation angles must be within -360..360, got 1000",
    ),
    (
        "an arena larger than the largest length",
        spec(arena="arena floor { size 10000000 x 800 start (50, 50) goal (950, 750) }\n"),
        "2:15",
        "arena size must be at most 1000000, got 10000000 x 800",
    ),
    (
        "a robot larger than the largest length",
        spec(arena=ARENA.replace("robot radius 20", "robot radius 10000000")),
        "2:65",
        "robot radius must be at most 1000000, got 10000000",
    ),
    (
        "genome 1000000000",
        spec(tail="evolution { genome 1000000000 }\n"),
        "4:13",
        "genome must be from 1 to 10000",
    ),
    (
        "population 100000000",
        spec(tail="evolution { population 100000000 }\n"),
        "4:13",
        "population must be from 1 to 1000000, got 100000000",
    ),
    (
        "runs of 20 digits",
        spec(tail="evolution { runs 99999999999999999999 }\n"),
        "4:13",
        "runs must be from 1 to 10000, got 99999999999999999999",
    ),
    (
        "codons beyond 32 bits",
        spec(tail="evolution { codons 0..2147483648 }\n"),
        "4:20",
        "codons 0..MAX: MAX must be from 1 to 2147483647, got 2147483648",
    ),
    (
        "wraps of 20 digits",
        spec(tail="evolution { wraps 99999999999999999999 }\n"),
        "4:13",
        "wraps must be from 0 to 100, got 99999999999999999999",
    ),
    (
        "seed beyond 64 bits",
        spec(tail="evolution { seed 9223372036854775808 }\n"),
        "4:13",
        "seed must be from 0 to 9223372036854775807, got 9223372036854775808",
    ),
    (
        "population x genome beyond the codons a machine holds",
        spec(tail="evolution { population 1000000 genome 1000 }\n"),
        "4:32",
        "population x genome must be at most 100000000 codons, got 1000000 x 1000",
    ),
    (
        "a weight beyond the largest",
        spec(tail="fitness { count weight 10000000 }\n"),
        "4:11",
        "weight must be at most 1000000, got 10000000",
    ),
    (
        "a size limit beyond the largest length",
        spec(tail="fitness { size limit 10000000 reject }\n"),
        "4:11",
        "size limit must be at most 1000000, got 10000000",
    ),
    (
        "a target beyond the largest",
        spec(tail="fitness { path_length 1..10000000000 }\n"),
        "4:23",
        "a target range cannot go above 1000000000, got 1..10000000000",
    ),
    (
        "grammar text with a line break",
        spec(scenario='scenario s on floor { grammar custom { <s> ::= box "a\nb" } }\n'),
        "3:52",
        "grammar text 'a\\nb' holds a control character (write \\n for a line break)",
    ),
    (
        "grammar text with a truncated escape",
        spec(scenario='scenario s on floor { grammar custom { <s> ::= box "\\x" } }\n'),
        "3:52",
        "bad escape in grammar text '\\x': truncated \\xXX escape",
    ),
    (
        "grammar text with an unknown character name",
        spec(scenario='scenario s on floor { grammar custom { <s> ::= box "\\N{NOPE}" } }\n'),
        "3:52",
        "bad escape in grammar text '\\N{NOPE}': unknown Unicode character name",
    ),
    (
        "a library name too long for a file name",
        "import " + "n" * 300 + "\n" + spec(),
        "1:1",
        "unknown library '" + "n" * 40 + "...' (bundled: figures, manufacturing",
    ),
    (
        "a huge token is quoted cut",
        "x" * 100_000 + " { }\n",
        "1:1",
        "found '" + "x" * 40 + "...'",
    ),
    (
        "robot: a typo in a limit",
        spec(tail="robot { sped 50 }\n"),
        "4:9",
        "expected 'speed', 'min', 'turn', 'acceleration', 'step', 'goal', 'timeout', 'stuck', 'contact', "
        "'footprint', 'lidar', 'drive', 'controller' or '}', found 'sped'",
    ),
    (
        "robot: a footprint is a length by a width",
        spec(tail="robot { footprint 50 x 43 }\n"),
        "4:22",
        "expected 'by', found 'x'",
    ),
    (
        "robot: a footprint has a positive width",
        spec(tail="robot { footprint 50 by 0 }\n"),
        "4:9",
        "footprint width must be within (0, 1000000] arena units, got 0",
    ),
    (
        "robot: what a touch does is end or continue",
        spec(tail="robot { contact bounce }\n"),
        "4:17",
        "expected 'end' or 'continue', found 'bounce'",
    ),
    ("robot: a typo in a two-word limit", spec(tail="robot { min sped 5 }\n"), "4:13", "expected 'speed'"),
    (
        "robot: speed must be positive",
        spec(tail="robot { speed 0 }\n"),
        "4:9",
        "speed must be within (0, 1000000] arena units per second, got 0",
    ),
    (
        "robot: min speed above the speed",
        spec(tail="robot { speed 50 min speed 60 }\n"),
        "4:18",
        "min speed 60 is above the speed 50",
    ),
    (
        "robot: min speed above the default speed",
        spec(tail="robot { min speed 60 }\n"),
        "4:9",
        "min speed 60 is above the speed 50",
    ),
    (
        "robot: backing up faster than the speed",
        spec(tail="robot { speed 50 min speed -60 }\n"),
        "4:18",
        "min speed -60 backs up faster than the speed 50",
    ),
    (
        "robot: turn rate in degrees, bounded",
        spec(tail="robot { turn rate 4000 }\n"),
        "4:9",
        "turn rate must be within (0, 3600] degrees per second, got 4000",
    ),
    (
        "robot: step too long",
        spec(tail="robot { step 5 }\n"),
        "4:9",
        "step must be within [0.001, 1] seconds",
    ),
    (
        "robot: timeout needs its factor",
        spec(tail="robot { timeout 5 }\n"),
        "4:17",
        "expected 'factor', found '5'",
    ),
    (
        "robot: timeout factor below 1",
        spec(tail="robot { timeout factor 0.5 }\n"),
        "4:9",
        "timeout factor must be within [1, 1000] times the optimal time, got 0.5",
    ),
    ("robot: no beams", spec(tail="robot { lidar { beams 0 } }\n"), "4:17", "beams must be within [1, 3600]"),
    (
        "robot: a fraction of a beam",
        spec(tail="robot { lidar { beams 36.5 } }\n"),
        "4:23",
        "expected a whole number, found '36.5'",
    ),
    (
        "robot: fov over a turn",
        spec(tail="robot { lidar { fov 400 } }\n"),
        "4:17",
        "fov must be within (0, 360]",
    ),
    (
        "robot: duplicate two-word limit",
        spec(tail="robot { min speed 1 min speed 2 }\n"),
        "4:21",
        "duplicate 'min speed' in robot (first given at",
    ),
    (
        "robot: duplicate lidar setting",
        spec(tail="robot { lidar { fov 9 fov 8 } }\n"),
        "4:23",
        "duplicate 'fov'",
    ),
    (
        "robot: two robot blocks",
        spec(tail="robot { }\nrobot { }\n"),
        "5:1",
        "only one robot block per spec (first at ",
    ),
    (
        "robot: drive nobody",
        spec(tail="robot { drive best 0 }\n"),
        "4:9",
        "drive best takes a fraction within (0, 1], got 0",
    ),
    (
        "robot: drive whom",
        spec(tail="robot { drive some }\n"),
        "4:15",
        "expected 'all' or 'best', found 'some'",
    ),
    (
        "robot: unknown controller",
        spec(tail="robot { controller dwaa { } }\n"),
        "4:9",
        "unknown controller 'dwaa' (did you mean 'dwa'?) (bundled: straight, dwa, purepursuit, vfh, "
        "movebase; or a policy's path package.module:name)",
    ),
    (
        "robot: a policy's path without its name",
        spec(tail="robot { controller pkg.mod { } }\n"),
        "4:9",
        "a policy's path reads package.module:name, got 'pkg.mod'",
    ),
    (
        "robot: a policy's path with a stray character",
        spec(tail="robot { controller pkg.mod:pol-icy { } }\n"),
        "4:31",
        "expected '{', found '-'",
    ),
    (
        "robot: parameters of a user's policy",
        spec(tail="robot { controller pkg.mod:policy { gain 2 } }\n"),
        "4:37",
        "controller 'pkg.mod:policy' is not bundled: its parameters are its own",
    ),
    (
        "robot: a policy whose module is not found, at the robot block before the term",
        spec(
            tail="robot { controller nosuch_policy_module:policy { } }\n"
            "fitness { controller nosuch_policy_module:policy fails }\n"
        ),
        "4:9",
        "controller 'nosuch_policy_module:policy': no module 'nosuch_policy_module' in the current folder, "
        "PYTHONPATH or the installed packages",
    ),
    (
        "drive term: a policy whose module is not in its package",
        spec(tail="fitness { count controllers dwa, json.nosuch:policy disagree }\n"),
        "4:17",
        "controller 'json.nosuch:policy': no module 'json.nosuch' in the current folder",
    ),
    (
        "robot: unknown controller parameter",
        spec(tail="robot { controller dwa { horizn 2 } }\n"),
        "4:26",
        "controller 'dwa' has no parameter 'horizn' (did you mean 'horizon'?) (its parameters: v_samples,",
    ),
    (
        "robot: controller parameter out of its bounds",
        spec(tail="robot { controller dwa { horizon 100 } }\n"),
        "4:26",
        "dwa horizon must be within 0.1..60 s, got 100",
    ),
    (
        "robot: a length parameter in the arena's unit",
        spec(tail="robot { controller purepursuit { lookahead -5 } }\n"),
        "4:34",
        "purepursuit lookahead must be at least 0 cm, got -5",
    ),
    (
        "robot: an angle parameter in degrees",
        spec(tail="robot { controller straight { turn_in_place 200 } }\n"),
        "4:31",
        "straight turn_in_place must be within 0..180.482 degrees, got 200",
    ),
    (
        "robot: a count parameter",
        spec(tail="robot { controller dwa { v_samples 8.5 } }\n"),
        "4:26",
        "dwa v_samples is a count: expected a whole number, got 8.5",
    ),
    (
        "robot: duplicate controller parameter",
        spec(tail="robot { controller dwa { horizon 1 horizon 2 } }\n"),
        "4:36",
        "duplicate 'horizon' in controller 'dwa'",
    ),
    (
        "robot: a controller set twice",
        spec(tail="robot { controller dwa { } controller dwa { } }\n"),
        "4:28",
        "controller 'dwa' is set twice (first at",
    ),
    (
        "drive term: unknown controller",
        spec(tail="fitness { controller purepursiut fails }\n"),
        "4:11",
        "unknown controller 'purepursiut' (did you mean 'purepursuit'?)",
    ),
    (
        "drive term: unknown measure",
        spec(tail="fitness { controller dwa fail }\n"),
        "4:26",
        "expected 'fails', 'time', 'clearance' or 'disagree', found 'fail'",
    ),
    (
        "drive term: disagree needs two controllers",
        spec(tail="fitness { controller dwa disagree }\n"),
        "4:11",
        "'disagree' compares two controllers: write 'controllers dwa, purepursuit disagree'",
    ),
    (
        "drive term: disagree of one controller with itself",
        spec(tail="fitness { controllers dwa, dwa disagree }\n"),
        "4:11",
        "'disagree' compares two different controllers, got 'dwa' twice",
    ),
    (
        "drive term: fails reads one controller",
        spec(tail="fitness { controllers dwa, vfh fails }\n"),
        "4:11",
        "'fails' reads one controller: write 'controller dwa fails'",
    ),
    (
        "drive term: no target for fails",
        spec(tail="fitness { controller dwa fails 0..1 }\n"),
        "4:32",
        "a 'fails' term takes no target range (only time and clearance do)",
    ),
    (
        "drive term: inverted target",
        spec(tail="fitness { controller dwa time 4..2 }\n"),
        "4:31",
        "a target range needs low < high, got 4..2",
    ),
    (
        "drive term: twice",
        spec(tail="fitness { controller dwa fails controller dwa fails }\n"),
        "4:32",
        "duplicate fitness term 'dwa_fails' (first given at",
    ),
    (
        "drive term: a number where a controller goes",
        spec(tail="fitness { controller 5 fails }\n"),
        "4:22",
        "expected a controller name (dwa, or a policy's path package.module:name), found '5'",
    ),
    (
        "drive term: a px arena with no robot to size it",
        spec(
            arena="arena floor { size 1000 x 800 px start (50, 50) goal (950, 750) }\n",
            tail="fitness { controller dwa fails }\n",
        ),
        "4:1",
        "arena 'floor' is in px with no robot radius: give it one ('robot radius 25')",
    ),
    (
        "mutation is int-flip only",
        spec(tail="evolution { mutation variable within used 0.05 }\n"),
        "4:22",
        "mutation is int-flip, not variable: write mutation within used RATE",
    ),
    (
        "crossover needs its kind",
        spec(tail="evolution {\n  crossover within genome 0.9 }\n"),
        "5:13",
        "say which crossover: crossover onepoint within genome RATE",
    ),
    (
        "variable crossover cuts within the used codons",
        spec(tail="evolution { crossover variable within genome 0.9 }\n"),
        "4:23",
        "variable crossover cuts within the used codons only, not within genome",
    ),
    (
        "an element that can never fit inside the arena (sizes in cm, arena in m)",
        spec(arena="arena floor { size 10 x 8 m start (1, 1) goal (9, 7) robot radius 0.2 }\n"),
        "1:1",
        "element 'box' can never fit inside arena 'floor' (10 x 8 m): at its smallest size it is "
        "28.28 m across, the arena's diagonal 12.81 m (are its sizes in another unit?)",
    ),
    (
        "syntax: an unknown operator scope",
        spec(tail="evolution { crossover onepoint within tail 0.9 }\n"),
        "4:39",
        "expected 'used' or 'genome'",
    ),
    (
        "metric plug-in: not installed",
        spec(tail="fitness { metric dock_clearence }\n"),
        "4:11",
        "unknown metric plug-in 'dock_clearence' (none is installed; or name the file that defines it: "
        'metric dock_clearence from "FILE.py")',
    ),
    (
        "metric plug-in: not in its file",
        spec(tail='fitness { metric dock_clearence from "dock.py" }\n'),
        "4:11",
        "metric 'dock_clearence': dock.py defines no 'dock_clearence' (did you mean 'dock_clearance'?)",
    ),
    (
        "metric plug-in: no such file",
        spec(tail='fitness { metric dock_clearance from "dok.py" }\n'),
        "4:11",
        "metric 'dock_clearance': no file 'dok.py' (looked for ",
    ),
    (
        "metric plug-in: its file is not Python",
        spec(tail='fitness { metric dock_clearance from "broken.py" }\n'),
        "4:11",
        "metric 'dock_clearance': ",
    ),
    (
        "metric plug-in: its file fails to run",
        spec(tail='fitness { metric dock_clearance from "failing.py" }\n'),
        "4:11",
        "failing.py fails to run (ZeroDivisionError: division by zero)",
    ),
    (
        "metric plug-in: an argument it does not take",
        spec(tail='fitness { metric dock_clearance(z=1) from "dock.py" }\n'),
        "4:11",
        "metric 'dock_clearance': got an unexpected keyword argument 'z' (it takes x, y after the floors)",
    ),
    (
        "metric plug-in: an argument given twice",
        spec(tail='fitness { metric dock_clearance(x=1, x=2) from "dock.py" }\n'),
        "4:38",
        "metric 'dock_clearance': argument 'x' given twice",
    ),
    (
        "map: no such file",
        spec(arena=hall('map "nohall.yaml"')),
        "2:15",
        "no map file 'nohall.yaml' (looked for ",
    ),
    (
        "map: and a size",
        spec(arena=hall('map "hall.yaml" size 200 x 160 cm')),
        "2:31",
        "an arena built on a map takes its size from the map: remove 'size'",
    ),
    (
        "map: unknown cells said of an arena without a map",
        spec(arena=ARENA.replace("{ ", "{ unknown free ")),
        "2:15",
        "'unknown' says what a map's unknown cells are, and this arena has no map",
    ),
    (
        "map: in pixels",
        spec(arena=hall('map "hall.yaml" px')),
        "2:15",
        "a map's cells are in metres: give its arena in mm, cm or m (map 'hall.yaml' cm)",
    ),
    (
        "map: an image, not its YAML",
        spec(arena=hall('map "hall.pgm"')),
        "2:15",
        "map 'hall.pgm': give a ROS map_server map's .yaml (its image beside it)",
    ),
    (
        "map: its YAML lacks a key",
        spec(arena=hall('map "noresolution.yaml" cm')),
        "2:15",
        "map 'noresolution.yaml': noresolution.yaml: the map has no 'resolution'",
    ),
    (
        "map: its image is short",
        spec(arena=hall('map "short.yaml" cm')),
        "2:15",
        "map 'short.yaml': short.pgm: image size mismatch: the header says 20 x 16 = 320 pixels, "
        "the file holds 3",
    ),
    (
        "map: a start on its walls",
        spec(arena=hall(start="(25, 50)")),
        "2:40",
        "start (25, 50) is on the map's walls or closer to them than the robot radius 20",
    ),
    (
        "map: a start beyond it",
        spec(arena=hall(start="(250, 50)")),
        "2:40",
        "start (250, 50) is outside the arena 200 x 160",
    ),
    (
        "zone: two of one name",
        spec(arena=ARENA.replace("{ ", TWO_ZONES)),
        "2:54",
        "duplicate zone 'a' (first given at ",
    ),
    (
        "zone: beyond the arena",
        spec(arena=ARENA.replace("{ ", "{ zone a rect (900, 700) (1100, 800) keep clear ")),
        "2:22",
        "zone 'a' reaches beyond the arena 1000 x 800 at (1100, 700)",
    ),
    (
        "zone: a rect's corners the wrong way round",
        spec(arena=ARENA.replace("{ ", "{ zone a rect (100, 100) (50, 200) keep clear ")),
        "2:22",
        "a zone's rect goes from its lower-left corner to its upper-right, got (100, 100) (50, 200)",
    ),
    (
        "zone: a polygon whose edges cross",
        spec(arena=ARENA.replace("{ ", "{ zone a polygon (0, 0) (100, 100) (100, 0) (0, 100) keep clear ")),
        "2:22",
        "zone 'a': polygon edges cross or touch each other",
    ),
    (
        "zone: an unknown element",
        spec(arena=ARENA.replace("{ ", "{ zone a rect (0, 0) (100, 100) accepts bx ")),
        "2:45",
        "zone 'a': unknown element 'bx' (did you mean 'box'?)",
    ),
    (
        "zone: holding an element it can never fit",
        spec(arena=ARENA.replace("{ ", "{ zone a rect (0, 0) (10, 20) holds box ")),
        "1:1",
        "element 'box' can never fit inside the zones that hold it ('a'): at its smallest size it is "
        "28.28 cm across, the widest zone's diagonal 22.36 cm",
    ),
    (
        "units: a file in cm under an arena in pixels",
        "units cm\n" + spec(arena=ARENA.replace(" cm ", " px ")),
        "1:1",
        "this file's lengths are in cm and arena 'floor' is in px: px has no size in metres to convert by "
        "(give both in mm, cm or m, or drop 'units')",
    ),
    (
        "metric plug-in: a negative penalty",
        spec(tail='fitness { metric dock_clearance from "dock.py" penalty -1 }\n'),
        "4:11",
        "penalty must not be negative, got -1",
    ),
    (
        "metric plug-in: two terms of one name",
        spec(tail='fitness { metric dock_clearance from "dock.py" metric dock_clearance from "dock.py" }\n'),
        "4:48",
        "duplicate fitness term 'dock_clearance' (first given at ",
    ),
    (
        "tasks: a task of an unknown station",
        spec(arena=tasks("station dock (50, 50) station line (900, 700) task dock -> lne")),
        "3:47",
        "no station 'lne' (did you mean 'line'?) (declare it: 'station lne (X, Y)')",
    ),
    (
        "tasks: a task that starts where it ends",
        spec(arena=tasks("station dock (50, 50) task dock -> dock")),
        "3:23",
        "task dock -> dock starts where it ends",
    ),
    (
        "tasks: two stations of one name",
        spec(arena=tasks("station a (50, 50) station a (90, 90) task a -> a")),
        "3:20",
        "duplicate station 'a' (first given at ",
    ),
    (
        "tasks: a station in no task",
        spec(arena=tasks("station a (50, 50) station b (900, 700) station c (500, 400) task a -> b")),
        "3:41",
        "station 'c' is in no task (add e.g. 'task c -> B')",
    ),
    (
        "tasks: stations and no task",
        spec(arena=tasks("station a (50, 50)")),
        "3:1",
        "station 'a' is in no task (add e.g. 'task a -> B')",
    ),
    (
        "tasks: a station in the arena's wall",
        spec(arena=tasks("station a (10, 50) station b (900, 700) task a -> b")),
        "3:11",
        "station 'a' (10, 50) is closer to the arena wall than the robot radius 20",
    ),
    (
        "tasks: a station on a map's walls",
        spec(
            arena='arena floor { map "hall.yaml" cm robot radius 20 station a (28, 50) station b (150, 110) '
            "task a -> b }\n"
        ),
        "2:60",
        "station 'a' (28, 50) is on the map's walls or closer to them than the robot radius 20",
    ),
    (
        "tasks: a start beside tasks",
        spec(arena=tasks("start (50, 50) station a (50, 50) station b (900, 700) task a -> b")),
        "3:1",
        "an arena with tasks takes its starts and goals from them: make this start a station and name it "
        "in a task",
    ),
    (
        "tasks: none to draw",
        spec(arena=tasks("tasks 0 seed 1")),
        "3:1",
        "tasks: give 1 to 1000 tasks to draw, got 0",
    ),
    (
        "tasks: drawn twice",
        spec(arena=tasks("tasks 2 seed 1 tasks 3 seed 2")),
        "3:16",
        "duplicate 'tasks' in arena 'floor' (first given at ",
    ),
    (
        "tasks: a min distance no task can keep",
        spec(arena=tasks("tasks 2 seed 1 min distance 20 m")),
        "3:1",
        "tasks: no start found a goal joined to it and 2000 or more away (on the arena's grid of 10 cm "
        "cells)",
    ),
    (
        "tasks: a min distance that cannot be converted",
        spec(arena=tasks("tasks 2 seed 1 min distance 2 m", unit="px")),
        "3:1",
        "tasks: a min distance in m cannot be converted to the arena's px",
    ),
    (
        "tasks: a heading beyond a turn",
        spec(arena=tasks("station a (50, 50) heading 400 station b (900, 700) task a -> b")),
        "3:1",
        "a heading is in degrees, -360..360, got 400",
    ),
    (
        "required: an element the scenario does not list",
        spec(
            element=ELEMENT + "element bar { shape square size 20..40 }\n",
            scenario="scenario s on floor { elements box exactly 2 bar }\n",
        ),
        "4:46",
        "'bar' is not an element of this scenario (elements box)",
    ),
    (
        "required: twice",
        spec(scenario="scenario s on floor { elements box exactly 2 box at least 1 box }\n"),
        "3:50",
        "'box' is required twice (first at ",
    ),
    (
        "required: none",
        spec(scenario="scenario s on floor { elements box at least 0 box }\n"),
        "3:36",
        "a required count must be at least 1, got 0",
    ),
    (
        "required: more than a floor holds",
        spec(scenario="scenario s on floor { elements box exactly 9 box max elements 8 }\n"),
        "3:36",
        "9 elements are required and a floor holds at most 8 (max elements)",
    ),
    (
        "required: with a custom grammar",
        spec(
            scenario="scenario s on floor { elements box exactly 2 box "
            "grammar custom { <s> ::= box | box <s> } }\n"
        ),
        "3:36",
        "a custom grammar says itself what a floor holds: required elements need a generated one",
    ),
    (
        "map: a file name with a NUL character",
        spec(arena=hall('map "hall\u0000.yaml" cm')),
        "2:15",
        "a file name holds no NUL character",
    ),
    (
        "required: exactly, and a row adds more",
        rows(scenario="scenario s on floor { elements box, line exactly 2 box }\n"),
        "3:42",
        "'box' is required exactly, and row 'line' adds more of it: write 'at least'",
    ),
    # Structure: steps, walls and rows.
    (
        "row: of an unknown element type",
        rows(row="row line of bx { count 2..4 spacing 10..20 }\n"),
        "4:1",
        "row 'line' of unknown element 'bx' (did you mean 'box'?)",
    ),
    (
        "row: of a row",
        rows(
            row=ROW + "row two of line { count 2 spacing 5 }\n",
            scenario="scenario s on floor { elements two }\n",
        ),
        "5:1",
        "row 'two' is of row 'line': a row's members are elements",
    ),
    (
        "row: no count",
        rows(row="row line of box { spacing 10..20 }\n"),
        "4:1",
        "row 'line' has no count (add e.g. 'count 2..6')",
    ),
    (
        "row: no spacing",
        rows(row="row line of box { count 2..4 }\n"),
        "4:1",
        "row 'line' has no spacing (add e.g. 'spacing 50..100')",
    ),
    (
        "row: fewer than two members",
        rows(row="row line of box { count 1..4 spacing 10 }\n"),
        "4:19",
        "a row has at least 2 members, got 1",
    ),
    (
        "row: an empty count range",
        rows(row="row line of box { count 5..3 spacing 10 }\n"),
        "4:19",
        "empty count range 5..3 (low is above high)",
    ),
    (
        "row: more members than a floor holds",
        rows(row="row line of box { count 2..2000 spacing 10 }\n"),
        "4:19",
        "a row has at most 1000 members (the most elements a floor holds), got 2000",
    ),
    (
        "row: a spacing that is not positive",
        rows(row="row line of box { count 2 spacing 0..5 }\n"),
        "4:35",
        "spacing must be positive, got 0",
    ),
    (
        "row: a spacing step that is not positive",
        rows(row="row line of box { count 2 spacing 5..10 step 0 }\n"),
        "4:35",
        "spacing step must be positive, got 0",
    ),
    (
        "row: a spacing whose unit cannot be converted",
        rows(row="row line of box { count 2 spacing 5 cm }\n", arena=PX_ARENA),
        "4:27",
        "spacing 5 cm cannot be converted into px, the unit of arena 'floor': px has no size in metres "
        "(write it in px, or without a unit)",
    ),
    (
        "row: can never fit the arena at any of its rotations",
        rows(
            scenario="scenario s on floor { elements line max elements 60 }\n",
            row="row line of box { count 40..50 spacing 10 rotation 0, 90 }\n",
        ),
        "4:1",
        "row 'line' can never fit inside arena 'floor' (1000 x 800 cm): at its fewest members (40), "
        "smallest size and spacing it is 1190 x 20 cm at rotation 0, 20 x 1190 cm at rotation 90",
    ),
    (
        "row: longer than the arena's diagonal",
        rows(
            scenario="scenario s on floor { elements line max elements 60 }\n",
            row="row line of box { count 50 spacing 10 rotation any }\n",
        ),
        "4:1",
        "row 'line' can never fit inside arena 'floor' (1000 x 800 cm): at its fewest members (50), "
        "smallest size and spacing it is 1490 cm across, the diagonal of the arena 1281 cm",
    ),
    (
        "row: can never fit the zones that hold its members",
        rows(
            arena=ARENA.replace(
                "robot radius 20", "robot radius 20 zone racks rect (0, 0) (200, 200) holds box"
            ),
            row="row line of box { count 8 spacing 10 }\n",
        ),
        "4:1",
        "row 'line' can never fit inside the zones that hold box ('racks'): at its fewest members (8), "
        "smallest size and spacing it is 230 x 20 cm at rotation 0",
    ),
    (
        "row: more members than max elements",
        rows(
            scenario="scenario s on floor { elements line max elements 3 }\n",
            row="row line of box { count 4..6 spacing 10 }\n",
        ),
        "3:37",
        "scenario 's' holds at most 3 elements ('max elements'), and row 'line' has at least 4 members",
    ),
    (
        "row: in a scenario placed by its grammar",
        rows(
            scenario="scenario s on floor { elements line placement grammar sizes 1..4 positions 0..800 }\n"
        ),
        "3:37",
        "row 'line' is placed by placement genes, and scenario 's' places its elements by its grammar's "
        "numbers (drop 'placement grammar', or the structure)",
    ),
    (
        "step: in a scenario placed by its grammar",
        spec(
            element="element box { shape square size 20..40 at step 50 }\n",
            scenario=placement(sizes="1..4", positions="0..800"),
        ),
        "3:36",
        "element 'box' (at step) is placed by placement genes, and scenario 's' places its elements by "
        "its grammar's numbers (drop 'placement grammar', or the structure)",
    ),
    (
        "step: not positive",
        spec(element="element box { shape square size 20..40 at step 0 }\n"),
        "1:40",
        "step must be positive, got 0",
    ),
    (
        "step: a unit that cannot be converted",
        spec(element="element box { shape square size 20..40 at step 5 cm }\n", arena=PX_ARENA),
        "1:40",
        "step 5 cm cannot be converted into px, the unit of arena 'floor': px has no size in metres "
        "(write it in px, or without a unit)",
    ),
    (
        "step: more positions than a gene chooses from",
        spec(element="element box { shape square size 20..40 at step 0.001 }\n"),
        "1:40",
        "step 0.001 cm gives 1000001 positions from 0 to 1000 cm across arena 'floor'; at most 65536, "
        "the values of a placement gene (give a larger step)",
    ),
    (
        "step: no position within the zones that hold it",
        spec(
            element="element box { shape square size 20..40 at step 50 }\n",
            arena=ARENA.replace(
                "robot radius 20", "robot radius 20 zone racks rect (110, 110) (140, 140) holds box"
            ),
        ),
        "1:40",
        "element 'box' can never stand on its step 50 cm: no multiple of it lies between 110 and 140 "
        "cm, across the zones that hold it ('racks')",
    ),
    (
        "step: too large",
        spec(element="element box { shape square size 20..40 at step 2000000 }\n"),
        "1:40",
        "step must be at most 1000000, got 2000000",
    ),
    (
        "wall: a free rotation",
        spec(element="element box { shape square size 20..40 rotation any against wall }\n"),
        "1:40",
        "against a wall, a rotation says which wall the back turns to: give multiples of 90 (0 bottom, "
        "90 right, 180 top, 270 left), not any",
    ),
    (
        "wall: a rotation that names no wall",
        spec(element="element box { shape square size 20..40 rotation 0, 45 against wall }\n"),
        "1:40",
        "against a wall, a rotation says which wall the back turns to: give multiples of 90 (0 bottom, "
        "90 right, 180 top, 270 left), not 45",
    ),
    (
        "wall: zones that reach no wall",
        spec(
            element="element box { shape square size 20..40 against wall }\n",
            arena=ARENA.replace(
                "robot radius 20", "robot radius 20 zone racks rect (100, 100) (400, 400) holds box"
            ),
        ),
        "1:40",
        "element 'box' stands against a wall (rotation 0, 90, 180, 270), and the zones that hold it "
        "('racks') reach none of those walls",
    ),
    (
        "size step: not positive",
        spec(element="element box { shape square size 20..40 step 0 }\n"),
        "1:33",
        "size step must be positive, got 0",
    ),
    (
        "step: given twice",
        spec(element="element box { shape square size 20..40 at step 5 at step 10 }\n"),
        "1:50",
        "duplicate 'at step' in element 'box' (first given at ",
    ),
    (
        "row: listed twice",
        rows(scenario="scenario s on floor { elements line, line }\n"),
        "3:38",
        "row 'line' is listed twice",
    ),
    (
        "row: named as an element",
        rows(row="row box of box { count 2 spacing 5 }\n"),
        "4:1",
        "'box' is already declared at ",
    ),
    (
        "zone: names a row",
        rows(
            arena=ARENA.replace(
                "robot radius 20", "robot radius 20 zone racks rect (0, 0) (900, 700) holds line"
            )
        ),
        "2:115",
        "zone 'racks': 'line' is a row: name its members' type 'box'",
    ),
    (
        "row: a custom rule named as its count",
        rows(
            scenario="scenario s on floor { grammar custom { <s> ::= line | <line-count>\n"
            " <line-count> ::= box } }\n"
        ),
        "4:2",
        "rule <line-count> chooses the count of row 'line', which MazeGen writes: give your rule "
        "another name",
    ),
    (
        "row: suggested for an unknown name",
        rows(scenario="scenario s on floor { elements lin }\n"),
        "3:32",
        "unknown element 'lin' (did you mean 'line'?)",
    ),
    (
        "row: of elements against a wall, at a rotation that names no wall",
        rows(
            element="element box { shape square size 20..40 against wall }\n",
            row="row line of box { count 2 spacing 5 rotation 45 }\n",
        ),
        "4:37",
        "against a wall, a rotation says which wall the back turns to: give multiples of 90 (0 bottom, "
        "90 right, 180 top, 270 left), not 45",
    ),
]


@pytest.mark.parametrize(("name", "text", "where", "fragment"), BAD_SPECS, ids=[row[0] for row in BAD_SPECS])
def test_bad_spec_gives_located_message(write_spec, name, text, where, fragment):
    for file, content in PLUGIN_FILES.items():
        write_spec(content, file)
    path = write_spec(text)
    with pytest.raises(MazeError) as caught:
        load_spec(path)
    message = str(caught.value)
    assert message.startswith(f"{caught.value.filename}:{where}: "), message
    assert caught.value.filename.endswith("spec.maze")
    assert fragment in message
    assert "\n" not in message
    assert len(caught.value.message) < 300  # a huge token is quoted cut


LIBRARY_PLUGIN = "library plug-in 'warehouse' of fake-plugins 1.0"

# (name, what packages register as libraries, text, expected line:col, expected message)
BAD_LIBRARY_PLUGINS = [
    (
        "a library plug-in that is no path",
        [{"warehouse": 3}],
        "import warehouse\n" + spec(),
        "1:1",
        f"{LIBRARY_PLUGIN} gives int, not the path of a .maze file",
    ),
    (
        "a library plug-in naming no file",
        [{"warehouse": "/nonexistent/warehouse.maze"}],
        "import figures\nimport warehouse\n" + spec(),
        "2:1",
        f"{LIBRARY_PLUGIN} gives the path '/nonexistent/warehouse.maze', which is no file",
    ),
    (
        "a library two packages register",
        [{"warehouse": "/a.maze"}, {"warehouse": "/b.maze"}],
        "import warehouse\n" + spec(),
        "1:1",
        "library plug-in 'warehouse' is registered by more than one package (fake-plugins 1.0, "
        "fake-plugins 1.0): uninstall all but one",
    ),
    (
        "an unknown library among registered ones",
        [{"warehouse": "/a.maze"}],
        "import wharehouse\n" + spec(),
        "1:1",
        "unknown library 'wharehouse' (did you mean 'warehouse'?) (bundled: figures, manufacturing; "
        "registered: warehouse; import a file with a quoted path)",
    ),
]


@pytest.mark.parametrize(
    ("name", "registered", "text", "where", "message"),
    BAD_LIBRARY_PLUGINS,
    ids=[row[0] for row in BAD_LIBRARY_PLUGINS],
)
def test_a_bad_library_plugin_gives_a_message_at_the_import(
    write_spec, register_plugins, name, registered, text, where, message
):
    for libraries in registered:
        register_plugins("libraries", libraries)
    path = write_spec(text)
    with pytest.raises(MazeError) as caught:
        load_spec(path)
    assert str(caught.value) == f"{caught.value.filename}:{where}: {message}"
    assert caught.value.filename.endswith("spec.maze")


def test_missing_file_is_reported(tmp_path):
    with pytest.raises(MazeError, match="no such spec file"):
        load_spec(tmp_path / "absent.maze")


@pytest.mark.parametrize(
    ("name", "reason"),
    [("a" * 300 + ".maze", "cannot read spec: File name too long"), ("a\0b", "no such spec")],
)
def test_a_spec_name_the_system_refuses_is_reported(tmp_path, name, reason):
    for read in (check_file, load_spec):
        with pytest.raises(MazeError, match=reason):
            read(tmp_path / name)


@pytest.mark.parametrize("text", ["", "   \n\n", "// only a comment\n"])
def test_a_file_that_declares_nothing_is_reported(write_spec, text):
    path = write_spec(text)
    for read in (check_file, load_spec):
        with pytest.raises(MazeError, match=r"spec\.maze: the file declares nothing \(a spec needs"):
            read(path)


def test_library_without_scenario_checks_but_does_not_load(write_spec):
    path = write_spec(ELEMENT)
    check_file(path)
    with pytest.raises(MazeError, match="no scenario declared"):
        load_spec(path)


def test_imported_file_may_not_hold_a_scenario(write_spec):
    write_spec(spec(), name="other.maze")
    path = write_spec(
        'import "other.maze"\n' + ARENA.replace("floor", "hall") + "scenario t on hall { elements box }\n"
    )
    with pytest.raises(
        MazeError, match="an imported file may declare only elements, rows, arenas and a robot"
    ) as caught:
        load_spec(path)
    assert caught.value.filename.endswith("other.maze")


def test_a_robot_block_may_come_from_an_imported_file_but_a_spec_has_one(write_spec):
    write_spec("robot { speed 40  contact continue }\n", name="robot.maze")
    path = write_spec('import "robot.maze"\n' + spec())
    robot = load_spec(path).robot
    assert robot is not None and (robot.max_speed, robot.contact) == (40, "continue")
    twice = write_spec('import "robot.maze"\n' + spec(tail="robot { speed 30 }\n"), name="twice.maze")
    with pytest.raises(MazeError, match=r"only one robot block per spec \(first at .*twice.maze:") as caught:
        load_spec(twice)
    assert caught.value.filename.endswith("robot.maze")


def test_error_in_imported_file_points_into_that_file(write_spec):
    write_spec("element bad { shape square size 9..1 }\n", name="lib.maze")
    path = write_spec('import "lib.maze"\n' + spec())
    with pytest.raises(MazeError) as caught:
        load_spec(path)
    assert caught.value.filename.endswith("lib.maze")
    assert (caught.value.line, caught.value.col) == (1, 33)


def test_library_check_finds_duplicate_names(write_spec):
    path = write_spec(ELEMENT + ELEMENT)
    with pytest.raises(MazeError, match="'box' is already declared at"):
        check_file(path)

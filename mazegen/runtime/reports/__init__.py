"""What people look at: scenario drawings (SVG, PNG) and the HTML reports of runs, suites
and sweeps.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.reports._render import render_file, rgb, scenario_png, scenario_svg
    from mazegen.runtime.reports._report import read_run, report_html
    from mazegen.runtime.reports._report_folders import folder_report

__all__ = [
    "folder_report",
    "read_run",
    "render_file",
    "report_html",
    "rgb",
    "scenario_png",
    "scenario_svg",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_render": ["render_file", "rgb", "scenario_png", "scenario_svg"],
        "_report": ["read_run", "report_html"],
        "_report_folders": ["folder_report"],
    },
)

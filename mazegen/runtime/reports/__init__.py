"""What people look at: scenario drawings (SVG, PNG) and the HTML reports of runs, suites
and sweeps.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from mazegen.runtime.reports.render import render_file, scenario_png, scenario_svg
from mazegen.runtime.reports.report import read_run, report_html
from mazegen.runtime.reports.report_folders import folder_report

__all__ = ["folder_report", "read_run", "render_file", "report_html", "scenario_png", "scenario_svg"]

"""Figures and the HTML report of a results file; the report's tables of joints
(:func:`joint_table`, :func:`static_joint_table`) and loads (:func:`load_rows`)."""

from ..interface import OPEN_CRACK_MIN_M
from ._plots import (
    plot_all,
    plot_energy,
    plot_joint,
    plot_probe,
    plot_rigid,
    plot_spectrum,
    plot_states,
    plot_static,
)
from ._report import (
    joint_table,
    load_rows,
    per_thickness,
    plot_run,
    solver_line,
    static_joint_table,
    write_report,
)

__all__ = ["OPEN_CRACK_MIN_M", "joint_table", "load_rows", "per_thickness", "plot_all",
           "plot_energy",
           "plot_joint", "plot_probe", "plot_rigid", "plot_run", "plot_spectrum",
           "plot_states", "plot_static", "solver_line", "static_joint_table",
           "write_report"]  # fmt: skip
from ._study import plot_fragility, plot_ida, save_figure

__all__ += ["plot_fragility", "plot_ida", "save_figure"]

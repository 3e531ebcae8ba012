"""pfeie: partitioned finite element / interface element dynamics of jointed structures.

The public API is flat; the subpackages mirror the method:

- :mod:`pfeie.mesh` — meshes and structured generators;
- :mod:`pfeie.element` — reference elements and quadrature;
- :mod:`pfeie.assembly` — vectorised element kernels and sparse assembly;
- :mod:`pfeie.model` — physics objects (materials, blocks, joints, supports, loads, ground
  motion) and the model;
- :mod:`pfeie.linalg` — sparse direct factorisations;
- :mod:`pfeie.interface` — cutting blocks apart, point pairs, joint laws, pair states and
  the interface solver;
- :mod:`pfeie.coupling` — the operators that couple blocks and pairs: G, the Delassus
  operator W, the static and the one-step interface problems;
- :mod:`pfeie.solvers` — statics, modal analysis, the yield coefficient, the factor of
  safety by strength reduction;
- :mod:`pfeie.dynamics` — Newmark / HHT-α time integration and the PFE/IE analysis.

A whole analysis:

>>> import pfeie as pf
>>> mesh = pf.rectangle(10.0, 1.0, 40, 4, cell="quad8")
>>> model = pf.Model(mesh, [pf.Block("all", pf.Elastic(E=30e9, nu=0.2, rho=2400))])
>>> model.fix("xmin")
>>> model.add_gravity()
>>> tip = pf.solve_static(model).u[model.nearest_node([10.0, 0.5]), 1]
>>> bool(tip < 0)
True
"""

from ._job import run_to_folder
from ._version import __version__
from .dynamics import Dynamic, DynamicResult, DynamicSettings, History, Newmark, RunStopped, State
from .errors import (
    InterfaceError,
    MechanismError,
    MeshError,
    ModelError,
    PfeieError,
    SolverError,
)  # fmt: skip
from .interface import Joint, JointLaw, MohrCoulomb, SlipWeakening, SolverSettings, Strength
from .io import read_mesh, read_record
from .mesh import Mesh, box, graded, rectangle
from .model import Block, Elastic, GroundMotion, Interface, Model, Rayleigh, Reservoir
from .solvers import (
    ModalResult,
    StaticResult,
    StrengthReduction,
    YieldCoefficient,
    factorize,
    modal,
    solve_static,
    strength_reduction,
    yield_coefficient,
)
from .study import Study, StudyTable

# No NullHandler on the package's logger: a Python user who has not configured logging
# then sees its warnings (a joint's strength that never acts, implausible units, a
# mechanism) on stderr through Python's last-resort handler, WARNING and above only;
# ``logging.getLogger("pfeie").setLevel(logging.ERROR)`` silences them

__all__ = [
    "Block", "Dynamic", "DynamicResult", "DynamicSettings", "Elastic", "GroundMotion", "History",
    "Interface", "InterfaceError", "Joint", "JointLaw", "MechanismError", "Mesh", "MeshError",
    "ModalResult", "Model", "ModelError", "MohrCoulomb", "Newmark", "PfeieError", "Rayleigh",
    "Reservoir", "RunStopped", "SlipWeakening", "SolverError", "SolverSettings", "State",
    "StaticResult", "Strength", "StrengthReduction", "Study", "StudyTable", "YieldCoefficient",
    "__version__", "box", "factorize", "graded", "modal", "read_mesh", "read_record", "rectangle",
    "run_to_folder", "solve_static", "strength_reduction", "yield_coefficient",
]  # fmt: skip

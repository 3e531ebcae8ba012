"""Typed exceptions of pfeie.

Every error that a user can cause derives from :class:`PfeieError`, so that a driver
(the command line, a batch over many records) can tell a modelling mistake from a bug.
"""

from __future__ import annotations


class PfeieError(Exception):
    """Base class of all errors raised by pfeie on purpose."""


class MeshError(PfeieError):
    """A mesh is malformed, or names a group it does not have."""


class MeshArgumentError(MeshError, ValueError):
    """An argument of a mesh generator out of its range (a size <= 0, a count < 1): both a
    :class:`MeshError` and a :class:`ValueError`."""


class ModelError(PfeieError):
    """A model is inconsistent: unknown group, bad material, bad load or support."""


class SettingsError(ModelError, ValueError):
    """A field of typed settings (:class:`pfeie.DynamicSettings`, :class:`pfeie.SolverSettings`)
    out of its range, of the wrong type, or unknown: both a :class:`ModelError` and a
    :class:`ValueError`."""


class MechanismError(PfeieError):
    """The stiffness is singular: some part of the model can move without resistance."""


class SolverError(PfeieError):
    """A linear or eigenvalue solver failed or is unavailable."""


class InterfaceError(PfeieError):
    """The interface problem of a step did not converge (the message names the step,
    the pairs that kept changing state and the residual). ``pairs``: the indices of the
    pairs the message names (the model's numbering of its pairs), most telling first, for
    a caller that knows the model to say where they are."""

    def __init__(self, message: str, pairs: tuple[int, ...] = ()) -> None:
        super().__init__(message)
        self.pairs = pairs


class RecordError(PfeieError):
    """A ground-motion record file is missing, malformed or inconsistent."""


class InputError(PfeieError):
    """A model file is invalid: the message names the file, the key path, what was
    expected and what was found."""


class ResultsError(PfeieError):
    """A results file is missing, is not a pfeie results file, or holds nothing for the
    asked output (the message names the file and what was expected)."""

"""Joint laws: the strength of the pairs of an interface (method.md §4).

A joint law is a class behind the :class:`JointLaw` protocol. The interface solver never
sees a law class: it asks the :class:`PairLaws` of the model, which gathers the laws of
all interfaces into per-pair arrays, for the *strength* of every pair in its current
state (intact or broken, and the slip path so far):

    τ_max = c A + μ X_n        (shear, X_n the normal force, compression positive)
    X_n ≥ −σ_t A               (tension cut-off)

with (c, μ, σ_t) the intact values until the pair breaks and the residual values after.
States, breaking and the friction cone are the solver's; *how strong* a pair is belongs to
its law. A new law is a new class with a ``strength`` method (and the contact data that
every law has: initial state, joint stiffness, initial gap); neither the solver nor the
time stepping changes.

Laws shipped:

- :class:`MohrCoulomb` (alias :class:`Joint`): cohesion, friction and tensile strength,
  residual values after breaking;
- :class:`SlipWeakening`: as Mohr-Coulomb, with the friction coefficient of a broken
  pair falling linearly from its peak tan φ to its residual tan φ_r over a slip distance
  D_c (Ida 1972; Andrews 1976),

      μ(δ) = μ_r + (μ_p − μ_r) max(0, 1 − δ/D_c),

  δ the slip path (m). The time stepping asks for the strength of a step at the path
  predicted for its end from the slip rate at its start (second order in the path).

Units: SI (Pa, m, N), angles in degrees.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields, is_dataclass, replace
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import ModelError
from ..typing import BoolArray, FloatArray, IntArray
from ._state import PairState


@dataclass(frozen=True)
class Strength:
    """Strength of each pair (m,): cohesion force c A (N), friction coefficient μ and
    tensile force σ_t A (N)."""

    cohesion: FloatArray
    friction: FloatArray
    tension: FloatArray


@runtime_checkable
class JointLaw(Protocol):
    """What the analysis needs from a joint law: its contact data and the strength of
    its pairs (the module docstring gives the strength criterion).

    - ``initial``, ``kn``, ``ks``, ``gap``: read once, when the model is built (a later
      change has no effect), and checked then (:func:`check_law`);
    - ``strength(area, broken, path)``: (c A, μ, σ_t A) of k pairs, each (k,), finite and
      ≥ 0 with σ_t A μ ≤ c A (checked at every call, :class:`~pfeie.ModelError` naming
      the law otherwise), from the pairs' tributary areas in m² (× the thickness in 2D),
      their broken flags and their slip paths in m (the distance slid since the start,
      the path predicted for the end of the step, so that a slip-weakening law is second
      order in Δt). It must be a pure function of its arguments: the answers are cached
      per state within a step, and the time stepping multiplies the forces by Δt itself
      where it works with impulses.

    The law sees no normal stress, closure, slip rate or time, and its stiffness is one
    constant: a stiffness that grows with closure (Barton–Bandis) or a rate-dependent
    friction cannot be written as a law yet. A law of one's own works in the Python API
    (:class:`pfeie.Interface`); model files and studies name the shipped laws only
    (``mohr-coulomb``, ``slip-weakening``), and the results file records its class, its
    contact data and its fields.

    >>> import numpy as np, pfeie as pf
    >>> class Frictional:                      # μ = 0.5, no cohesion, no tension
    ...     initial, kn, ks, gap = "broken", None, None, 0.0
    ...     def strength(self, area, broken, path):
    ...         zero = np.zeros_like(area)
    ...         return pf.Strength(zero, np.full_like(area, 0.5), zero)
    >>> isinstance(Frictional(), JointLaw)
    True
    """

    @property
    def initial(self) -> str:
        """'intact' (bonded until its strength is exceeded) or 'broken'."""
        ...

    @property
    def kn(self) -> float | None:
        """Normal stiffness of a weak layer (Pa/m), None for a rigid contact."""
        ...

    @property
    def ks(self) -> float | None:
        """Shear stiffness of a weak layer (Pa/m), None for a rigid contact."""
        ...

    @property
    def gap(self) -> float:
        """Initial normal gap (m)."""
        ...

    def strength(self, area: FloatArray, broken: BoolArray, path: FloatArray) -> Strength:
        """Strength of pairs of tributary area ``area`` (m²), broken flags ``broken`` and
        slip paths ``path`` (m), all (k,)."""
        ...


_PROTOCOL = ("initial", "kn", "ks", "gap", "strength")


def check_law(law: Any, where: str = "") -> None:
    """Raise :class:`ModelError` unless ``law`` is a joint law with valid contact data
    (what the solver reads once, when the model is built): ``initial`` 'intact' or
    'broken'; ``kn``, ``ks`` None or a number ≥ :data:`JOINT_STIFFNESS_MIN` Pa/m; ``gap``
    a number ≥ 0 m, 0 for an intact joint; ``strength`` a method. ``where`` (an interface)
    leads the message. The built-in laws check the same in their constructors; this
    names what a law of one's own gets wrong.

    >>> check_law(MohrCoulomb(phi=30.0))
    >>> class Soft:                       # a law of one's own, with a zero stiffness
    ...     initial, kn, ks, gap = "broken", 0.0, None, 0.0
    ...     def strength(self, area, broken, path): ...
    >>> check_law(Soft(), "interface 'base'")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pfeie.errors.ModelError: interface 'base': joint law Soft: kn: expected None (a rigid ...
    """
    head = f"{where}: " if where else ""
    name = f"joint law {type(law).__name__}"
    missing = [k for k in _PROTOCOL if not hasattr(law, k)]
    if missing:
        raise ModelError(f"{head}{name} lacks {', '.join(missing)} of the joint-law protocol "
                         "(pfeie.interface.JointLaw: initial, kn, ks, gap and strength(area, "
                         "broken, path) -> Strength); e.g. pf.Joint(phi=30.0)")  # fmt: skip
    if not callable(law.strength):
        raise ModelError(f"{head}{name}: strength must be a method strength(area, broken, "
                         "path) -> Strength")  # fmt: skip

    def number(v: object) -> bool:
        return (isinstance(v, int | float | np.integer | np.floating)
                and not isinstance(v, bool | np.bool_) and bool(np.isfinite(v)))  # fmt: skip

    def got(v: object) -> str:
        return f"{type(v).__name__} {v!r}"

    initial = law.initial
    if not isinstance(initial, str) or initial not in ("intact", "broken"):
        raise ModelError(f"{head}{name}: initial: expected 'intact' or 'broken', got "
                         f"{got(initial)}")  # fmt: skip
    for key in ("kn", "ks"):
        v = getattr(law, key)
        if v is not None and not (number(v) and v >= JOINT_STIFFNESS_MIN):
            raise ModelError(f"{head}{name}: {key}: expected None (a rigid contact) or a "
                             f"number >= {JOINT_STIFFNESS_MIN:g} Pa/m, got {got(v)}")  # fmt: skip
    gap = law.gap
    if not (number(gap) and gap >= 0):
        raise ModelError(f"{head}{name}: gap: expected a number >= 0 (m), got {got(gap)}")
    if gap > 0 and initial == "intact":
        raise ModelError(f"{head}{name}: gap = {gap:g} m on an intact (bonded) joint; "
                         "expected gap = 0, or initial = 'broken'")  # fmt: skip


def law_fields(law: object) -> dict[str, Any]:
    """A joint law's fields, what determines its strength besides its class: a
    dataclass's fields, else its instance attributes (and slots), name → value."""
    import dataclasses

    if dataclasses.is_dataclass(law):
        return {f.name: getattr(law, f.name) for f in dataclasses.fields(law)}
    out = dict(getattr(law, "__dict__", {}))
    for cls in type(law).__mro__:
        for name in getattr(cls, "__slots__", ()):
            if hasattr(law, name):
                out.setdefault(name, getattr(law, name))
    return out


def law_key(law: Any) -> bytes:
    """What identifies a joint law, for digests: its class (module and name), its contact
    data and its fields (:func:`law_fields`; arrays by dtype, shape and bytes, a nested
    law by its own key, other values by repr, an object whose repr holds its address by
    its class). Deterministic: the same law built again gives the same bytes, where
    ``repr`` of a class of one's own holds its address."""
    parts = [f"{type(law).__module__}.{type(law).__qualname__}",
             repr((law.initial, law.kn, law.ks, law.gap))]  # fmt: skip
    for k, v in sorted(law_fields(law).items()):
        if callable(v) and not hasattr(v, "strength"):
            continue
        parts.append(f"{k}={_value_key(v)}")
    return "\0".join(parts).encode()


def _value_key(v: object) -> str:
    """A field's value for :func:`law_key`, the same in every process: an array by dtype,
    shape and bytes; a nested law by its key; a set by its sorted elements and a mapping
    by its sorted items (their repr follows the hash seed); a list or tuple element by
    element, a dataclass field by field; else its repr, or its class where the repr holds
    its address."""
    if isinstance(v, np.ndarray):
        a = np.ascontiguousarray(v)
        return f"{a.dtype.str}{a.shape}:{a.tobytes().hex()}"
    if hasattr(v, "strength") and hasattr(v, "initial"):
        return f"<{law_key(v).decode()}>"
    if isinstance(v, set | frozenset):
        return "{" + ", ".join(sorted(_value_key(x) for x in v)) + "}"
    if isinstance(v, dict):
        items = sorted(f"{_value_key(a)}: {_value_key(b)}" for a, b in v.items())
        return "{" + ", ".join(items) + "}"
    if isinstance(v, list | tuple):
        return type(v).__name__ + "(" + ", ".join(_value_key(x) for x in v) + ")"
    if is_dataclass(v) and not isinstance(v, type):
        # field by field (a frozenset inside: its repr follows the hash seed)
        parts = ", ".join(f"{f.name}={_value_key(getattr(v, f.name))}" for f in fields(v))
        return f"{type(v).__qualname__}({parts})"
    r = repr(v)
    return type(v).__qualname__ if " at 0x" in r else r


def _checked(st: object, k: int, law: object, where: str,
             held: BoolArray | None = None) -> tuple[FloatArray, ...]:  # fmt: skip
    """The arrays (c A, μ, σ_t A), each (k,), of a law's answer ``st`` to
    :meth:`JointLaw.strength`, checked: a :class:`Strength` of finite values ≥ 0 whose
    tension lies within the apex of the cone, σ_t A μ ≤ c A (an intact or broken pair in
    tension beyond it would have no shear capacity), on the pairs ``held`` (k,) (default
    all): those that can hold the strength asked, not the intact strength of a pair of a
    joint that starts broken (asked with the others, never used; a model file's or
    :class:`MohrCoulomb`'s tensile strength of an existing joint is not checked either).
    Else :class:`ModelError` naming the law, the field and the first bad value."""
    head = f"{where}joint law {type(law).__name__}: strength(area, broken, path)"
    fields = ("cohesion", "friction", "tension")
    if not all(hasattr(st, f) for f in fields):
        raise ModelError(f"{head} returned {type(st).__name__}; expected a "
                         "pfeie.interface.Strength(cohesion, friction, tension)")  # fmt: skip
    out = []
    for f, unit in zip(fields, ("N: c A", "-: μ", "N: σ_t A"), strict=True):
        a = np.asarray(getattr(st, f), dtype=float)
        if a.shape != (k,):
            raise ModelError(f"{head}: {f} has shape {a.shape}; expected ({k},), one value "
                             "a pair")  # fmt: skip
        bad = np.flatnonzero(~(np.isfinite(a) & (a >= 0.0)))
        if bad.size:
            raise ModelError(f"{head}: {f} ({unit}) must be finite and >= 0; got "
                             f"{float(a[bad[0]])!r} at {bad.size} of its {k} pairs")  # fmt: skip
        out.append(a)
    c, mu, t = out
    if isinstance(law, Reduced):  # F < 1 moves the apex (t μ / F² against c / F): the
        return c, mu, t  # law inside was held to it
    over = t * mu > c * (1.0 + 1e-12) + 1e-300
    beyond = np.flatnonzero(over if held is None else over & held)
    if beyond.size:
        j = beyond[0]
        raise ModelError(f"{head}: tension {t[j]:g} N lies beyond the apex of the cone, "
                         f"cohesion / friction = {c[j]:g} / {mu[j]:g} N, at {beyond.size} "
                         "pair(s): a pair in tension there has no shear capacity; expected "
                         "tension * friction <= cohesion")  # fmt: skip
    return c, mu, t


#: m, the least normal opening of a pair that counts as a crack: in the open share, the
#: open crack (``max_open_length_m``, ``max_open_area_m2``) and the joint figures of a run,
#: and in a joint's sliding safety factor, whose capacity keeps the c A of the pairs open
#: by less (:meth:`PairLaws.safety_factor`). 0.01 mm, the resolution of the printed
#: maximum opening: a pair with no contact force but an opening below it (round-off, the
#: micro-gaps of the corner nodes of quadratic faces, 1e-8 to 1e-7 m, or the free end of a
#: joint) is not a crack.
OPEN_CRACK_MIN_M = 1e-5


#: Pa/m, the least normal or shear stiffness of a weak layer: 1 m of closure under 1 Pa.
#: No joint is that soft; below it the compliance 1/k overflows the pair operators.
JOINT_STIFFNESS_MIN = 1.0

FS_ROUNDOFF = 1e-10
"""A joint's shear force counts for its safety factor above FS_ROUNDOFF times the sum of
the magnitudes of its own pair forces (smooth and step forces, static ones): below, it
is round-off (a pair closed by an impulse within the step has a smooth force of 1e-16 to
1e-20 of its step force; a frictionless joint between blocks at rest carried 8e-12 of
its normal force in a static state), and the ratio would be round-off too."""


#: κ: the normal force over which a broken pair's residual cohesion is mobilised, as a
#: fraction of its cohesion force c A (:func:`cohesion_ramp`)
COHESION_RAMP = 1e-3


def cohesion_ramp(
    c: FloatArray, mu: FloatArray, t: FloatArray, Xn: FloatArray, broken: BoolArray
) -> tuple[BoolArray, FloatArray, FloatArray]:
    r"""The shear capacity of broken pairs about to part, with their residual cohesion
    mobilised smoothly with the normal force, all arrays (m,) in N (c = c A, t = σ_t A,
    forces at the rate level of the problem: forces or impulses):

    .. math::

        τ = μ (X_n + t) + \tilde c\,(2u − u^2),\quad u = \frac{X_n + t}{κ \tilde c},
        \quad \tilde c = c − μ t \quad \text{for } 0 < u < 1
        \quad (κ = \texttt{COHESION_RAMP}),

    0 for u ≤ 0 (the pair parts), and τ = c + μ X_n = c̃ + μ (X_n + t) for u ≥ 1 (the
    Mohr–Coulomb cone; c̃ is its radius at the tension cut-off X_n = −t, which a law keeps
    short of the cone's apex: t ≤ c/μ, :class:`MohrCoulomb`). Without a residual tensile
    strength (t = 0, the default) τ = μ X_n + c (2u − u²), u = X_n/(κ c). Without it the
    capacity of a broken pair with a residual cohesion jumps from c̃, while it touches,
    to 0 once it parts (X_n < −t), and a pair that would touch with no
    normal force while carrying shear has no state of the law: stuck, it pulls; open, it
    penetrates; the discrete problem then has no solution over a band of loads
    (measured: a block pushed horizontally on a cohesive joint, every static analysis of
    the band 0.498 ≤ k_h ≤ 0.565 failed). With the ramp the capacity is continuous and
    such a pair carries its shear on a normal force within κ c̃ of the cut-off; the strength
    of every pair loaded beyond (10⁻³ of the cohesion) is untouched. The ramp's slope,
    2/κ + μ where the pair parts, falls to μ where it meets the cone c + μ X_n, so that the
    cone radius is C¹ in X_n there: with a straight ramp (slope 1/κ, then μ) the 3D Newton
    stalled at the corner, stepping from one piece to the other (docs/theory.md).

    Returns the mask of the pairs on the ramp (broken, c̃ > 0, X_n + t < κ c̃), their
    capacity (≥ 0) and its slope dτ/dX_n there (0 where X_n + t ≤ 0), zero elsewhere.

    >>> on, tau, slope = cohesion_ramp(np.array([100.0, 100.0, 0.0]), np.ones(3),
    ...                                np.zeros(3), np.array([0.05, 1.0, 0.0]),
    ...                                np.ones(3, dtype=bool))
    >>> on.tolist(), tau.tolist(), slope.tolist()   # u = 0.5: 0.05 + 100 · 0.75
    ([True, False, False], [75.05, 0.0, 0.0], [1001.0, 0.0, 0.0])
    """
    if not c.any():  # no cohesion (the default residual strength): nothing on the ramp
        none = np.zeros_like(Xn)
        return np.zeros(Xn.shape, dtype=bool), none, none
    k = COHESION_RAMP
    y = Xn + t  # the normal force above the tension cut-off
    ct = c - mu * t  # the cone's radius at the cut-off (c without tensile strength)
    on = np.asarray(broken & (ct > 0) & (y < k * ct))
    if not on.any():
        return on, np.zeros_like(Xn), np.zeros_like(Xn)
    u = np.where(on, y, 0.0) / np.where(on, k * ct, 1.0)
    tau = np.where(on, np.maximum(mu * y + ct * u * (2.0 - u), 0.0), 0.0)
    slope = np.where(on & (y > 0), mu + 2.0 * (1.0 - u) / k, 0.0)
    return on, tau, slope


def cone(
    c: FloatArray, mu: FloatArray, t: FloatArray, Xn: FloatArray, broken: BoolArray
) -> tuple[FloatArray, FloatArray]:
    """The radius τ (m,) of each pair's Mohr-Coulomb cone at its normal force X_n
    (compression +) and its slope dτ/dX_n: max(0, c + μ X_n) (friction in tension too: an
    intact pair holds c − μ σ_t ≥ 0 at its tensile strength), μ where the cone is open; on
    the residual cohesion's ramp, :func:`cohesion_ramp`'s curve and slope. All arrays in
    N at the rate level of the problem (c = c A, t = σ_t A). The one home of the cone that
    the pair solvers, the residual and :meth:`PairLaws.cone` take.

    >>> c, mu, t = np.array([10.0, 0.0]), np.array([1.0, 0.5]), np.zeros(2)
    >>> tau, slope = cone(c, mu, t, np.array([-4.0, -2.0]), np.zeros(2, dtype=bool))
    >>> tau.tolist(), slope.tolist()
    ([6.0, 0.0], [1.0, 0.0])
    """
    tau = np.maximum(c + mu * Xn, 0.0)
    slope = np.where(tau > 0, mu, 0.0)
    ramp, tau_ramp, ramp_slope = cohesion_ramp(c, mu, t, Xn, broken)
    if ramp.any():
        tau = np.where(ramp, tau_ramp, tau)
        slope = np.where(ramp, ramp_slope, slope)
    return tau, slope


def cohesion_ramp_tangent(
    c: FloatArray, mu: FloatArray, t: FloatArray, Xn: FloatArray, broken: BoolArray
) -> tuple[BoolArray, FloatArray, FloatArray]:
    r"""The tangent τ ≈ c_l + μ_l X_n of :func:`cohesion_ramp`'s capacity at X_n, for the
    linear state systems (a sliding pair's X_t = −(c_l + μ_l X_n) ŝ), all arrays (m,):
    where the pair parts (X_n + t ≤ 0), the ramp's start, c_l = 2t/κ and
    μ_l = μ [X_n > 0] + 2/κ. Returns the ramp's mask and (c_l, μ_l), zero off it.

    >>> on, cl, ml = cohesion_ramp_tangent(np.array([100.0]), np.ones(1), np.zeros(1),
    ...                                    np.array([0.05]), np.ones(1, dtype=bool))
    >>> round(float(cl[0] + ml[0] * 0.05), 12)   # the capacity 75.05 at the point
    75.05
    """
    on, tau, slope = cohesion_ramp(c, mu, t, Xn, broken)
    if not on.any():
        return on, tau, slope
    k = COHESION_RAMP
    start = on & (Xn + t <= 0)
    mu_l = np.where(start, mu * (Xn > 0) + 2.0 / k, slope)
    c_l = np.where(start, 2.0 * t / k, tau - slope * Xn)
    return on, np.where(on, c_l, 0.0), np.where(on, mu_l, 0.0)


#: the model file's keys of ``[interfaces.<name>]`` and the Python API's names for them
MODEL_FILE_KEYS = {
    "cohesion": "c", "friction_angle": "phi", "tensile_strength": "tensile",
    "residual_cohesion": "c_r", "residual_friction_angle": "phi_r",
    "residual_tensile_strength": "tensile_r", "normal_stiffness": "kn",
    "shear_stiffness": "ks",
}  # fmt: skip


@dataclass(frozen=True)
class MohrCoulomb:
    """Mohr-Coulomb joint with a tension cut-off and residual strength.

    Parameters (SI; angles in degrees):

    - ``c`` cohesion (Pa), ``phi`` friction angle, ``tensile`` tensile strength σ_t (Pa):
      the strength of an intact (bonded) pair;
    - ``c_r``, ``phi_r``, ``tensile_r``: residual values once broken (defaults 0, ``phi``,
      0); an existing joint (``initial="broken"``) has only these;
    - ``initial``: "intact" (bonded until its strength is exceeded) or "broken";
    - ``kn``, ``ks``: optional normal and shear stiffness (Pa/m) of a weak layer; None
      means a rigid contact (no spring, no penetration);
    - ``gap``: initial normal gap (m) of an existing (broken) joint: its pairs start open
      and close when the gap is used up (e.g. a bar moving towards a wall).

    Stresses are X/A with X the force on side b, normal positive in compression. An
    intact pair breaks when σ < −σ_t (opens) or |τ| > c + σ tan φ (slides).

    >>> law = MohrCoulomb(c=1e5, phi=45.0, initial="intact")
    >>> st = law.strength(np.array([2.0]), np.array([False]), np.zeros(1))
    >>> float(st.cohesion[0]), round(float(st.friction[0]), 12)   # N, -
    (200000.0, 1.0)
    >>> Joint(phi=30.0).mu_r
    0.5773502691896257
    """

    c: float = 0.0
    phi: float = 30.0
    tensile: float = 0.0
    c_r: float = 0.0
    phi_r: float | None = None
    tensile_r: float = 0.0
    initial: str = "broken"
    kn: float | None = None
    ks: float | None = None
    gap: float = 0.0

    def __new__(cls, *args: object, **kwargs: object) -> MohrCoulomb:
        """A keyword of the model file's ``[interfaces.<name>]`` (``cohesion``, ...) is
        refused with the Python API's name for it, before the bare ``TypeError`` of an
        unknown keyword."""
        for key in kwargs:
            if key in MODEL_FILE_KEYS:
                name = "Joint" if cls is MohrCoulomb else cls.__name__
                raise ModelError(
                    f"{name}: {key!r} is the model file's name; the Python "
                    f"keyword is {MODEL_FILE_KEYS[key]!r} (c, phi, tensile, c_r, phi_r, "
                    "tensile_r, initial, kn, ks, gap; Pa, degrees, Pa/m, m)"
                )  # fmt: skip
        return super().__new__(cls)

    def __post_init__(self) -> None:
        name = "Joint" if type(self) is MohrCoulomb else type(self).__name__
        for key, unit, none in (("c", "Pa", False), ("phi", "degrees", False),
                                ("tensile", "Pa", False), ("c_r", "Pa", False),
                                ("phi_r", "degrees", True), ("tensile_r", "Pa", False),
                                ("kn", "Pa/m", True), ("ks", "Pa/m", True),
                                ("gap", "m", False)):  # fmt: skip
            v = getattr(self, key)
            if v is None and none:
                continue
            if not (isinstance(v, int | float | np.integer | np.floating)
                    and not isinstance(v, bool) and np.isfinite(v)):  # fmt: skip
                raise ModelError(f"{name}: {key}: expected a finite number ({unit})"
                                 f"{' or None' if none else ''}, got {type(v).__name__} "
                                 f"{v!r}")  # fmt: skip
        for key in ("c", "tensile", "c_r", "tensile_r"):
            if not getattr(self, key) >= 0:
                raise ModelError(f"joint {key} must be >= 0 Pa, got {getattr(self, key)}")
        for key in ("phi", "phi_r"):
            val = getattr(self, key)
            if val is not None and not 0 <= val < 90:
                raise ModelError(f"joint {key} must lie in [0, 90) degrees, got {val}")
        if self.initial not in ("intact", "broken"):
            raise ModelError(f"joint initial must be 'intact' or 'broken', got {self.initial!r}")
        for key in ("kn", "ks"):
            val = getattr(self, key)
            if val is not None and not val >= JOINT_STIFFNESS_MIN:
                raise ModelError(
                    f"joint {key} must be >= {JOINT_STIFFNESS_MIN:g} Pa/m "
                    f"(1 m of closure under 1 Pa) or None, got {val}"
                )
        if not self.gap >= 0:
            raise ModelError(f"joint gap must be >= 0 m, got {self.gap}")
        if self.gap > 0 and self.initial == "intact":
            raise ModelError("an intact (bonded) joint cannot start with a gap")
        self._check_residual_apex()
        if self.initial == "intact" and self.tensile * self.mu > self.c * (1.0 + 1e-12):
            apex = self.c / self.mu
            raise ModelError(
                f"joint tensile = {self.tensile:g} Pa lies beyond the apex of the intact "
                f"strength, c / tan φ = {apex:g} Pa (c = {self.c:g} Pa, φ = {self.phi:g}°): "
                "an intact pair in tension beyond it has no shear capacity; expected "
                f"tensile <= {apex:g} Pa (0 without cohesion)"
            )

    def _check_residual_apex(self) -> None:
        """A residual tensile strength beyond the apex of the residual cone, c_r/μ, would
        leave a broken pair in tension with no shear capacity: refused (:data:`ModelError`,
        naming both). The largest friction a broken pair has is :attr:`_broken_mu_max`."""
        mu, name = self._broken_mu_max
        if self.tensile_r * mu > self.c_r * (1.0 + 1e-12):
            apex = self.c_r / mu
            raise ModelError(
                f"joint tensile_r = {self.tensile_r:g} Pa lies beyond the apex of the "
                f"residual strength, c_r / {name} = {apex:g} Pa (c_r = {self.c_r:g} Pa, "
                f"{name} = {mu:.4g}): a broken pair in tension beyond it has no shear "
                f"capacity; expected tensile_r <= {apex:g} Pa (0 without residual cohesion)"
            )

    @property
    def _broken_mu_max(self) -> tuple[float, str]:
        """The largest friction coefficient of a broken pair, μ_r, and its name."""
        return self.mu_r, "tan φ_r"

    @property
    def mu(self) -> float:
        """Friction coefficient of the intact joint, tan φ."""
        return float(np.tan(np.radians(self.phi)))

    @property
    def mu_r(self) -> float:
        """Residual friction coefficient, tan φ_r."""
        return float(np.tan(np.radians(self.phi if self.phi_r is None else self.phi_r)))

    def residual_friction(self, path: FloatArray) -> FloatArray:
        """Friction coefficient of broken pairs with slip path ``path`` (m): μ_r."""
        return np.full(path.shape, self.mu_r)

    def strength(self, area: FloatArray, broken: BoolArray, path: FloatArray) -> Strength:
        """(c A, μ, σ_t A) of each pair for its broken flag (N, -, N)."""
        c = np.where(broken, self.c_r, self.c) * area
        mu = np.where(broken, self.residual_friction(path), self.mu)
        t = np.where(broken, self.tensile_r, self.tensile) * area
        return Strength(c, mu, t)


Joint = MohrCoulomb
"""The default joint law: Mohr-Coulomb with a tension cut-off (:class:`MohrCoulomb`)."""


@dataclass(frozen=True)
class Reduced:
    """A joint law whose strength is another's divided by a factor F > 0: cohesion,
    friction coefficient and tensile strength, intact and residual alike,

        c/F,  tan φ / F,  σ_t/F,

    the reduction of a strength-reduction analysis (Dawson, Roth and Drescher 1999;
    Griffiths and Lane 1999): the least F at which the structure loses its static
    equilibrium is its factor of safety against sliding. The contact data (initial state,
    springs, gap) are the law's own.

    >>> law = Reduced(MohrCoulomb(c=1e5, phi=45.0, initial="intact"), 2.0)
    >>> st = law.strength(np.array([1.0]), np.array([False]), np.zeros(1))
    >>> float(st.cohesion[0]), round(float(st.friction[0]), 12)   # N, -
    (50000.0, 0.5)
    """

    law: JointLaw
    factor: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.factor) and self.factor > 0):
            raise ModelError(f"a strength reduction factor must be > 0, got {self.factor}")

    @property
    def initial(self) -> str:
        return self.law.initial

    @property
    def kn(self) -> float | None:
        return self.law.kn

    @property
    def ks(self) -> float | None:
        return self.law.ks

    @property
    def gap(self) -> float:
        return self.law.gap

    def strength(self, area: FloatArray, broken: BoolArray, path: FloatArray) -> Strength:
        """The law's (c A, μ, σ_t A) divided by the factor (N, -, N)."""
        st = self.law.strength(area, broken, path)
        f = self.factor
        return Strength(st.cohesion / f, st.friction / f, st.tension / f)


@dataclass(frozen=True)
class SlipWeakening(MohrCoulomb):
    """Linear slip-weakening friction (Ida 1972; Andrews 1976).

    As :class:`MohrCoulomb`, except that the friction coefficient of a broken pair falls
    from its peak μ_p = tan ``phi`` to its residual μ_r = tan ``phi_r`` over the slip
    distance ``dc`` (m):

        μ(δ) = μ_r + (μ_p − μ_r) max(0, 1 − δ/D_c),

    δ the slip path of the pair (m). An intact pair breaks on the peak strength, as a
    Mohr-Coulomb pair, then weakens as it slips.

    >>> law = SlipWeakening(phi=40.0, phi_r=30.0, dc=0.01)
    >>> mu = law.residual_friction(np.array([0.0, 0.005, 0.02]))
    >>> [round(float(x), 4) for x in mu]     # tan 40°, halfway, tan 30°
    [0.8391, 0.7082, 0.5774]
    """

    dc: float = 0.01

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (np.isfinite(self.dc) and self.dc > 0):
            raise ModelError(f"slip-weakening distance dc must be > 0 m, got {self.dc}")
        if self.phi_r is None:
            raise ModelError("slip weakening needs a residual friction angle phi_r")
        if self.phi_r > self.phi:
            raise ModelError(f"slip weakening: phi_r = {self.phi_r:g}° exceeds phi = "
                             f"{self.phi:g}°: the friction would harden with slip; expected "
                             "phi_r <= phi (the residual angle is the weakened one)")  # fmt: skip

    def _check_residual_apex(self) -> None:
        if self.phi_r is not None:  # (else refused above)
            super()._check_residual_apex()

    @property
    def _broken_mu_max(self) -> tuple[float, str]:
        """A broken pair starts at the peak friction μ_p = tan φ."""
        return max(self.mu, self.mu_r), "tan φ (the peak)"

    def residual_friction(self, path: FloatArray) -> FloatArray:
        mu_p, mu_r = self.mu, self.mu_r
        return np.asarray(mu_r + (mu_p - mu_r) * np.maximum(0.0, 1.0 - path / self.dc))


@dataclass(frozen=True)
class PairLaws:
    """The laws of all pairs of a model as per-pair arrays (what the solver sees).

    ``area`` (m,) tributary area (m², × thickness in 2D); ``compliance`` (m, d) joint
    compliance 1/(k A) in m/N (0 for rigid contact); ``gap`` (m,) initial gap (m);
    ``initially_broken`` (m,); ``laws`` with the pair indices ``index`` of each.
    """

    area: FloatArray
    compliance: FloatArray
    gap: FloatArray
    initially_broken: BoolArray
    laws: tuple[JointLaw, ...]
    index: tuple[IntArray, ...]
    #: the rate level of the strengths: the cohesion and tension forces times ``rate``
    #: (1: forces; h: step impulses, :meth:`scaled`); the laws see the areas in m² always
    rate: float = 1.0
    #: the interface of each law, for messages (empty: the laws are named by their class)
    names: tuple[str, ...] = ()
    _cache: dict[bytes, tuple[FloatArray, ...]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    @classmethod
    def from_interfaces(
        cls, area: FloatArray, interface: IntArray, laws: Sequence[JointLaw], dim: int,
        names: Sequence[str] = (),
    ) -> PairLaws:  # fmt: skip
        """Per-pair arrays from the law of each interface (``interface`` (m,) indexes
        ``laws``; ``names`` the interfaces' names, for messages)."""
        names = tuple(names)
        for i, law in enumerate(laws):
            check_law(law, f"interface {names[i]!r}" if names else "")
        index = tuple(np.flatnonzero(interface == i) for i in range(len(laws)))

        def col(values: list[float]) -> FloatArray:
            return np.asarray(values, dtype=float)[interface]

        m = area.size
        comp = np.zeros((m, dim))
        kn = col([0.0 if jt.kn is None else 1.0 / jt.kn for jt in laws])
        ks = col([0.0 if jt.ks is None else 1.0 / jt.ks for jt in laws])
        comp[:, -1] = kn / area
        comp[:, :-1] = (ks / area)[:, None]
        broken = col([float(jt.initial == "broken") for jt in laws]).astype(bool)
        return cls(area, comp, col([jt.gap for jt in laws]), broken, tuple(laws), index,
                   names=names)  # fmt: skip

    @property
    def n(self) -> int:
        return int(self.area.size)

    def s_of(self, w: FloatArray, X: FloatArray) -> FloatArray:
        """The pairs' gaps and slips s = w + C X + g₀ n (m, d) of their relative motion w
        and forces X (m, d): the joint springs' share C X, and the initial gap g₀ on the
        normal (the last column)."""
        s = w + self.compliance * X
        s[:, -1] += self.gap
        return s

    def w_of(self, s: FloatArray, X: FloatArray) -> FloatArray:
        """The relative motion w = s − C X − g₀ n (m, d) of gaps and slips s: the inverse
        of :meth:`s_of`."""
        w = s - self.compliance * X
        w[:, -1] -= self.gap
        return w

    def strength(self, broken: BoolArray, path: FloatArray) -> tuple[FloatArray, ...]:
        """(c A, μ, σ_t A) of every pair for the broken flags and slip paths given (the
        arrays are shared: do not modify them). The last few answers are cached: within a
        step the solver asks again and again for the same states."""
        key = broken.tobytes() + path.tobytes()
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        c, mu, t = np.zeros(self.n), np.zeros(self.n), np.zeros(self.n)
        for i, (law, idx) in enumerate(zip(self.laws, self.index, strict=True)):
            st = law.strength(self.area[idx], broken[idx], path[idx])
            where = f"interface {self.names[i]!r}: " if self.names else ""
            # (the intact strength of a pair that starts broken is asked, never used)
            held = broken[idx] | ~self.initially_broken[idx]
            c[idx], mu[idx], t[idx] = _checked(st, idx.size, law, where, held)
        if self.rate != 1.0:
            c *= self.rate
            t *= self.rate
        for arr in (c, mu, t):
            arr.setflags(write=False)
        if len(self._cache) >= 8:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = (c, mu, t)
        return c, mu, t

    def overstressed(self, X: FloatArray, path: FloatArray, tol: float = 0.0) -> BoolArray:
        """Pairs (m,) whose force X (m, d) exceeds their intact strength by more than
        ``tol`` (N): tension X_n < −σ_t A or shear ‖X_t‖ > c A + μ X_n. The time stepping
        uses it to decide breaking on converged forces."""
        c, mu, t = self.strength(np.zeros(self.n, dtype=bool), path)
        Xn = X[:, -1]
        nt = np.linalg.norm(X[:, :-1], axis=1)
        return np.asarray((Xn < -t - tol) | (nt > c + mu * Xn + tol))

    @property
    def springs(self) -> BoolArray:
        """Pairs (m,) of joints with springs (a weak layer: k_n or k_s given)."""
        return np.asarray(self.compliance.any(axis=1))

    def safety_factor(
        self, X: FloatArray, open_: BoolArray, broken: BoolArray, path: FloatArray,
        frames: FloatArray | None = None, noise: float | FloatArray = 0.0,
        opening: FloatArray | None = None,
    ) -> FloatArray:  # fmt: skip
        """The sliding safety factor of each interface (n_interfaces,), the ratio of the
        joint's shear capacity to its shear force (USACE EM 1110-2-2100; FERC Ch. III):

            FS = Σ max(0, c A + μ N) / ‖Σ T‖,

        over its pairs, with each pair's current strength (intact or residual, the slip
        path for slip-dependent laws), N its normal force (compression +: tension lowers
        the capacity, :meth:`cone`, as in the law and in the hand computation) and T its shear
        force (vector sum: the joint slides as a whole; with the pairs' ``frames`` (m, d, d)
        the shears are summed as global vectors, Σ t_iᵀ T_i, as a joint whose frames turn
        along it needs, else their local components are added); open pairs carry no shear (a
        force recorded on a pair that ends its step open is an impact impulse over the step,
        not a shear the joint carries) and no capacity, except, given the pairs' normal
        ``opening`` (m,) in m, those open by at most :data:`OPEN_CRACK_MIN_M`: they touch
        (the zero-force pair at the free end of a joint, the corner pairs of quadratic faces
        parted by 1e-8 m under compression) and keep their c A, as in the hand computation,
        whose cohesion acts on the base that is not cracked, and as in the open share and
        the cracked length of the summary, which use the same threshold. ∞ when the joint
        carries no shear: ‖Σ T‖ ≤ ``noise`` (N; a number, or one per interface), the
        round-off of its forces: a shear of that order gives a ratio of round-off (0.02
        was seen on a pair whose smooth force was 5e-16 N), or ‖Σ T‖ ≤
        :data:`FS_ROUNDOFF` times the capacity (a factor beyond 1e10 is ∞).

        >>> law = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64),
        ...                                [MohrCoulomb(phi=45.0)], 2)
        >>> X = np.array([[30.0, 100.0], [10.0, 100.0]])   # T, N of two pairs (N)
        >>> no = np.zeros(2, dtype=bool)
        >>> round(float(law.safety_factor(X, no, ~no, np.zeros(2))[0]), 6)  # 200/40
        5.0
        >>> op = np.array([False, True])                   # the second pair open
        >>> round(float(law.safety_factor(X, op, ~no, np.zeros(2))[0]), 6)  # 100/30
        3.333333
        >>> law = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64),
        ...                                [MohrCoulomb(phi=45.0, c_r=5.0)], 2)
        >>> X[1] = 0.0                                     # open, carrying nothing
        >>> round(float(law.safety_factor(X, op, ~no, np.zeros(2))[0]), 6)  # (5 + 100)/30
        3.5
        >>> gaps = np.array([0.0, 1e-8])                   # the open pair touches
        >>> round(float(law.safety_factor(X, op, ~no, np.zeros(2), opening=gaps)[0]), 6)
        3.666667
        """
        capacity, shear = self.capacity_and_shear(X, open_, broken, path, frames, opening)
        # a shear below FS_ROUNDOFF of the capacity is round-off too (a bonded joint lifted
        # by a vertical ramp, its forces near zero and its c A whole, read FS 5.9e15)
        floor = np.maximum(np.broadcast_to(np.asarray(noise, dtype=float), shear.shape),
                           FS_ROUNDOFF * capacity)  # fmt: skip
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where((shear > floor) & (shear > 0), capacity / shear, np.inf)

    def cone(
        self, Xn: FloatArray, broken: BoolArray, path: FloatArray, ramp: bool = False
    ) -> FloatArray:
        """Each pair's shear capacity (m,), N, at its normal force ``Xn`` (compression +):
        the radius of its Mohr-Coulomb cone, max(0, c A + μ X_n), with its current
        strength (intact or residual, the slip path for slip-dependent laws). Tension
        lowers it, as in the law (an intact pair holds c A − μ σ_t A ≥ 0 at its tensile
        strength) and as in the hand computation, whose c B + μ (W − U) counts the
        normal force with its sign. With ``ramp``, on the residual cohesion's ramp
        (:func:`cohesion_ramp`) the part that a pair touching with almost no normal force
        mobilises.

        >>> law = PairLaws.from_interfaces(np.ones(2), np.zeros(2, dtype=np.int64),
        ...                                [MohrCoulomb(c=100.0, phi=45.0, tensile=50.0)], 2)
        >>> law.cone(np.array([30.0, -30.0]), np.zeros(2, dtype=bool), np.zeros(2)).round(9)
        array([130.,  70.])
        """
        c, mu, t = self.strength(broken, path)
        if ramp:
            return cone(c, mu, t, Xn, broken)[0]
        return np.asarray(np.maximum(c + mu * Xn, 0.0))

    def capacity_and_shear(
        self, X: FloatArray, open_: BoolArray, broken: BoolArray, path: FloatArray,
        frames: FloatArray | None = None, opening: FloatArray | None = None,
        ramp: bool = False,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """Each interface's shear capacity Σ max(0, c A + μ N) (:meth:`cone`) and the
        magnitude of its shear force ‖Σ T‖ (n_interfaces,), N, as :meth:`safety_factor`
        takes them; with ``ramp`` each pair's capacity under its law: on the residual
        cohesion's ramp (:func:`cohesion_ramp`) the part a pair that touches with almost no
        normal force mobilises (the hand computation counts c A on every pair that
        touches)."""
        cap = self.cone(X[:, -1], broken, path, ramp=ramp)
        cracked = open_ if opening is None else open_ & (opening > OPEN_CRACK_MIN_M)
        cap = np.where(cracked, 0.0, cap)
        T = np.where(open_[:, None], 0.0, X[:, :-1])
        if frames is not None:  # the tangential rows of the frames: local → global
            T = np.einsum("mkd,mk->md", frames[:, :-1, :], T)
        capacity = np.array([cap[idx].sum() for idx in self.index])
        shear = np.array([np.linalg.norm(T[idx].sum(axis=0)) for idx in self.index])
        return capacity, shear

    def scaled(self, factor: float) -> PairLaws:
        """The laws seen at a rate level: the strengths (cohesion and tension forces)
        times ``factor`` (1 for forces at the acceleration level, h for step impulses at
        the velocity level), each law still asked at the pairs' areas in m² (a law whose
        strength is not proportional to the area, a capped cohesion, is scaled as a
        force). Rigid contacts lose their gap (the law acts on relative
        accelerations or velocities, not on displacements); the pairs of joints with
        springs keep their compliance and gap: a spring is a smooth force of the
        displacement, whose law the time stepping poses on the displacement at the end of
        the step."""
        return replace(
            self,
            compliance=self.compliance.copy(),
            gap=np.where(self.springs, self.gap, 0.0),
            rate=self.rate * factor,
        )

    def reduced(self, factor: float) -> PairLaws:
        """These laws with every strength divided by ``factor`` (:class:`Reduced`): the
        laws of a strength-reduction analysis (:func:`pfeie.strength_reduction`); the
        areas, compliances, gaps and initial states are the same, so that a solver of W
        takes them by :meth:`~pfeie.interface.InterfaceSolver.with_laws`."""
        return replace(self, laws=tuple(Reduced(law, factor) for law in self.laws))

    def subset(self, idx: IntArray) -> PairLaws:
        """The laws of the pairs ``idx`` only (a sub-problem of these pairs)."""
        pos = np.full(self.n, -1, dtype=np.int64)
        pos[idx] = np.arange(idx.size)
        index = tuple(pos[i][pos[i] >= 0] for i in self.index)
        return replace(self, area=self.area[idx], compliance=self.compliance[idx],
                       gap=self.gap[idx], initially_broken=self.initially_broken[idx],
                       index=index)  # fmt: skip

    def initial_state(self, dim: int) -> PairState:
        """Pairs before any load (see :meth:`PairState.initial`)."""
        return PairState.initial(self.initially_broken, self.gap, dim)


__all__ = ["COHESION_RAMP", "FS_ROUNDOFF", "JOINT_STIFFNESS_MIN", "MODEL_FILE_KEYS",
           "OPEN_CRACK_MIN_M", "Joint", "JointLaw", "MohrCoulomb", "PairLaws", "Reduced",
           "SlipWeakening", "Strength", "check_law", "cohesion_ramp", "cone", "law_fields",
           "law_key"]  # fmt: skip

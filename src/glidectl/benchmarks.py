"""Benchmark systems for region-of-attraction certification."""

from __future__ import annotations

import numpy as np

from . import checks
from .errors import SolverError
from .roa.polynomial import Poly
from .roa.systems import PolySystem, polynomial_system

__all__ = ["VAN_DER_POL_AREA", "drake_van_der_pol", "van_der_pol", "van_der_pol_limit_cycle"]

#: Area enclosed by the limit cycle of the Van der Pol oscillator with mu = 1 (the true region of attraction of
#: the time-reversed system); :func:`van_der_pol_limit_cycle` recomputes it (13.7222).
VAN_DER_POL_AREA = 13.72


def van_der_pol() -> PolySystem:
    """Time-reversed Van der Pol oscillator ``x1' = -x2``, ``x2' = x1 + (x1^2 - 1) x2`` (states ``x1, x2``).

    The origin is exponentially stable; its region of attraction is the inside of the (unstable) limit cycle.

    Returns
    -------
    PolySystem
        The system, with the box ``[-3, 3] x [-3.5, 3.5]`` and a nondimensional time unit.

    Raises
    ------
    GlidectlError
        Not raised: the system is fixed (listed for uniformity).
    """
    x1, x2 = Poly.variables(2)
    return polynomial_system("van_der_pol", ("x1", "x2"), [-x2, x1 + (x1**2 - 1.0) * x2],
                             box=((-3.0, -3.5), (3.0, 3.5)), time_unit="1",
                             provenance="time-reversed Van der Pol oscillator (mu = 1), Drake RegionOfAttraction "
                                        "example")


def van_der_pol_limit_cycle(n: int = 2001) -> tuple[np.ndarray, float]:
    """The limit cycle of the Van der Pol oscillator (mu = 1): ``(points (n, 2), enclosed area)``.

    Simulated forward in time (where the cycle is attracting) with ``solve_ivp`` at tight tolerances; the area is
    the shoelace formula over one period (13.7222).

    Parameters
    ----------
    n : int
        Points returned on the cycle, in ``[3, 100001]``.

    Returns
    -------
    points : ndarray, shape (n, 2)
        The cycle ``(x1, x2)``.
    area : float
        The area it encloses.

    Raises
    ------
    ArgumentTypeError
        If ``n`` is not an integer.
    ArgumentError
        If ``n`` is outside ``[3, 100001]``.
    SolverError
        If the integration fails.
    """
    from scipy.integrate import solve_ivp

    n = checks.integer("n", n, lo=3, hi=100_001)
    sol = solve_ivp(lambda t, x: [x[1], -x[0] + (1 - x[0] ** 2) * x[1]], (0.0, 80.0), [2.0, 0.0], rtol=1e-11,
                    atol=1e-11, dense_output=True)
    t = np.linspace(60.0, 80.0, 200_001)
    y = sol.sol(t)[1]
    up = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    if not sol.success or up.size < 2:
        raise SolverError(f"the Van der Pol limit cycle could not be traced: {sol.message}")
    tt = np.linspace(t[up[-2]], t[up[-1]], 100_001)
    X = sol.sol(tt).T
    area = 0.5 * abs(float(np.sum(X[:-1, 0] * X[1:, 1] - X[1:, 0] * X[:-1, 1])))
    idx = np.linspace(0, X.shape[0] - 1, n).astype(int)
    return X[idx], area


def drake_van_der_pol(repeats: int = 5) -> dict[str, float] | None:
    """Drake's ``RegionOfAttraction`` on :func:`van_der_pol` (optional extra ``drake``): ``{"rho", "time"}`` (level
    of ``V = x'Px``, median seconds over ``repeats`` calls), or ``None`` when pydrake is not installed.

    Parameters
    ----------
    repeats : int
        Calls timed, in ``[1, 100]``.

    Returns
    -------
    dict or None
        ``{"rho": level, "time": median seconds}``, or None without pydrake.

    Raises
    ------
    ArgumentTypeError
        If ``repeats`` is not an integer.
    ArgumentError
        If ``repeats`` is outside ``[1, 100]``.
    """
    import time

    repeats = checks.integer("repeats", repeats, lo=1, hi=100)

    from .roa.programs import lyapunov_matrix

    try:
        from pydrake.symbolic import Variable
        from pydrake.systems.analysis import RegionOfAttraction
        from pydrake.systems.primitives import SymbolicVectorSystem
    except ImportError:
        return None
    x1, x2 = Variable("x1"), Variable("x2")
    system = SymbolicVectorSystem(state=[x1, x2], dynamics=[-x2, x1 + (x1 * x1 - 1) * x2])
    ctx = system.CreateDefaultContext()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        V = RegionOfAttraction(system=system, context=ctx)
        times.append(time.perf_counter() - t0)
    env = dict(zip(sorted(V.GetVariables(), key=lambda v: v.get_name()), (0.3, -0.7), strict=True))
    x = np.array([0.3, -0.7])
    P = lyapunov_matrix(van_der_pol())       # Drake returns V = x'Px / rho
    return {"rho": float(x @ P @ x / V.Evaluate(env)), "time": float(np.median(times))}

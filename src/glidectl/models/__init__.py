"""Vector fields ``xdot = f(x, u)`` of glidectl's vehicle models (one right-hand side per model): the
longitudinal glider of chapter 2 (force, acceleration and glide-path forms), the reduced chapter-5 glider, its
nondimensional (singular-perturbation) and slow forms, its torque-, buoyancy- and elevator-controlled variants of
chapter 6 and the torque loop realized by the moving mass, the phugoid model of chapter 4 and its
Hamiltonian descriptions, the three-dimensional glider of chapters 2 and 8, the CTOL aircraft of chapter 7 (full,
reduced, thrust-extended and closed-loop forms), the generic :class:`ClosedLoop` of a plant under a state feedback
and the :class:`SaturatedLoop` of a plant under a saturated linear state feedback. ``REDUCED_STATES`` is defined by
both :mod:`~glidectl.models.ctol` and :mod:`~glidectl.models.reduced` with different meanings, so it is not
re-exported here; import it from its module."""

from .buoyancy_glider import (
    BUOYANCY_STATES,
    BUOYANCY_UNITS,
    ActuatorLimits,
    BuoyancyGlider,
    actuator_limits,
    loaded_rates,
)
from .closed_loop import ClosedLoop
from .ctol import (
    CTOL_INPUTS,
    CTOL_STATES,
    CTOLAircraft,
    CTOLReduced,
    ExtendedCTOL,
    drag_coefficient,
    lift_coefficient,
    require_ctol,
)
from .ctol_closed_loop import ClosedLoopCTOL, ClosedLoopCTOLAlpha, steady_glide_inputs
from .elevator_glider import ElevatorBuoyancyGlider, effective_coefficients, elevator_loads
from .glider3d import (
    FIXED_STATES,
    FORCE3D_INPUTS,
    FORCE3D_STATES,
    FixedMassGlider3D,
    Glider3D,
    R_to_ypr,
    hat,
    quat_to_R,
    ypr_to_quat,
    ypr_to_R,
)
from .longitudinal import (
    ACCEL_INPUTS,
    ACCEL_STATES,
    FORCE_INPUTS,
    FORCE_STATES,
    STATE_UNITS,
    AccelerationControlledGlider,
    GlidePathModel,
    LongitudinalGlider,
)
from .nondimensional import NondimensionalModel, NondimensionalScaling, SlowModel
from .phugoid import C_STEADY, PHUGOID_STATES, PhugoidClass, PhugoidModel, classify_C, initial_state_for_C, orbit_period
from .phugoid_hamiltonian import (
    PendulumAnalogue,
    canonical_field,
    canonical_vector_field,
    charged_particle_field,
    charged_particle_omega,
    euler_lagrange_field,
    from_canonical,
    interior_product,
    lagrangian,
    legendre_field,
    legendre_hamiltonian,
    legendre_vector_field,
    omega_B,
    pdot_as_printed,
    symplectic_field,
    to_canonical,
    vector_potential,
    wedge,
    zero_energy_shift,
)
from .realized_torque import RealizedTorqueLoop
from .reduced import REDUCED_UNITS, ReducedLongitudinalGlider
from .saturated_loop import SaturatedLoop
from .torque_glider import TORQUE_INPUTS, TorqueControlledGlider

__all__ = [
    "ACCEL_INPUTS",
    "ACCEL_STATES",
    "BUOYANCY_STATES",
    "BUOYANCY_UNITS",
    "CTOL_INPUTS",
    "CTOL_STATES",
    "C_STEADY",
    "FIXED_STATES",
    "FORCE3D_INPUTS",
    "FORCE3D_STATES",
    "FORCE_INPUTS",
    "FORCE_STATES",
    "PHUGOID_STATES",
    "REDUCED_UNITS",
    "STATE_UNITS",
    "TORQUE_INPUTS",
    "AccelerationControlledGlider",
    "ActuatorLimits",
    "BuoyancyGlider",
    "CTOLAircraft",
    "CTOLReduced",
    "ClosedLoop",
    "ClosedLoopCTOL",
    "ClosedLoopCTOLAlpha",
    "ElevatorBuoyancyGlider",
    "ExtendedCTOL",
    "FixedMassGlider3D",
    "GlidePathModel",
    "Glider3D",
    "LongitudinalGlider",
    "NondimensionalModel",
    "NondimensionalScaling",
    "PendulumAnalogue",
    "PhugoidClass",
    "PhugoidModel",
    "R_to_ypr",
    "RealizedTorqueLoop",
    "ReducedLongitudinalGlider",
    "SaturatedLoop",
    "SlowModel",
    "TorqueControlledGlider",
    "actuator_limits",
    "canonical_field",
    "canonical_vector_field",
    "charged_particle_field",
    "charged_particle_omega",
    "classify_C",
    "drag_coefficient",
    "effective_coefficients",
    "elevator_loads",
    "euler_lagrange_field",
    "from_canonical",
    "hat",
    "initial_state_for_C",
    "interior_product",
    "lagrangian",
    "legendre_field",
    "legendre_hamiltonian",
    "legendre_vector_field",
    "lift_coefficient",
    "loaded_rates",
    "omega_B",
    "orbit_period",
    "pdot_as_printed",
    "quat_to_R",
    "require_ctol",
    "steady_glide_inputs",
    "symplectic_field",
    "to_canonical",
    "vector_potential",
    "wedge",
    "ypr_to_R",
    "ypr_to_quat",
    "zero_energy_shift",
]

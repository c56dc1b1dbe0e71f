"""glidectl: control-systems design for gliding vehicles (after Bhatta, Princeton 2006)."""
from .errors import GlidectlError, InfeasibleGlideError, ModelError, SolverError, VehicleFileError
from .params import Vehicle, list_presets, load_vehicle

__version__ = "0.1.0"

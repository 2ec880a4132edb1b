"""Moving ice: rigid-body dynamics of the pieces (docs/model.md, "Ice motion").

`IceMotionSettings` (coefficients, window, time step), `IceMotionEngine` (a pymunk space with a kinematic
hull, the pieces by id, water forces, the awake window), `body_geometry` (mass properties of a polygon).
"""

from floebreak.dynamics.bodies import BodyGeometry, body_geometry
from floebreak.dynamics.engine import IceMotionEngine, PieceState
from floebreak.dynamics.settings import IceMotionSettings

__all__ = ["BodyGeometry", "IceMotionEngine", "IceMotionSettings", "PieceState", "body_geometry"]

"""consph: SPH fluid simulation with consistent rigid-fluid coupling."""
from ._consph import __version__, precision  # noqa: F401

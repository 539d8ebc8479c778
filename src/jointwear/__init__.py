"""jointwear: non-uniform wear of revolute clearance joints and the wear reliability of planar mechanisms."""

__version__ = "0.1.0"

"""jointwear: non-uniform wear of revolute clearance joints and the wear reliability of planar mechanisms.

>>> import jointwear
>>> study = jointwear.Study("jin2025_flapping_wing", out="results")   # doctest: +SKIP
>>> results = study.run()                                            # doctest: +SKIP
"""

import importlib
import importlib.util
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the names type checkers see; at run time __getattr__ imports them on first use
    from jointwear.config import load_config, updated
    from jointwear.schema import ConfigError
    from jointwear.study import Study, compare_studies, load_results

try:
    __version__ = version("jointwear")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

__all__ = ["Study", "load_results", "load_config", "updated", "compare_studies", "ConfigError", "__version__"]


def __getattr__(name: str) -> object:
    # the study pulls in numba and the reliability engine: import it on first use, not with the package
    if name in ("Study", "load_results", "compare_studies"):
        from jointwear import study

        return getattr(study, name)
    if name in ("load_config", "updated"):  # a config, and a variation of one
        from jointwear import config

        return getattr(config, name)
    if name == "ConfigError":  # what every boundary check raises: `except jointwear.ConfigError`
        from jointwear.schema import ConfigError

        return ConfigError
    if not name.startswith("_") and importlib.util.find_spec(f"jointwear.{name}") is not None:
        # a subpackage reached as an attribute (jointwear.study.ReliabilityCurve), as SciPy's load on first use
        return importlib.import_module(f"jointwear.{name}")
    raise AttributeError(f"module 'jointwear' has no attribute {name!r}")


def __dir__() -> list[str]:
    # the public names, the lazily imported ones too, so that tab completion offers them
    return sorted(set(__all__) | {name for name in globals() if name.startswith("__")})

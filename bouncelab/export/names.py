"""The export's languages and default names: light, so that the command line's parser can name them without
importing the translator (``bouncelab --help`` stays quick)."""

from __future__ import annotations

__all__ = ["DEFAULT_CLASS", "DEFAULT_PREFIX", "DEFAULT_SURFACE_CLASS", "DEFAULT_SURFACE_PREFIX", "LANGUAGES"]

#: The languages a law or a surface exports to.
LANGUAGES = ("c", "js", "cs")
#: The prefix of every name an exported C header defines, unless told another.
DEFAULT_PREFIX = "bouncelab_"
#: The name of an exported C# class, unless told another.
DEFAULT_CLASS = "BouncelabLaw"
#: The prefix of every name an exported surface's C header defines, unless told another.
DEFAULT_SURFACE_PREFIX = "bouncelab_"
#: The name of an exported surface's C# class, unless told another.
DEFAULT_SURFACE_CLASS = "BouncelabSurface"

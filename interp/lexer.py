"""The old path of ``cutsim.interp.core.lexer``: this name is that very module (the modules not yet
in a dialect package and plug-in dialects import it from here)."""
import sys

from .core import lexer as _module

sys.modules[__name__] = _module

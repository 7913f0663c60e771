"""``cutsim.interp.core.compensation`` under its former path: this name is that very module. Kept while the
Sinumerik and RS274NGC packages import it here (tests/test_imports.py lists them; new code imports
``cutsim.interp.core.compensation``)."""
import sys

from .core import compensation as _module

sys.modules[__name__] = _module

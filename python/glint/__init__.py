"""Glint from Python (docs/python.md): scenes, rendering, frames and their layers as numpy
arrays, every filter, the bank, auto, sessions and the metrics.

    PYTHONPATH=build/python python3 -c "import glint"
"""
import os as _os

# An installed package carries the unet's weights beside itself (cmake --install ... --component
# python); the library reads them from GLINT_UNET_WEIGHTS_DIR unless the user named a folder.
# In the build tree there is no such folder and the library falls back to the source tree's.
_weights = _os.path.join(_os.path.dirname(_os.path.abspath(__file__)), "weights", "oidn")
if _os.path.isdir(_weights):
    _os.environ.setdefault("GLINT_UNET_WEIGHTS_DIR", _weights)
del _weights

from ._glint import *  # noqa: F401,F403,E402
from ._glint import FrameBuffers, Image  # noqa: E402
from . import testing  # noqa: F401,E402


def _repr_png_(self):
    """The image's display values as PNG bytes (Jupyter), at `self.exposure` stops."""
    return self._png(float(self.exposure))


for _cls in (Image, FrameBuffers):
    _cls.exposure = 0.0  # stops; set it on an instance to brighten its picture in Jupyter
    _cls._repr_png_ = _repr_png_
del _cls

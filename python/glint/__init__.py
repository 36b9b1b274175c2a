"""Glint from Python (docs/python.md): scenes, rendering, frames and their layers as numpy
arrays, every filter, the bank, auto, sessions and the metrics.

    PYTHONPATH=build/python python3 -c "import glint"
"""
from ._glint import *  # noqa: F401,F403
from ._glint import FrameBuffers, Image
from . import testing  # noqa: F401


def _repr_png_(self):
    """The image's display values as PNG bytes (Jupyter), at `self.exposure` stops."""
    return self._png(float(self.exposure))


for _cls in (Image, FrameBuffers):
    _cls.exposure = 0.0  # stops; set it on an instance to brighten its picture in Jupyter
    _cls._repr_png_ = _repr_png_
del _cls

"""Shared fixtures of the Python module's tests: where the sources and the CLIs are, tiny scenes
written into the test's own folder."""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("GLINT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
BIN_DIR = pathlib.Path(os.environ.get("GLINT_BIN_DIR", SOURCE_DIR / "build" / "bin"))


def write_cornell(folder, size, spp=4, max_depth=8):
    """A Cornell box scene.json of size x size pixels in `folder` (the box's OBJ from scenes/)."""
    scene = {
        "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "up": [0, 1, 0],
                   "fovY": 39.3},
        "film": {"width": size, "height": size},
        "materials": {"light": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [17, 12, 4]}},
        "shapes": [{"obj": str(SOURCE_DIR / "scenes" / "cornell" / "cornell_box.obj")}],
        "render": {"spp": spp, "maxDepth": max_depth},
    }
    path = pathlib.Path(folder) / "scene.json"
    path.write_text(json.dumps(scene))
    return path


@pytest.fixture
def tiny_scene(tmp_path):
    return write_cornell(tmp_path, 32)


@pytest.fixture
def tiny_frame(tiny_scene):
    """A 32x32 render with variance and half buffers (8 spp, 1 thread)."""
    import glint
    with glint.load_scene(tiny_scene) as scene:
        return scene.render(spp=8, seed=3, threads=1, half_buffers=True).frame


def run_cli(tool, *args):
    """Runs build/bin/TOOL with `args`; returns the completed process (check=True)."""
    return subprocess.run([str(BIN_DIR / tool), *map(str, args)], check=True,
                          capture_output=True, text=True)

"""The installed package (cmake --install build --component python --prefix P) works on its own:
imported from P alone, with no GLINT_* variable set and the build tree off PYTHONPATH, it finds
the unet's weights inside itself (not in the source tree the library was built from)."""
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

BUILD_DIR = pathlib.Path(os.environ["GLINT_BUILD_DIR"])
CMAKE = os.environ.get("GLINT_CMAKE", "cmake")

# Runs in a fresh interpreter from the install: the unet as a filter and in the default bank.
SCRIPT = """
import sys
import numpy as np
import glint
assert glint.__file__.startswith(sys.argv[1]), glint.__file__
frame = glint.FrameBuffers(32, 32)
frame["color"] = np.random.default_rng(1).random((32, 32, 3), dtype=np.float32)
try:
    out = glint.apply_filter(frame, "unet", threads=1)
except glint.Error as e:
    print("ERROR", e.file, e)
    sys.exit(3)
assert np.asarray(out).shape == (32, 32, 3) and np.isfinite(np.asarray(out)).all()
# The default bank takes the unet only when its weights are there.
assert [f["name"] for f in glint.filters() if f["name"] == "unet" and f["default_bank"]]
print("OK")
"""


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The python component installed into a temporary prefix; returns (prefix, package parent)."""
    prefix = tmp_path_factory.mktemp("prefix")
    subprocess.run([CMAKE, "--install", str(BUILD_DIR), "--component", "python", "--prefix",
                    str(prefix)], check=True, capture_output=True, text=True)
    inits = list(prefix.rglob("glint/__init__.py"))
    assert len(inits) == 1, inits
    return prefix, inits[0].parents[1]


def run_installed(prefix, site, weights_env=None):
    """Runs SCRIPT from the install with only `site` on PYTHONPATH, from inside the prefix."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("GLINT_") and k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    if weights_env:
        env["GLINT_UNET_WEIGHTS_DIR"] = weights_env
    return subprocess.run([sys.executable, "-c", SCRIPT, str(prefix)], cwd=prefix, env=env,
                          capture_output=True, text=True)


def test_the_installed_module_runs_the_unet_with_the_weights_installed_beside_it(installed):
    prefix, site = installed
    done = run_installed(prefix, site)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().endswith("OK")


def test_the_installed_module_reads_the_weights_from_its_own_folder_not_the_source_tree(
        installed, tmp_path):
    prefix, site = installed
    weights = site / "glint" / "weights" / "oidn"
    assert (weights / "LICENSE.txt").is_file()
    # With the install's weights moved away the unet fails naming the install's file, which
    # shows that the source tree's copy (still in place) is not what it reads.
    moved = tmp_path / "oidn"
    shutil.move(str(weights), str(moved))
    weights.mkdir()
    try:
        done = run_installed(prefix, site)
    finally:
        weights.rmdir()
        shutil.move(str(moved), str(weights))
    assert done.returncode == 3, done.stdout + done.stderr
    assert str(weights) in done.stdout


def test_glint_unet_weights_dir_still_overrides_the_installed_weights(installed, tmp_path):
    prefix, site = installed
    done = run_installed(prefix, site, weights_env=str(tmp_path))
    assert done.returncode == 3, done.stdout + done.stderr
    assert str(tmp_path) in done.stdout

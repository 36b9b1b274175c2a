"""glint.testing: the assertions of glint/image/testing.h from Python, on files and on frames."""
import numpy as np
import pytest

import glint
from glint.testing import assert_image_matches, assert_mc_matches, images_match


@pytest.fixture
def renders(tmp_path, tiny_scene):
    """Two independent 32x32 renders of one scene (seeds 1 and 2), and a biased copy of the
    second (25 % brighter in a 16-pixel square), as EXR files."""
    with glint.load_scene(tiny_scene) as scene:
        a = scene.render(spp=64, seed=1, threads=1).frame
        b = scene.render(spp=64, seed=2, threads=1).frame
    paths = {"a": tmp_path / "a.exr", "b": tmp_path / "b.exr", "biased": tmp_path / "biased.exr"}
    a.write_exr(paths["a"])
    b.write_exr(paths["b"])
    b["color"][8:24, 8:24] *= 1.25
    b.write_exr(paths["biased"])
    return paths


def test_an_unbiased_render_passes_and_a_biased_one_fails_the_mc_assertion(renders):
    assert_mc_matches(renders["a"], renders["b"])
    with pytest.raises(AssertionError, match=r"does not match .*mc: worst window"):
        assert_mc_matches(renders["biased"], renders["b"])


def test_metric_expectations_pass_and_fail_with_a_one_line_account(renders):
    match = images_match(renders["a"], renders["b"], ["ssim>=0.5", "psnr>=10"])
    assert match and "matches" in match.message and "\n" not in match.message
    with pytest.raises(AssertionError, match="ssim"):
        assert_image_matches(renders["a"], renders["b"], expect="ssim>=0.9999")


def test_frames_in_memory_are_compared_as_radiance(renders):
    a, b = glint.read_exr(renders["a"]), glint.read_exr(renders["b"])
    assert images_match(a, b, ["mc", "flip<=0.5"])


def test_bad_input_is_a_failed_match_carrying_glint_s_error(renders, tmp_path):
    missing = images_match(tmp_path / "missing.exr", renders["b"], "ssim>=0.9")
    assert not missing and "missing.exr" in missing.message
    bad = images_match(renders["a"], renders["b"], "ssim=>0.9")
    assert not bad and "ssim=>0.9" in bad.message
    with pytest.raises(AssertionError, match="missing.exr"):
        assert_image_matches(tmp_path / "missing.exr", renders["b"])

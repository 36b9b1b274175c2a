"""Image assertions for test suites, the same as the installed C++ header glint/image/testing.h
(docs/testing.md): expectations such as "ssim>=0.98", "flip<=0.05", "psnr>=30" or "mc" (the
Monte Carlo-aware comparison of the images' variance layers, at a stated false-alarm rate).

    from glint.testing import assert_image_matches
    assert_image_matches("out.exr", "ref.exr", expect=["mc", "flip<=0.05"])
"""
import os

from . import _glint


class ImageMatch:
    """Whether an image meets its expectations (truthy when it does), and a one-line account."""

    def __init__(self, ok, message):
        self.ok = ok
        self.message = message

    def __bool__(self):
        return self.ok

    def __repr__(self):
        return "ImageMatch(%r, %r)" % (self.ok, self.message)


def _name(image):
    return os.fspath(image) if isinstance(image, (str, os.PathLike)) else repr(image)


def _expectations(expect):
    return [expect] if isinstance(expect, str) else list(expect)


def images_match(image, reference, expect="ssim>=0.98"):
    """Checks each expectation of `image` against `reference` (file names, read as glint-image
    diff reads them, or glint.FrameBuffers). Never raises for bad input: a failed match then
    carries Glint's one-line error."""
    try:
        outcomes = _glint.check_expectations(image, reference, _expectations(expect))
    except _glint.Error as e:
        return ImageMatch(False, str(e))
    failures = [o["message"] for o in outcomes if not o["passed"]]
    passes = [o["message"] for o in outcomes if o["passed"]]
    if not failures:
        return ImageMatch(True, "%s matches %s: %s" % (_name(image), _name(reference), "; ".join(passes)))
    return ImageMatch(False, "%s does not match %s: %s" % (_name(image), _name(reference), "; ".join(failures)))


def assert_image_matches(image, reference, expect="ssim>=0.98"):
    """Raises AssertionError with the one-line account unless `image` meets every expectation."""
    match = images_match(image, reference, expect)
    if not match:
        raise AssertionError(match.message)


def assert_mc_matches(image, reference, false_alarm_rate=1e-4):
    """The Monte Carlo-aware assertion: fails when the difference between two renders is more than
    their variance layers explain; an unbiased pair fails at most at `false_alarm_rate`."""
    assert_image_matches(image, reference, "mc:%g" % false_alarm_rate)

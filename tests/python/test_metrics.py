"""Metrics from Python equal to their definitions (numpy) and to glint-image diff, FLIP, the Monte
Carlo comparison, and bad input raising instead of crashing."""
import numpy as np
import pytest

import glint


def noisy_pair(seed=1, size=32):
    rng = np.random.default_rng(seed)
    reference = rng.random((size, size, 3), dtype=np.float32)
    image = np.clip(reference + rng.normal(0, 0.05, reference.shape), 0, 1).astype(np.float32)
    return image, reference


def test_mse_psnr_and_relmse_are_their_definitions():
    image, reference = noisy_pair()
    d = image.astype(np.float64) - reference
    assert glint.mse(image, reference) == pytest.approx(np.mean(d * d), rel=1e-6)
    assert glint.psnr(image, reference) == pytest.approx(-10 * np.log10(np.mean(d * d)), rel=1e-6)
    rel = np.mean(d * d / (reference.astype(np.float64) ** 2 + 1e-2))
    assert glint.relmse(image, reference) == pytest.approx(rel, rel=1e-6)


def test_ssim_of_an_image_with_itself_is_one_and_drops_with_noise():
    image, reference = noisy_pair()
    assert glint.ssim(reference, reference) == pytest.approx(1.0)
    assert glint.ssim(image, reference) < 0.99
    assert glint.ssim_map(image, reference).shape == (32, 32, 1)
    assert glint.ssim(image, reference, crop=(0, 0, 16, 16)) != glint.ssim(image, reference)


def test_flip_is_zero_for_equal_images_and_gives_its_map():
    image, reference = noisy_pair()
    assert glint.flip(reference, reference).mean == 0.0
    result = glint.flip(image, reference)
    assert 0.0 < result.mean < 1.0 and result.map.shape == (32, 32, 1)
    hdr = glint.flip(image * 4, reference * 4, hdr=True)
    assert hdr.exposures >= 2 and 0.0 < hdr.mean < 1.0
    with pytest.raises(glint.InvalidArgument, match="(?i)hdr"):
        glint.flip(image * 4, reference * 4)  # LDR-FLIP on HDR values


def test_the_monte_carlo_comparison_passes_noise_and_catches_a_bias():
    rng = np.random.default_rng(4)
    truth = np.full((64, 64, 3), 0.5, np.float32)
    variance = np.full_like(truth, 0.01 ** 2)
    a = (truth + rng.normal(0, 0.01, truth.shape)).astype(np.float32)
    b = (truth + rng.normal(0, 0.01, truth.shape)).astype(np.float32)
    assert glint.mc_compare(a, variance, b, variance)
    b[16:32, 16:32] *= 1.05
    result = glint.mc_compare(a, variance, b, variance)
    assert not result.passed and result.statistic > result.threshold


def test_metrics_refuse_mismatched_shapes_and_bad_arrays():
    image, reference = noisy_pair()
    with pytest.raises(glint.InvalidArgument):
        glint.mse(image[:16].copy(), reference)
    with pytest.raises(glint.InvalidArgument, match="float32"):
        glint.ssim(image.astype(np.float64), reference)
    with pytest.raises(glint.InvalidArgument, match="C-contiguous"):
        glint.psnr(image[:, ::2], reference[:, ::2])

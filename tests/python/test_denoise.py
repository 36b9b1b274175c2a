"""Every filter by name, the bank, auto and a session's composite from Python, each checked
against the library's CLI or an invariant, and bad parameters raising with Glint's message."""
import numpy as np
import pytest

import glint
from conftest import run_cli


def test_every_registered_filter_is_listed_with_its_parameter_descriptions():
    filters = {f["name"]: f for f in glint.filters()}
    listed = run_cli("glint-denoise", "list").stdout
    for name in filters:
        assert name in listed
    gaussian = filters["gaussian"]
    assert gaussian["default_bank"] and gaussian["params"]
    spec = gaussian["params"][0]
    assert {"name", "min", "max", "default", "help", "choices"} <= spec.keys()


def test_apply_filter_by_name_equals_glint_denoise_apply(tmp_path, tiny_frame):
    source = tmp_path / "in.exr"
    tiny_frame.write_exr(source)
    out = tmp_path / "out.exr"
    run_cli("glint-denoise", "apply", source, "--filter", "cross-bilateral", "--param", "sigmaS=2",
            "--out", out)
    ours = glint.apply_filter(tiny_frame, "cross-bilateral", {"sigmaS": 2.0}, threads=1)
    assert isinstance(ours, glint.Image)
    assert np.array_equal(np.asarray(ours), glint.read_exr(out)["color"])


def test_every_filter_runs_with_its_defaults_on_a_region(tiny_frame):
    for f in glint.filters():
        if not f["default_bank"]:
            continue
        out = glint.apply_filter(tiny_frame, f["name"], region=(4, 8, 20, 16))
        assert out.shape == (8, 16, 3), f["name"]
        assert np.isfinite(np.asarray(out)).all(), f["name"]


def test_bad_filter_names_and_parameters_raise_value_error_naming_them(tiny_frame):
    with pytest.raises(ValueError, match="no-such-filter"):
        glint.apply_filter(tiny_frame, "no-such-filter")
    with pytest.raises(glint.InvalidArgument, match="sigmaS"):
        glint.apply_filter(tiny_frame, "cross-bilateral", {"sigmaS": -5.0})
    with pytest.raises(glint.InvalidArgument, match="sigmaQ"):
        glint.apply_filter(tiny_frame, "cross-bilateral", {"sigmaQ": 1.0})
    with pytest.raises(glint.InvalidArgument):
        glint.apply_filter(tiny_frame, "gaussian", region=(0, 0, 64, 64))  # past the frame


def test_a_cancelled_filter_raises_cancelled():
    frame = glint.FrameBuffers(1024, 1024)  # long enough to be asked (every 50 ms) before it ends
    frame["color"] = np.random.default_rng(1).random((1024, 1024, 3), dtype=np.float32)
    with pytest.raises(glint.Cancelled, match="returned False"):
        glint.apply_filter(frame, "nlmeans", progress=lambda f: False, threads=1)


def test_a_bank_s_results_are_read_only_views_equal_to_each_member_applied_alone(
        tiny_frame, tmp_path, monkeypatch):
    (tmp_path / "cwd").mkdir()
    monkeypatch.chdir(tmp_path / "cwd")
    bank = glint.build_bank(tiny_frame, size=4, seed=2, filters=["gaussian", "cross-bilateral"])
    assert not list((tmp_path / "cwd").iterdir())  # no cache folder: nothing written
    assert len(bank) >= 4 and bank.region == (0, 0, 32, 32)
    for i, member in enumerate(bank.members):
        result = bank.result(i)
        assert result.base is bank and not result.flags.writeable
        alone = glint.apply_filter(tiny_frame, member["filter"], member["params"])
        assert np.array_equal(result, np.asarray(alone)), member
    with pytest.raises(IndexError):
        bank.result(len(bank))
    with pytest.raises(glint.InvalidArgument, match="size"):
        glint.build_bank(tiny_frame, size=0)


def test_auto_from_python_equals_glint_denoise_auto(tmp_path, tiny_frame):
    source = tmp_path / "in.exr"
    tiny_frame.write_exr(source)
    out = tmp_path / "auto.exr"
    session = tmp_path / "auto.glint-session.json"
    run_cli("glint-denoise", "auto", source, "--quality", "fast", "--out", out,
            "--session", session)
    result = glint.auto(tiny_frame, quality="fast")
    assert result.estimator == "halves"
    assert np.array_equal(np.asarray(result.composite), glint.read_exr(out)["color"])
    assert len(result.bank) == len(result.estimated_mse)
    # The session auto wrote composites to the same image.
    loaded = glint.load_session(session)
    assert loaded.layers and np.array_equal(loaded.composite, np.asarray(result.composite))


def test_a_denoised_output_keeps_its_render_and_render_of_gives_it_back(tmp_path, tiny_frame):
    source = tmp_path / "in.exr"
    tiny_frame.write_exr(source)
    out = tmp_path / "auto.exr"
    run_cli("glint-denoise", "auto", source, "--quality", "fast", "--out", out)
    denoised = glint.read_exr(out)
    assert "noisy" in denoised
    assert np.array_equal(denoised["noisy"], tiny_frame["color"])
    # Its colour is denoised and its halves are the render's: auto names the way back.
    with pytest.raises(glint.Error, match="render_of"):
        glint.auto(denoised, quality="fast")
    render = glint.render_of(denoised)
    assert "noisy" not in render
    assert "denoiseFilter" not in render.metadata
    assert np.array_equal(render["color"], tiny_frame["color"])
    again = glint.auto(render, quality="fast")
    assert np.array_equal(np.asarray(again.composite), denoised["color"])


def test_auto_on_a_given_bank_uses_its_members(tiny_frame):
    bank = glint.build_bank(tiny_frame, size=4, filters=["gaussian"])
    result = glint.auto(tiny_frame, bank=bank)
    assert 0 <= result.best_member < len(bank)
    assert result.bank is bank


def test_auto_without_variance_or_halves_refuses_sure(tiny_frame):
    frame = glint.FrameBuffers(tiny_frame.width, tiny_frame.height)
    frame["color"] = tiny_frame["color"]
    with pytest.raises(glint.Error, match="variance"):
        glint.auto(frame, estimator="sure")


def test_a_bank_with_a_cache_folder_is_read_back_from_it(tiny_frame, tmp_path):
    first = glint.build_bank(tiny_frame, size=4, cache_dir=tmp_path / "bank")
    assert (tmp_path / "bank" / "index.json").exists() and first.cache_hits == 0
    again = glint.build_bank(tiny_frame, size=4, cache_dir=tmp_path / "bank")
    assert again.cache_hits == len(again) == len(first)

"""glint.Scene: a render from Python bit-identical to glint-render's, progress callbacks, Ctrl-C
and cancelling, look edits, and a closed ("dead") scene raising instead of crashing."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import glint
from conftest import SOURCE_DIR, run_cli, write_cornell


def test_a_256_pixel_render_from_python_is_bit_identical_to_glint_render_s(tmp_path):
    scene_file = SOURCE_DIR / "scenes" / "cornell" / "scene.json"  # 256 x 256
    cli = tmp_path / "cli.exr"
    run_cli("glint-render", scene_file, "--spp", 4, "--seed", 5, "--threads", 2, "--out", cli)
    with glint.load_scene(scene_file) as scene:
        assert (scene.width, scene.height) == (256, 256)
        frame = scene.render(spp=4, seed=5, threads=1).frame
    expected = glint.read_exr(cli)
    assert frame.layers == expected.layers
    for layer in expected.layers:
        assert np.array_equal(frame[layer], expected[layer]), layer
    assert frame.metadata["spp"] == 4 and frame.metadata["seed"] == 5


def test_progress_is_reported_on_the_calling_thread_up_to_one(tiny_scene):
    seen = []
    caller = threading.get_ident()

    def progress(fraction):
        assert threading.get_ident() == caller
        seen.append(fraction)

    with glint.load_scene(tiny_scene) as scene:
        result = scene.render(spp=2, threads=1, progress=progress)
    assert seen and seen[-1] == 1.0
    assert seen == sorted(seen)
    assert result.stats["completed_spp"] == 2 and not result.stats["cancelled"]


def test_a_progress_callback_returning_false_raises_cancelled(tmp_path):
    with glint.load_scene(write_cornell(tmp_path, 64)) as scene:
        with pytest.raises(glint.Cancelled, match="progress callback returned False"):
            scene.render(spp=100000, threads=1, progress=lambda f: False)
        # The scene is still usable afterwards.
        assert scene.render(spp=1, threads=1).stats["completed_spp"] == 1


def test_an_exception_in_the_progress_callback_stops_the_render_and_propagates(tmp_path):
    def progress(fraction):
        raise RuntimeError("stop here")

    with glint.load_scene(write_cornell(tmp_path, 64)) as scene:
        with pytest.raises(RuntimeError, match="stop here"):
            scene.render(spp=100000, threads=1, progress=progress)


def test_ctrl_c_stops_a_render_with_keyboard_interrupt(tmp_path):
    with glint.load_scene(write_cornell(tmp_path, 64)) as scene:
        timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                scene.render(spp=1000000, threads=1)  # hours without the interrupt
        finally:
            timer.cancel()


def test_other_python_threads_run_while_glint_renders(tmp_path):
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    with glint.load_scene(write_cornell(tmp_path, 64)) as scene:
        ticker = threading.Thread(target=tick)
        ticker.start()
        try:
            result = scene.render(spp=256, threads=1)
            during = len(ticks)
        finally:
            stop.set()
            ticker.join()
    # With the GIL held through the render the ticker would not run at all.
    assert result.stats["completed_spp"] == 256 and during > 5


def test_settings_are_given_by_name_and_checked_by_glint(tiny_scene):
    with glint.load_scene(tiny_scene) as scene:
        assert scene.settings["spp"] == 4 and scene.settings["maxDepth"] == 8
        frame = scene.render(spp=2, max_depth=2, sampler="independent", half_buffers=True,
                             threads=1).frame
        assert "halfColor" in frame.layers
        with pytest.raises(ValueError, match="unknown setting 'max_deep'"):
            scene.render(max_deep=2)
        with pytest.raises(glint.InvalidArgument, match="sampler"):
            scene.render(sampler="halton")
        with pytest.raises(ValueError):
            scene.render(spp=-1)


def test_look_edits_change_the_next_render_and_out_of_range_values_raise(tiny_scene):
    with glint.load_scene(tiny_scene) as scene:
        light = next(item for item in scene.look() if item["name"] == "light")
        strength = next(p for p in light["properties"] if p["name"] == "strength")
        assert strength["value"] == 17.0 and strength["min"] == 0.0
        before = scene.render(spp=2, threads=1).frame["color"].copy()
        scene.set_look("light", "strength", 34.0)
        after = scene.render(spp=2, threads=1).frame["color"]
        assert after.sum() == pytest.approx(2 * before.sum(), rel=1e-4)  # light is all there is
        scene.set_look("light", "emission", (1.0, 1.0, 1.0))
        assert scene.look()[0]["properties"][1]["value"] == (1.0, 1.0, 1.0)
        with pytest.raises(ValueError, match="light"):
            scene.set_look("light", "strength", -1.0)
        with pytest.raises(glint.InvalidArgument, match="3 values"):
            scene.set_look("light", "emission", (1.0, 1.0))
        with pytest.raises(glint.InvalidArgument):
            scene.set_look("no-such-material", "albedo", 0.5)


def test_a_closed_scene_raises_instead_of_crashing(tiny_scene):
    scene = glint.load_scene(tiny_scene)
    scene.close()
    for use in (lambda: scene.render(spp=1), lambda: scene.width, scene.look,
                lambda: scene.set_look("light", "strength", 1.0)):
        with pytest.raises(glint.InvalidArgument, match="the scene was closed"):
            use()
    with glint.load_scene(tiny_scene) as scene:
        pass
    with pytest.raises(glint.InvalidArgument, match="closed"):
        scene.render(spp=1)


def test_a_missing_or_malformed_scene_raises_with_the_file_and_place(tmp_path):
    with pytest.raises(OSError, match="nothing.json"):
        glint.load_scene(tmp_path / "nothing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"film": {"width": "wide"}}')
    with pytest.raises(glint.Error, match="bad.json"):
        glint.load_scene(bad)

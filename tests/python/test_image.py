"""glint.Image and glint.FrameBuffers: numpy views without copies, EXR round trips, PNG display,
and bad arrays raising Python exceptions with Glint's message."""
import numpy as np
import pytest

import glint


def test_importing_glint_gives_the_compiled_module_and_its_error_classes():
    assert issubclass(glint.InvalidArgument, glint.Error)
    assert issubclass(glint.InvalidArgument, ValueError)
    assert issubclass(glint.IoError, OSError)
    assert "color" in glint.layer_names()


def test_a_4k_frame_s_layers_are_numpy_views_of_its_memory_not_copies():
    frame = glint.FrameBuffers(3840, 2160)
    color = frame["color"]
    assert color.shape == (2160, 3840, 3) and color.dtype == np.float32
    # The view's base is the frame itself, and writing through it writes the frame.
    assert color.base is frame
    assert np.shares_memory(color, frame["color"])
    color[10, 20] = (1.0, 2.0, 3.0)
    assert tuple(frame["color"][10, 20]) == (1.0, 2.0, 3.0)
    # A view outlives the name of its frame.
    del frame
    assert color[10, 20, 1] == 2.0


def test_an_image_is_a_buffer_numpy_reads_without_copying():
    image = glint.Image(64, 32, 3, 0.5)
    view = np.asarray(image)
    assert view.shape == (32, 64, 3)
    assert np.shares_memory(view, image.array)
    view[0, 0, 0] = 7.0
    assert image.array[0, 0, 0] == 7.0


def test_setting_a_layer_copies_the_array_into_the_frame_s_own_storage(tmp_path):
    frame = glint.FrameBuffers(8, 4)
    view = frame["color"]
    frame["color"] = np.full((4, 8, 3), 0.25, np.float32)
    assert view[3, 7, 2] == 0.25  # the old view still sees the frame
    frame["albedo"] = np.ones((4, 8, 3), np.float32)
    assert frame.layers == ["color", "albedo"]
    assert "albedo" in frame and "depth" not in frame


def test_a_frame_round_trips_through_exr_bit_for_bit(tmp_path):
    frame = glint.FrameBuffers(16, 8)
    rng = np.random.default_rng(1)
    frame["color"] = rng.random((8, 16, 3), dtype=np.float32)
    frame["depth"] = rng.random((8, 16, 1), dtype=np.float32)
    path = tmp_path / "frame.exr"
    frame.write_exr(path)
    back = glint.read_exr(path)
    assert back.layers == ["color", "depth"]
    assert np.array_equal(back["color"], frame["color"])
    assert np.array_equal(back["depth"], frame["depth"])


def test_images_show_themselves_as_png_with_their_exposure():
    image = glint.Image(np.full((4, 4, 3), 0.1, np.float32))
    dark = image._repr_png_()
    assert dark.startswith(b"\x89PNG")
    image.exposure = 3.0
    assert image._repr_png_() != dark
    frame = glint.FrameBuffers(4, 4)
    assert frame._repr_png_().startswith(b"\x89PNG")


@pytest.mark.parametrize("array, says", [
    (np.zeros((4, 4, 3), np.float64), "float32"),
    (np.zeros((4, 4, 3, 2), np.float32), "dimensions"),
    (np.zeros((4, 8, 3), np.float32)[:, ::2], "C-contiguous"),
    ([[1.0, 2.0]], "expected a glint.Image or a numpy float32 array"),
])
def test_a_bad_array_raises_invalid_argument_with_glint_s_message(array, says):
    with pytest.raises(glint.InvalidArgument, match=says):
        glint.Image(array)


def test_a_layer_of_the_wrong_shape_or_name_is_refused():
    frame = glint.FrameBuffers(8, 4)
    with pytest.raises(ValueError, match=r"expected shape \(4, 8, 3\)"):
        frame["color"] = np.zeros((4, 8, 1), np.float32)
    with pytest.raises(KeyError, match="no layer 'colour'"):
        frame["colour"]
    with pytest.raises(KeyError, match="no layer 'albedo'"):
        frame["albedo"]


def test_reading_a_missing_or_broken_file_raises_os_error_or_value_error(tmp_path):
    with pytest.raises(OSError) as missing:
        glint.read_exr(tmp_path / "missing.exr")
    assert missing.value.kind == "io" and "missing.exr" in str(missing.value)
    broken = tmp_path / "broken.exr"
    broken.write_bytes(b"v/1\x01" + b"\0" * 40)
    with pytest.raises(glint.Error):
        glint.read_exr(broken)

"""Images to and from files: integer images keep their levels, and what
is not an image of floats or levels is refused."""

import numpy as np
import pytest

import glint


@pytest.mark.parametrize("dtype, top", [(np.uint8, 255), (np.uint16, 65535)])
def test_an_integer_image_is_written_at_its_levels(tmp_path, dtype, top):
    # Levels are sRGB-encoded, as a PNG's: decoded to linear.
    levels = np.full((2, 3, 3), top // 2 + 1, dtype=dtype)
    path = tmp_path / "x.pfm"
    glint.write(levels, path)
    back = glint.read(path)
    c = (top // 2 + 1) / top
    assert np.allclose(back, ((c + 0.055) / 1.055) ** 2.4, rtol=1e-6)
    png = tmp_path / "x.png"
    glint.write(np.full((2, 3, 3), 128, dtype=np.uint8), png)
    assert np.all(np.round(glint.read(png, srgb=False) * 255) == 128)


@pytest.mark.parametrize("array", [np.ones((2, 2, 3), dtype=bool), np.ones((2, 2, 3), dtype=np.int32)])
def test_an_image_of_bools_or_plain_integers_is_refused(tmp_path, array):
    with pytest.raises(ValueError, match="an image is floats"):
        glint.write(array, tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()

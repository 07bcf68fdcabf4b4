"""Session.render: the simulation drawn by the desktop's code into an RGB array."""

import numpy as np
import pytest

import salsa
from conftest import SMALL, SOURCE

WAREHOUSE = str(SOURCE / "examples" / "maps" / "warehouse.json")  # bounds (0, 0) to (300, 200)
ONE_GROUP = (0x1F, 0x3F, 0x8C)  # a lone group's drones: gui-qt/frame/view_drones.cpp
GROUPS = [(0xE6, 0x9F, 0x00), (0x00, 0x72, 0xB2)]  # the first two of Okabe & Ito's, as the plots'


def to_pixels(position, width, height, bounds=((0, 0), (300, 200))):
    """Where the desktop's fitted view (fit_transform: 12 px margins, y up) puts world points."""
    (x0, y0), (x1, y1) = bounds
    scale = min((width - 24) / (x1 - x0), (height - 24) / (y1 - y0))
    x = width / 2 + scale * (position[:, 0] - (x0 + x1) / 2)
    y = height / 2 - scale * (position[:, 1] - (y0 + y1) / 2)
    return np.stack([x, y], axis=1)


def near_colour(image, at, colour, reach=1, tolerance=12):
    """Whether a pixel within `reach` of `at` is `colour`."""
    x, y = int(round(at[0])), int(round(at[1]))
    patch = image[max(0, y - reach):y + reach + 1, max(0, x - reach):x + reach + 1].astype(int)
    return bool((np.abs(patch - colour).max(axis=2) <= tolerance).any())


def coloured(image, colour, tolerance=12):
    return np.abs(image.astype(int) - colour).max(axis=2) <= tolerance


def test_the_drones_are_where_they_fly():
    s = salsa.Session({**SMALL, "map": WAREHOUSE, "targets": {"kind": "tree", "count": 40}, "drones": 12})
    s.run_until(3)
    image = s.render(600, 400)
    assert image.shape == (400, 600, 3) and image.dtype == np.uint8 and image.flags.c_contiguous
    at = to_pixels(s.column("position"), 600, 400)
    assert all(near_colour(image, p, ONE_GROUP) for p in at)
    # No drone's colour away from the drones (a drone's disc is 3 px, its velocity tick 8 px long).
    mask = coloured(image, ONE_GROUP)
    ys, xs = np.nonzero(mask)
    distance = np.hypot(xs[:, None] - at[None, :, 0], ys[:, None] - at[None, :, 1]).min(axis=1)
    assert mask.sum() > 12 * 9 and distance.max() <= 10
    # The map's background inside the bounds, the window's outside them.
    assert tuple(image[200, 300]) == (0xF4, 0xF1, 0xEA) and tuple(image[2, 2]) != (0xF4, 0xF1, 0xEA)
    # Another moment, another picture; the same moment, the same picture.
    assert np.array_equal(image, s.render(600, 400))
    s.step(60)
    later = s.render(600, 400)
    assert not np.array_equal(image, later)
    assert all(near_colour(later, p, ONE_GROUP) for p in to_pixels(s.column("position"), 600, 400))


def test_groups_in_their_colours_and_stopped_drones():
    groups = [{"name": "a", "drones": 5, "behavior": "random_walk"},
              {"name": "b", "drones": 7, "behavior": "flocking", "spawn": {"point": [250, 150]}}]
    s = salsa.Session({**{k: v for k, v in SMALL.items() if k not in ("behavior", "drones", "drone")}, "groups": groups,
                       "map": WAREHOUSE, "targets": {"kind": "tree", "count": 20}})
    s.run_until(2)
    s.change("fail.drone", 3)
    image = s.render(900, 600)
    at = to_pixels(s.column("position"), 900, 600)
    group, status = s.column("group"), s.column("status")
    flying = status == 0
    assert (~flying).sum() == 1 and flying.sum() == 11
    for i in np.nonzero(flying)[0]:
        assert near_colour(image, at[i], GROUPS[group[i]]), i
    stopped = np.nonzero(~flying)[0][0]  # a cross in its group's colour with a white rim
    assert near_colour(image, at[stopped], GROUPS[group[stopped]], reach=2)
    # The legend, top left, with both groups' discs: their colours there, far from any drone.
    legend = image[:60, :200]
    assert all(coloured(legend, c).any() for c in GROUPS)


def test_a_png_as_the_desktop_draws_it(tmp_path):
    image = salsa.Session(SOURCE / "examples" / "groups-forest.json").render()
    assert image.shape == (800, 800, 3)
    try:
        from PIL import Image
    except ImportError:
        plt = pytest.importorskip("matplotlib.pyplot", reason="neither PIL nor matplotlib to write a PNG with")
        plt.imsave(tmp_path / "frame.png", image)
        assert plt.imread(tmp_path / "frame.png").shape[:2] == (800, 800)
    else:
        Image.fromarray(image).save(tmp_path / "frame.png")
        assert np.array_equal(np.asarray(Image.open(tmp_path / "frame.png").convert("RGB")), image)


def test_bad_sizes():
    s = salsa.Session(SMALL)
    with pytest.raises(ValueError, match=r"^width: 0 is out of range \(allowed: whole number of pixels in \[1, 16384\]\)"):
        s.render(0, 10)
    with pytest.raises(ValueError, match=r"^height: 20000 is out of range"):
        s.render(10, 20000)
    with pytest.raises(TypeError):
        s.render("800")
    assert s.render(1, 1).shape == (1, 1, 3)
